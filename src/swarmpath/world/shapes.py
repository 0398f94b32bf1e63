"""Static obstacle shapes: circles, axis-aligned rectangles and simple polygons.

Each shape answers the few geometric questions the rest of swarmpath asks, vectorised over
many points, segments or grid squares:

- ``signed_distance(points)``: negative inside;
- ``box_clearance(lo, hi)`` / ``overlaps_open_box(lo, hi)``: for rasterising onto a grid;
- ``segment_clearance(a, b)`` / ``segment_crosses_interior(a, b)``: for checking moves.

Touching a shape's boundary is not a collision; entering its interior is.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world import geometry as g

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


def _box_gap(lo1: FloatArray, hi1: FloatArray, lo2: FloatArray, hi2: FloatArray) -> FloatArray:
    gap = np.maximum(np.maximum(lo2 - hi1, lo1 - hi2), 0.0)
    return np.linalg.norm(gap, axis=-1)


@dataclass(frozen=True)
class Circle:
    """A disc of ``radius`` around ``center`` (world units)."""

    center: tuple[float, float]
    radius: float
    id: str = ""

    @property
    def bbox(self) -> tuple[FloatArray, FloatArray]:
        c = np.asarray(self.center, dtype=float)
        return c - self.radius, c + self.radius

    def signed_distance(self, points: ArrayLike) -> FloatArray:
        return np.linalg.norm(np.asarray(points, float) - self.center, axis=-1) - self.radius

    def box_clearance(self, lo: ArrayLike, hi: ArrayLike) -> FloatArray:
        return np.maximum(g.point_box_distance(self.center, lo, hi) - self.radius, 0.0)

    def overlaps_open_box(self, lo: ArrayLike, hi: ArrayLike) -> BoolArray:
        return g.point_box_distance(self.center, lo, hi) < self.radius - g.EPS

    def segment_clearance(self, a: ArrayLike, b: ArrayLike) -> FloatArray:
        return np.maximum(g.point_segment_distance(self.center, a, b) - self.radius, 0.0)

    def segment_crosses_interior(self, a: ArrayLike, b: ArrayLike) -> BoolArray:
        return g.point_segment_distance(self.center, a, b) < self.radius - g.EPS

    def to_dict(self) -> dict:
        return {"type": "circle", "center": list(self.center), "radius": self.radius}


@dataclass(frozen=True)
class Rect:
    """An axis-aligned rectangle ``[min_x, max_x] x [min_y, max_y]``."""

    min: tuple[float, float]
    max: tuple[float, float]
    id: str = ""

    @property
    def bbox(self) -> tuple[FloatArray, FloatArray]:
        return np.asarray(self.min, dtype=float), np.asarray(self.max, dtype=float)

    def signed_distance(self, points: ArrayLike) -> FloatArray:
        return g.point_box_signed_distance(points, self.min, self.max)

    def box_clearance(self, lo: ArrayLike, hi: ArrayLike) -> FloatArray:
        return _box_gap(np.asarray(lo, float), np.asarray(hi, float), *self.bbox)

    def overlaps_open_box(self, lo: ArrayLike, hi: ArrayLike) -> BoolArray:
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        mn, mx = self.bbox
        return np.all((np.minimum(hi, mx) - np.maximum(lo, mn)) > g.EPS, axis=-1)

    def segment_clearance(self, a: ArrayLike, b: ArrayLike) -> FloatArray:
        return g.segment_box_distance(a, b, self.min, self.max)

    def segment_crosses_interior(self, a: ArrayLike, b: ArrayLike) -> BoolArray:
        return g.segment_crosses_open_box(a, b, self.min, self.max)

    def to_dict(self) -> dict:
        return {"type": "rectangle", "min": list(self.min), "max": list(self.max)}


@dataclass(frozen=True)
class Polygon:
    """A simple polygon (not self-intersecting), vertices in order, not repeated at the end."""

    points: tuple[tuple[float, float], ...]
    id: str = ""

    @property
    def vertices(self) -> FloatArray:
        return np.asarray(self.points, dtype=float)

    @property
    def edges(self) -> tuple[FloatArray, FloatArray]:
        v = self.vertices
        return v, np.roll(v, -1, axis=0)

    @property
    def bbox(self) -> tuple[FloatArray, FloatArray]:
        v = self.vertices
        return v.min(axis=0), v.max(axis=0)

    def signed_distance(self, points: ArrayLike) -> FloatArray:
        return g.polygon_signed_distance(points, self.vertices)

    def box_clearance(self, lo: ArrayLike, hi: ArrayLike) -> FloatArray:
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        a, b = self.edges
        edge_gap = g.segment_box_distance(a, b, lo[..., None, :], hi[..., None, :]).min(axis=-1)
        centre_inside = g.points_in_polygon((lo + hi) / 2, self.vertices)
        return np.where(centre_inside, 0.0, edge_gap)

    def overlaps_open_box(self, lo: ArrayLike, hi: ArrayLike) -> BoolArray:
        # If no edge enters the open box, the box lies wholly inside or wholly outside.
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        a, b = self.edges
        edge_enters = g.segment_crosses_open_box(a, b, lo[..., None, :], hi[..., None, :]).any(axis=-1)
        centre = (lo + hi) / 2
        centre_inside = self.signed_distance(centre) < -g.EPS
        return edge_enters | centre_inside

    def segment_clearance(self, a: ArrayLike, b: ArrayLike) -> FloatArray:
        a, b = np.asarray(a, float), np.asarray(b, float)
        c, d = self.edges
        dist = g.segment_segment_distance(a[..., None, :], b[..., None, :], c, d).min(axis=-1)
        inside = g.points_in_polygon(a, self.vertices)
        return np.where(inside, 0.0, dist)

    def segment_crosses_interior(self, a: ArrayLike, b: ArrayLike) -> BoolArray:
        a, b = np.asarray(a, float), np.asarray(b, float)
        c, d = self.edges
        t = g.segment_intersection_params(a[..., None, :], b[..., None, :], c, d)
        t = np.where(np.isnan(t), 1.0, t)
        ends = np.broadcast_to(np.array([0.0, 1.0]), t.shape[:-1] + (2,))
        ts = np.sort(np.concatenate([ends, t], axis=-1), axis=-1)
        probes = np.concatenate([ts, (ts[..., 1:] + ts[..., :-1]) / 2], axis=-1)
        pts = a[..., None, :] + probes[..., None] * (b - a)[..., None, :]
        return (self.signed_distance(pts) < -g.EPS).any(axis=-1)

    def to_dict(self) -> dict:
        return {"type": "polygon", "points": [list(p) for p in self.points]}


Shape = Union[Circle, Rect, Polygon]
