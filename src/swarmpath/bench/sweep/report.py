"""``swarmpath bench report``: the stored jobs as files a person reads and tools load.

- ``jobs.csv``: one row per job (inputs, status, outcome, timings);
- ``summary.csv`` and ``summary.md``: one row per group (``--by``, default scenario,
  n_agents, method) with the field's measures;
- ``plot_data.csv`` and PNG plots against the number of agents, one line per method and one
  panel per scenario: success rate, sum of costs / lower bound, makespan, contacts, wall time.

The measures (MAPF names; docs/bench.md defines each):

- success rate (CSR): share of the group's jobs that are a success, every robot at its goal at
  the end and no contact of any kind (a job that failed or timed out counts as no success);
- individual success rate (ISR): mean share of robots at their goals (0 for a failed job);
- sum of costs (SOC), SOC / lower bound and makespan: means over the jobs where every robot
  arrived (``solved``);
- flowtime: mean over the jobs that ran of the sum over robots of the arrival step, or the
  run's length for a robot that never arrived;
- contacts: mean over the jobs that ran; wall time: mean over all jobs.

Plain Python and matplotlib only: the report works without pandas.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

from swarmpath.bench.sweep.store import is_number
from swarmpath.errors import ConfigError

#: Columns of jobs.csv, in order.
JOB_COLUMNS = ("key", "suite", "scenario", "detail", "n_agents", "n_moving", "motion", "planner", "controller",
               "method", "seed", "status", "success", "reached", "n_robots", "isr", "sum_of_costs", "lower_bound",
               "soc_over_lb", "makespan", "flowtime", "sum_of_lengths", "contacts", "robot_robot", "robot_static",
               "robot_moving", "deadlocks", "invalid_moves", "violations", "min_clearance", "steps", "run_status",
               "source", "wall_s", "setup_s", "planning_time_s", "sim_time_s", "planner_params", "controller_params",
               "max_steps", "error")
#: Fields a report may group by.
GROUP_FIELDS = ("suite", "scenario", "detail", "n_agents", "n_moving", "motion", "planner", "controller", "method",
                "seed", "source", "status", "max_steps")
DEFAULT_BY = ("scenario", "n_agents", "method")
#: Columns of summary.csv after the group fields.
SUMMARY_COLUMNS = ("jobs", "ok", "errors", "timeouts", "solved", "success_rate", "isr", "sum_of_costs",
                   "soc_over_lb", "makespan", "flowtime", "contacts", "wall_s")
#: The plots: file name, measure (a SUMMARY_COLUMNS name), axis label.
PLOTS = (("success_rate.png", "success_rate", "success rate (CSR)"),
         ("soc_over_lb.png", "soc_over_lb", "sum of costs / lower bound"),
         ("makespan.png", "makespan", "makespan (steps)"),
         ("contacts.png", "contacts", "contacts per run"),
         ("wall_time.png", "wall_s", "wall time per job (s)"))


def job_rows(rows: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """The rows of jobs.csv: stored rows plus the derived ISR and SOC / lower bound."""
    out = []
    for r in rows:
        row = {k: r.get(k) for k in JOB_COLUMNS}
        ok = r.get("status") == "ok"
        row["isr"] = r["reached"] / r["n_robots"] if ok and r.get("n_robots") else (0.0 if not ok else None)
        soc, lb = r.get("sum_of_costs"), r.get("lower_bound")
        row["soc_over_lb"] = soc / lb if is_number(soc) and is_number(lb) and lb > 0 else None
        out.append(row)
    return out


def _mean(values: Iterable[Any]) -> float | None:
    vals = [float(v) for v in values if is_number(v)]
    return math.fsum(vals) / len(vals) if vals else None


def _group_order(group: tuple) -> tuple:
    """Numbers in numeric order, then text, then missing values."""
    return tuple((0, v, "") if is_number(v) else (1, 0, str(v)) if v is not None else (2, 0, "") for v in group)


def summarise(rows: Sequence[dict[str, Any]], by: Sequence[str]) -> list[dict[str, Any]]:
    """One summary row per group of ``rows`` (jobs.csv rows) by the fields ``by``, in sorted
    group order."""
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(tuple(r.get(f) for f in by), []).append(r)
    out = []
    for group in sorted(groups, key=_group_order):
        jobs = groups[group]
        ran = [r for r in jobs if r["status"] == "ok"]
        solved = [r for r in ran if r.get("sum_of_costs") is not None]
        out.append({
            **dict(zip(by, group)), "jobs": len(jobs), "ok": len(ran),
            "errors": sum(r["status"] == "error" for r in jobs),
            "timeouts": sum(r["status"] == "timeout" for r in jobs), "solved": len(solved),
            "success_rate": sum(1 for r in ran if r.get("success")) / len(jobs),
            "isr": math.fsum(r["isr"] if r["status"] == "ok" else 0.0 for r in jobs) / len(jobs),
            "sum_of_costs": _mean(r["sum_of_costs"] for r in solved),
            "soc_over_lb": _mean(r["soc_over_lb"] for r in solved),
            "makespan": _mean(r["makespan"] for r in solved),
            "flowtime": _mean(r["flowtime"] for r in ran),
            "contacts": _mean(r["contacts"] for r in ran),
            "wall_s": _mean(r.get("wall_s") for r in jobs),
        })
    return out


def _fmt(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _write_csv(path: Path, columns: Sequence[str], rows: Iterable[dict[str, Any]]) -> Path:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(columns)
        for r in rows:
            w.writerow(["" if r.get(c) is None else (repr(r[c]) if isinstance(r[c], float) else r[c]) for c in columns])
    return path


def _md_cell(value: Any, digits: int = 3) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.{digits}f}" if abs(value) < 1e6 else f"{value:.4g}"
    return str(value).replace("|", "\\|").replace("\n", " ")


def _markdown(summary: list[dict[str, Any]], by: Sequence[str], rows: list[dict[str, Any]],
              skipped: list[dict[str, Any]], title: str) -> str:
    names = {"success_rate": "CSR", "isr": "ISR", "sum_of_costs": "SOC", "soc_over_lb": "SOC/LB",
             "wall_s": "wall s"}
    cols = list(by) + list(SUMMARY_COLUMNS)
    lines = [f"# {title}", "",
             f"{len(rows)} jobs: {sum(r['status'] == 'ok' for r in rows)} ran, "
             f"{sum(r['status'] == 'error' for r in rows)} failed, {sum(r['status'] == 'timeout' for r in rows)} "
             "timed out. CSR: share of jobs with every robot at its goal and no contact; ISR: mean share of robots "
             "at their goals; SOC (sum of costs), SOC/LB (over the sum of single-robot shortest paths) and makespan: "
             "means over the solved jobs (every robot arrived); flowtime, contacts: means over the jobs that ran.", "",
             "| " + " | ".join(names.get(c, c) for c in cols) + " |",
             "|" + "|".join("---" for _ in cols) + "|"]
    for s in summary:
        lines.append("| " + " | ".join(_md_cell(s.get(c)) for c in cols) + " |")
    errors: dict[str, int] = {}
    for r in rows:
        if r["status"] != "ok":
            errors[f"{r['status']}: {r['error']}"] = errors.get(f"{r['status']}: {r['error']}", 0) + 1
    if errors:
        lines += ["", "## Jobs that did not run to the end", ""]
        lines += [f"- {n} x {_md_cell(e)}" for e, n in sorted(errors.items(), key=lambda kv: (-kv[1], kv[0]))[:50]]
    if skipped:
        lines += ["", "## Skipped pairs (cannot run together)", "",
                  "| scenario | world | planner | controller | jobs | why |", "|---|---|---|---|---|---|"]
        lines += [f"| {_md_cell(s['scenario'])} | {_md_cell(s['detail'])} | {_md_cell(s['planner'])} | "
                  f"{_md_cell(s['controller'])} | {s['n_jobs']} | {_md_cell(s['reason'])} |" for s in skipped]
    return "\n".join(lines) + "\n"


def plot_series(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """The plotted points: per measure, scenario and method, the value at each agent count
    (the summary of the jobs with that scenario, method and n_agents)."""
    out = []
    for s in summarise(rows, ("scenario", "method", "n_agents")):
        for _, measure, _ in PLOTS:
            if s[measure] is not None:
                out.append({"measure": measure, "scenario": s["scenario"], "method": s["method"],
                            "n_agents": s["n_agents"], "value": s[measure], "jobs": s["jobs"]})
    return out


MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")
DASHES = ("-", "--", "-.", ":")


def _plot(path: Path, measure: str, label: str, series: list[dict[str, Any]]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    points = [p for p in series if p["measure"] == measure]
    scenarios = sorted({p["scenario"] for p in series}) or ["(no jobs)"]
    methods = sorted({p["method"] for p in series})
    cols = min(3, len(scenarios))
    nrows = math.ceil(len(scenarios) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.2 * nrows), squeeze=False)
    colours = plt.get_cmap("tab10" if len(methods) <= 10 else "tab20")
    for k, scenario in enumerate(scenarios):
        ax = axes[k // cols][k % cols]
        for j, method in enumerate(methods):
            pts = sorted((p["n_agents"], p["value"]) for p in points if p["scenario"] == scenario
                         and p["method"] == method)
            if pts:   # methods that coincide stay visible: each its own marker, dash and size
                ax.plot([x for x, _ in pts], [y for _, y in pts], marker=MARKERS[j % len(MARKERS)],
                        linestyle=DASHES[j % len(DASHES)], markersize=9 - 1.5 * (j % 4), alpha=0.85,
                        color=colours(j % colours.N), label=method)
        ax.set_title(scenario, fontsize=9)
        ax.set_xlabel("agents")
        ax.set_ylabel(label, fontsize=8)
        if measure == "success_rate":
            ax.set_ylim(-0.05, 1.05)
        ax.grid(alpha=0.3)
    for k in range(len(scenarios), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    handles, labels = [], []
    for ax in axes.ravel():
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    if handles:
        fig.legend(handles, labels, loc="lower center", ncol=min(3, len(labels)), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, min(0.3, 0.06 * math.ceil(len(labels) / 3) / nrows) if handles else 0, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def parse_by(text: str | None) -> tuple[str, ...]:
    """``--by`` as field names (comma-separated), each one a report may group by."""
    if text is None:
        return DEFAULT_BY
    fields = tuple(f.strip() for f in text.split(",") if f.strip())
    if not fields:
        raise ConfigError("--by: give at least one field")
    bad = [f for f in fields if f not in GROUP_FIELDS]
    if bad:
        raise ConfigError(f"--by: unknown field {bad[0]!r} (choose from: {', '.join(GROUP_FIELDS)})")
    if len(set(fields)) != len(fields):
        raise ConfigError("--by: a field appears twice")
    return fields


def write_report(store_path: str | Path, out_dir: str | Path, by: Sequence[str] = DEFAULT_BY, *,
                 progress: Callable[[int, int], None] | None = None) -> list[Path]:
    """Write jobs.csv, summary.csv, summary.md, plot_data.csv and the plots of a store into
    ``out_dir``; the files written."""
    from swarmpath.bench.sweep.store import Store

    with Store(store_path).open() as store:
        stored = store.rows()
        skipped = store.skipped()
    rows = job_rows(stored)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = [_write_csv(out / "jobs.csv", JOB_COLUMNS, rows)]
    summary = summarise(rows, by)
    written.append(_write_csv(out / "summary.csv", list(by) + list(SUMMARY_COLUMNS), summary))
    suites = sorted({r["suite"] for r in rows})
    title = f"Sweep report: {', '.join(suites) or 'empty store'}"
    (out / "summary.md").write_text(_markdown(summary, by, rows, skipped, title), encoding="utf-8")
    written.append(out / "summary.md")
    series = plot_series(rows)
    written.append(_write_csv(out / "plot_data.csv", ("measure", "scenario", "method", "n_agents", "value", "jobs"),
                              series))
    for k, (name, measure, label) in enumerate(PLOTS):
        written.append(_plot(out / name, measure, label, series))
        if progress is not None:
            progress(k + 1, len(PLOTS))
    return written


__all__ = ["DEFAULT_BY", "GROUP_FIELDS", "JOB_COLUMNS", "PLOTS", "SUMMARY_COLUMNS", "job_rows", "parse_by",
           "plot_series", "summarise", "write_report"]
