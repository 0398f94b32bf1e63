"""Sensing: what every robot perceives of the others and of the moving obstacles this step,
as :class:`~swarmpath.control.observation.Sensed` pairs with distance classes."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.control.observation import Sensed, SensingConfig, classify


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
