"""Turning grid cell paths into world polylines, shared by the grid-based planners."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.world.grid import OccupancyGrid


def cells_to_polyline(grid: OccupancyGrid, cells: NDArray[np.int64], start, goal) -> NDArray[np.float64]:
    """World polyline: the exact start, the centres of ``cells``, the exact goal (points that
    coincide with a neighbour are dropped). Shape (n_points, 2)."""
    pts = [np.asarray(start, float)[None], grid.centers(cells), np.asarray(goal, float)[None]]
    poly = np.concatenate(pts)
    keep = np.ones(len(poly), dtype=bool)
    keep[1:] = np.linalg.norm(np.diff(poly, axis=0), axis=1) > 1e-12
    return poly[keep]
