"""What a controller receives at every step: the :class:`Observation`.

It lives here, beside the controllers that read it, so that the contract of ``act()`` is
typed in the controllers' own layer; the simulator (above) fills it in. The sensing part,
:class:`Sensed`, carries the distance classes of Jaleel & Hassan 2016 (Algorithms 2-3):
the paper's classes overlap ("D > 1 and D <= 3"); we make them disjoint and configurable
with :class:`SensingConfig`: short (0, 2], medium (2, 3], long (3, 4], very long (4, range],
in grid cells, multiplied by the world's resolution. Objects beyond ``range`` are not sensed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import ConfigError

FloatArray = NDArray[np.float64]

#: Distance classes (indices into :data:`CLASS_NAMES`).
SHORT, MEDIUM, LONG, VERY_LONG = 0, 1, 2, 3
CLASS_NAMES = ("short", "medium", "long", "very long")
#: Class index by name, for controllers configured with a class name.
CLASS_INDEX = {name: k for k, name in enumerate(CLASS_NAMES)}


@dataclass(frozen=True)
class SensingConfig:
    """Upper bounds of the short, medium and long classes and the sensing range, in cells."""

    short: float = 2.0
    medium: float = 3.0
    long: float = 4.0
    range: float = 6.0

    def __post_init__(self) -> None:
        if not (0 < self.short < self.medium < self.long <= self.range):
            raise ConfigError("sensing: need 0 < short < medium < long <= range, got "
                              f"{self.short}, {self.medium}, {self.long}, {self.range}")


def classify(distance: FloatArray, config: SensingConfig, resolution: float) -> NDArray[np.int8]:
    """Distance class (0 short ... 3 very long) of each distance (world units)."""
    edges = np.array([config.short, config.medium, config.long]) * resolution
    return np.searchsorted(edges, distance, side="left").astype(np.int8)


@dataclass(frozen=True)
class Sensed:
    """Pairs within sensing range: ``robot_pairs`` (k, 2) with i < j, and ``obstacle_pairs``
    (k2, 2) of (robot, obstacle); distances between centres and their classes (0-3)."""

    robot_pairs: NDArray[np.int64]
    robot_distance: FloatArray
    robot_class: NDArray[np.int8]
    obstacle_pairs: NDArray[np.int64]
    obstacle_distance: FloatArray
    obstacle_class: NDArray[np.int8]


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
