"""Shared type aliases: points, paths and ids, with their array shapes."""
from __future__ import annotations

from typing import Union

import numpy as np
from numpy.typing import NDArray

#: A point in world coordinates, ``(x, y)``.
Point = tuple[float, float]
#: A grid cell, ``(x, y)`` = (column, row), as in MovingAI files.
Cell = tuple[int, int]
#: A polyline: ndarray of shape (n_points, 2), float64, world coordinates.
Path = NDArray[np.float64]
#: Positions of several robots or obstacles: ndarray of shape (n, 2).
Positions = NDArray[np.float64]
#: A robot's identifier as written in scenario files.
RobotId = str
#: Something that can become a numpy Generator (see :func:`swarmpath.rng.make_rng`).
SeedLike = Union[int, np.random.Generator, None]
