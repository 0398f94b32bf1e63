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
from scipy.spatial import cKDTree

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.control.orca.core import ORCAParams, ORCASolver, tidy_moves
from swarmpath.control.orca.guidance import Guidance
from swarmpath.control.orca.obstacles import forecast_obstacles
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.world.world import World

#: Distance (world units) within which a chosen end position is snapped onto the goal.
GOAL_SNAP = 1e-6


def rotate(v: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Vectors (n, 2) turned counter-clockwise by ``angle`` (n,) radians."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=1)


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
        if not 0 <= side_bias < np.pi / 2:
            raise ConfigError(f"side_bias must be in [0, pi/2) radians, got {side_bias}")
        if patience < 1:
            raise ConfigError(f"patience must be >= 1, got {patience}")
        self.side_bias = side_bias
        if yield_after < 0:
            raise ConfigError(f"yield_after must be >= 0 (0 = off), got {yield_after}")
        self.yield_after = yield_after
        self.patience = patience
        self.guidance = guidance or Guidance(clearance=safety_margin)

    # -------------------------------------------------------------- run state
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self.world_ = world
        self.solver_ = ORCASolver(self.params)
        self.solver_.reset(world)
        self.guidance.reset(world, plan)
        n = world.n_robots
        self.previous_ = world.starts.copy()
        self.constrained_ = np.zeros(n, bool)
        # each robot's turn: side_bias times a factor in [0.5, 1.5) spread by the golden ratio,
        # so that no two neighbours in a symmetric crowd turn alike
        self.bias_ = self.side_bias * (0.5 + np.mod(np.arange(n) * 0.6180339887498949, 1.0))
        self.best_ = self.guidance.remaining(world.starts) if n else np.zeros(0)
        self.since_ = np.zeros(n, np.int64)
        self.reported_ = np.zeros(n, bool)

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
        if self.side_bias > 0:
            pref = np.where(self.constrained_[:, None], rotate(pref, -self.bias_), pref)
        pref = self._yield(pos, pref)
        forecast = None
        if len(world.moving_obstacles):
            forecast = forecast_obstacles(world, obs.obstacle_positions, obs.obstacle_previous, obs.step, dt)
        v, status = solver.velocities(pos, vel, pref, forecast)
        p1 = tidy_moves(pos, pos + v * dt, obs.goals, solver.step_len, GOAL_SNAP)
        safe = solver.make_safe(pos, p1, forecast)
        final = safe.positions
        speeds = np.maximum(solver.speeds, 1e-12)
        self.constrained_ = (np.linalg.norm(v - pref, axis=1) > 0.05 * speeds) | (safe.scale < 1.0)
        self.previous_ = pos.copy()
        events = self._progress(obs.step, final)
        for i in np.flatnonzero(safe.exposed):
            events.append({"robot": int(i), "kind": "exposed",
                           "detail": "no move keeps clear of a moving obstacle's next step"})
        at_goal = np.linalg.norm(final - obs.goals, axis=1) <= 1e-9
        moved = np.any(final != pos, axis=1)
        avoiding = (status > 0) | (safe.scale < 1.0)
        modes = ["arrived" if at_goal[i] else ("wait" if not moved[i] else ("avoid" if avoiding[i] else "seek"))
                 for i in range(n)]
        return Decision(final, modes, tuple(events))

    def _yield(self, pos: np.ndarray, pref: np.ndarray) -> np.ndarray:
        """Deadlock breaking by priority: among robots stalled for ``yield_after`` steps,
        one within reach of a stalled robot of smaller index backs away from it at full
        speed (until that robot makes progress again), so the robot of highest priority in
        every jam gets room; the order is fixed, so two robots never undo each other. A robot
        that has reached its goal ranks below every stalled robot: parked in a door or a
        corridor, it backs away from a stalled robot near it, and returns afterwards."""
        if self.yield_after == 0:
            return pref
        stalled = (self.since_ >= self.yield_after) & (self.best_ > 1e-9)
        if not stalled.any():
            return pref
        parked = self.best_ <= 1e-9
        group = np.flatnonzero(stalled | parked)
        if len(group) < 2:
            return pref
        solver = self.solver_
        reach = 2 * float(solver.radii.max()) + 2 * float(solver.step_len.max()) + solver.params.safety_margin \
            + (np.sqrt(2.0) * solver.resolution if solver.points.any() else 0.0)
        pairs = cKDTree(pos[group]).query_pairs(reach, output_type="ndarray")
        if not len(pairs):
            return pref
        a, b = group[pairs[:, 0]], group[pairs[:, 1]]
        keep = stalled[a] | stalled[b]                        # two parked robots leave each other be
        a, b = a[keep], b[keep]
        # the parked one yields to the stalled one; of two stalled, the larger index yields
        b_yields = parked[b] | (stalled[a] & stalled[b])
        lo = np.where(b_yields, b, a)
        hi = np.where(b_yields, a, b)
        away = pos[lo] - pos[hi]
        away /= np.maximum(np.linalg.norm(away, axis=1), 1e-12)[:, None]
        push = np.zeros_like(pref)
        np.add.at(push, lo, away)
        norm = np.linalg.norm(push, axis=1)
        yielding = norm > 1e-9
        out = pref.copy()
        out[yielding] = push[yielding] / norm[yielding, None] * solver.speeds[yielding, None]
        return out

    def _progress(self, step: int, pos: np.ndarray) -> list[dict]:
        """Deadlock events: a robot not at its goal whose remaining path did not shrink by a
        tenth of a step's travel for ``patience`` steps is reported once, and again when it
        makes progress."""
        remaining = self.guidance.remaining(pos)
        better = remaining < self.best_ - 0.1 * self.solver_.step_len
        arrived = remaining <= 1e-9
        self.best_ = np.where(better | arrived, remaining, self.best_)
        self.since_ = np.where(better | arrived, 0, self.since_ + 1)
        events = []
        for i in np.flatnonzero((self.since_ >= self.patience) & ~self.reported_):
            events.append({"robot": int(i), "kind": "deadlock",
                           "detail": f"no progress for {self.patience} steps"})
            self.reported_[i] = True
        for i in np.flatnonzero(self.reported_ & (self.since_ == 0)):
            events.append({"robot": int(i), "kind": "deadlock_resolved"})
            self.reported_[i] = False
        return events
