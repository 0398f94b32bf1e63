"""Workspace bounds: a rectangle ``[0, width] x [0, height]`` or a circle (the "spherical
workspace" of Jaleel & Hassan 2016, section III.1.A).

Robots (discs of radius r) must stay inside; both bounds are convex, so a straight move is
inside when both of its end discs are.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world.geometry import EPS

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class RectBounds:
    """The rectangle ``[0, width] x [0, height]`` (world units)."""

    width: float
    height: float

    @property
    def extent(self) -> tuple[float, float]:
        """Width and height of the axis-aligned box that holds the workspace."""
        return self.width, self.height

    def clearance(self, points: ArrayLike) -> FloatArray:
        """Distance from points to the boundary: positive inside, negative outside."""
        p = np.asarray(points, dtype=float)
        return np.minimum.reduce([p[..., 0], p[..., 1], self.width - p[..., 0], self.height - p[..., 1]])

    def contains(self, points: ArrayLike, margin: float | ArrayLike = 0.0) -> NDArray[np.bool_]:
        """Whether discs of radius ``margin`` at ``points`` lie inside (touching allowed)."""
        return self.clearance(points) >= np.asarray(margin) - EPS

    def boxes_inside(self, lo: ArrayLike, hi: ArrayLike, margin: float = 0.0) -> NDArray[np.bool_]:
        """Whether boxes grown by ``margin`` lie inside."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        return (np.all(lo - margin >= -EPS, axis=-1) & (hi[..., 0] + margin <= self.width + EPS)
                & (hi[..., 1] + margin <= self.height + EPS))

    def to_dict(self) -> dict:
        return {"type": "rectangle", "width": self.width, "height": self.height}


@dataclass(frozen=True)
class CircleBounds:
    """The disc of ``radius`` around ``center``; it must lie in the quadrant x, y >= 0."""

    center: tuple[float, float]
    radius: float

    @property
    def extent(self) -> tuple[float, float]:
        return self.center[0] + self.radius, self.center[1] + self.radius

    def clearance(self, points: ArrayLike) -> FloatArray:
        return self.radius - np.linalg.norm(np.asarray(points, float) - self.center, axis=-1)

    def contains(self, points: ArrayLike, margin: float | ArrayLike = 0.0) -> NDArray[np.bool_]:
        return self.clearance(points) >= np.asarray(margin) - EPS

    def boxes_inside(self, lo: ArrayLike, hi: ArrayLike, margin: float = 0.0) -> NDArray[np.bool_]:
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        c = np.asarray(self.center, float)
        far = np.maximum(np.abs(lo - c), np.abs(hi - c))
        return np.linalg.norm(far, axis=-1) + margin <= self.radius + EPS

    def to_dict(self) -> dict:
        return {"type": "circle", "center": list(self.center), "radius": self.radius}


Bounds = Union[RectBounds, CircleBounds]
