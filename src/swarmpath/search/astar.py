"""A* on an occupancy grid: 8-connected octile (no corner cutting) or 4-connected.

The search itself runs in C (``_gridsearch.c``); this module checks the arguments and wraps
the result. Costs are in cells (multiply by the grid resolution for world units).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError
from swarmpath.search import _gridsearch
from swarmpath.search.grid_input import blocked_array, check_cell, check_connectivity

SQRT2 = float(np.sqrt(2.0))


@dataclass(frozen=True)
class GridPath:
    """Result of a grid search: ``cells`` (int array (n, 2) of (x, y), start first) or None
    when the goal is unreachable; ``cost`` in cells (``inf`` when unreachable)."""

    cost: float
    cells: NDArray[np.int64] | None
    expansions: int

    def __bool__(self) -> bool:
        return self.cells is not None


def astar(grid: ArrayLike, start: ArrayLike, goal: ArrayLike, *, connectivity: int = 8,
          method: str = "jps") -> GridPath:
    """Shortest grid path from ``start`` to ``goal`` (cells (x, y)).

    ``grid`` is an :class:`~swarmpath.world.OccupancyGrid` or a boolean array ``blocked[y, x]``.
    With 8-connectivity the search is jump point search by default (``method="jps"``: the same
    optimal cost as plain A*, far fewer expansions; ``expansions`` then counts jump points);
    ``method="astar"`` runs plain A*. A blocked or outside start/goal raises
    :class:`ConfigError`; an unreachable goal returns a falsy :class:`GridPath`.
    """
    blocked = blocked_array(grid)
    h, w = blocked.shape
    diagonal = check_connectivity(connectivity)
    if method not in ("jps", "astar"):
        raise ConfigError(f"method must be 'jps' or 'astar', got {method!r}")
    sx, sy = check_cell(blocked, start, "start")
    gx, gy = check_cell(blocked, goal, "goal")
    if diagonal and method == "jps":
        cost, raw, expansions = _gridsearch.jps(blocked.view(np.uint8), w, h, sx, sy, gx, gy)
    else:
        cost, raw, expansions = _gridsearch.astar(blocked.view(np.uint8), w, h, sx, sy, gx, gy, diagonal)
    if raw is None:
        return GridPath(float("inf"), None, int(expansions))
    cells = np.frombuffer(raw, dtype=np.int32).reshape(-1, 2).astype(np.int64)
    return GridPath(float(cost), cells, int(expansions))


def path_cost(cells: ArrayLike) -> float:
    """Octile length of a cell path: orthogonal steps cost 1, diagonal steps sqrt 2."""
    c = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    if len(c) < 2:
        return 0.0
    d = np.abs(np.diff(c, axis=0))
    if np.any(d > 1):
        raise ConfigError("not a grid path: consecutive cells must be neighbours")
    diag = np.count_nonzero((d[:, 0] == 1) & (d[:, 1] == 1))
    straight = np.count_nonzero(d.sum(axis=1) == 1)
    return float(straight + SQRT2 * diag)
