"""The lower bound that sums of costs are divided by: for each robot alone, the fewest steps
from its start to its goal, summed over the robots (the MAPF convention, "sum of individual
shortest paths").

- Robots that move cell to cell (every robot can reach a neighbouring cell centre in one
  step and is at most half a cell wide, as grid controllers require): the fewest moves on
  the world's grid, 8-connected without corner cutting (breadth-first search).
- Any other world: the straight line at the robot's speed, ``ceil(|goal - start| / (max_speed * dt))``.

The bound is a property of the world, so every method run on it is divided by the same
number. A continuous method run on a grid world may beat the grid bound slightly (it can
move ``max_speed * dt`` in any direction), which shows up as a ratio below 1.
"""
from __future__ import annotations

import math

import numpy as np

from swarmpath.errors import ConfigError


def _moves_cell_to_cell(world) -> bool:
    from swarmpath.control.grid_robots import check_grid_robots

    try:
        check_grid_robots(world, "lower bound")
    except ConfigError:
        return False
    grid = world.grid()
    for points in (world.starts, world.goals):
        cells = grid.cell_of(points)
        if not np.allclose(grid.centers(cells), points, atol=1e-9 * world.resolution) or not grid.is_free(cells).all():
            return False
    return True


def grid_steps(blocked: np.ndarray, starts: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """Fewest 8-connected moves (no corner cutting) from each start cell to its goal cell
    (cells as (x, y)); inf where a goal cannot be reached."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import shortest_path

    from swarmpath.control.pibt.core import static_moves
    from swarmpath.world.move_rules import GRID_MOVES

    h, w = blocked.shape
    moves = static_moves(blocked, 8)
    ys, xs, a = np.nonzero(moves[:, :, 1:])
    d = GRID_MOVES[1:][a]
    src = ys * w + xs
    dst = (ys + d[:, 1]) * w + xs + d[:, 0]
    graph = coo_matrix((np.ones(len(src)), (dst, src)), shape=(h * w, h * w)).tocsr()   # reversed: from goals
    unique, inverse = np.unique(goals[:, 1] * w + goals[:, 0], return_inverse=True)
    dist = shortest_path(graph, unweighted=True, indices=unique)
    return dist[inverse.ravel(), starts[:, 1] * w + starts[:, 0]]


def lower_bound(world) -> int | None:
    """Sum over robots of each one's fewest steps alone (see the module's docstring); None
    when a goal cannot be reached at all."""
    if world.n_robots == 0:
        return 0
    if _moves_cell_to_cell(world):
        grid = world.grid()
        steps = grid_steps(grid.blocked, grid.cell_of(world.starts), grid.cell_of(world.goals))
        if not np.all(np.isfinite(steps)):
            return None
        return int(steps.sum())
    total = 0
    for r in world.robots:
        total += max(0, math.ceil(math.dist(r.start, r.goal) / (r.max_speed * world.dt) - 1e-9))
    return total
