"""A frozen boolean raster ``blocked[y, x]``: what occupancy grids and static maps share."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, eq=False)
class Raster:
    """``blocked`` of shape (height, width), stored C-contiguous and read-only."""

    blocked: NDArray[np.bool_]

    def __post_init__(self) -> None:
        b = np.ascontiguousarray(self.blocked, dtype=bool)
        b.setflags(write=False)
        object.__setattr__(self, "blocked", b)

    @property
    def height(self) -> int:
        return int(self.blocked.shape[0])

    @property
    def width(self) -> int:
        return int(self.blocked.shape[1])
