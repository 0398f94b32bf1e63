"""Finishing together: the step on which every robot stands on its goal at once.

A run succeeds at the end of the first step on which every robot stands on its goal (the
simulator stops there, status ``all_reached``). Among moving obstacles that never stop, a
cautious robot does not stand on a goal that an obstacle may enter next step: it waits beside
it, and some goal is nearly always under such a threat, so the robots are rarely all home at
the same moment.

The last step of a run can be checked exactly, because in a step the obstacles move first and
then stand still while the robots move (the checker's phase 2): when every robot that is not
home can step straight onto its goal in this step, and those moves touch no static obstacle,
no obstacle where it now stands, and no other robot by :mod:`swarmpath.world.move_rules`,
the robots all step home and the run ends with zero contacts. The moves the obstacles may make
after the run are not part of it: a controller that must keep robots on their goals for ever
after (rather than deliver them) should leave this off.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.control.base import Decision
from swarmpath.control.observation import Observation
from swarmpath.world.move_rules import NO_CONFLICT, footprint_hits, move_conflicts
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]


def finish_positions(world: World, obs: Observation) -> FloatArray | None:
    """Every robot's goal (n, 2) when all robots can end this step on their goals without any
    contact of the robots' move (phase 2 of the step, the simulator's own rules); else None.

    The move of each robot must be within its reach (``max_speed * dt``), touch no static
    obstacle or the workspace's edge, enter no moving obstacle's footprint where it stands now
    (``obs.obstacle_positions``), and conflict with no other robot's move.
    """
    pos = obs.positions
    goals = world.goals
    n = len(pos)
    if n == 0:
        return None
    step = goals - pos
    length = np.linalg.norm(step, axis=1)
    if np.any(length > world.max_speeds * world.dt):
        return None
    moving = np.flatnonzero(length > 0)
    if not len(moving):
        return None
    radii = world.radii
    if world.static_hits(pos[moving], goals[moving], radii[moving]).any():
        return None
    for k, ob in enumerate(world.moving_obstacles):
        centre = obs.obstacle_positions[k]
        near = np.flatnonzero(np.linalg.norm(goals[moving] - centre, axis=1)
                              <= ob.extent + radii[moving] + length[moving] + 1e-9)
        if len(near):
            rows = moving[near]
            if footprint_hits(ob.placed((0.0, 0.0)), pos[rows] - centre, goals[rows] - centre, radii[rows]).any():
                return None
    if n > 1:
        reach = 2 * float(length.max()) + 2 * float(radii.max(initial=0.0)) + 2 * world.resolution
        pairs = cKDTree(pos).query_pairs(reach, output_type="ndarray")
        if len(pairs):
            i, j = pairs[:, 0], pairs[:, 1]
            kinds = move_conflicts(pos[i], goals[i], pos[j], goals[j], radii[i], radii[j], world.resolution)
            if np.any(kinds != NO_CONFLICT):
                return None
    return goals.copy()


def finishing_step(world: World, obs: Observation) -> Decision | None:
    """The Decision of the finishing step (every robot to its goal, an event naming how many
    robots stepped home together) when :func:`finish_positions` allows it this step; else
    None and the controller acts as usual."""
    home = finish_positions(world, obs)
    if home is None:
        return None
    moved = int(np.count_nonzero(np.any(home != obs.positions, axis=1)))
    return Decision(home, ["arrived"] * len(home),
                    [{"robot": -1, "kind": "finish_together", "detail": f"{moved} robots stepped onto their goals"}])
