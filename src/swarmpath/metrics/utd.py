"""Performance measures of the PSO-prediction paper (2013, section 7): uncovered target
distance (UTD) per step, its average over runs (AUTD), average path deviation (APD) and the
number of steps the robots need to reach all their goals.

All functions are plain functions over arrays: positions of shape (n_steps + 1, n_robots, 2)
as recorded in a :class:`~swarmpath.sim.trajectory.Trajectory`.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.metrics.paths import arrival_steps, executed_lengths

FloatArray = NDArray[np.float64]


def uncovered_target_distance(positions: ArrayLike, goals: ArrayLike) -> FloatArray:
    """UTD(t) = sum_i ||G_i - C_i(t)|| (section 7) at every recorded step.

    positions : (n_steps + 1, n, 2); goals : (n, 2). Returns (n_steps + 1,).
    """
    p = np.asarray(positions, float)
    g = np.asarray(goals, float)
    if p.ndim != 3 or p.shape[1:] != g.shape:
        raise ValueError(f"positions {p.shape} do not fit goals {g.shape}")
    return np.linalg.norm(p - g[None], axis=2).sum(axis=1)


def pad_curves(curves: Sequence[ArrayLike], length: int | None = None) -> FloatArray:
    """Curves of different lengths as one array (k, length): each is extended with its last
    value (a finished run stays where it ended)."""
    arrays = [np.asarray(c, float).ravel() for c in curves]
    if not arrays:
        return np.zeros((0, length or 0))
    if any(len(a) == 0 for a in arrays):
        raise ValueError("empty curve")
    n = length if length is not None else max(len(a) for a in arrays)
    out = np.empty((len(arrays), n))
    for k, a in enumerate(arrays):
        m = min(len(a), n)
        out[k, :m] = a[:m]
        out[k, m:] = a[m - 1]
    return out


def average_uncovered_target_distance(curves: Sequence[ArrayLike], length: int | None = None) -> FloatArray:
    """AUTD(t): the mean of k runs' UTD curves (section 7, k = 10 in the paper); runs that
    ended early keep their final UTD. Returns (length,) (default: the longest run)."""
    padded = pad_curves(curves, length)
    if padded.shape[0] == 0:
        raise ValueError("no runs")
    return padded.mean(axis=0)


def path_deviation(positions_with: ArrayLike, positions_without: ArrayLike) -> FloatArray:
    """Per robot |D_traversed - (D_static + D_dynamic)| (section 7): the absolute difference
    between the length a robot travelled among the obstacles and the length it travelled in
    the same world without obstacles. Returns (n,)."""
    a = executed_lengths(positions_with)
    b = executed_lengths(positions_without)
    if a.shape != b.shape:
        raise ValueError(f"runs with {a.shape[0]} and {b.shape[0]} robots")
    return np.abs(a - b)


def average_path_deviation(runs_with: Sequence[ArrayLike], runs_without: Sequence[ArrayLike]) -> float:
    """APD: the path deviation summed over robots ("the sum of individual APD for separate
    robots"), averaged over paired runs (same seeds with and without obstacles)."""
    if len(runs_with) != len(runs_without) or not runs_with:
        raise ValueError("need the same positive number of runs with and without obstacles")
    return float(np.mean([path_deviation(a, b).sum() for a, b in zip(runs_with, runs_without)]))


def steps_to_reach_goals(positions: ArrayLike, goals: ArrayLike) -> int | None:
    """The step after which every robot stays at its goal (the makespan); None when some
    robot is not at its goal at the end."""
    steps = arrival_steps(positions, goals)
    if any(s is None for s in steps):
        return None
    return int(max(steps, default=0))
