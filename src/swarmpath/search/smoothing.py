"""B-spline smoothing of a collision-free polyline that stays collision-free.

The paper (Jaleel & Hassan 2016, Algorithm 1) smooths the A* part of a path with a B-spline.
We use the path's vertices as the control points of a clamped uniform B-spline of degree
``degree`` (scipy.interpolate.BSpline): the curve starts and ends exactly at the path's ends
and each span lies in the convex hull of its ``degree + 1`` control points, so it cuts the
staircase corners of a grid path but may cut an obstacle's corner too. The returned polyline
(samples of the curve) is checked segment by segment against the exact geometry
(``world.static_hits`` with the robot radius). Where a segment hits, the control points of the
offending spans are repeated (multiplicity 1 -> 2 -> ... -> ``degree``); a control point
repeated ``degree`` times pulls the curve onto the control polygon next to it, which is the
original collision-free path. Spans are refined locally, so the rest of the curve keeps its
smoothing. If a hit remains when every offending control point has full multiplicity (it
cannot, up to floating point), the original polyline is returned.

Resampling: consecutive points of the result are at most ``max_step`` apart (default: one
cell of the world's grid, ``world.resolution``), so grid controllers that move at most one
cell a step can follow the smoothed part vertex by vertex. The curve's knots (span ends) are
always among the samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import BSpline

from swarmpath.errors import ConfigError

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class SmoothResult:
    """A smoothed polyline ``path`` of shape (n_points, 2) with what it took:
    ``refinements`` rounds of raising control point multiplicities, ``kept_points`` control
    points that ended at full multiplicity (the curve passes through them), and
    ``fallback`` True when the original polyline had to be returned."""

    path: FloatArray
    refinements: int
    kept_points: int
    fallback: bool


def dedupe(path: ArrayLike, tol: float = 1e-12) -> FloatArray:
    """``path`` (n, 2) without consecutive duplicate points."""
    p = np.asarray(path, float).reshape(-1, 2)
    if len(p) < 2:
        return p.copy()
    keep = np.ones(len(p), dtype=bool)
    keep[1:] = np.linalg.norm(np.diff(p, axis=0), axis=1) > tol
    return p[keep]


def clamped_bspline(control: ArrayLike, degree: int) -> BSpline:
    """The clamped uniform B-spline with ``control`` points (m, 2) on the parameter [0, 1]
    (degree lowered to m - 1 when there are too few points)."""
    c = np.asarray(control, float)
    m = len(c)
    k = max(1, min(int(degree), m - 1))
    n_inner = m - k - 1
    inner = np.linspace(0.0, 1.0, n_inner + 2)[1:-1]
    t = np.concatenate([np.zeros(k + 1), inner, np.ones(k + 1)])
    return BSpline(t, c, k, extrapolate=False)


def sample_spline(spline: BSpline, max_step: float) -> tuple[FloatArray, FloatArray]:
    """Parameters ``u`` (n,) and points (n, 2) of ``spline`` with consecutive points at most
    ``max_step`` apart (Euclidean), including the curve's ends and every knot."""
    knots = np.unique(spline.t)
    c = np.asarray(spline.c, float)
    m = len(c)
    k = spline.k
    # First guess per knot interval: its control polygon's length (a bound on its arc length)
    # in max_step pieces; then halve any piece whose chord is still too long.
    poly = np.linalg.norm(np.diff(c, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(poly)])
    a, b = knots[:-1], knots[1:]
    span = np.clip(np.searchsorted(spline.t, a, side="right") - 1, k, m - 1)
    hull = cum[span] - cum[span - k]
    n = np.maximum(1, np.ceil(hull / max_step).astype(np.int64))
    # n pieces per interval: parameters a + (b - a) * j / n for j = 1..n, plus the first knot
    which = np.repeat(np.arange(len(a)), n)
    j = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n) + 1
    u = np.concatenate([knots[:1], a[which] + (b - a)[which] * j / n[which]])
    u[np.cumsum(n)] = b  # exact knots at the interval ends
    pts = _evaluate(spline, u)
    for _ in range(30):
        long = np.linalg.norm(np.diff(pts, axis=0), axis=1) > max_step
        if not long.any():
            break
        mids = (u[:-1][long] + u[1:][long]) / 2
        u = np.sort(np.concatenate([u, mids]))
        pts = _evaluate(spline, u)
    keep = np.isin(u, knots)
    idx = _thin(pts, keep, max_step)
    return u[idx], pts[idx]


def _evaluate(spline: BSpline, u: FloatArray) -> FloatArray:
    pts = spline(u)
    pts[0], pts[-1] = spline.c[0], spline.c[-1]  # exact ends (clamped)
    return pts


