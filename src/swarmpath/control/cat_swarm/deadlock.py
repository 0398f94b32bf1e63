"""Deadlock handling for grid controllers: detect robots that stopped making progress and
resolve it by priority, yielding and backing off.

The paper calls its cat swarm "deadlock free"; it is not in general (two robots head-on in a
one-cell corridor wait for each other forever, and a robot parked on its goal in a corridor
blocks everyone behind it). We therefore

1. **detect**: a robot that is not at its goal and has not improved its best remaining
   path length for ``patience`` steps is *stuck*;
2. **resolve**: a stuck robot becomes *urgent* and stays urgent until it reaches its goal.
   Urgent robots act before everyone else, the one stuck first going first (a fixed order,
   so two urgent robots cannot keep undoing each other), and they may *push*: a robot in
   the cell an urgent robot wants must yield — it moves to its own best free neighbour,
   backing off if that is the only way, and may push in turn (priority inheritance, as in
   PIBT, Okumura et al. 2022). Robots that are not urgent never push; they may only *ask*
   a robot in their way to move first along its own preferred direction;
3. **report**: a robot stuck for ``report_after`` steps gives a ``deadlock`` event, and a
   ``deadlock_resolved`` event once it moves on. A deadlock that stays is visible in the
   trajectory (the robot never reaches its goal) and is never counted as success.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

NOT_URGENT = np.iinfo(np.int64).max


def progress_update(best: FloatArray, since: IntArray, remaining: FloatArray, at_goal: BoolArray,
                    tolerance: float = 1e-6) -> tuple[FloatArray, IntArray]:
    """New (best remaining length so far, steps since it last improved) per robot (n,).
    At the goal both reset (best to infinity), so a robot that steps off its goal to let
    others or an obstacle pass starts counting afresh from where it is."""
    improved = remaining < best - tolerance
    best = np.where(at_goal, np.inf, np.where(improved, remaining, best))
    since = np.where(improved | at_goal, 0, since + 1)
    return best, since


def priority_order(urgent_since: IntArray, danger: BoolArray, threatened: BoolArray, options: IntArray,
                   active: BoolArray, remaining: FloatArray, tiebreak: FloatArray) -> IntArray:
    """Robot indices from first to act to last: robots that must leave their cell before a
    moving obstacle arrives, then robots that should (both with the fewest safe options
    first), then urgent robots (stuck earliest first), then robots still travelling (longest
    remaining path first, as the mixture split favours them), then parked robots;
    ``tiebreak`` (random keys) orders the rest."""
    rem = np.where(np.isfinite(remaining), remaining, -1.0)
    level = np.where(danger, 0, np.where(threatened, 1, 2))
    opts = np.where(level < 2, options, 0)
    return np.lexsort((tiebreak, -rem, ~active, urgent_since, opts, level))


@dataclass
class DeadlockMonitor:
    """Per-run state of the detector (created by the controller's ``reset``)."""

    patience: int
    report_after: int
    best: FloatArray
    since: IntArray
    urgent_since: IntArray
    reported: BoolArray

    @classmethod
    def start(cls, n_robots: int, *, patience: int, report_after: int) -> DeadlockMonitor:
        return cls(patience, report_after, np.full(n_robots, np.inf), np.zeros(n_robots, np.int64),
                   np.full(n_robots, NOT_URGENT, np.int64), np.zeros(n_robots, bool))

    def update(self, step: int, remaining: FloatArray, at_goal: BoolArray) -> list[dict]:
        """Record this step's remaining lengths; returns deadlock events."""
        self.best, self.since = progress_update(self.best, self.since, remaining, at_goal)
        events: list[dict] = []
        newly = (self.since >= self.patience) & (self.urgent_since == NOT_URGENT) & ~at_goal
        self.urgent_since[newly] = step
        self.urgent_since[at_goal] = NOT_URGENT
        for i in np.flatnonzero(~self.reported & (self.since >= self.report_after) & ~at_goal):
            events.append({"robot": int(i), "kind": "deadlock",
                           "detail": f"no progress for {int(self.since[i])} steps"})
            self.reported[i] = True
        for i in np.flatnonzero(self.reported & ((self.since == 0) | at_goal)):
            events.append({"robot": int(i), "kind": "deadlock_resolved", "detail": "moving on"})
            self.reported[i] = False
        return events

    @property
    def urgent(self) -> BoolArray:
        return self.urgent_since != NOT_URGENT
