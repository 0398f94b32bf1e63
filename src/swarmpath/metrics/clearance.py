"""Minimum clearance of a run: the smallest free distance between a robot and anything else."""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree


def min_clearance(world, positions: np.ndarray, obstacle_positions: np.ndarray) -> float:
    """Smallest surface-to-surface distance, over all recorded steps, between a robot and a
    static obstacle or the boundary, another robot, or a moving obstacle (world units; a
    moving obstacle counts as the disc that covers its footprint). Negative means overlap."""
    radii = world.radii
    n = positions.shape[1]
    if n == 0:
        return float("inf")
    flat = positions.reshape(-1, 2)
    unique, inverse = np.unique(np.round(flat, 9), axis=0, return_inverse=True)
    rr = np.tile(radii, positions.shape[0])
    # Static clearance: computed once per distinct position, then per (position, radius).
    static_free = world.static_clearance(unique)[inverse.ravel()] - rr
    best = float(static_free.min())
    extents = np.array([o.extent for o in world.moving_obstacles])
    for t in range(positions.shape[0]):
        p = positions[t]
        if n > 1:
            pairs = cKDTree(p).query_pairs(2 * world.resolution + 2 * float(radii.max()) + 1e-9, output_type="ndarray")
            if len(pairs):
                d = np.linalg.norm(p[pairs[:, 0]] - p[pairs[:, 1]], axis=1) - radii[pairs[:, 0]] - radii[pairs[:, 1]]
                best = min(best, float(d.min()))
        if len(extents):
            d = np.linalg.norm(p[:, None] - obstacle_positions[t][None], axis=2) - radii[:, None] - extents[None]
            best = min(best, float(d.min()))
    return best
