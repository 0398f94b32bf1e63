"""``swarmpath path``: one shortest grid path on a MovingAI map."""
from __future__ import annotations

import click

from swarmpath.cli.common import emit_json
from swarmpath.cli.group import cli


@cli.command()
@click.option("--map", "map_file", required=True, type=click.Path(dir_okay=False),
              help="MovingAI .map file, or a built-in map's name")
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
        emit_json({"cost": result.cost if result else None, "path": cells, "expansions": result.expansions})
        return
    expanded = f"{result.expansions} cell{'s' if result.expansions != 1 else ''} expanded"
    if not result:
        click.echo(f"no path from {start} to {goal} on {map_file} ({expanded})")
        return
    click.echo(f"cost {result.cost:.8f} over {len(cells) - 1} move{'s' if len(cells) != 2 else ''} ({expanded})")
    click.echo(" ".join(f"({x},{y})" for x, y in cells))
