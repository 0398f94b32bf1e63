"""Objectives of AMOPSO path planning (Abbas & Abdulsahab, section 2.1), as pure vectorised
functions over a whole swarm of candidate polylines.

Encoding. A particle is K intermediate waypoints, 2K numbers ``(x1, y1, ..., xK, yK)``; its
path is the polyline ``start, w1, ..., wK, goal`` (:func:`decode_paths`). All functions below
take ``paths`` of shape (n_paths, n_points, 2) (n_points = K + 2) and return one value per
path, so one call scores the whole swarm.

Objectives (all minimised):

- :func:`path_lengths`: Euclidean length of the polyline. It replaces the paper's f2 (eq. 2,
  the distance from a particle's position to the goal): every decoded path ends at the goal,
  so what is left to minimise is the distance travelled.
- :func:`danger_inverse_sum`: the paper's f1 (eq. 1), ``1 / sum_j d_j``, evaluated over the
  whole polyline: d_j is the exact distance from danger zone j's centre to the polyline (the
  minimum over its segments of the point-segment distance), i.e. the closest the path comes
  to that zone. The paper evaluates eq. 1 at one particle position; over a polyline, the
  closest approach is what "the path keeps away from the danger zone" means, and it is
  exact (no sampling). Zone radii and weights do not enter f1 (the paper has neither).
- :func:`danger_clearance`: ``min_j (d_j - r_j)``, the free distance between the path and the
  nearest danger zone's disc (negative inside). Reported, used by the choice rule from the
  Pareto front, and available as the second objective instead of f1 (as ``-clearance``).
- :func:`obstacle_violation`: how deep the path goes into static obstacles, for a robot of
  radius ``radius``, evaluated with the world's exact geometry per segment: circles
  ``max(0, r + radius - dist(centre, segment))``; rectangles the length of the segment inside
  the box plus ``radius`` when it crosses the interior, else ``max(0, radius - distance)``;
  polygons the depth of the deepest probe point (:func:`polygon_depth`) plus ``radius`` when
  it crosses, else ``max(0, radius - distance)``; raster maps 1 per segment that touches a
  blocked cell; the workspace ``max(0, radius - clearance to the boundary)`` at each vertex (the workspace is
  convex, so a segment stays inside when its ends do). Zero for a collision-free path.
- :func:`segment_hits` / :func:`static_collisions`: whether a segment (any segment of a path)
  enters a static obstacle or leaves the workspace, with the predicates of
  ``World.static_hits`` (the validator's test): the exact feasibility.

:func:`penalised_objectives` turns these into the optimiser's objective matrix: an infeasible
path gets ``offset + scale * violation`` added to every objective, so every feasible path
dominates every infeasible one (a penalty form of Deb's constrained domination) and among
infeasible paths the shallower ones are preferred.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world import geometry as g
from swarmpath.world.shapes import Circle, Polygon, Rect

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Multiplies the violation depth of an infeasible path.
PENALTY_SCALE = 1.0e3
#: Smallest sum of danger distances in f1 (so f1 <= 1 / DANGER_FLOOR).
DANGER_FLOOR = 1.0e-3


def penalty_offset(lower: ArrayLike, upper: ArrayLike, n_waypoints: int) -> float:
    """A penalty offset larger than any feasible objective value: ten times the longest
    possible path through ``n_waypoints`` waypoints of the box [lower, upper] (each of the K + 1
    segments at most the box's diagonal) plus ten times the largest f1 (1 / DANGER_FLOOR)."""
    diag = float(np.linalg.norm(np.asarray(upper, float) - np.asarray(lower, float)))
    return 10.0 * ((n_waypoints + 1) * diag + 1.0 / DANGER_FLOOR)


def decode_paths(X: ArrayLike, start: ArrayLike, goal: ArrayLike) -> FloatArray:
    """Polylines of particles: ``start, w1, ..., wK, goal``.

    Parameters
    ----------
    X : array_like of shape (n_paths, 2K)
        Waypoints ``(x1, y1, ..., xK, yK)`` per particle.
    start, goal : array_like of shape (2,)

    Returns
    -------
    ndarray of shape (n_paths, K + 2, 2)
    """
    X = np.asarray(X, dtype=float)
    n = X.shape[0]
    w = X.reshape(n, -1, 2)
    s = np.broadcast_to(np.asarray(start, float), (n, 1, 2))
    e = np.broadcast_to(np.asarray(goal, float), (n, 1, 2))
    return np.concatenate([s, w, e], axis=1)


def encode_waypoints(waypoints: ArrayLike) -> FloatArray:
    """The particle of K waypoints (K, 2) -> (2K,): the inverse of :func:`decode_paths`."""
    return np.asarray(waypoints, dtype=float).reshape(-1)


def path_lengths(paths: ArrayLike) -> FloatArray:
    """Euclidean length of each polyline; paths (n_paths, n_points, 2) -> (n_paths,)."""
    p = np.asarray(paths, dtype=float)
    return np.linalg.norm(np.diff(p, axis=1), axis=2).sum(axis=1)


def danger_distances(paths: ArrayLike, centers: ArrayLike) -> FloatArray:
    """Closest approach of each polyline to each danger-zone centre (exact).

    Parameters
    ----------
    paths : array_like of shape (n_paths, n_points, 2)
    centers : array_like of shape (n_zones, 2)

    Returns
    -------
    ndarray of shape (n_paths, n_zones): ``min over segments of dist(centre, segment)``.
    """
    p = np.asarray(paths, dtype=float)
    c = np.asarray(centers, dtype=float).reshape(-1, 2)
    if c.shape[0] == 0:
        return np.zeros((p.shape[0], 0))
    a = p[:, :-1, None, :]          # (n, s, 1, 2)
    b = p[:, 1:, None, :]
    d = g.point_segment_distance(c[None, None, :, :], a, b)   # (n, s, z)
    return d.min(axis=1)


def danger_inverse_sum(distances: ArrayLike, floor: float = DANGER_FLOOR) -> FloatArray:
    """Eq. 1 over a polyline: f1 = 1 / sum_j d_j; distances (n_paths, n_zones) -> (n_paths,).

    ``d_j`` from :func:`danger_distances`. Without danger zones f1 is 0 for every path (nothing
    to avoid); a sum below ``floor`` (a path through every centre) counts as ``floor``.
    """
    d = np.asarray(distances, dtype=float)
    if d.shape[1] == 0:
        return np.zeros(d.shape[0])
    return 1.0 / np.maximum(d.sum(axis=1), floor)


def danger_clearance(distances: ArrayLike, radii: ArrayLike) -> FloatArray:
    """Free distance to the nearest danger zone: ``min_j (d_j - r_j)`` (negative inside).

    distances (n_paths, n_zones), radii (n_zones,) -> (n_paths,); +inf without danger zones.
    """
    d = np.asarray(distances, dtype=float)
    if d.shape[1] == 0:
        return np.full(d.shape[0], np.inf)
    return (d - np.asarray(radii, dtype=float)[None, :]).min(axis=1)


def _segment_violation(shape, a: FloatArray, b: FloatArray, radius: float) -> FloatArray:
    """Penetration of segments a-b (m, 2) into one static shape for a disc of ``radius``."""
    if isinstance(shape, Circle):
        d = g.point_segment_distance(np.asarray(shape.center, float), a, b)
        return np.maximum(shape.radius + radius - d, 0.0)
    near = np.maximum(radius - shape.segment_clearance(a, b), 0.0) if radius > 0 else np.zeros(len(a))
    crossed = shape.segment_crosses_interior(a, b)
    if not crossed.any():
        return near
    if isinstance(shape, Rect):
        _, t0, t1 = g.segment_box_clip(a, b, shape.min, shape.max)
        depth = np.maximum(t1 - t0, 0.0) * np.linalg.norm(b - a, axis=-1)
    else:
        depth = polygon_depth(shape, a, b)
    return np.where(crossed, depth + radius, near)


def polygon_depth(shape: Polygon, a: FloatArray, b: FloatArray) -> FloatArray:
    """Deepest point of segments a-b (m, 2) inside a polygon, probed where
    ``Polygon.segment_crosses_interior`` probes (the ends, the edge crossings and the
    midpoints between them) plus 9 evenly spaced points; 0 outside. Returns (m,)."""
    c, d = shape.edges
    t = g.segment_intersection_params(a[..., None, :], b[..., None, :], c, d)
    t = np.where(np.isnan(t), 1.0, t)
    even = np.broadcast_to(np.linspace(0.0, 1.0, 9), t.shape[:-1] + (9,))
    ts = np.sort(np.concatenate([even, t], axis=-1), axis=-1)
    probes = np.concatenate([ts, (ts[..., 1:] + ts[..., :-1]) / 2], axis=-1)
    pts = a[..., None, :] + probes[..., None] * (b - a)[..., None, :]
    return np.maximum(-shape.signed_distance(pts), 0.0).max(axis=-1)


def _bounding_circle(shape) -> tuple[FloatArray, float]:
    """Centre (2,) and radius of a circle that contains ``shape``."""
    if isinstance(shape, Circle):
        return np.asarray(shape.center, float), float(shape.radius)
    lo, hi = shape.bbox
    return (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2)


def segment_hits(world, paths: ArrayLike, radius: float = 0.0) -> BoolArray:
    """Per segment: whether it enters a static obstacle or leaves the workspace for a disc of
    ``radius``; paths (n_paths, n_points, 2) -> (n_paths, n_points - 1).

    The same predicates as ``World.static_hits`` (the validator's test): a segment leaves the
    (convex) workspace when an end does; it hits a shape when it crosses the shape's interior
    or, for a disc robot, comes closer than ``radius`` (``EPS`` slack: touching is allowed).
    Only segments within reach of a shape's bounding circle are tested against it. Worlds with
    a raster map use ``World.static_hits`` directly.
    """
    p = np.asarray(paths, dtype=float)
    n, k = p.shape[0], p.shape[1]
    a = p[:, :-1].reshape(-1, 2)
    b = p[:, 1:].reshape(-1, 2)
    r = float(radius)
    if world.static_map is not None:
        return world.static_hits(a, b, np.full(a.shape[0], r)).reshape(n, k - 1)
    inside = world.bounds.contains(p.reshape(-1, 2), r).reshape(n, k)
    hits = ~(inside[:, :-1] & inside[:, 1:]).reshape(-1)
    for shape in world.obstacles:
        c, reach = _bounding_circle(shape)
        idx = np.flatnonzero(~hits & (g.point_segment_distance(c, a, b) < reach + r + 1e-6))
        if len(idx) == 0:
            continue
        hit = shape.segment_crosses_interior(a[idx], b[idx])
        if r > 0:
            hit |= shape.segment_clearance(a[idx], b[idx]) < r - g.EPS
        hits[idx] = hit
    return hits.reshape(n, k - 1)


def obstacle_violation(world, paths: ArrayLike, radius: float = 0.0, hits: ArrayLike | None = None) -> FloatArray:
    """Total penetration of each polyline into static obstacles and the boundary (see the
    module docstring for the per-shape measure); paths (n_paths, n_points, 2) -> (n_paths,).

    Zero when no segment comes closer than ``radius`` to an obstacle and every vertex keeps
    ``radius`` from the boundary. ``hits`` (n_paths, n_points - 1), from
    :func:`segment_hits`, limits the work to the segments that hit (the others contribute 0).
    """
    p = np.asarray(paths, dtype=float)
    n, k = p.shape[0], p.shape[1]
    a = p[:, :-1].reshape(-1, 2)
    b = p[:, 1:].reshape(-1, 2)
    todo = np.ones(a.shape[0], bool) if hits is None else np.asarray(hits, bool).reshape(-1)
    total = np.zeros(a.shape[0])
    lo_seg, hi_seg = np.minimum(a, b) - radius, np.maximum(a, b) + radius
    for shape in world.obstacles:
        lo, hi = shape.bbox
        near = todo & np.all((lo_seg < hi) & (hi_seg > lo), axis=1)
        if near.any():
            idx = np.flatnonzero(near)
            total[idx] += _segment_violation(shape, a[idx], b[idx], radius)
    if world.static_map is not None and todo.any():
        idx = np.flatnonzero(todo)
        total[idx] += world.static_map.segment_hits(a[idx], b[idx], np.full(len(idx), radius)).astype(float)
    per_path = total.reshape(n, k - 1).sum(axis=1)
    boundary = np.maximum(radius - world.bounds.clearance(p.reshape(-1, 2)), 0.0).reshape(n, k).sum(axis=1)
    return per_path + boundary


def static_collisions(world, paths: ArrayLike, radius: float = 0.0) -> BoolArray:
    """Whether any segment of each polyline enters a static obstacle or leaves the workspace
    (:func:`segment_hits`, i.e. ``World.static_hits``, exact); (n_paths, n_points, 2) -> (n_paths,)."""
    return segment_hits(world, paths, radius).any(axis=1)


def penalised_objectives(F: ArrayLike, violation: ArrayLike, infeasible: ArrayLike, offset: float,
                         scale: float = PENALTY_SCALE) -> FloatArray:
    """Objective matrix with the obstacle constraint folded in.

    F (n, m) raw objectives; violation (n,) from :func:`obstacle_violation`; infeasible (n,)
    from :func:`static_collisions`. Infeasible rows get ``offset + scale * violation`` added to
    every objective (``offset`` from :func:`penalty_offset`); feasible rows are unchanged.
    Returns (n, m).
    """
    F = np.asarray(F, dtype=float)
    extra = np.where(np.asarray(infeasible, bool), offset + scale * np.asarray(violation, float), 0.0)
    return F + extra[:, None]


def resample_polyline(path: ArrayLike, n_waypoints: int) -> FloatArray:
    """K = ``n_waypoints`` interior points for a polyline (n_points, 2), keeping its corners.

    When the polyline has at most K interior vertices, all of them are kept (so the
    resampled path is the same curve) and the remaining waypoints are spread over the
    segments in proportion to their lengths; otherwise K points equally spaced by arc length
    (which may cut corners). Returns (K, 2).
    """
    p = np.asarray(path, dtype=float)
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    interior = p[1:-1]
    K = int(n_waypoints)
    if len(interior) > K or seg.sum() == 0:
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        s = np.linspace(0.0, cum[-1], K + 2)[1:-1]
        return np.column_stack([np.interp(s, cum, p[:, 0]), np.interp(s, cum, p[:, 1])])
    extra = K - len(interior)
    # Distribute ``extra`` points over the segments by largest remainder of length share.
    share = seg / seg.sum() * extra
    count = np.floor(share).astype(int)
    rest = extra - count.sum()
    if rest > 0:
        count[np.argsort(-(share - count), kind="stable")[:rest]] += 1
    pts = []
    for s in range(len(seg)):
        if s > 0:
            pts.append(p[s])
        for q in range(1, count[s] + 1):
            pts.append(p[s] + (p[s + 1] - p[s]) * q / (count[s] + 1))
    return np.asarray(pts).reshape(K, 2)
