"""What a controller sees at each step."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.sim.sensing import Sensed

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Observation:
    """The state a controller acts on at ``step``.

    positions, goals : (n, 2) robots' current positions and goals (world units)
    at_goal : (n,) whether each robot is at its goal
    obstacle_positions : (m, 2) moving obstacles after their move of this step
    obstacle_previous : (m, 2) the same one step earlier (two samples give a velocity)
    sensed : nearby robots and obstacles with distance classes
    """

    step: int
    dt: float
    positions: FloatArray
    goals: FloatArray
    at_goal: NDArray[np.bool_]
    obstacle_positions: FloatArray
    obstacle_previous: FloatArray
    sensed: Sensed

    @property
    def n_robots(self) -> int:
        return int(self.positions.shape[0])
