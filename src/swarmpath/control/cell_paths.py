"""Offline paths as grid cell sequences, for controllers that move cell to cell.

A planner's path is a polyline in world units (grid centres for A*, a smooth curve for the
hybrid APF planner). A grid controller tracks it as the sequence of cells the polyline passes
through, made 8-connected, without corner cutting, loops or staircases; stretches that run
through cells the (conservative) grid blocks are repaired with A* between the free cells on
either side.
"""
from __future__ import annotations

from itertools import pairwise

import numpy as np
from numpy.typing import NDArray

from swarmpath.search import astar

IntArray = NDArray[np.int64]
SQRT2 = float(np.sqrt(2.0))


def _move_ok(blocked: NDArray[np.bool_], a: IntArray, b: IntArray) -> bool:
    h, w = blocked.shape
    if not (0 <= b[0] < w and 0 <= b[1] < h) or blocked[b[1], b[0]]:
        return False
    d = b - a
    if np.max(np.abs(d)) != 1:
        return False
    if d[0] and d[1]:
        return not (blocked[a[1], b[0]] or blocked[b[1], a[0]])
    return True


def polyline_cells(points: NDArray[np.float64], resolution: float, shape: tuple[int, int] | None = None) -> IntArray:
    """Cells visited by a polyline (n_points, 2), in order, without repeats in a row;
    consecutive cells are 8-neighbours (the polyline is sampled finely and gaps filled).
    With ``shape`` (height, width), points on the grid's far edge belong to the last cell."""
    pts = np.asarray(points, float).reshape(-1, 2)
    samples = [pts[:1]]
    for a, b in pairwise(pts):
        k = max(1, int(np.ceil(np.linalg.norm(b - a) / (resolution / 8))))
        t = np.linspace(0.0, 1.0, k + 1)[1:, None]
        samples.append(a + (b - a) * t)
    cells = np.floor(np.concatenate(samples) / resolution + 1e-9).astype(np.int64)
    if shape is not None:
        cells = np.clip(cells, 0, [shape[1] - 1, shape[0] - 1])
    keep = np.r_[True, np.any(cells[1:] != cells[:-1], axis=1)]
    cells = cells[keep]
    out = [cells[0]]
    for c in cells[1:]:
        prev = out[-1]
        while np.max(np.abs(c - prev)) > 1:  # a jump across a corner: walk there
            prev = prev + np.sign(c - prev)
            out.append(prev)
        out.append(c)
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)


def tidy_cells(cells: IntArray, blocked: NDArray[np.bool_]) -> IntArray:
    """Remove loops (a cell visited twice: keep the way through its last visit) and
    staircases (a -> b -> c with a, c neighbours and the move a -> c allowed)."""
    out: list[IntArray] = []
    where: dict[tuple[int, int], int] = {}
    for c in cells:
        key = (int(c[0]), int(c[1]))
        if key in where:
            cut = where[key]
            for dropped in out[cut + 1:]:
                where.pop((int(dropped[0]), int(dropped[1])), None)
            del out[cut + 1:]
            continue
        while len(out) >= 2 and np.max(np.abs(c - out[-2])) == 1 and _move_ok(blocked, out[-2], c):
            where.pop((int(out[-1][0]), int(out[-1][1])), None)
            out.pop()
        where[key] = len(out)
        out.append(c)
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)


def repair_cells(cells: IntArray, blocked: NDArray[np.bool_]) -> IntArray | None:
    """Replace every stretch that enters a blocked cell or makes an invalid move by an A*
    path between the free cells around it. None when the ends are blocked or unconnected."""
    h, w = blocked.shape

    def free(c: IntArray) -> bool:
        return 0 <= c[0] < w and 0 <= c[1] < h and not blocked[c[1], c[0]]

    if not (free(cells[0]) and free(cells[-1])):
        return None
    out = [cells[0]]
    k = 1
    while k < len(cells):
        if free(cells[k]) and _move_ok(blocked, out[-1], cells[k]):
            out.append(cells[k])
            k += 1
            continue
        j = k
        while not free(cells[j]):
            j += 1
        found = astar(blocked, out[-1], cells[j])
        if not found:
            return None
        out.extend(found.cells[1:])
        k = j + 1
    return np.asarray(out, dtype=np.int64)


def plan_cells(path: NDArray[np.float64] | None, resolution: float, blocked: NDArray[np.bool_]) -> IntArray | None:
    """The cell sequence a grid robot follows for a planned polyline (None without one)."""
    if path is None or len(path) == 0:
        return None
    cells = polyline_cells(path, resolution, blocked.shape)
    repaired = repair_cells(cells, blocked)
    if repaired is None:
        return None
    return tidy_cells(repaired, blocked)


def remaining_lengths(cells: IntArray) -> NDArray[np.float64]:
    """Octile length (cells) from each cell of a path to its end, shape (n_cells,)."""
    if len(cells) < 2:
        return np.zeros(len(cells))
    d = np.abs(np.diff(cells, axis=0))
    step = np.where(np.all(d == 1, axis=1), SQRT2, 1.0)
    return np.r_[np.cumsum(step[::-1])[::-1], 0.0]
