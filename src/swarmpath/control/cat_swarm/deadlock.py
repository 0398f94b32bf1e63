"""Robots that stopped making progress: detected, handed to the core's ranking, reported.

The paper calls its cat swarm "deadlock free"; with robots choosing one after the other it is
not (two robots head-on in a one-cell corridor wait for each other forever). In ``cat-swarm``
the PIBT core resolves conflicts (priority inheritance, backtracking, the swap emulation);
this module only

1. **detects**: a robot that is not at its goal and has not improved its best remaining
   path length for ``patience`` steps is *stuck*, and stays *urgent* until it reaches its
   goal: it then ranks its candidates by exact distance first (:mod:`.ranking`), the ranking
   under which PIBT guarantees progress, instead of following the swarm's preference;
2. **reports**: a robot stuck for ``report_after`` steps gives a ``deadlock`` event, and a
   ``deadlock_resolved`` event once it moves on. A deadlock that stays is visible in the
   trajectory (the robot never reaches its goal) and is never counted as success.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.progress import progress_update

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

NOT_URGENT = np.iinfo(np.int64).max


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
