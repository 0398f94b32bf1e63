"""What every grid controller asks of its robots before a run: a robot must be able to reach
a neighbouring cell centre in one step (``max_speed * dt`` at least one cell), and be no
wider than half a cell (so the cell reasoning of the move rules holds). A world that asks
for more is refused at ``reset`` with one line naming the robot, never run with every move
silently rejected."""
from __future__ import annotations

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.world.world import World


def check_grid_robots(world: World, controller: str, *, max_radius_cells: float = 0.5) -> None:
    """Raise :class:`ConfigError` unless every robot of ``world`` can move cell to cell."""
    res = world.resolution
    reach = world.max_speeds * world.dt
    slow = np.flatnonzero(reach < res * (1 - 1e-9))
    if len(slow):
        r = world.robots[slow[0]]
        raise ConfigError(f"{controller} moves one grid cell per step: robot {r.id!r} has max_speed * dt = "
                          f"{reach[slow[0]]:g} < resolution {res:g} (raise max_speed or dt, or use a finer "
                          "resolution)")
    wide = np.flatnonzero(world.radii > max_radius_cells * res + 1e-12)
    if len(wide):
        r = world.robots[wide[0]]
        raise ConfigError(f"{controller} moves robots cell to cell: robot {r.id!r} has radius {r.radius:g} > "
                          f"{max_radius_cells:g} cell ({max_radius_cells * res:g}); use a finer resolution or a "
                          "continuous controller (orca, pso-predictive)")
