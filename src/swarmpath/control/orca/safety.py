"""A safety layer for any continuous controller: it takes the next position each robot's
controller proposes and returns the closest safe one.

"Closest safe" is ORCA's answer (eq. (7) of van den Berg et al., ISRR 2011) with the
proposal as the preferred velocity: the permitted velocity nearest to it under every
robot-robot, moving-obstacle and static half-plane, then the exact one-step check of
:meth:`~swarmpath.control.orca.core.ORCASolver.make_safe` (shortening the move, down to
standing still, where the simulator's rules would still see a contact). A proposal that is
already permitted comes back unchanged, bit for bit. The layer never moves a robot outside
the workspace or through a wall: static lines are hard and the exact check re-tests every
move against the world's geometry.

Usage in a controller::

    def reset(self, world, plan, rng):
        self.safety_ = SafetyLayer()          # or SafetyLayer(safety_margin=0.05, ...)
        self.safety_.reset(world)

    def act(self, obs):
        proposed = ...                        # (n, 2) this controller's choice
        positions, adjusted = self.safety_.safe_positions(obs, proposed)
        return Decision(positions, events=self.safety_.events(adjusted))
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.observation import Observation
from swarmpath.control.orca.core import ORCAParams, ORCASolver, tidy_moves
from swarmpath.control.orca.obstacles import ObstacleForecast, forecast_obstacles
from swarmpath.errors import ConfigError
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


#: How the layer sees moving obstacles: their forecast next moves, or standing where they are.
OBSTACLE_VIEWS = ("forecast", "standing")


def standing_forecast(now: FloatArray, extent: FloatArray) -> ObstacleForecast:
    """The forecast of obstacles taken to stand where they are now (m, 2): no next move, no
    reach, no velocity, nothing jumps. What a controller without prediction assumes."""
    now = np.asarray(now, float).reshape(-1, 2)
    zero = np.zeros(len(now))
    return ObstacleForecast(now, now.copy(), zero, np.zeros_like(now), np.asarray(extent, float), zero.astype(bool),
                            now.copy(), zero.copy())


class SafetyLayer:
    """ORCA as a filter in front of proposed moves (hyperparameters as in
    :class:`~swarmpath.control.orca.core.ORCAParams`).

    ``obstacles`` says how moving obstacles are seen: ``"forecast"`` (their worst-case next
    moves per motion model, redraw jumps included: the layer then avoids them) or
    ``"standing"`` (where they are now, the view of a controller without prediction: the
    layer then keeps robots off walls, the workspace's edge, each other and the obstacles'
    current footprints, but an obstacle can still run a robot over).

    Run state (set by :meth:`reset`, updated by :meth:`safe_positions`): ``previous_``
    positions (for the robots' current velocities), and of the last call ``status_`` (LP
    status per robot: 0 all lines held, 1 robot lines relaxed, 2 obstacle lines relaxed),
    ``scale_`` (fraction of the ORCA move kept by the exact check) and ``exposed_`` (robots
    that no move kept clear of a moving obstacle's next step).
    """

    def __init__(self, *, time_horizon: float = 4.0, obstacle_time_horizon: float = 2.0,
                 neighbour_distance: float = 8.0, max_neighbours: int = 10, safety_margin: float = 0.02,
                 obstacles: str = "forecast"):
        self.params = ORCAParams(time_horizon, obstacle_time_horizon, neighbour_distance, max_neighbours,
                                 safety_margin)
        if obstacles not in OBSTACLE_VIEWS:
            raise ConfigError(f"SafetyLayer: obstacles must be one of {OBSTACLE_VIEWS}, got {obstacles!r}")
        self.obstacles = obstacles

    def reset(self, world: World) -> None:
        """Prepare for a run of ``world`` (static features, radii, speeds)."""
        self.world_ = world
        self.solver_ = ORCASolver(self.params)
        self.solver_.reset(world)
        if self.obstacles == "standing":
            self.solver_.redraw = None
        self.extent_ = np.array([ob.extent for ob in world.moving_obstacles], float)
        n = world.n_robots
        self.previous_ = world.starts.copy()
        self.status_ = np.zeros(n, np.int64)
        self.scale_ = np.ones(n)
        self.exposed_ = np.zeros(n, bool)

    def safe_positions(self, obs: Observation, proposed: FloatArray, fixed: BoolArray | None = None
                       ) -> tuple[FloatArray, BoolArray]:
        """The closest safe next positions (n, 2) to ``proposed`` (n, 2), and which robots'
        proposals were changed (n,). A non-finite proposal counts as "stay"; one beyond the
        robot's speed is shortened first. Robots ``fixed`` (n,) stand still whatever happens
        (a robot without a plan, say): the others take the whole avoidance on themselves."""
        if not hasattr(self, "solver_"):
            raise ConfigError("SafetyLayer: call reset(world) before safe_positions")
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        proposed = np.asarray(proposed, float)
        if proposed.shape != pos.shape:
            raise ConfigError(f"SafetyLayer: proposed positions must have shape {pos.shape}, got {proposed.shape}")
        solver = self.solver_
        dt = float(obs.dt)
        if n == 0:
            return pos.copy(), np.zeros(0, bool)
        wanted = np.where(np.all(np.isfinite(proposed), axis=1)[:, None], proposed, pos)
        if fixed is not None:
            fixed = np.asarray(fixed, bool)
            wanted = np.where(fixed[:, None], pos, wanted)
        pref = (wanted - pos) / dt
        speed = np.linalg.norm(pref, axis=1)
        over = speed > solver.speeds
        pref[over] *= (solver.speeds[over] / speed[over])[:, None]
        vel = (pos - self.previous_) / dt
        forecast = None
        if len(self.world_.moving_obstacles):
            if self.obstacles == "standing":
                forecast = standing_forecast(obs.obstacle_positions, self.extent_)
            else:
                forecast = forecast_obstacles(self.world_, obs.obstacle_positions, obs.obstacle_previous, obs.step,
                                              dt)
        v, status = solver.velocities(pos, vel, pref, forecast, fixed)
        p1 = pos + v * dt
        # the proposal itself when ORCA kept it (up to rounding), exact goals, no dust moves
        kept = np.linalg.norm(p1 - wanted, axis=1) <= 1e-9 * np.maximum(1.0, np.abs(wanted).max(axis=1))
        kept &= ~over
        p1 = tidy_moves(pos, p1, obs.goals, solver.step_len)
        p1[kept] = wanted[kept]
        safe = solver.make_safe(pos, p1, forecast, fixed)
        self.previous_ = pos.copy()
        self.status_, self.scale_, self.exposed_ = status, safe.scale, safe.exposed
        adjusted = np.any(safe.positions != proposed, axis=1)
        return safe.positions, adjusted

    def events(self, adjusted: BoolArray) -> list[dict]:
        """Events of the last call for a :class:`~swarmpath.control.base.Decision`:
        ``safety_adjusted`` per changed proposal and ``exposed`` per cornered robot."""
        out = [{"robot": int(i), "kind": "safety_adjusted"} for i in np.flatnonzero(adjusted)]
        out += [{"robot": int(i), "kind": "exposed", "detail": "no move keeps clear of a moving obstacle's next step"}
                for i in np.flatnonzero(self.exposed_)]
        return out
