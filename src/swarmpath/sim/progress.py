"""Whether robots still make progress: the simulator ends a run that stalled, and the run
summary counts the robots that stalled at the end."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def distinct_positions(window: NDArray[np.float64]) -> NDArray[np.int64]:
    """Number of distinct positions each robot took in ``window`` (shape (k, n, 2))."""
    keys = np.round(window * 1e6).astype(np.int64)
    keys = keys[..., 0] * 4_000_000_007 + keys[..., 1]
    keys.sort(axis=0)
    return 1 + np.count_nonzero(np.diff(keys, axis=0), axis=0)


class ProgressWatch:
    """Ends runs that stopped making progress, whatever the step budget.

    Progress means some robot that is not at its goal came closer to its goal (straight-line
    distance) than it had been since it last left its goal. When no robot has made progress
    for ``window`` steps the run has stalled (a livelock: robots wandering without getting
    anywhere, or waiting for a goal they cannot reach). The default window is the default
    step budget of the world, so within that budget the step budget ends a run first."""

    def __init__(self, goals: NDArray[np.float64], starts: NDArray[np.float64], window: int, tolerance: float):
        self.goals = goals
        self.window = window
        self.tolerance = tolerance
        self.best = np.linalg.norm(starts - goals, axis=1)
        self.last_progress = 0

    def update(self, step: int, positions: NDArray[np.float64]) -> bool:
        """Record the positions after ``step``; True when the run has stalled."""
        gap = np.linalg.norm(positions - self.goals, axis=1)
        at_goal = gap <= self.tolerance
        improved = ~at_goal & (gap < self.best - 1e-9)
        if improved.any() or at_goal.all():
            self.last_progress = step
        # at the goal the record restarts: a robot that steps off counts from where it is
        self.best = np.where(at_goal, np.inf, np.minimum(self.best, gap))
        return step - self.last_progress >= self.window


def unreachable_goals(world, radii: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Robots whose goal lies in another region of the free grid than their start (for the
    grid of each robot's radius; 4-connected regions, which is what 8-connected moves without
    corner cutting can reach). Such a robot can never arrive, whatever the controller does."""
    from scipy import ndimage

    out = np.zeros(world.n_robots, dtype=bool)
    for r in np.unique(radii):
        grid = world.grid(radius=float(r))
        labels, _ = ndimage.label(~grid.blocked)
        mine = np.flatnonzero(radii == r)
        h, w = labels.shape
        starts = np.clip(grid.cell_of(world.starts[mine]), 0, [w - 1, h - 1])
        goals = np.clip(grid.cell_of(world.goals[mine]), 0, [w - 1, h - 1])
        a = labels[starts[:, 1], starts[:, 0]]
        b = labels[goals[:, 1], goals[:, 0]]
        out[mine] = (a == 0) | (b == 0) | (a != b)
    return out
