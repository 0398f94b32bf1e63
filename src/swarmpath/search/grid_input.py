"""Argument checks shared by the grid searches (grids, cells, connectivity)."""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError


def blocked_array(grid: Any) -> NDArray[np.bool_]:
    """The C-contiguous boolean ``blocked[y, x]`` array of an OccupancyGrid or array."""
    blocked = getattr(grid, "blocked", grid)
    arr = np.ascontiguousarray(blocked, dtype=bool)
    if arr.ndim != 2 or arr.size == 0:
        raise ConfigError(f"a grid must be a non-empty 2-D array, got shape {arr.shape}")
    return arr


def check_connectivity(connectivity: int) -> bool:
    """True for 8-connectivity, False for 4; anything else is an error."""
    if connectivity not in (4, 8):
        raise ConfigError(f"connectivity must be 4 or 8, got {connectivity}")
    return connectivity == 8


def check_cell(blocked: NDArray[np.bool_], cell: ArrayLike, what: str) -> tuple[int, int]:
    """``cell`` as (x, y) ints, checked to be inside the grid and free."""
    c = np.asarray(cell)
    if c.shape != (2,) or not np.all(np.equal(np.mod(c, 1), 0)):
        raise ConfigError(f"{what} must be a cell (x, y) of two whole numbers, got {cell!r}")
    x, y = int(c[0]), int(c[1])
    h, w = blocked.shape
    if not (0 <= x < w and 0 <= y < h):
        raise ConfigError(f"{what} ({x}, {y}) is outside the map ({w}x{h})")
    if blocked[y, x]:
        raise ConfigError(f"{what} ({x}, {y}) is a blocked cell")
    return x, y
