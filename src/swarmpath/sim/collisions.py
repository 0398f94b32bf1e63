"""The independent collision checker: decides, from geometry alone, whether a step collided.

A step has two phases. First the moving obstacles move (robots stand still): an obstacle
that sweeps over a robot collides with it. Then the robots move in straight lines, all at
once, among the obstacles' new positions. Contacts are:

- robot-robot: discs that come closer than the sum of their radii at any time of the step;
  point robots (radius 0) occupy grid cells and also collide when they end in the same cell,
  swap cells, or pass through the same point at the same time (crossing diagonals);
- robot-static: a move that enters a static obstacle or leaves the workspace (for point
  robots on raster maps, touching a blocked cell's square, i.e. corner cutting, counts);
- robot-moving: a robot inside an obstacle's footprint at any time of either phase.

Touching without overlap is not a collision. Nothing here trusts a controller or a planner.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.world import geometry as g
from swarmpath.world.move_rules import KIND_NAMES, footprint_hits, move_conflicts

FloatArray = NDArray[np.float64]

ROBOT_ROBOT, ROBOT_STATIC, ROBOT_MOVING = "robot_robot", "robot_static", "robot_moving"


@dataclass(frozen=True)
class Contact:
    """One collision: at ``step`` (the step that moved from positions[step-1] to
    positions[step]), between robot ``robot`` and ``other`` (a robot or obstacle index; -1 for
    static obstacles and the boundary)."""

    step: int
    kind: str
    robot: int
    other: int
    detail: str

    def to_dict(self) -> dict:
        return {"step": self.step, "kind": self.kind, "robot": self.robot, "other": self.other,
                "detail": self.detail}


def robot_robot_contacts(p0: FloatArray, p1: FloatArray, radii: FloatArray, resolution: float
                         ) -> list[tuple[int, int, str]]:
    """Robot pairs (i < j) that collide while moving from ``p0`` to ``p1`` (both (n, 2)), by
    the move rules of :mod:`swarmpath.world.move_rules`, with the kind of each contact."""
    n = len(p0)
    if n < 2:
        return []
    step_len = np.linalg.norm(p1 - p0, axis=1)
    reach = 2 * float(step_len.max(initial=0.0)) + 2 * float(radii.max(initial=0.0)) + 2 * resolution
    pairs = cKDTree(p0).query_pairs(reach, output_type="ndarray")
    if len(pairs) == 0:
        return []
    i, j = pairs[:, 0], pairs[:, 1]
    kind = move_conflicts(p0[i], p1[i], p0[j], p1[j], radii[i], radii[j], resolution)
    return sorted((int(i[k]), int(j[k]), KIND_NAMES[kind[k]]) for k in np.flatnonzero(kind))


def robot_static_contacts(world, p0: FloatArray, p1: FloatArray, radii: FloatArray) -> list[tuple[int, str]]:
    """Robots whose move enters a static obstacle or leaves the workspace."""
    moved = np.flatnonzero(np.any(p0 != p1, axis=1))
    if len(moved) == 0:
        return []
    hits = moved[world.static_hits(p0[moved], p1[moved], radii[moved])]
    if len(hits) == 0:
        return []
    inside = world.bounds.contains(p1[hits], radii[hits])
    return [(int(i), "obstacle" if ok else "boundary") for i, ok in zip(hits.tolist(), inside.tolist())]


def robot_moving_contacts(world, robots_before: FloatArray, robots_after: FloatArray, obstacles_before: FloatArray,
                          obstacles_after: FloatArray, radii: FloatArray) -> list[tuple[int, int, str]]:
    """Robot-obstacle collisions of both phases of a step: (robot, obstacle, detail)."""
    out = []
    obstacles = world.moving_obstacles
    # Phase 1: the obstacle sweeps o0 -> o1 over robots standing at robots_before. An obstacle
    # whose motion teleports (redraw) does not travel: it reappears at o1, so only o1 is checked.
    jumps = np.array([ob.motion.teleports for ob in obstacles], dtype=bool)
    starts = np.where(jumps[:, None], obstacles_after, obstacles_before)
    reach = np.array([ob.extent for ob in obstacles], float) + float(radii.max(initial=0.0)) + g.EPS
    # Which robots come near which obstacle (shape (n_robots, n_obstacles)), for all at once.
    d1 = g.point_segment_distance(robots_before[:, None, :], starts[None], obstacles_after[None])
    d2 = g.point_segment_distance(obstacles_after[None], robots_before[:, None, :], robots_after[:, None, :])
    close1, close2 = d1 < reach, d2 < reach
    for j in np.flatnonzero(close1.any(axis=0) | close2.any(axis=0)):
        shape = obstacles[j].placed((0.0, 0.0))
        o0, o1 = starts[j], obstacles_after[j]
        near1 = np.flatnonzero(close1[:, j])
        if len(near1):
            rel0 = robots_before[near1] - o0
            rel1 = robots_before[near1] - o1
            hit = footprint_hits(shape, rel0, rel1, radii[near1])
            out.extend((int(i), int(j), "obstacle moved into robot") for i in near1[hit])
        # Phase 2: robots move among the obstacle standing at o1.
        near2 = np.flatnonzero(close2[:, j])
        if len(near2):
            hit = footprint_hits(shape, robots_before[near2] - o1, robots_after[near2] - o1, radii[near2])
            out.extend((int(i), int(j), "robot moved into obstacle") for i in near2[hit])
    # one contact per (robot, obstacle) and step
    seen: dict[tuple[int, int], str] = {}
    for i, j, detail in out:
        seen.setdefault((i, j), detail)
    return sorted((i, j, d) for (i, j), d in seen.items())


def step_contacts(world, step: int, robots_before: FloatArray, robots_after: FloatArray,
                  obstacles_before: FloatArray, obstacles_after: FloatArray) -> list[Contact]:
    """Every contact of one step, all kinds."""
    radii = world.radii
    out = [Contact(step, ROBOT_ROBOT, i, j, d)
           for i, j, d in robot_robot_contacts(robots_before, robots_after, radii, world.resolution)]
    out += [Contact(step, ROBOT_STATIC, i, -1, d)
            for i, d in robot_static_contacts(world, robots_before, robots_after, radii)]
    if len(world.moving_obstacles):
        out += [Contact(step, ROBOT_MOVING, i, j, d)
                for i, j, d in robot_moving_contacts(world, robots_before, robots_after, obstacles_before,
                                                     obstacles_after, radii)]
    return out
