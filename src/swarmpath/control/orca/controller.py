"""The ``orca`` controller: Optimal Reciprocal Collision Avoidance (van den Berg, Guy, Lin &
Manocha, ISRR 2011) for disc robots in continuous space, with static geometry, moving
obstacles and the simulator's discrete steps handled as described in docs/algorithms/orca.md.

Each step: (1) :class:`~swarmpath.control.orca.guidance.Guidance` gives a preferred
velocity along the offline plan or the goal's distance field; a robot whose velocity was
constrained last step turns it by ``side_bias`` to its right (a consistent side preference
breaks symmetric deadlocks such as head-on pairs and the antipodal circle, deterministically);
(2) :class:`~swarmpath.control.orca.core.ORCASolver` builds every robot's half-planes and
solves the 2-D/3-D linear programs; (3) the resulting straight move of one step is checked
exactly (static geometry, moving footprints, every pair of robots by the simulator's move
rules) and shortened, down to standing still, where it fails; (4) a robot that made no
progress for ``patience`` steps is reported with a ``deadlock`` event (and
``deadlock_resolved`` when it moves on).
"""
from __future__ import annotations

import numpy as np

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.control.orca.coordination import Coordination
from swarmpath.control.orca.core import ORCAParams, ORCASolver, tidy_moves
from swarmpath.control.orca.guidance import Guidance
from swarmpath.control.orca.obstacles import forecast_obstacles
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.world.world import World

#: Distance (world units) within which a chosen end position is snapped onto the goal.
GOAL_SNAP = 1e-6


@register_controller("orca")
class ORCAController(Controller):
    """ORCA with guidance along plans or distance fields and an exact per-step safety check.

    Parameters (hyperparameters only; run state is created in ``reset``)
    ----------
    time_horizon : tau of robot-robot and moving-obstacle lines (time units)
    obstacle_time_horizon : tau of static-obstacle lines (time units; at least one step)
    neighbour_distance : robots farther apart are ignored (world units)
    max_neighbours : at most this many nearest robots constrain a robot
    safety_margin : added to every contact distance (world units)
    obstacle_margin : extra room asked of moving obstacles in ORCA's (soft) lines (world units)
    side_bias : turn (radians, clockwise) of the preferred velocity of a robot that was
        constrained last step (0 = off)
    yield_after : steps without progress after which a robot backs away from a stalled robot
        of smaller index nearby (priority deadlock breaking; 0 = off)
    patience : steps without progress before a ``deadlock`` event
    guidance : the :class:`Guidance` (window, lookahead, clearance)
    """

    capabilities = Capabilities(continuous=True, moving_obstacles=True, multi_robot=True)

    def __init__(self, *, time_horizon: float = 4.0, obstacle_time_horizon: float = 2.0,
                 neighbour_distance: float = 8.0, max_neighbours: int = 10, safety_margin: float = 0.02,
                 obstacle_margin: float = 0.0, side_bias: float = 0.15, yield_after: int = 8, patience: int = 40,
                 guidance: Guidance | None = None):
        self.params = ORCAParams(time_horizon, obstacle_time_horizon, neighbour_distance, max_neighbours,
                                 safety_margin, obstacle_margin)
        # validates side_bias, yield_after and patience
        Coordination(side_bias=side_bias, yield_after=yield_after, patience=patience, margin=safety_margin)
        self.side_bias = side_bias
        self.yield_after = yield_after
        self.patience = patience
        self.guidance = guidance or Guidance(clearance=safety_margin)

    # -------------------------------------------------------------- run state
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self.world_ = world
        self.solver_ = ORCASolver(self.params)
        self.solver_.reset(world)
        self.guidance.reset(world, plan)
        self.previous_ = world.starts.copy()
        self.coordination_ = Coordination(side_bias=self.side_bias, yield_after=self.yield_after,
                                          patience=self.patience, margin=self.params.safety_margin)
        self.coordination_.reset(world, self.guidance)

    def act(self, obs: Observation) -> Decision:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        if n == 0:
            return Decision(pos.copy(), [])
        world = self.world_
        dt = float(obs.dt)
        solver = self.solver_
        vel = (pos - self.previous_) / dt
        pref = self.guidance.preferred_velocities(pos, solver.speeds, dt)
        pref = self.coordination_.preferred(pos, pref)
        forecast = None
        if len(world.moving_obstacles):
            forecast = forecast_obstacles(world, obs.obstacle_positions, obs.obstacle_previous, obs.step, dt)
        v, status = solver.velocities(pos, vel, pref, forecast)
        p1 = tidy_moves(pos, pos + v * dt, obs.goals, solver.step_len, GOAL_SNAP)
        safe = solver.make_safe(pos, p1, forecast)
        final = safe.positions
        speeds = np.maximum(solver.speeds, 1e-12)
        constrained = (np.linalg.norm(v - pref, axis=1) > 0.05 * speeds) | (safe.scale < 1.0)
        self.previous_ = pos.copy()
        events = self.coordination_.record(obs.step, final, constrained)
        for i in np.flatnonzero(safe.exposed):
            events.append({"robot": int(i), "kind": "exposed",
                           "detail": "no move keeps clear of a moving obstacle's next step"})
        at_goal = np.linalg.norm(final - obs.goals, axis=1) <= 1e-9
        moved = np.any(final != pos, axis=1)
        avoiding = (status > 0) | (safe.scale < 1.0)
        modes = ["arrived" if at_goal[i] else ("wait" if not moved[i] else ("avoid" if avoiding[i] else "seek"))
                 for i in range(n)]
        return Decision(final, modes, tuple(events))
