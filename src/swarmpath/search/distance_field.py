"""Distance fields: the grid path length from every cell to a goal, in one Dijkstra pass.

The cat swarm and fish swarm controllers ask "how far is this cell from my goal?" for many
cells every step; one field per goal answers each query in O(1) with exactly the A* cost.
The search runs in C (``_gridsearch.c``).
"""
from __future__ import annotations

from collections import OrderedDict
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.search import _gridsearch
from swarmpath.search.grid_input import blocked_array, check_cell, check_connectivity

FloatArray = NDArray[np.float64]


def distance_field(grid: Any, goals: ArrayLike, *, connectivity: int = 8) -> FloatArray:
    """Cost (in cells) from every cell to the nearest of ``goals`` (one cell (x, y) or an
    array (k, 2)); ``inf`` for blocked and unreachable cells. Shape (height, width)."""
    blocked = blocked_array(grid)
    h, w = blocked.shape
    diagonal = check_connectivity(connectivity)
    g = np.asarray(goals).reshape(-1, 2)
    for cell in g:
        check_cell(blocked, cell, "goal")
    sources = np.ascontiguousarray(g, dtype=np.int64)
    out = np.empty((h, w), dtype=np.float64)
    _gridsearch.distance_field(blocked.view(np.uint8), w, h, sources, out, diagonal)
    return out


def descend(field: FloatArray, start: ArrayLike, blocked: Any, *, connectivity: int = 8) -> NDArray[np.int64] | None:
    """A shortest path from ``start`` to the field's goal, read off the field by always
    stepping to the neighbour that keeps ``field[next] + step == field[here]`` (None when the
    start is unreachable)."""
    b = blocked_array(blocked)
    diagonal = check_connectivity(connectivity)
    x, y = (int(v) for v in np.asarray(start))
    if not np.isfinite(field[y, x]):
        return None
    moves = [(1, 0, 1.0), (-1, 0, 1.0), (0, 1, 1.0), (0, -1, 1.0)]
    if diagonal:
        s2 = float(np.sqrt(2))
        moves += [(1, 1, s2), (1, -1, s2), (-1, 1, s2), (-1, -1, s2)]
    h, w = field.shape
    path = [(x, y)]
    while field[y, x] > 0:
        best = None
        for dx, dy, step in moves:
            nx, ny = x + dx, y + dy
            if not (0 <= nx < w and 0 <= ny < h) or b[ny, nx]:
                continue
            if dx and dy and (b[y, nx] or b[ny, x]):
                continue
            if abs(field[ny, nx] + step - field[y, x]) < 1e-9 * max(1.0, field[y, x]):
                best = (nx, ny)
                break
        if best is None:  # pragma: no cover - a consistent field always has a predecessor
            return None
        x, y = best
        path.append(best)
    return np.asarray(path, dtype=np.int64)


class DistanceFieldCache:
    """Distance fields of one grid, computed on first use and kept per goal cell.

    ``max_fields`` bounds memory (8 bytes a cell a field); the least recently used field is
    dropped first.
    """

    def __init__(self, grid: Any, *, connectivity: int = 8, max_fields: int = 4096):
        self.blocked = blocked_array(grid)
        self.connectivity = connectivity
        self.max_fields = max_fields
        self._fields: OrderedDict[tuple[int, int], FloatArray] = OrderedDict()

    def field(self, goal: ArrayLike) -> FloatArray:
        key = tuple(int(v) for v in np.asarray(goal).reshape(2))
        f = self._fields.get(key)
        if f is None:
            f = distance_field(self.blocked, key, connectivity=self.connectivity)
            self._fields[key] = f
            if len(self._fields) > self.max_fields:
                self._fields.popitem(last=False)
        else:
            self._fields.move_to_end(key)
        return f

    def __len__(self) -> int:
        return len(self._fields)
