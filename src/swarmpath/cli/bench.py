"""``swarmpath bench``: sweeps from a suite file into a results store, and reports from it.

    swarmpath bench SUITE --store DB [--workers N] [--dask ADDRESS|local]
    swarmpath bench report DB [--by FIELDS] [--out DIR]
    swarmpath bench suites

``bench`` is a group whose first word may be a suite instead of a subcommand: anything that
is not ``report``, ``suites`` or ``run`` is taken as ``bench run SUITE ...`` (a suite file
literally called ``report`` is ``./report``).
"""
from __future__ import annotations

import os
from typing import Any

import click

from swarmpath.cli.common import console, emit_json, progress, safe, writable_file, writable_folder
from swarmpath.cli.group import cli


class BenchGroup(click.Group):
    """A group that runs ``run`` when its first argument is not one of its subcommands."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        if args and args[0] not in self.commands and args[0] not in ctx.help_option_names:
            args = ["run", *args]
        return super().parse_args(ctx, args)

    def format_usage(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        formatter.write_usage(ctx.command_path, "SUITE --store DB [--workers N] [--dask ADDRESS|local]")
        formatter.write_usage(ctx.command_path, "report DB [--by FIELDS] [--out DIR]", prefix="       ")


def _cores() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:   # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


@cli.group(cls=BenchGroup)
def bench() -> None:
    """Run a suite of jobs (scenarios x planners x controllers x seeds) into a results store,
    on local worker processes or a Dask cluster; resume by running it again; report."""


@bench.command("run")
@click.argument("suite")
@click.option("--store", required=True, type=click.Path(dir_okay=False),
              help="SQLite results store (made if missing; jobs already in it are not run again)")
@click.option("--workers", type=click.IntRange(min=1, max=4096), default=None,
              help="worker processes (default: the cores this process may use); with --dask local, Dask workers")
@click.option("--dask", default=None, metavar="ADDRESS|local",
              help="run on Dask: 'local' starts a LocalCluster, an address connects to a running scheduler")
@click.option("--retry", default=None, metavar="STATUSES",
              help="run again the stored jobs with these statuses (error, timeout; comma-separated)")
@click.option("--list", "list_only", is_flag=True, help="list the jobs and skipped pairs; run nothing")
@click.option("--json", "json_mode", is_flag=True, help="print one JSON object")
def run_suite(suite: str, store: str, workers: int | None, dask: str | None, retry: str | None, list_only: bool,
              json_mode: bool) -> None:
    """Run the jobs of SUITE (a suite file or a built-in suite's name) not yet in --store."""
    from swarmpath.bench.sweep.jobs import expand
    from swarmpath.bench.sweep.run import SweepInterrupted, make_engine, parse_retry, run_sweep
    from swarmpath.bench.sweep.store import Store
    from swarmpath.bench.sweep.suite import load_suite

    retry_statuses = parse_retry(retry)
    workers = workers or _cores()
    make_engine(workers, dask)                      # --dask without dask: one line, before any work
    loaded = load_suite(suite)
    out = console(json_mode)
    expansion = expand(loaded)
    if list_only:
        stored: dict[str, str] = {}
        if os.path.isfile(store):
            with Store(store).open() as s:
                stored = s.stored_keys(j.key for j in expansion.jobs)
        _print_list(out, loaded.name, expansion, stored, json_mode)
        return
    writable_file(store, "--store")
    label = f"{loaded.name} ({'dask ' + dask if dask else f'{workers} worker' + ('s' if workers > 1 else '')})"
    try:
        with progress(out, label, None, "job", enabled=not json_mode) as advance:
            outcome = run_sweep(loaded, store, workers=workers, dask=dask, retry=retry_statuses,
                                expansion=expansion, progress=advance)
    except SweepInterrupted as exc:
        o = exc.outcome
        click.echo(f"swarmpath: {o.suite}: stopped after {o.ran} of {o.total - o.already} jobs; {store} keeps "
                   f"{o.already + o.ran} of {o.total}; run the same command again to resume", err=True)
        raise KeyboardInterrupt from None
    doc = {"suite": outcome.suite, "store": store, "engine": outcome.engine, "workers": workers,
           "jobs": outcome.total, "already": outcome.already, "ran": outcome.ran, **outcome.statuses,
           "stored": outcome.already + outcome.ran, "wall_s": outcome.wall_s,
           "skipped": [_skip_doc(s) for s in expansion.skipped]}
    if json_mode:
        emit_json(doc)
        return
    _print_skipped(out, expansion.skipped)
    s = outcome.statuses
    out.print(f"{safe(outcome.suite)}: {outcome.total} jobs, {outcome.already} already in {safe(store)}; ran "
              f"{outcome.ran} in {outcome.wall_s:.1f} s: {s['ok']} ok, {s['error']} failed, {s['timeout']} timed out. "
              f"Report: swarmpath bench report {safe(store)} --out DIR", soft_wrap=True)


def _skip_doc(s: Any) -> dict[str, Any]:
    return {"scenario": s.scenario, "world": s.detail, "planner": s.planner, "controller": s.controller,
            "jobs": s.n_jobs, "reason": s.reason}


def _print_skipped(out, skipped: list[Any], limit: int = 12) -> None:
    """Skipped pairs, one line per planner/controller/reason with its worlds and jobs."""
    if not skipped:
        return
    groups: dict[tuple[str, str, str], list[Any]] = {}
    for s in skipped:
        groups.setdefault((s.planner, s.controller, s.reason), []).append(s)
    total = sum(s.n_jobs for s in skipped)
    out.print(f"skipped {total} job{'s' if total != 1 else ''} (pairs that cannot run together):", soft_wrap=True)
    for k, ((planner, controller, reason), items) in enumerate(sorted(groups.items())):
        if k == limit:
            out.print(f"  ... and {len(groups) - limit} more (swarmpath bench report lists them all)", soft_wrap=True)
            break
        who = controller if planner == "-" else f"{planner} + {controller}"
        worlds = sorted({s.scenario for s in items})
        where = ", ".join(worlds[:3]) + (f" and {len(worlds) - 3} more" if len(worlds) > 3 else "")
        out.print(f"  {safe(who)} on {safe(where)} ({sum(s.n_jobs for s in items)} jobs): {safe(reason)}",
                  soft_wrap=True)


def _print_list(out, name: str, expansion: Any, stored: dict[str, str], json_mode: bool) -> None:
    jobs = expansion.jobs
    if json_mode:
        emit_json({"suite": name, "jobs": [{"key": j.key, "scenario": j.scenario, "world": j.detail,
                                            "n_agents": j.n_agents, "planner": j.planner, "controller": j.controller,
                                            "method": j.method, "seed": j.seed, "stored": stored.get(j.key)}
                                           for j in jobs],
                   "skipped": [_skip_doc(s) for s in expansion.skipped]})
        return
    from rich.table import Table

    groups: dict[tuple[str, str, str], list[Any]] = {}
    for j in jobs:
        groups.setdefault((j.scenario, j.detail, j.method), []).append(j)
    table = Table("scenario", "world", "method", "seeds", "stored", box=None)
    for (scenario, detail, method), items in groups.items():
        table.add_row(safe(scenario), safe(detail), safe(method), str(len(items)),
                      str(sum(1 for j in items if j.key in stored)))
    out.print(table)
    _print_skipped(out, expansion.skipped)
    already = sum(1 for j in jobs if j.key in stored)
    out.print(f"{safe(name)}: {len(jobs)} jobs, {already} already stored", soft_wrap=True)


@bench.command("report")
@click.argument("store", type=click.Path(dir_okay=False))
@click.option("--by", default=None, metavar="FIELDS",
              help="group the summary by these fields (comma-separated; default: scenario,n_agents,method)")
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="folder for jobs.csv, summary.csv/.md, plot_data.csv and the plots (default: STORE-report)")
def report(store: str, by: str | None, out: str | None) -> None:
    """Write jobs.csv, summary tables (CSV, Markdown) and plots of a results store."""
    from pathlib import Path

    from swarmpath.bench.sweep.report import parse_by, write_report
    from swarmpath.bench.sweep.store import Store

    fields = parse_by(by)
    Store(store).open().close()                     # a missing or foreign file: one line, before any work
    folder = writable_folder(out or f"{Path(store).with_suffix('')}-report", "--out")
    out_console = console(False)
    with progress(out_console, "plotting", None, "plot") as advance:
        written = write_report(store, folder, fields, progress=advance)
    out_console.print(f"wrote {len(written)} files to {safe(folder)}: {', '.join(safe(p.name) for p in written)}",
                      soft_wrap=True)


@bench.command("suites")
def suites() -> None:
    """List the built-in suites."""
    from rich.table import Table

    from swarmpath.bench.sweep.suite import builtin_suites

    table = Table("name", "description", box=None)
    for name, description in builtin_suites().items():
        table.add_row(safe(name), safe(description))
    console(False).print(table)
