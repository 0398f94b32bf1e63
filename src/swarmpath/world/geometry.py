"""Vectorised 2-D distance and intersection kernels shared by shapes, rasteriser and checker.

All functions broadcast over leading axes: ``a`` of shape (..., 2) against ``b`` of shape
(..., 2) and so on. Boxes are closed axis-aligned rectangles given by their min and max
corners. Distances are Euclidean, in world units.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Slack for "touching is not penetrating": geometry within this of a contact is a touch.
EPS = 1e-9


def planar_norm(v: ArrayLike) -> FloatArray:
    """Euclidean length of 2-D vectors (shape (..., 2)), written out per coordinate."""
    v = np.asarray(v, dtype=float)
    return np.sqrt(v[..., 0] * v[..., 0] + v[..., 1] * v[..., 1])


def origin_segment_distance(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Distance from the origin to segments ``a``-``b`` (shape (..., 2)), written out per
    coordinate: the hot kernel of swept-disc tests (a moving disc against a fixed point is a
    segment in the point's frame)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    ax, ay = a[..., 0], a[..., 1]
    dx, dy = b[..., 0] - ax, b[..., 1] - ay
    denom = dx * dx + dy * dy
    safe = np.where(denom > 0, denom, 1.0)
    t = np.clip(-(ax * dx + ay * dy) / safe, 0.0, 1.0)
    cx, cy = ax + t * dx, ay + t * dy
    return np.sqrt(cx * cx + cy * cy)


def point_segment_distance(p: ArrayLike, a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Distance from points ``p`` to segments ``a``-``b`` (all of shape (..., 2)). (The
    checker and the path objectives use this form; :func:`origin_segment_distance` is the
    same quantity written for speed, which the per-step PSO evaluates millions of times;
    their last bits may differ, and stored results depend on each.)"""
    p, a, b = (np.asarray(v, dtype=float) for v in (p, a, b))
    ab = b - a
    denom = np.einsum("...i,...i->...", ab, ab)
    t = np.einsum("...i,...i->...", p - a, ab) / np.where(denom > 0, denom, 1.0)
    t = np.clip(np.where(denom > 0, t, 0.0), 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.linalg.norm(p - closest, axis=-1)


def point_box_distance(p: ArrayLike, lo: ArrayLike, hi: ArrayLike) -> FloatArray:
    """Distance from points to closed boxes; 0 inside or on the boundary."""
    p, lo, hi = (np.asarray(v, dtype=float) for v in (p, lo, hi))
    gap = np.maximum(np.maximum(lo - p, p - hi), 0.0)
    return np.linalg.norm(gap, axis=-1)


def point_box_signed_distance(p: ArrayLike, lo: ArrayLike, hi: ArrayLike) -> FloatArray:
    """Signed distance to boxes: negative inside (minus the depth), positive outside."""
    p, lo, hi = (np.asarray(v, dtype=float) for v in (p, lo, hi))
    outside = point_box_distance(p, lo, hi)
    depth = np.min(np.minimum(p - lo, hi - p), axis=-1)
    return np.where(outside > 0, outside, -np.maximum(depth, 0.0))


def segment_box_clip(a: ArrayLike, b: ArrayLike, lo: ArrayLike, hi: ArrayLike
                     ) -> tuple[NDArray[np.bool_], FloatArray, FloatArray]:
    """Liang-Barsky clipping of segments ``a``-``b`` against closed boxes.

    Returns ``(hit, t0, t1)``: whether the segment meets the box and the parameter interval
    ``[t0, t1]`` (0 = ``a``, 1 = ``b``) of the part inside it.
    """
    a, b, lo, hi = (np.asarray(v, dtype=float) for v in (a, b, lo, hi))
    d = b - a
    shape = np.broadcast_shapes(a.shape, b.shape, lo.shape, hi.shape)[:-1]
    t0 = np.zeros(shape)
    t1 = np.ones(shape)
    hit = np.ones(shape, dtype=bool)
    for axis in range(2):
        da = np.broadcast_to(d[..., axis], shape)
        pa = np.broadcast_to(a[..., axis], shape)
        lo_a = np.broadcast_to(lo[..., axis], shape)
        hi_a = np.broadcast_to(hi[..., axis], shape)
        parallel = np.abs(da) < 1e-15
        hit &= ~(parallel & ((pa < lo_a) | (pa > hi_a)))
        with np.errstate(divide="ignore", invalid="ignore"):
            ta = (lo_a - pa) / da
            tb = (hi_a - pa) / da
        enter = np.where(parallel, -np.inf, np.minimum(ta, tb))
        leave = np.where(parallel, np.inf, np.maximum(ta, tb))
        t0 = np.maximum(t0, enter)
        t1 = np.minimum(t1, leave)
    hit &= t0 <= t1
    return hit, t0, t1


def segment_box_distance(a: ArrayLike, b: ArrayLike, lo: ArrayLike, hi: ArrayLike) -> FloatArray:
    """Distance between segments ``a``-``b`` and closed boxes; 0 when they meet.

    When a segment and a convex polygon do not meet, the closest pair involves an endpoint of
    the segment or a corner of the box, so six point distances suffice.
    """
    a, b, lo, hi = (np.asarray(v, dtype=float) for v in (a, b, lo, hi))
    hit, _, _ = segment_box_clip(a, b, lo, hi)
    corners = [lo, hi, np.stack([lo[..., 0], hi[..., 1]], -1), np.stack([hi[..., 0], lo[..., 1]], -1)]
    dist = np.minimum(point_box_distance(a, lo, hi), point_box_distance(b, lo, hi))
    for c in corners:
        dist = np.minimum(dist, point_segment_distance(c, a, b))
    return np.where(hit, 0.0, dist)


def segment_crosses_open_box(a: ArrayLike, b: ArrayLike, lo: ArrayLike, hi: ArrayLike) -> NDArray[np.bool_]:
    """Whether segments pass through the interior of boxes (touching the boundary does not count)."""
    lo = np.asarray(lo, dtype=float) + EPS
    hi = np.asarray(hi, dtype=float) - EPS
    hit, _, _ = segment_box_clip(a, b, lo, hi)
    return hit & np.all(lo < hi, axis=-1)


def segment_segment_distance(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> FloatArray:
    """Distance between segments ``a``-``b`` and ``c``-``d``; 0 when they intersect."""
    a, b, c, d = (np.asarray(v, dtype=float) for v in (a, b, c, d))
    crossing = segments_intersect(a, b, c, d)
    dist = np.minimum.reduce([
        point_segment_distance(a, c, d), point_segment_distance(b, c, d),
        point_segment_distance(c, a, b), point_segment_distance(d, a, b),
    ])
    return np.where(crossing, 0.0, dist)


def _cross(o: FloatArray, p: FloatArray, q: FloatArray) -> FloatArray:
    return (p[..., 0] - o[..., 0]) * (q[..., 1] - o[..., 1]) - (p[..., 1] - o[..., 1]) * (q[..., 0] - o[..., 0])


def segments_intersect(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> NDArray[np.bool_]:
    """Whether closed segments ``a``-``b`` and ``c``-``d`` share a point (touching included)."""
    a, b, c, d = (np.asarray(v, dtype=float) for v in (a, b, c, d))
    d1, d2 = _cross(c, d, a), _cross(c, d, b)
    d3, d4 = _cross(a, b, c), _cross(a, b, d)
    proper = (d1 * d2 < 0) & (d3 * d4 < 0)
    touch = ((np.abs(d1) <= EPS) & (point_segment_distance(a, c, d) <= EPS)) | \
            ((np.abs(d2) <= EPS) & (point_segment_distance(b, c, d) <= EPS)) | \
            ((np.abs(d3) <= EPS) & (point_segment_distance(c, a, b) <= EPS)) | \
            ((np.abs(d4) <= EPS) & (point_segment_distance(d, a, b) <= EPS))
    return proper | touch


def segment_intersection_params(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> FloatArray:
    """Parameter ``t`` along ``a``-``b`` where it crosses line segment ``c``-``d``, NaN if it does not."""
    a, b, c, d = (np.asarray(v, dtype=float) for v in (a, b, c, d))
    r = b - a
    s = d - c
    denom = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    qp = c - a
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qp[..., 0] * s[..., 1] - qp[..., 1] * s[..., 0]) / denom
        u = (qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]) / denom
    ok = (np.abs(denom) > 1e-15) & (t >= -EPS) & (t <= 1 + EPS) & (u >= -EPS) & (u <= 1 + EPS)
    return np.where(ok, np.clip(t, 0.0, 1.0), np.nan)


def points_in_polygon(p: ArrayLike, vertices: ArrayLike) -> NDArray[np.bool_]:
    """Even-odd test of points ``p`` (..., 2) against one polygon ``vertices`` (n, 2).

    Points on the boundary may fall either way; callers that care use distances too.
    """
    p = np.asarray(p, dtype=float)
    v = np.asarray(vertices, dtype=float)
    x = p[..., 0][..., None]
    y = p[..., 1][..., None]
    x0, y0 = v[:, 0], v[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    straddles = (y0 > y) != (y1 > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    crossings = straddles & (x < x_at)
    return (np.count_nonzero(crossings, axis=-1) % 2) == 1


def polygon_signed_distance(p: ArrayLike, vertices: ArrayLike) -> FloatArray:
    """Signed distance from points to a simple polygon: negative inside."""
    p = np.asarray(p, dtype=float)
    v = np.asarray(vertices, dtype=float)
    a, b = v, np.roll(v, -1, axis=0)
    dist = point_segment_distance(p[..., None, :], a, b).min(axis=-1)
    return np.where(points_in_polygon(p, v), -dist, dist)


def relative_min_distance(p0: ArrayLike, p1: ArrayLike, q0: ArrayLike, q1: ArrayLike) -> FloatArray:
    """Smallest distance between two points moving linearly from p0->p1 and q0->q1 in one step.

    The relative motion (p - q) is a segment; its distance to the origin is the answer.
    """
    p0, p1, q0, q1 = (np.asarray(v, dtype=float) for v in (p0, p1, q0, q1))
    return point_segment_distance(np.zeros(2), p0 - q0, p1 - q1)
