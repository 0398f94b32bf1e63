"""Linear prediction of moving obstacles from their last two observations (PSO-prediction
paper, 2013, section 2.C and the pseudo-code of section 4).

The paper predicts the next position of the dynamic obstacle by linear extrapolation:

    x_p' = x_p + u dt',   y_p' = y_p + w dt'                                     (eq. 4 text)

with (u, w) the obstacle's velocity estimated from its last two sampled positions and the
"sampling time" dt' = arr[i] / arr[j]: the total time of the obstacle's movement divided by
the number of steps it took (:func:`sampling_time`). The prediction assumes linear motion
between two samples; the obstacle of the paper "changes its direction at regular intervals".

Everything here is a pure function of arrays plus one frozen record, :class:`ObstacleTrack`,
that a controller threads through :func:`update_track` from step to step. The track also
remembers at which steps the obstacle turned *although the linear prediction was possible*
(deliberate turns, as opposed to bounces off walls); from those it estimates the turning
period (:func:`estimate_turn_period`) so that a controller knows when linear prediction is
about to be wrong (:func:`turn_expected`). That part is our addition (docs/papers/
pso-prediction-2013.md, "Turn guard").
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Two displacements differ (a turn) when |d_k - d_{k-1}| exceeds this fraction of |d_{k-1}|.
TURN_TOLERANCE = 1e-6


def sampling_time(total_time: float, n_steps: int, default: float = 1.0) -> float:
    """The paper's sampling time dt' = arr[i] / arr[j] (section 2.C): total time of the
    obstacle's movement divided by the number of steps it made; ``default`` before it moved."""
    if n_steps <= 0 or not total_time > 0:
        return float(default)
    return float(total_time) / int(n_steps)


def estimate_velocity(previous: ArrayLike, current: ArrayLike, interval: float) -> FloatArray:
    """Velocity (u, w) from two samples ``interval`` time units apart: (current - previous) /
    interval. ``previous`` and ``current`` have shape (m, 2); so has the result."""
    if not interval > 0:
        raise ValueError(f"interval must be > 0, got {interval}")
    return (np.asarray(current, float) - np.asarray(previous, float)) / float(interval)


def predict_linear(previous: ArrayLike, current: ArrayLike, interval: float, dt_sampling: float,
                   horizon: int = 1) -> FloatArray:
    """Linear prediction x_p' = x_p + u dt' (section 2.C), ``horizon`` sampling times ahead.

    previous, current : (m, 2) the last two observed positions, ``interval`` time units apart
    dt_sampling : dt', the obstacle's time per step (:func:`sampling_time`)
    Returns (m, 2) predicted positions.
    """
    u = estimate_velocity(previous, current, interval)
    return np.asarray(current, float) + u * (float(dt_sampling) * horizon)


def displacement_changed(before: ArrayLike, after: ArrayLike, tol: float = TURN_TOLERANCE) -> NDArray[np.bool_]:
    """Whether each obstacle's step displacement changed (direction or speed), shape (m,)."""
    b = np.asarray(before, float).reshape(-1, 2)
    a = np.asarray(after, float).reshape(-1, 2)
    scale = np.maximum(np.linalg.norm(b, axis=1), np.linalg.norm(a, axis=1))
    return np.linalg.norm(a - b, axis=1) > tol * np.maximum(scale, 1e-12)


def estimate_turn_period(turn_steps: tuple[int, ...] | list[int]) -> int | None:
    """Regular turning interval from the steps of observed deliberate turns: the greatest
    common divisor of the gaps between them (turns every P steps give gaps that are multiples
    of P). None with fewer than two turns."""
    if len(turn_steps) < 2:
        return None
    gaps = np.diff(np.asarray(turn_steps, dtype=np.int64))
    period = 0
    for g in gaps:
        period = math.gcd(period, int(g))
    return period or None


def turn_expected(next_step: int, turn_steps: tuple[int, ...], period: int | None) -> bool:
    """Whether the obstacle may turn in the move of ``next_step``: always when the period is
    unknown (conservative), else when ``next_step`` is a multiple of the period after the
    last observed turn."""
    if period is None or not turn_steps:
        return True
    return (next_step - turn_steps[-1]) % period == 0


@dataclass(frozen=True)
class ObstacleTrack:
    """What a predictor remembers about m moving obstacles between steps.

    displacement : (m, 2) the last observed step displacement (None before the first)
    linear_possible : (m,) whether the last linear prediction was geometrically possible (its
        footprint fitted the workspace); a direction change after an impossible prediction is
        a bounce, not a deliberate turn
    turn_steps : per obstacle, the steps whose move was a deliberate turn
    total_time, n_moves : per obstacle, time observed and number of steps in which it moved
        (the paper's arr[i] and arr[j]; dt' = total_time / n_moves)
    """

    displacement: FloatArray | None = None
    linear_possible: NDArray[np.bool_] | None = None
    turn_steps: tuple[tuple[int, ...], ...] = ()
    total_time: tuple[float, ...] = ()
    n_moves: tuple[int, ...] = ()

    def sampling_times(self, default: float) -> FloatArray:
        """dt' of every obstacle, shape (m,)."""
        return np.array([sampling_time(t, n, default) for t, n in zip(self.total_time, self.n_moves)], float)

    def periods(self) -> list[int | None]:
        """Estimated turning period of every obstacle (None while unknown)."""
        return [estimate_turn_period(s) for s in self.turn_steps]


def update_track(track: ObstacleTrack, step: int, previous: ArrayLike, current: ArrayLike,
                 dt: float) -> ObstacleTrack:
    """The track after observing the obstacles' move of ``step`` (previous -> current, both
    (m, 2)). Records a deliberate turn when the displacement changed although the last linear
    prediction was possible."""
    prev = np.asarray(previous, float).reshape(-1, 2)
    cur = np.asarray(current, float).reshape(-1, 2)
    m = len(cur)
    d = cur - prev
    moved = np.linalg.norm(d, axis=1) > 0
    if track.displacement is None or len(track.turn_steps) != m:
        turns = tuple(() for _ in range(m))
        return ObstacleTrack(d, np.ones(m, bool), turns, (float(dt),) * m, tuple(int(x) for x in moved))
    changed = displacement_changed(track.displacement, d)
    possible = track.linear_possible if track.linear_possible is not None else np.ones(m, bool)
    turns = tuple(t + (step,) if (changed[k] and possible[k]) else t for k, t in enumerate(track.turn_steps))
    total = tuple(float(t + dt) for t in track.total_time)
    n_moves = tuple(int(n + moved[k]) for k, n in enumerate(track.n_moves))
    return ObstacleTrack(d, possible, turns, total, n_moves)


def with_linear_possible(track: ObstacleTrack, possible: ArrayLike) -> ObstacleTrack:
    """The same track remembering whether this step's linear prediction is possible (m,)."""
    return ObstacleTrack(track.displacement, np.asarray(possible, bool).copy(), track.turn_steps,
                         track.total_time, track.n_moves)