def _thin(pts: FloatArray, keep: NDArray[np.bool_], max_step: float) -> NDArray[np.int64]:
    """Indices of the samples kept when dropping samples while every chord stays <= max_step
    (``keep`` marks samples never dropped; consecutive input samples are <= max_step apart)."""
    xs, ys = pts[:, 0].tolist(), pts[:, 1].tolist()
    must = keep.tolist()
    last = len(xs) - 1
    out = [0]
    lx, ly = xs[0], ys[0]
    for i in range(1, len(xs)):
        if must[i] or i == last or math.hypot(xs[i + 1] - lx, ys[i + 1] - ly) > max_step:
            if math.hypot(xs[i] - lx, ys[i] - ly) > 1e-12:
                out.append(i)
                lx, ly = xs[i], ys[i]
    return np.asarray(out, dtype=np.int64)


def smooth_path(world, path: ArrayLike, radius: float = 0.0, *, degree: int = 3, max_step: float | None = None,
                max_rounds: int | None = None) -> SmoothResult:
    """Smooth a collision-free polyline ``path`` (n, 2) of a disc robot of ``radius`` with a
    B-spline, keeping it collision-free (see the module docstring). The result starts and ends
    exactly at the ends of ``path``; consecutive points are at most ``max_step`` apart
    (default ``world.resolution``)."""
    if int(degree) < 1:
        raise ConfigError(f"degree must be >= 1, got {degree!r}")
    step = float(world.resolution if max_step is None else max_step)
    if not step > 0:
        raise ConfigError(f"max_step must be > 0, got {max_step!r}")
    original = dedupe(path)
    if len(original) < 3:
        return SmoothResult(_resample_polyline(original, step), 0, 0, False)
    k = min(int(degree), len(original) - 1)
    checker = _local_checker(world, original, float(radius))
    mult = np.ones(len(original), dtype=np.int64)
    rounds = 0
    limit = np.inf if max_rounds is None else int(max_rounds)
    while True:
        control = np.repeat(original, mult, axis=0)
        owner = np.repeat(np.arange(len(original)), mult)
        spline = clamped_bspline(control, k)
        pts, spans = _samples_with_spans(spline, step)
        hits = checker.static_hits(pts[:-1], pts[1:], np.full(len(pts) - 1, float(radius)))
        if not hits.any():
            kept = int(np.count_nonzero(mult >= k))
            return SmoothResult(pts, rounds, kept, False)
        if rounds >= limit:
            return SmoothResult(_resample_polyline(original, step), rounds, len(original), True)
        rounds += 1
        # The control points of every span a hitting segment touches get one more copy.
        bad = np.unique(np.concatenate([spans[np.flatnonzero(hits)], spans[np.flatnonzero(hits) + 1]]))
        touched = np.zeros(len(original), dtype=bool)
        for s in bad:
            touched[owner[max(0, s - k):s + 1]] = True
        grow = touched & (mult < k)
        if not grow.any():
            return SmoothResult(_resample_polyline(original, step), rounds, len(original), True)
        mult[grow] += 1


def _local_checker(world, control: FloatArray, radius: float):
    """``world`` reduced to the static obstacles that can touch the curve: every sample lies in
    the bounding box of the control points (convex hull property), so obstacles whose own box
    is farther than ``radius`` cannot be hit. Same geometry, same ``static_hits``, fewer
    obstacles to loop over on large worlds."""
    if len(world.obstacles) < 32:  # building the reduced world would cost more than it saves
        return world
    lo = control.min(axis=0) - radius - 1e-6
    hi = control.max(axis=0) + radius + 1e-6
    near = []
    for ob in world.obstacles:
        olo, ohi = ob.bbox
        if np.all(olo <= hi) and np.all(ohi >= lo):
            near.append(ob)
    if 2 * len(near) > len(world.obstacles):
        return world
    return world.replace(obstacles=tuple(near), robots=(), moving_obstacles=(), danger_zones=())


def _samples_with_spans(spline: BSpline, max_step: float) -> tuple[FloatArray, NDArray[np.int64]]:
    """Samples of ``spline`` (see :func:`sample_spline`) and, per sample, the index ``s`` of
    the span it starts (the span uses control points ``s - k .. s``)."""
    u, pts = sample_spline(spline, max_step)
    span = np.clip(np.searchsorted(spline.t, u, side="right") - 1, spline.k, len(spline.c) - 1)
    return pts, span.astype(np.int64)


def _resample_polyline(path: FloatArray, max_step: float) -> FloatArray:
    """``path`` with extra points on its segments so no segment is longer than ``max_step``
    (the original vertices are kept)."""
    p = dedupe(path)
    if len(p) < 2:
        return p
    out = [p[:1]]
    for a, b in zip(p[:-1], p[1:]):
        n = max(1, int(np.ceil(np.linalg.norm(b - a) / max_step - 1e-9)))
        ts = np.arange(1, n + 1) / n
        out.append(a + ts[:, None] * (b - a))
    return np.concatenate(out)
