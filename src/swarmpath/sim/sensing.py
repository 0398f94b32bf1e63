"""What robots sense: nearby robots and moving obstacles with the distance classes of
Jaleel & Hassan 2016, Algorithms 2-3.

The paper's classes overlap ("D > 1 and D <= 3"); we make them disjoint and configurable:
short (0, 2], medium (2, 3], long (3, 4], very long (4, range] — in grid cells, multiplied
by the world's resolution. Objects beyond ``range`` are not sensed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

SHORT, MEDIUM, LONG, VERY_LONG = 0, 1, 2, 3
CLASS_NAMES = ("short", "medium", "long", "very long")


@dataclass(frozen=True)
class SensingConfig:
    """Upper bounds of the short, medium and long classes and the sensing range, in cells."""

    short: float = 2.0
    medium: float = 3.0
    long: float = 4.0
    range: float = 6.0

    def __post_init__(self) -> None:
        from swarmpath.errors import ConfigError

        if not (0 < self.short < self.medium < self.long <= self.range):
            raise ConfigError("sensing: need 0 < short < medium < long <= range, got "
                              f"{self.short}, {self.medium}, {self.long}, {self.range}")


@dataclass(frozen=True)
class Sensed:
    """Pairs within sensing range: ``robot_pairs`` (k, 2) with i < j, and ``obstacle_pairs``
    (k2, 2) of (robot, obstacle); distances between centres and their classes (0-3)."""

    robot_pairs: NDArray[np.int64]
    robot_distance: NDArray[np.float64]
    robot_class: NDArray[np.int8]
    obstacle_pairs: NDArray[np.int64]
    obstacle_distance: NDArray[np.float64]
    obstacle_class: NDArray[np.int8]


def classify(distance: NDArray[np.float64], config: SensingConfig, resolution: float) -> NDArray[np.int8]:
    """Distance class (0 short ... 3 very long) of each distance (world units)."""
    edges = np.array([config.short, config.medium, config.long]) * resolution
    return np.searchsorted(edges, distance, side="left").astype(np.int8)


def sense(robots: NDArray[np.float64], obstacles: NDArray[np.float64], config: SensingConfig,
          resolution: float) -> Sensed:
    """Everything within ``config.range`` cells of each robot (KD-tree queries, O(n log n))."""
    reach = config.range * resolution
    if len(robots) > 1:
        pairs = cKDTree(robots).query_pairs(reach, output_type="ndarray").astype(np.int64)
    else:
        pairs = np.zeros((0, 2), dtype=np.int64)
    d = np.linalg.norm(robots[pairs[:, 0]] - robots[pairs[:, 1]], axis=1) if len(pairs) else np.zeros(0)
    if len(obstacles) and len(robots):
        sparse = cKDTree(robots).sparse_distance_matrix(cKDTree(obstacles), reach, output_type="ndarray")
        opairs = np.stack([sparse["i"], sparse["j"]], axis=1).astype(np.int64)
        od = sparse["v"].astype(float)
        # sparse_distance_matrix drops exact zeros: a robot at an obstacle's centre must be sensed
        coincide = np.argwhere(np.all(np.isclose(robots[:, None], obstacles[None]), axis=-1))
        if len(coincide):
            opairs = np.concatenate([opairs, coincide.astype(np.int64)])
            od = np.concatenate([od, np.zeros(len(coincide))])
    else:
        opairs, od = np.zeros((0, 2), dtype=np.int64), np.zeros(0)
    return Sensed(pairs, d, classify(d, config, resolution), opairs, od, classify(od, config, resolution))
