"""``swarmpath scenarios``, ``validate`` and ``schema``: the scenario files."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from swarmpath.cli.common import EXIT_BAD_INPUT, console, safe
from swarmpath.cli.group import cli


@cli.command()
def scenarios() -> None:
    """List the built-in scenarios and MovingAI maps."""
    from rich.table import Table

    from swarmpath.world.movingai import builtin_movingai
    from swarmpath.world.scenario import builtin_scenarios

    table = Table("name", "description", box=None, show_header=True)
    for name, description in builtin_scenarios().items():
        table.add_row(safe(name), safe(description))
    out = console(False)
    out.print(table)
    out.print("built-in MovingAI files (use by name with --map/--scen): " + ", ".join(builtin_movingai()))


@cli.command()
@click.argument("file", type=click.Path(dir_okay=False))
def validate(file: str) -> None:
    """Check a scenario file (or a MovingAI .map/.scen file) and print its problems."""
    from swarmpath.world.limits import clean_text
    from swarmpath.world.scenario import read_scenario_file, scenario_problems, world_from_dict

    if file.endswith(".map"):
        from swarmpath.world.movingai import read_map

        m = read_map(file)
        click.echo(f"{clean_text(file)}: ok: {m.width}x{m.height} map, {int((~m.blocked).sum())} passable cells")
        return
    if file.endswith(".scen"):
        from swarmpath.world.movingai import read_scen

        entries = read_scen(file)
        click.echo(f"{clean_text(file)}: ok: {len(entries)} rows")
        return
    doc, source = read_scenario_file(file)
    problems = scenario_problems(doc) if isinstance(doc, dict) else []
    if len(problems) > 1:
        for p in problems[:20]:
            click.echo(clean_text(str(p.with_source(source))), err=True)
        if len(problems) > 20:
            click.echo(f"{clean_text(source)}: and {len(problems) - 20} more problems", err=True)
        sys.exit(EXIT_BAD_INPUT)
    world = world_from_dict(doc, source, Path(file).parent)
    click.echo(f"{clean_text(file)}: ok: scenario {clean_text(world.name)!r}, {world.n_robots} robots, "
               f"{len(world.obstacles)} obstacles, {len(world.moving_obstacles)} moving obstacles, "
               f"{len(world.danger_zones)} danger zones")


@cli.command()
def schema() -> None:
    """Print the JSON Schema of scenario files."""
    from swarmpath.world.scenario import scenario_json_schema

    click.echo(json.dumps(scenario_json_schema(), indent=2))
