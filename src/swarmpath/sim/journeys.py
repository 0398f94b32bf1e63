"""How long the robots' journeys are at least, round the static obstacles: what the simulator's
step budget needs on maps where the straight line says little (a maze).

The shortest grid path from a start to a goal is at least ``|d_L(start) - d_L(goal)|`` for any
landmark cell L (the triangle inequality on the grid's path lengths; the ALT bound of
Goldberg and Harrelson, SODA 2005). A few landmarks far apart (farthest-point selection) give
nearly the exact length on mazes, rooms and warehouses for the cost of a few distance fields.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Landmarks for the bound: on generated mazes and room maps four already gave the longest
#: journey within 3 % of the exact one.
LANDMARKS = 4
#: Maps with more cells than this (1024 x 1024) are left to the straight line: the fields cost
#: 32 bytes and a Dijkstra visit per cell, about 0.3 s on 512 x 512, before every run.
MAX_CELLS = 1 << 20


def journey_lower_bounds(world) -> FloatArray:
    """For each robot (n,), a length (world units) its journey round the static obstacles is at
    least: the landmark bound on the world's occupancy grid (8-connected, no corner cutting,
    robots as points, so never above a grid robot's shortest path, whatever its radius; a
    robot moving freely between raster cells may find a way up to 8 % shorter than the grid's,
    which a budget of four journeys absorbs); 0 for robots whose start or goal cell the grid
    blocks or cuts off from the landmarks, and for all robots on a map without blocked cells or
    with more than :data:`MAX_CELLS` cells."""
    from swarmpath.search.lazy_distance import landmark_fields

    n = world.n_robots
    out = np.zeros(n)
    grid = world.grid()
    blocked = np.asarray(grid.blocked, bool)
    if n == 0 or not blocked.any() or blocked.size > MAX_CELLS:
        return out
    found = landmark_fields(blocked, LANDMARKS)
    if found is None:
        return out
    fields, _ = found
    h, w = blocked.shape
    cells = [grid.cell_of(p) for p in (world.starts, world.goals)]
    inside = np.ones(n, bool)
    for c in cells:
        inside &= np.all((c >= 0) & (c < [w, h]), axis=1)
    s, g = (np.clip(c, 0, [w - 1, h - 1]) for c in cells)
    a = fields[s[:, 1] * w + s[:, 0]]
    b = fields[g[:, 1] * w + g[:, 0]]
    known = np.isfinite(a) & np.isfinite(b)              # landmarks in the robot's region
    gap = np.abs(np.where(known, a, 0.0) - np.where(known, b, 0.0)).max(axis=1)
    return np.where(inside, gap * grid.resolution, 0.0)
