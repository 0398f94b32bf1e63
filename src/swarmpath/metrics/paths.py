"""Path and time measures of a run (plain functions over arrays and trajectories)."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.sim.stepper import GOAL_TOLERANCE


def path_length(points: ArrayLike) -> float:
    """Euclidean length of a polyline of shape (n_points, 2)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) if len(p) > 1 else 0.0


def executed_lengths(positions: ArrayLike) -> NDArray[np.float64]:
    """Length travelled by each robot: positions of shape (n_steps + 1, n, 2) -> (n,)."""
    p = np.asarray(positions, dtype=float)
    if p.shape[0] < 2:
        return np.zeros(p.shape[1])
    return np.linalg.norm(np.diff(p, axis=0), axis=2).sum(axis=0)


def at_goal(positions: ArrayLike, goals: ArrayLike) -> NDArray[np.bool_]:
    """(n_steps + 1, n) whether each robot is at its goal at each step."""
    return np.linalg.norm(np.asarray(positions) - np.asarray(goals)[None], axis=2) <= GOAL_TOLERANCE


def arrival_steps(positions: ArrayLike, goals: ArrayLike) -> list[int | None]:
    """For each robot, the step after which it stays at its goal (None if it is not there at
    the end). A robot that starts at its goal and never leaves arrives at step 0."""
    ok = at_goal(positions, goals)
    out: list[int | None] = []
    for i in range(ok.shape[1]):
        col = ok[:, i]
        if not col[-1]:
            out.append(None)
            continue
        away = np.flatnonzero(~col)
        out.append(int(away[-1] + 1) if len(away) else 0)
    return out


def waiting_steps(positions: ArrayLike, goals: ArrayLike) -> NDArray[np.int64]:
    """Steps in which each robot stood still while not at its goal."""
    p = np.asarray(positions, dtype=float)
    if p.shape[0] < 2:
        return np.zeros(p.shape[1], dtype=np.int64)
    still = np.all(p[1:] == p[:-1], axis=2)
    away = ~at_goal(p[:-1], goals)
    return np.count_nonzero(still & away, axis=0).astype(np.int64)


def first_arrival_steps(positions: ArrayLike, goals: ArrayLike) -> list[int | None]:
    """For each robot, the first step at which it stood on its goal (None if never). Among
    moving obstacles a robot may have to step off its goal again; this says it got there."""
    ok = at_goal(positions, goals)
    return [int(np.argmax(col)) if col.any() else None for col in ok.T]
