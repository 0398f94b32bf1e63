"""Progress toward the goal: how many steps since each robot last came closer to it.

Used by ``cat-swarm``'s deadlock detector and by the detours of both grid controllers
(:mod:`swarmpath.control.detour`).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


def progress_update(best: FloatArray, since: IntArray, remaining: FloatArray, at_goal: BoolArray,
                    tolerance: float = 1e-6) -> tuple[FloatArray, IntArray]:
    """New (best remaining length so far, steps since it last improved) per robot (n,).
    At the goal both reset (best to infinity), so a robot that steps off its goal to let
    others or an obstacle pass starts counting afresh from where it is."""
    improved = remaining < best - tolerance
    best = np.where(at_goal, np.inf, np.where(improved, remaining, best))
    since = np.where(improved | at_goal, 0, since + 1)
    return best, since
