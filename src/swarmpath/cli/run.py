"""``swarmpath run``: plan and simulate one scenario, then report (table, JSON, files)."""
from __future__ import annotations

from typing import Any

import click

from swarmpath.cli.common import NamesOption, console, emit_json, progress, safe, writable_file, writable_folder
from swarmpath.cli.group import cli

DEFAULT_SCENARIO = "jaleel2016"


@cli.command()
@click.argument("scenario", required=False)
@click.option("--map", "map_file", type=click.Path(dir_okay=False),
              help="MovingAI .map file, or a built-in map's name (instead of SCENARIO)")
@click.option("--scen", "scen_file", type=click.Path(dir_okay=False), help="MovingAI .scen file (with --map)")
@click.option("--agents", type=click.IntRange(min=1), default=None, help="first N rows of --scen (default: all)")
@click.option("--planner", cls=NamesOption, registry="PLANNERS", default=None,
              help="offline planner (default: the scenario's)")
@click.option("--controller", cls=NamesOption, registry="CONTROLLERS", default=None,
              help="online controller (default: the scenario's)")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--max-steps", type=click.IntRange(min=1, max=10**9), default=None,
              help="step budget (default: from path lengths)")
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="write summary, trajectory, figures, animation and replay.html here")
@click.option("--plan-out", type=click.Path(dir_okay=False), default=None,
              help="write the offline plan of a grid run in LaCAM's result.txt format here")
@click.option("--json", "json_mode", is_flag=True, help="print one JSON object")
def run(scenario: str | None, map_file: str | None, scen_file: str | None, agents: int | None, planner: str | None,
        controller: str | None, seed: int, max_steps: int | None, out: str | None, plan_out: str | None,
        json_mode: bool) -> None:
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
    if out:
        writable_folder(out, "--out")
    if plan_out:
        writable_file(plan_out, "--plan-out")
    out_console = console(json_mode)
    with progress(out_console, f"simulating {world.name}", None, "step") as advance:
        result = run_world(world, planner=planner, controller=controller, seed=seed, max_steps=max_steps,
                           progress=advance)
    if plan_out:
        from swarmpath.sim.mapf_result import write_mapf_result

        source = getattr(world.static_map, "source", "") if world.static_map is not None else ""
        write_mapf_result(plan_out, result.trajectory, map_file=source.rsplit("/", 1)[-1],
                          solver=f"swarmpath-{result.planner}+{result.controller}",
                          comp_time_ms=1000 * (result.summary.planning_time_s + result.summary.sim_time_s))
    if out:
        from swarmpath.viz.run_outputs import write_run_outputs

        with progress(out_console, "rendering the animation", None, "frame") as advance:
            written = write_run_outputs(out, result, progress=advance)
        if not json_mode:
            out_console.print(f"wrote {len(written)} files to {safe(out)}")
    if json_mode:
        emit_json(result.summary.to_dict())
        return
    print_run_summary(out_console, result.summary.to_dict())


def _fmt_len(v: float | None) -> str:
    return "-" if v is None else f"{v:.2f}"


def print_run_summary(out_console, s: dict[str, Any]) -> None:
    """The per-robot table and the verdict of a run (every user text escaped)."""
    from rich.table import Table

    from swarmpath.metrics.summary import unfinished_reason

    table = Table(title=f"{safe(s['scenario'])}: planner {safe(s['planner'])}, controller {safe(s['controller'])}, "
                        f"seed {s['seed']}")
    for col in ("robot", "offline length", "executed length", "arrival step", "waits", "reached"):
        table.add_column(col, justify="right" if col != "robot" else "left")
    for r in s["robots"]:
        planned = _fmt_len(r["planned_length"])
        if r["planned_length"] is None and r.get("plan_reason"):
            planned = f"[yellow]{safe(r['plan_reason'])}[/yellow]"
        table.add_row(safe(r["id"]), planned, _fmt_len(r["path_length"]),
                      "-" if r["arrival_step"] is None else str(r["arrival_step"]), str(r["waits"]),
                      "yes" if r["reached"] else "[red]no[/red]" + (" (goal sealed)" if r.get("goal_sealed") else ""))
    out_console.print(table)
    c = s["collisions"]
    contacts = sum(c.values())
    if s["success"]:
        verdict = "[green]success[/green]"
    else:
        why = []
        if s["reached"] < s["n_robots"]:
            why.append(unfinished_reason(s["n_robots"], s["reached"], s["status"], s.get("sealed_goals", 0)))
        if contacts:
            why.append(f"{contacts} contact{'s' if contacts != 1 else ''}")
        verdict = f"[red]not a success[/red]: {'; '.join(why)}"
    out_console.print(f"{verdict}. {s['reached']}/{s['n_robots']} robots at their goals after {s['steps']} steps; "
                      f"contacts robot-robot {c['robot_robot']}, robot-static {c['robot_static']}, "
                      f"robot-moving {c['robot_moving']}; deadlocked robots {s['deadlocks']}")
    clearance = "-" if s["min_clearance"] is None else f"{s['min_clearance']:.3f}"
    out_console.print(f"sum of lengths {s['sum_of_lengths']:.2f}, makespan {s['makespan']}, "
                      f"min clearance {clearance}; planning {s['planning_time_s']:.3f} s, "
                      f"simulation {s['sim_time_s']:.3f} s")
