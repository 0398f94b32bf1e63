"""The half-planes of ORCA in velocity space (van den Berg et al., ISRR 2011), as small pure
functions vectorised over pairs.

Every function returns lines in the form of :mod:`swarmpath.control.orca.lp`: a point on the
boundary and a unit direction, velocities on the left permitted.

- :func:`orca_halfplanes_robots`: ORCA^tau_{A|B} of eq. (6) for pairs of discs: the truncated
  velocity obstacle VO^tau_{A|B} (eq. (2)), the smallest change ``u`` of the relative
  velocity that leaves it (eq. (5)), and the half-plane through ``v_A + c u`` with normal
  ``n = u / ||u||``; ``c = 1/2`` for robots (reciprocal: each takes half), ``c = 1`` for a
  moving obstacle that does not react (non-reciprocal). Pairs already closer than their
  combined radius use the cut-off of one time step instead of tau, as RVO2 does.
- :func:`halfplane_below`: the half-plane ``v . n <= bound``.
- :func:`clearance_halfplanes`: keep at least ``clearance`` from a convex obstacle whose
  closest point lies at ``offset`` from the robot: the supporting line through the closest
  point separates the obstacle from the robot, so ``v . n <= (|offset| - clearance) / tau``
  with ``n = offset / |offset|`` keeps the disc swept in one step of ``dt <= tau`` out of the
  obstacle (a linearisation of the obstacle's truncated velocity obstacle, conservative).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

_TINY = 1e-12


def halfplane_below(normal: ArrayLike, bound: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Lines for ``v . normal <= bound``: normal (e, 2) unit vectors, bound (e,).
    Returns points (e, 2) and directions (e, 2)."""
    n = np.asarray(normal, float).reshape(-1, 2)
    b = np.asarray(bound, float).reshape(-1)
    return n * b[:, None], np.stack([-n[:, 1], n[:, 0]], axis=1)


def orca_halfplanes_robots(rel_pos: ArrayLike, rel_vel: ArrayLike, velocity: ArrayLike, combined_radius: ArrayLike,
                           time_horizon: ArrayLike, dt: float, responsibility: ArrayLike = 0.5
                           ) -> tuple[FloatArray, FloatArray]:
    """ORCA^tau_{A|B} (eq. (6)) of e pairs, as RVO2 computes it.

    rel_pos (e, 2) = p_B - p_A; rel_vel (e, 2) = v_A - v_B; velocity (e, 2) = v_A (the
    current velocity, RVO2's v_A^opt); combined_radius (e,) = r_A + r_B (+ margin);
    time_horizon tau (scalar or (e,)); dt the time step (the cut-off for pairs already in
    contact); responsibility (scalar or (e,)): 1/2 reciprocal, 1 when B does not react.
    Returns points (e, 2) = v_A + c u and unit directions (e, 2).
    """
    p = np.asarray(rel_pos, float).reshape(-1, 2)
    v = np.asarray(rel_vel, float).reshape(-1, 2)
    va = np.asarray(velocity, float).reshape(-1, 2)
    e = len(p)
    R = np.broadcast_to(np.asarray(combined_radius, float), (e,))
    inv_tau = 1.0 / np.broadcast_to(np.asarray(time_horizon, float), (e,))
    c = np.broadcast_to(np.asarray(responsibility, float), (e,))
    dist_sq = np.einsum("ij,ij->i", p, p)
    r_sq = R * R
    apart = dist_sq > r_sq
    # vector from the cut-off centre to the relative velocity: tau for pairs apart, dt in contact
    inv = np.where(apart, inv_tau, 1.0 / dt)
    w = v - inv[:, None] * p
    w_sq = np.einsum("ij,ij->i", w, w)
    dot1 = np.einsum("ij,ij->i", w, p)
    on_circle = ~apart | ((dot1 < 0.0) & (dot1 * dot1 > r_sq * w_sq))
    w_len = np.sqrt(w_sq)
    safe_len = np.where(w_len > _TINY, w_len, 1.0)
    unit_w = w / safe_len[:, None]
    # degenerate (w = 0 while in contact): push straight apart
    d_len = np.sqrt(dist_sq)
    away = np.where(d_len[:, None] > _TINY, -p / np.where(d_len > _TINY, d_len, 1.0)[:, None], np.array([[-1.0, 0.0]]))
    unit_w = np.where((w_len > _TINY)[:, None], unit_w, away)
    dir_circle = np.stack([unit_w[:, 1], -unit_w[:, 0]], axis=1)
    u_circle = (R * inv - w_len)[:, None] * unit_w
    # legs of the cone (pairs apart, projection not on the cut-off circle)
    leg = np.sqrt(np.maximum(dist_sq - r_sq, 0.0))
    safe_sq = np.where(dist_sq > _TINY, dist_sq, 1.0)
    left = (p[:, 0] * w[:, 1] - p[:, 1] * w[:, 0]) > 0.0
    left_dir = np.stack([p[:, 0] * leg - p[:, 1] * R, p[:, 0] * R + p[:, 1] * leg], axis=1) / safe_sq[:, None]
    right_dir = -np.stack([p[:, 0] * leg + p[:, 1] * R, -p[:, 0] * R + p[:, 1] * leg], axis=1) / safe_sq[:, None]
    dir_leg = np.where(left[:, None], left_dir, right_dir)
    dot2 = np.einsum("ij,ij->i", v, dir_leg)
    u_leg = dot2[:, None] * dir_leg - v
    direction = np.where(on_circle[:, None], dir_circle, dir_leg)
    u = np.where(on_circle[:, None], u_circle, u_leg)
    return va + c[:, None] * u, direction


def clearance_halfplanes(offset: ArrayLike, clearance: ArrayLike, horizon: ArrayLike, floor: float | None = 0.0
                         ) -> tuple[FloatArray, FloatArray]:
    """Keep ``clearance`` (e,) from convex obstacles whose closest points lie at ``offset``
    (e, 2) from the robots: ``v . n <= (|offset| - clearance) / horizon``.

    ``floor`` (default 0) bounds the right-hand side from below so that standing still is
    always permitted (hard lines); ``None`` leaves it negative when the robot is already too
    close, which then asks it to move away (firm lines)."""
    off = np.asarray(offset, float).reshape(-1, 2)
    d = np.sqrt(np.einsum("ij,ij->i", off, off))
    n = np.where((d > _TINY)[:, None], off / np.where(d > _TINY, d, 1.0)[:, None], np.array([[1.0, 0.0]]))
    bound = (d - np.asarray(clearance, float)) / np.asarray(horizon, float)
    if floor is not None:
        bound = np.maximum(bound, floor)
    return halfplane_below(n, bound)
