"""The ``swarmpath`` command: a thin shell over the library (docs/guide.md lists the
command line). Bad input prints one line on stderr and exits with code 2; ``--json`` prints
exactly one JSON object on stdout.
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any, NoReturn

import click

from swarmpath.errors import SwarmpathError

EXIT_BAD_INPUT = 2


def _fail(message: str) -> NoReturn:
    click.echo(f"swarmpath: error: {message}", err=True)
    sys.exit(EXIT_BAD_INPUT)


def _emit_json(doc: Any) -> None:
    click.echo(json.dumps(doc, allow_nan=False, default=_json_default))


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return None if not math.isfinite(obj) else float(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def _console(json_mode: bool):
    """A rich console for human output; on stderr when stdout must hold only JSON."""
    from rich.console import Console

    return Console(stderr=json_mode, highlight=False)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="swarmpath")
def cli() -> None:
    """Plan, simulate, compare and visualise many robots with swarm intelligence."""


# ---------------------------------------------------------------------------------- run
@cli.command()
@click.argument("scenario", required=False)
@click.option("--map", "map_file", type=click.Path(dir_okay=False), help="MovingAI .map file (instead of SCENARIO)")
@click.option("--scen", "scen_file", type=click.Path(dir_okay=False), help="MovingAI .scen file (with --map)")
@click.option("--agents", type=click.IntRange(min=1), default=None, help="first N rows of --scen (default: all)")
@click.option("--planner", default=None, help="offline planner (default: the scenario's)")
@click.option("--controller", default=None, help="online controller (default: the scenario's)")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--max-steps", type=click.IntRange(min=1), default=None, help="step budget (default: from path lengths)")
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="write summary, trajectory, figures, animation and replay.html here")
@click.option("--json", "json_mode", is_flag=True, help="print one JSON object")
def run(scenario: str | None, map_file: str | None, scen_file: str | None, agents: int | None, planner: str | None,
        controller: str | None, seed: int, max_steps: int | None, out: str | None, json_mode: bool) -> None:
    """Plan and simulate a scenario (default: jaleel2016) and report the outcome."""
    from swarmpath.errors import ConfigError
    from swarmpath.runner import run_world
    from swarmpath.world import load_scenario, world_from_movingai

    if map_file or scen_file:
        if scenario:
            raise ConfigError("give either SCENARIO or --map/--scen, not both")
        if not (map_file and scen_file):
            raise ConfigError("--map and --scen go together")
        world = world_from_movingai(map_file, scen_file, agents)
    else:
        if agents is not None:
            raise ConfigError("--agents needs --map and --scen")
        world = load_scenario(scenario or DEFAULT_SCENARIO)
    console = _console(json_mode)
    with _step_progress(console, f"simulating {world.name}") as progress:
        result = run_world(world, planner=planner, controller=controller, seed=seed, max_steps=max_steps,
                           progress=progress)
    if out:
        from swarmpath.viz.run_outputs import write_run_outputs

        with _progress(console, "rendering the animation", None, enabled=console.is_terminal) as advance:
            written = write_run_outputs(out, result, progress=advance)
        if not json_mode:
            console.print(f"wrote {len(written)} files to {out}")
    if json_mode:
        _emit_json(result.summary.to_dict())
        return
    _print_run_summary(console, result.summary.to_dict())


DEFAULT_SCENARIO = "jaleel2016"


class _step_progress:
    """A transient progress bar over simulation steps, shown on terminals only."""

    def __init__(self, console, label: str):
        self.console, self.label = console, label
        self._bar = None
        self._task = None

    def __enter__(self):
        if not self.console.is_terminal:
            return None
        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

        self._bar = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("step {task.completed}"),
                             TimeElapsedColumn(), console=self.console, transient=True)
        self._bar.__enter__()
        self._task = self._bar.add_task(self.label, total=None)

        def update(step: int, total: int) -> None:
            if step % 10 == 0:
                self._bar.update(self._task, completed=step, total=total)

        return update

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.__exit__(*exc)
        return False


def _fmt_len(v: float | None) -> str:
    return "-" if v is None else f"{v:.2f}"


def _print_run_summary(console, s: dict) -> None:
    from rich.table import Table

    table = Table(title=f"{s['scenario']}: planner {s['planner']}, controller {s['controller']}, seed {s['seed']}")
    for col in ("robot", "offline length", "executed length", "arrival step", "waits", "reached"):
        table.add_column(col, justify="right" if col != "robot" else "left")
    for r in s["robots"]:
        table.add_row(r["id"], _fmt_len(r["planned_length"]), _fmt_len(r["path_length"]),
                      "-" if r["arrival_step"] is None else str(r["arrival_step"]), str(r["waits"]),
                      "yes" if r["reached"] else "[red]no[/red]")
    console.print(table)
    c = s["collisions"]
    verdict = "[green]success[/green]" if s["success"] else f"[red]{s['status']}[/red]"
    console.print(f"{verdict}: {s['reached']}/{s['n_robots']} robots reached their goals in {s['steps']} steps; "
                  f"collisions robot-robot {c['robot_robot']}, robot-static {c['robot_static']}, "
                  f"robot-moving {c['robot_moving']}; deadlocks {s['deadlocks']}")
    console.print(f"sum of lengths {s['sum_of_lengths']:.2f}, makespan {s['makespan']}, "
                  f"min clearance {s['min_clearance']:.3f}; planning {s['planning_time_s']:.3f} s, "
                  f"simulation {s['sim_time_s']:.3f} s")


# ---------------------------------------------------------------------------------- path
@cli.command()
@click.option("--map", "map_file", required=True, type=click.Path(dir_okay=False), help="MovingAI .map file")
@click.option("--start", nargs=2, type=int, required=True, metavar="X Y", help="start cell (x = column, y = row)")
@click.option("--goal", nargs=2, type=int, required=True, metavar="X Y", help="goal cell (x = column, y = row)")
@click.option("--connectivity", type=click.Choice(["8", "4"]), default="8", show_default=True)
@click.option("--json", "json_mode", is_flag=True, help="print one JSON object")
def path(map_file: str, start: tuple[int, int], goal: tuple[int, int], connectivity: str, json_mode: bool) -> None:
    """Shortest grid path on a MovingAI map (octile, no corner cutting)."""
    from swarmpath.errors import ConfigError
    from swarmpath.search import astar
    from swarmpath.world.movingai import read_map

    grid_map = read_map(map_file)
    try:
        result = astar(grid_map.blocked, start, goal, connectivity=int(connectivity))
    except ConfigError as exc:
        raise ConfigError(f"{map_file}: {exc}") from None
    cells = result.cells.tolist() if result else None
    if json_mode:
        _emit_json({"cost": result.cost if result else None, "path": cells, "expansions": result.expansions})
        return
    if not result:
        click.echo(f"no path from {start} to {goal} on {map_file} ({result.expansions} cells expanded)")
        return
    click.echo(f"cost {result.cost:.8f} over {len(cells) - 1} moves ({result.expansions} cells expanded)")
    click.echo(" ".join(f"({x},{y})" for x, y in cells))


# ---------------------------------------------------------------------------------- scenarios
@cli.command()
def scenarios() -> None:
    """List the built-in scenarios."""
    from rich.table import Table

    from swarmpath.world.scenario import builtin_scenarios

    table = Table("name", "description", box=None, show_header=True)
    for name, description in builtin_scenarios().items():
        table.add_row(name, description)
    _console(False).print(table)


@cli.command()
@click.argument("file", type=click.Path(dir_okay=False))
def validate(file: str) -> None:
    """Check a scenario file (or a MovingAI .map/.scen file) and print its problems."""
    from swarmpath.world.scenario import read_scenario_file, scenario_problems, world_from_dict

    if file.endswith(".map"):
        from swarmpath.world.movingai import read_map

        m = read_map(file)
        click.echo(f"{file}: ok: {m.width}x{m.height} map, {int((~m.blocked).sum())} passable cells")
        return
    if file.endswith(".scen"):
        from swarmpath.world.movingai import read_scen

        entries = read_scen(file)
        click.echo(f"{file}: ok: {len(entries)} rows")
        return
    doc, source = read_scenario_file(file)
    problems = scenario_problems(doc) if isinstance(doc, dict) else []
    if len(problems) > 1:
        for p in problems:
            click.echo(str(p.with_source(source)), err=True)
        sys.exit(EXIT_BAD_INPUT)
    world = world_from_dict(doc, source, Path(file).parent)
    click.echo(f"{file}: ok: scenario {world.name!r}, {world.n_robots} robots, {len(world.obstacles)} obstacles, "
               f"{len(world.moving_obstacles)} moving obstacles, {len(world.danger_zones)} danger zones")


@cli.command()
def schema() -> None:
    """Print the JSON Schema of scenario files."""
    from swarmpath.world.scenario import scenario_json_schema

    click.echo(json.dumps(scenario_json_schema(), indent=2))


# ---------------------------------------------------------------------------------- optimize
@cli.command()
@click.option("--algorithm", required=True, help="optimiser name (pso, amopso1..4, mopso, cso, afsa)")
@click.option("--function", "function", required=True, help="benchmark function (sphere, rastrigin, ...)")
@click.option("--dim", type=click.IntRange(min=1), default=30, show_default=True)
@click.option("--particles", type=click.IntRange(min=1), default=30, show_default=True)
@click.option("--iterations", type=click.IntRange(min=1), default=1000, show_default=True)
@click.option("--runs", type=click.IntRange(min=1), default=1, show_default=True)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--json", "json_mode", is_flag=True, help="print one JSON object")
def optimize(algorithm: str, function: str, dim: int, particles: int, iterations: int, runs: int, seed: int,
             json_mode: bool) -> None:
    """Run an optimiser on a benchmark function over several seeded runs."""
    from swarmpath.optim import run_benchmark

    console = _console(json_mode)
    with _progress(console, f"{algorithm} on {function}", runs, enabled=runs > 1) as advance:
        doc = run_benchmark(algorithm, function, dim, particles, iterations, runs, seed, progress=advance)
    if json_mode:
        _emit_json(doc)
        return
    console.print(f"{algorithm} on {function} ({dim}-D, {particles} particles x {iterations} iterations, "
                  f"{runs} run{'s' if runs > 1 else ''}, seed {seed})")
    console.print(f"min {doc['min']:.6g}   mean {doc['mean']:.6g}   std {doc['std']:.6g}")


class _progress:
    """A rich progress bar on the given console (a no-op when disabled). The callable it
    yields takes ``(done, total=None)``: runs finished so far and, optionally, a new total."""

    def __init__(self, console, label: str, total: int | None, enabled: bool = True):
        self.console, self.label, self.total, self.enabled = console, label, total, enabled
        self._bar = None

    def __enter__(self):
        if not self.enabled:
            return lambda *_args, **_kw: None
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        self._bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                             TimeRemainingColumn(), console=self.console, transient=True)
        self._bar.__enter__()
        task = self._bar.add_task(self.label, total=self.total)

        def update(done: int, total: int | None = None) -> None:
            self._bar.update(task, completed=done, total=total if total is not None else self._bar.tasks[0].total)

        return update

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.__exit__(*exc)
        return False


# ---------------------------------------------------------------------------------- reproduce
@cli.command()
@click.argument("paper")
@click.option("--out", type=click.Path(file_okay=False), default=None, help="directory for the report")
@click.option("--runs", type=click.IntRange(min=1), default=None, help="runs per configuration (default: the paper's)")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
def reproduce(paper: str, out: str | None, runs: int | None, seed: int) -> None:
    """Run a paper's experiments and write tables and figures."""
    from swarmpath.registry import REPRODUCTIONS

    experiment = REPRODUCTIONS.get(paper)
    out_dir = Path(out or f"reproduce-{paper}")
    out_dir.mkdir(parents=True, exist_ok=True)
    console = _console(False)
    with _progress(console, f"reproducing {paper}", None, enabled=console.is_terminal) as advance:
        report = experiment(out_dir, runs=runs, seed=seed, progress=advance)
    console.print(f"wrote {report}")


