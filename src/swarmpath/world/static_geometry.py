"""Fast static-obstacle queries for worlds made of circles and rectangles only: the two
questions a per-step optimiser asks thousands of times (clearance of points, swept-disc hits
of moves), vectorised over all shapes, answering like :class:`~swarmpath.world.World` does."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.world import geometry as g
from swarmpath.world.geometry import origin_segment_distance, planar_norm
from swarmpath.world.shapes import Circle, Rect

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


class StaticGeometry:
    """Fast static-obstacle queries for worlds made of circles and rectangles (no raster map,
    no polygons), with the same two methods as :class:`~swarmpath.world.World` that the
    objective needs. Slightly conservative: a move that only touches an obstacle counts as a
    hit. Use :func:`static_geometry` to get this or the world itself."""

    def __init__(self, world) -> None:
        circles = [o for o in world.obstacles if isinstance(o, Circle)]
        rects = [o for o in world.obstacles if not isinstance(o, Circle)]
        self.bounds = world.bounds
        self.centers = np.array([c.center for c in circles], float).reshape(-1, 2)
        self.rho = np.array([c.radius for c in circles], float)
        self.lo = np.array([r.min for r in rects], float).reshape(-1, 2)
        self.hi = np.array([r.max for r in rects], float).reshape(-1, 2)

    def near(self, points: FloatArray, distance: FloatArray) -> "StaticGeometry":
        """The same geometry keeping only the shapes closer than ``distance`` (k,) to some
        point of ``points`` (k, 2)."""
        out = object.__new__(StaticGeometry)
        out.bounds = self.bounds
        keep = np.any(planar_norm(points[:, None, :] - self.centers[None]) - self.rho < distance[:, None], axis=0)
        out.centers, out.rho = self.centers[keep], self.rho[keep]
        gap = g.point_box_distance(points[:, None, :], self.lo, self.hi)
        keep = np.any(gap < distance[:, None], axis=0)
        out.lo, out.hi = self.lo[keep], self.hi[keep]
        return out

    def static_clearance(self, points: FloatArray, radius: FloatArray) -> FloatArray:
        """Free distance between discs at points (N, 2) of radius (N,) and the nearest
        obstacle or the boundary."""
        best = self.bounds.clearance(points)
        if len(self.rho):
            d = planar_norm(points[:, None, :] - self.centers[None]) - self.rho
            best = np.minimum(best, d.min(axis=1))
        if len(self.lo):
            best = np.minimum(best, g.point_box_signed_distance(points[:, None, :], self.lo, self.hi).min(axis=1))
        return best - radius

    def static_hits(self, a: FloatArray, b: FloatArray, radius: FloatArray) -> BoolArray:
        """Whether discs moving a -> b (N, 2) touch an obstacle or leave the workspace."""
        hit = ~(self.bounds.contains(a, radius) & self.bounds.contains(b, radius))
        if len(self.rho):
            c = self.centers[None]
            d = origin_segment_distance(a[:, None, :] - c, b[:, None, :] - c) - self.rho
            hit |= np.any(d < radius[:, None] + 1e-9, axis=1)
        if len(self.lo):
            d = g.segment_box_distance(a[:, None, :], b[:, None, :], self.lo, self.hi)
            hit |= np.any(d < radius[:, None] + 1e-9, axis=1)
        return hit


def static_geometry(world):
    """:class:`StaticGeometry` for worlds of circles and rectangles, else the world itself."""
    if world.static_map is None and all(isinstance(o, (Circle, Rect)) for o in world.obstacles):
        return StaticGeometry(world)
    return world
