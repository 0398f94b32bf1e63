"""Moving along a polyline with a distance budget per step (shared by path-following
controllers)."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def advance_along(path: NDArray[np.float64], position: NDArray[np.float64], next_vertex: int, budget: float
                  ) -> tuple[NDArray[np.float64], int]:
    """Move from ``position`` toward ``path[next_vertex]`` and beyond, spending at most
    ``budget`` (world units), never skipping a vertex (so the robot stays on the path).

    Whole vertices are taken while they fit in the budget; if the very next vertex is farther
    than the budget the robot moves part of the way. Returns (new position, index of the next
    vertex still ahead)."""
    p = np.asarray(position, float)
    k = next_vertex
    left = budget
    moved = False
    while k < len(path):
        gap = float(np.linalg.norm(path[k] - p))
        if gap <= left + 1e-12:
            p, left, k, moved = path[k].copy(), left - gap, k + 1, True
            continue
        if not moved:
            p = p + (path[k] - p) * (left / gap)
        break
    return p, k