# ---------------------------------------------------------------------------------- replay
@cli.command()
@click.argument("trajectory", type=click.Path(dir_okay=False))
@click.option("--html", "html_out", type=click.Path(dir_okay=False), default=None, help="write an HTML replay here")
@click.option("--gif", "gif_out", type=click.Path(dir_okay=False), default=None, help="write a GIF (or .mp4) here")
def replay(trajectory: str, html_out: str | None, gif_out: str | None) -> None:
    """Turn a saved trajectory (.npz or .json) into an HTML replay and/or an animation."""
    from swarmpath.errors import ConfigError
    from swarmpath.sim.trajectory import Trajectory

    if not (html_out or gif_out):
        raise ConfigError("give --html FILE and/or --gif FILE")
    traj = Trajectory.load(trajectory)
    if html_out:
        from swarmpath.viz.html_replay import write_replay_html

        click.echo(f"wrote {write_replay_html(traj, html_out)}")
    if gif_out:
        from swarmpath.viz.animation import save_animation

        console = _console(False)
        with _progress(console, "rendering the animation", None, enabled=console.is_terminal) as advance:
            written = save_animation(traj, gif_out, progress=advance)
        click.echo(f"wrote {written}")


# ---------------------------------------------------------------------------------- entry point
def main(argv: list[str] | None = None) -> None:
    """Console entry point: errors of the user's making become one line and exit code 2."""
    try:
        cli.main(args=argv, prog_name="swarmpath", standalone_mode=False)
    except SwarmpathError as exc:
        _fail(str(exc).splitlines()[0] if str(exc) else type(exc).__name__)
    except click.exceptions.Abort:
        click.echo("swarmpath: aborted", err=True)
        sys.exit(130)
    except click.ClickException as exc:
        _fail(exc.format_message().replace("\n", " "))
    except KeyboardInterrupt:
        click.echo("swarmpath: interrupted", err=True)
        sys.exit(130)
    except BrokenPipeError:
        sys.exit(0)


if __name__ == "__main__":  # pragma: no cover
    main()
