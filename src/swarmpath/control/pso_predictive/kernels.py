"""The equations of the PSO-prediction paper (2013, eq. 1-8) as small pure functions over
arrays: motion of a particle (eq. 1-2), the objective's terms (eq. 3-7) and the heading-aware
velocity update (eq. 8). docs/papers/pso-prediction-2013.md gives the reading of each."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.world.geometry import origin_segment_distance, planar_norm

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

TWO_PI = 2.0 * np.pi


def wrap_angle(theta: FloatArray) -> FloatArray:
    """Angles wrapped to [-pi, pi)."""
    return (np.asarray(theta, float) + np.pi) % TWO_PI - np.pi


def next_position(position: FloatArray, theta: FloatArray, sigma: FloatArray, reach: FloatArray) -> FloatArray:
    """Eq. 1-2: x' = x + sigma v dt cos(theta), y' = y + sigma v dt sin(theta).

    position : (k, 2); theta, sigma : (k, p); reach : (k,) = v dt. Returns (k, p, 2).
    """
    step = (np.asarray(sigma, float) * np.asarray(reach, float)[:, None])[..., None]
    return position[:, None, :] + step * np.stack([np.cos(theta), np.sin(theta)], axis=-1)


def goal_distance(x_next: FloatArray, goal: FloatArray) -> FloatArray:
    """Eq. 3 (one robot's term): ||x' - g||; x_next (k, p, 2), goal (k, 2) -> (k, p)."""
    return planar_norm(x_next - goal[:, None, :])


def kin_penalty(x_next: FloatArray, pair_row: NDArray[np.int64], announced: FloatArray,
                separation: FloatArray) -> FloatArray:
    """Eq. 5, second term: sum_j min(0, d'_ij - (r_i + r_j + eps))^2 over sensed robots j.

    x_next (k, p, 2); one entry per sensed pair (i, j): pair_row (e,) the row i, announced
    (e, 2) robot j's announced/predicted next position, separation (e,) = r_i + r_j + eps.
    Returns (k, p).
    """
    out = np.zeros(x_next.shape[:2])
    if len(pair_row):
        diff = x_next[pair_row] - announced[:, None, :]
        d = np.sqrt(diff[..., 0] ** 2 + diff[..., 1] ** 2)
        short = np.minimum(0.0, d - separation[:, None])
        np.add.at(out, pair_row, short * short)
    return out


def inverse_obstacle_distance(x_next: FloatArray, target: FloatArray, mask: BoolArray,
                              floor: float = 1e-6) -> FloatArray:
    """Eq. 7, last term: sum_m 1 / ||x' - p_m'|| over sensed obstacles (the paper maximises
    the distance to the predicted position by minimising its inverse).

    x_next (k, p, 2); target (m, 2) predicted (or current) obstacle positions; mask (k, m).
    Returns (k, p).
    """
    if target.shape[0] == 0:
        return np.zeros(x_next.shape[:2])
    d = planar_norm(x_next[:, :, None, :] - target[None, None, :, :])
    return np.sum(np.where(mask[:, None, :], 1.0 / np.maximum(d, floor), 0.0), axis=-1)


def path_buffer_penalty(x_next: FloatArray, start: FloatArray, end: FloatArray, need: FloatArray,
                        buffer: FloatArray) -> FloatArray:
    """Soft keep-away from a moving obstacle's predicted path over the next few steps (our
    addition to eq. 7): ((need + b - d) / b)^2 when the distance d from x' to the segment
    start-end is below need + b, else 0.

    x_next (k, p, 2); start, end (2,) the predicted path; need (k,) the contact distance
    R + r + margin; buffer b (scalar > 0). Returns (k, p).
    """
    d = origin_segment_distance(start - x_next, end - x_next)
    short = np.maximum(0.0, need[:, None] + buffer - d) / buffer
    return short * short


def static_clearance_penalty(clearance: FloatArray, margin: FloatArray | float,
                             scale: float | None = None) -> FloatArray:
    """Eq. 6, static term as implemented: (margin - c)/scale for a disc whose clearance c to
    the nearest static obstacle is below ``margin`` (0 when clear, 1 when touching at
    margin = scale, more when penetrating); the paper's constant "f_st when a static obstacle
    is on the local trajectory" becomes a clearance-based ramp so that PSO has a slope to
    follow. ``margin`` may vary per candidate (array broadcast with ``clearance``); ``scale``
    defaults to ``margin``."""
    return np.maximum(0.0, margin - clearance) / (margin if scale is None else scale)


def pso_velocity_update_wrapped(v: FloatArray, x: FloatArray, pbest: FloatArray, gbest: FloatArray, w: float,
                                c1: float, c2: float, r1: FloatArray, r2: FloatArray) -> FloatArray:
    """Eq. 8: V(t+1) = w V(t) + C1 phi1 (P - X) + C2 phi2 (g - X), for particles (theta,
    sigma) whose heading is periodic: the heading differences are wrapped to [-pi, pi).

    v, x, pbest, r1, r2 : (k, p, 2); gbest : (k, 1, 2). Returns (k, p, 2).
    """
    dp = pbest - x
    dg = gbest - x
    dp[..., 0] = wrap_angle(dp[..., 0])
    dg[..., 0] = wrap_angle(dg[..., 0])
    return w * v + c1 * r1 * dp + c2 * r2 * dg
