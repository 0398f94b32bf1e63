"""Multi-robot PSO with linear prediction of moving obstacles, in continuous space
(controllers ``pso-predictive`` and ``pso-reactive``; PSO-prediction paper 2013, eq. 1-8).

Each step every robot i chooses its next position with a 10-particle PSO over its heading
theta and a speed fraction sigma in [0, 1] (eq. 1-2, speed up to ``max_speed``):

    x_i' = x_i + sigma v_i dt cos(theta),   y_i' = y_i + sigma v_i dt sin(theta)

minimising the objective of eq. 3-7 (the text's equations are garbled; the reading used is
written out in docs/papers/pso-prediction-2013.md):

    F_i = ||x_i' - g_i||                                             goal term (eq. 3)
        + f_dp sum_j min(0, ||x_i' - a_j|| - (r_i + r_j + eps))^2    kin term (eq. 5), a_j the
                                                                     announced/predicted next
                                                                     position of robot j
        + f_st [static clearance penalty on the local trajectory]    (eq. 6)
        + f_dy sum_m 1 / ||x_i' - p_m'||                             (eq. 7), p_m' the predicted
                                                                     next obstacle position
        + f_buf sum_m buffer(x_i', predicted path over 2 steps)      our addition (see below)
        + H (violation + [violation > 0])                            hard safety constraints

The hard constraints make a candidate unacceptable (H = 1000 dominates every soft term):
the swept disc of the move enters a static obstacle or leaves the workspace; the move comes
closer than r_i + r_j + eps to another robot (others stand still, or move along their
already decided segment: robots are resolved sequentially by index, the paper's "i-th
algorithm for the i-th robot"); the move passes through the obstacle's current footprint
(phase 2 of the simulator's step); and the end position lies where the obstacle will sweep
in the next step (phase 1 of the next step). Only the last one differs between the two
controllers:

- ``pso-predictive``: the obstacle's next sweep is the segment from its current position to
  its linear prediction (:mod:`.prediction`); when the obstacle may turn at
  the next step (its turning period is not yet known, or the next step is a turning step) or
  the prediction is impossible (it would bounce off a wall), the whole disc it can reach in
  one step is kept clear instead (the "turn guard", our addition).
  The predictive controller also keeps, softly, one obstacle step of extra room around the
  obstacle's predicted path over the next ``buffer_steps`` steps (:func:`path_buffer_penalty`,
  our addition: without it robots crowd the obstacle's path and get cornered).
- ``pso-reactive``: the paper's "classical non-prediction approach": the obstacle is taken to
  stand where it is now (all terms use its current position; no guard, no buffer).

All robots' swarms run in one vectorised PSO (n_robots x 10 particles); a robot whose result
conflicts with the segment of a robot decided before it is solved again alone. The pure
kernels (:mod:`.kernels`) carry the equations, :mod:`.step_problem` the objective,
:mod:`.step_solver` the swarm, and the controller classes here wire them to the simulator.
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.control.orca.coordination import Coordination
from swarmpath.control.orca.guidance import Guidance, velocity_toward
from swarmpath.control.orca.safety import SafetyLayer
from swarmpath.control.pso_predictive import prediction as pred
from swarmpath.control.pso_predictive.step_problem import StepProblem, Weights, objective
from swarmpath.control.pso_predictive.step_solver import SwarmSettings, solve_step
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.world.geometry import origin_segment_distance
from swarmpath.world.static_geometry import StaticGeometry, static_geometry
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


@register_controller("pso-predictive")
class PredictivePSOController(Controller):
    """Per-step multi-robot PSO with linear prediction of moving obstacles (PSO-prediction
    paper 2013). Needs no offline plan; robots are discs (radius >= 0) in continuous space.

    Parameters (hyperparameters only; state is created in ``reset``):
    sensing_factor : n in the sensing radius n (R + r), n > 1 (pseudo-code of section 4)
    eps : the paper's robot-robot threshold epsilon (world units)
    obstacle_margin : extra clearance kept from moving obstacles (world units)
    buffer_steps : horizon (steps) of the predicted path kept clear softly, with a buffer of
        one obstacle step (0 = off; the paper has no such term)
    yield_reach : robots pressed by the moving obstacle (no safe move, or inside the buffer of
        its predicted path) ask their neighbours, through the kin term, for this many steps of
        travel of extra room (our addition; 0 = off)
    stuck_steps : a robot whose distance to its goal has not shrunk for this many steps takes
        a detour: for up to ``stuck_steps`` steps its goal term aims at a waypoint
        ``detour_reach`` steps of travel to one side (random) of its goal direction (our
        addition: eq. 3 alone leaves robots in local minima, e.g. two robots crossing on top
        of an obstacle); 0 = off
    turn_guard : "learned" (keep the obstacle's whole one-step reach clear when it may turn:
        period not yet learnt, turning step, or impossible prediction), "always", or "never"
        (the paper's pure linear prediction)
    safety : put the ORCA safety layer (:class:`~swarmpath.control.orca.SafetyLayer`) after
        the swarm: the chosen positions become the closest safe ones (our addition; the
        predictive controller's layer sees the obstacles' forecast next moves, the reactive
        one's sees them standing)
    safety_horizon : the layer's time horizon for robots and moving obstacles, in steps (1:
        it keeps the next step safe and leaves anticipation to the swarm's own terms; ORCA's
        usual 4 steps overrule the swarm's choice whenever a neighbour is within reach of the
        next 4 steps)
    guidance : steer along the offline plan, or without one along the goal's distance field
        (:class:`~swarmpath.control.orca.Guidance`): eq. 3's goal becomes the steering point
        (the goal itself when it is in sight; our addition: a straight-line distance leaves
        robots in front of walls, doors and maze corridors)
    side_bias, yield_after, patience : deterministic symmetry breaking and deadlock events
        (:class:`~swarmpath.control.orca.coordination.Coordination`): a robot constrained last
        step turns its steering direction right by ``side_bias`` radians (0 = off); robots
        stalled ``yield_after`` steps back away from a stalled robot of smaller index (0 =
        off); a robot without progress for ``patience`` steps gives a ``deadlock`` event
    yield_chain : with ``yield_after``, a robot parked on its goal that another backs into
        backs away too, up to this many robots deep (0 = off): with goals in a one-cell door
        and just behind it (room-32-32-4) the first alone would push into the second
    weights, swarm : :class:`Weights` and :class:`SwarmSettings`
    """

    capabilities = Capabilities(continuous=True, moving_obstacles=True, multi_robot=True, randomized=True)
    predictive: ClassVar[bool] = True

    def __init__(self, *, sensing_factor: float = 3.0, eps: float = 0.05, obstacle_margin: float = 0.05,
                 turn_guard: str = "learned", buffer_steps: int = 2, stuck_steps: int = 10,
                 detour_reach: float = 6.0, yield_reach: float = 2.0, safety: bool = True,
                 safety_horizon: float = 1.0, guidance: bool = True,
                 side_bias: float = 0.15, yield_after: int = 8, patience: int = 40, yield_chain: int = 4,
                 weights: Weights | None = None, swarm: SwarmSettings | None = None):
        if not sensing_factor > 1:
            raise ConfigError(f"sensing_factor must be > 1 (the paper's n), got {sensing_factor}")
        if eps <= 0 or obstacle_margin < 0:
            raise ConfigError(f"eps must be > 0 and obstacle_margin >= 0, got {eps}, {obstacle_margin}")
        if turn_guard not in ("learned", "always", "never"):
            raise ConfigError(f"turn_guard must be 'learned', 'always' or 'never', got {turn_guard!r}")
        self.sensing_factor = sensing_factor
        self.eps = eps
        self.obstacle_margin = obstacle_margin
        self.turn_guard = turn_guard
        if buffer_steps < 0:
            raise ConfigError(f"buffer_steps must be >= 0, got {buffer_steps}")
        self.buffer_steps = buffer_steps
        if stuck_steps < 0 or not detour_reach > 0:
            raise ConfigError(f"need stuck_steps >= 0 and detour_reach > 0, got {stuck_steps}, {detour_reach}")
        self.stuck_steps = stuck_steps
        if yield_reach < 0:
            raise ConfigError(f"yield_reach must be >= 0, got {yield_reach}")
        self.yield_reach = yield_reach
        self.detour_reach = detour_reach
        self.safety = bool(safety)
        if not safety_horizon > 0:
            raise ConfigError(f"safety_horizon must be > 0 steps, got {safety_horizon}")
        self.safety_horizon = safety_horizon
        self.guidance = bool(guidance)
        Coordination(side_bias=side_bias, yield_after=yield_after, patience=patience, chain=yield_chain)  # validates
        self.yield_chain = yield_chain
        self.side_bias = side_bias
        self.yield_after = yield_after
        self.patience = patience
        self.weights = weights or Weights()
        self.swarm = swarm or SwarmSettings()
        if self.swarm.n_particles < 1 or self.swarm.n_iterations < 1:
            raise ConfigError("swarm needs n_particles >= 1 and n_iterations >= 1")

    # -------------------------------------------------------------- run state
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self.world_ = world
        self.static_ = static_geometry(world)
        self.rng_ = rng
        n = world.n_robots
        self.radii_ = world.radii
        self.reach_ = world.max_speeds * world.dt
        self.goals_ = world.goals
        # robot-robot contact distance; point robots occupy grid cells, so two of them must stay
        # more than a cell diagonal apart (then they never share or swap cells)
        rsum = self.radii_[:, None] + self.radii_[None, :]
        both_points = (self.radii_[:, None] == 0) & (self.radii_[None, :] == 0)
        contact = np.where(both_points, np.sqrt(2.0) * world.resolution, rsum)
        self.separation_ = contact + self.eps
        reach_pair = self.reach_[:, None] + self.reach_[None, :]
        self.kin_range_ = np.maximum(self.sensing_factor * rsum, self.separation_ + reach_pair + self.eps)
        self.extent_ = np.array([ob.extent for ob in world.moving_obstacles], float)
        # each obstacle's worst-case travel per step by its motion model (inf: it teleports)
        self.obstacle_step_ = np.array([ob.max_step(world.dt, world.resolution) for ob in world.moving_obstacles],
                                       float)
        self.previous_positions_ = world.starts.copy()
        self.best_gap_ = np.linalg.norm(world.starts - self.goals_, axis=1)
        self.stalled_ = np.zeros(n, dtype=np.int64)
        self.detour_ = np.full((n, 2), np.nan)
        self.detour_left_ = np.zeros(n, dtype=np.int64)
        self.pressed_ = np.zeros(n, dtype=bool)
        self.track_ = pred.ObstacleTrack()
        self.eye_ = np.eye(n, dtype=bool)
        # guidance along the plan or the distance field (also measures progress for deadlocks)
        self.guidance_ = Guidance()
        self.guidance_.reset(world, plan if self.guidance else None)
        self.coordination_ = Coordination(side_bias=self.side_bias, yield_after=self.yield_after,
                                          patience=self.patience, chain=self.yield_chain)
        self.coordination_.reset(world, self.guidance_)
        self.layer_ = None
        if self.safety:
            self.layer_ = SafetyLayer(time_horizon=self.safety_horizon * world.dt,
                                      obstacles="forecast" if self.predictive else "standing")
            self.layer_.reset(world)

    def _obstacle_terms(self, obs) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """(sweep end, inverse-distance target, guard radius, buffered path end, buffer) of
        every moving obstacle."""
        now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        if not self.predictive:
            zero = np.zeros(len(now))
            return now, now, zero, now, zero
        prev = np.asarray(obs.obstacle_previous, float).reshape(-1, 2)
        self.track_ = pred.update_track(self.track_, obs.step, prev, now, obs.dt)
        dt_s = self.track_.sampling_times(obs.dt)
        predicted = np.stack([pred.predict_linear(prev[j:j + 1], now[j:j + 1], obs.dt, dt_s[j])[0]
                              for j in range(len(now))]) if len(now) else now
        # a jump is not a velocity: an obstacle whose model teleports (redraw), or whose last
        # move was longer than its model's reach, is not extrapolated (it was: a redraw of 8
        # units became a keep-out disc of 8 units that no move could clear)
        jumps = ~np.isfinite(self.obstacle_step_) | \
            (np.linalg.norm(now - prev, axis=1) > self.obstacle_step_ * (1 + 1e-9) + 1e-12)
        predicted = np.where(jumps[:, None], now, predicted)
        possible = np.array([bool(self.world_.obstacle_fits(ob, predicted[j:j + 1])[0])
                             for j, ob in enumerate(self.world_.moving_obstacles)], bool)
        self.track_ = pred.with_linear_possible(self.track_, possible)
        speed = np.linalg.norm(predicted - now, axis=1)
        # a turning or bouncing obstacle stays within its model's reach of `now` (random-walk:
        # a diagonal grid step); a jumping one gets no guard (it stands for phase 2 only)
        reach = np.where(jumps, 0.0, self.obstacle_step_)
        if self.turn_guard == "never":
            guard = np.zeros(len(now))
        elif self.turn_guard == "always":
            guard = np.maximum(speed, reach)
        else:
            periods = self.track_.periods()
            uncertain = np.array([not possible[j] or pred.turn_expected(obs.step + 1, self.track_.turn_steps[j],
                                                                        periods[j]) for j in range(len(now))], bool)
            guard = np.where(uncertain, np.maximum(speed, reach), 0.0)
        # a turning or bouncing obstacle keeps its speed: it stays within `speed` of `now`
        sweep_end = np.where((guard > 0)[:, None], now, predicted)
        path_end = now + self.buffer_steps * (predicted - now)
        buffer = speed if self.buffer_steps > 0 else np.zeros(len(now))
        return sweep_end, predicted, guard * (1 + 1e-6), path_end, buffer

    def _near_path(self, x: FloatArray, problem: StepProblem) -> BoolArray:
        """Robots whose position ``x`` (n, 2) lies within the buffer of an obstacle's
        predicted path (pressed by it); none without a buffer."""
        out = np.zeros(len(x), bool)
        for j in np.flatnonzero(problem.buffer > 0):
            d = origin_segment_distance(problem.obstacle_now[j] - x, problem.path_end[j] - x)
            out |= problem.obstacle_mask[:, j] & (d < problem.obstacle_clear[:, j] + problem.buffer[j])
        return out

    def _targets(self, pos: FloatArray, events: list, heading: FloatArray | None = None) -> FloatArray:
        """Each robot's goal, or its detour waypoint while it is taking a detour (updates the
        stall counters; appends "detour" events). Progress is the straight distance to the
        goal, or with ``guidance`` the guidance's remaining length; a detour turns away from
        ``heading`` (n, 2) (default: the goals)."""
        gap = self.guidance_.remaining(pos) if self.guidance else np.linalg.norm(pos - self.goals_, axis=1)
        improved = gap < self.best_gap_ - 0.25 * self.reach_
        self.best_gap_ = np.where(improved, gap, self.best_gap_)
        self.stalled_ = np.where(improved | (gap <= 1e-9), 0, self.stalled_ + 1)
        if self.stuck_steps == 0:
            return self.goals_
        active = ~np.isnan(self.detour_[:, 0])
        self.detour_left_ = np.where(active, self.detour_left_ - 1, 0)
        done = active & ((self.detour_left_ <= 0) | (np.linalg.norm(pos - self.detour_, axis=1) <= self.reach_))
        self.detour_[done] = np.nan
        self.best_gap_ = np.where(done, gap, self.best_gap_)
        self.stalled_[done] = 0
        for i in np.flatnonzero(np.isnan(self.detour_[:, 0]) & (self.stalled_ >= self.stuck_steps)):
            self.detour_[i] = self._waypoint(pos[i], i, self.goals_[i] if heading is None else heading[i])
            self.detour_left_[i] = self.stuck_steps
            self.stalled_[i] = 0
            events.append({"robot": int(i), "kind": "detour", "detail": f"to {np.round(self.detour_[i], 3).tolist()}"})
        return np.where(np.isnan(self.detour_), self.goals_, self.detour_)

    def _waypoint(self, p: FloatArray, i: int, toward: FloatArray) -> FloatArray:
        """A point ``detour_reach`` steps of travel to a random side of the direction from
        robot i to ``toward`` (its goal or steering point; the other side, or straight back,
        when that one is not free)."""
        d = toward - p
        d = d / max(float(np.linalg.norm(d)), 1e-12)
        side = 1.0 if self.rng_.random() < 0.5 else -1.0
        length = self.detour_reach * self.reach_[i]
        options = [p + length * side * np.array([-d[1], d[0]]), p - length * side * np.array([-d[1], d[0]]),
                   p - length * d]
        for w in options:
            if self.static_.static_clearance(w[None], self.radii_[i:i + 1])[0] > 0:
                return w
        return p.copy()

    def _problem(self, obs, targets: FloatArray) -> StepProblem:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        sweep_end, target, guard, path_end, buffer = self._obstacle_terms(obs)
        now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        dist = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
        pair_row, pair_other = np.nonzero((dist <= self.kin_range_) & ~self.eye_)
        # kin prediction: every other robot continues its last displacement
        announced = pos + (pos - self.previous_positions_)
        # robots pressed by the moving obstacle ask their neighbours for room (our addition)
        extra = np.where(self.pressed_, self.yield_reach * self.reach_, 0.0)
        clear = self.extent_[None, :] + self.radii_[:, None] + self.obstacle_margin
        if len(now):
            d_obs = np.linalg.norm(pos[:, None] - now[None], axis=-1)
            speed = np.maximum(np.linalg.norm(path_end - now, axis=1), guard) + buffer
            sense = np.maximum(self.sensing_factor * (self.extent_[None, :] + self.radii_[:, None]),
                               clear + self.reach_[:, None] + 2 * speed[None, :] + self.obstacle_margin)
            obstacle_mask = d_obs <= sense
        else:
            obstacle_mask = np.zeros((n, 0), bool)
        if self.weights.line_of_sight > 0:
            static_near = np.ones(n, bool)
        else:
            free = self.static_.static_clearance(pos, self.radii_) - self.reach_
            static_near = free < self.weights.static_margin + 1e-6
        return StepProblem(start=pos, goal=targets, radius=self.radii_, reach=self.reach_,
                           robot=np.arange(n), pair_row=pair_row, pair_other=pair_other,
                           pair_from=pos[pair_other], pair_to=pos[pair_other],
                           pair_announced=announced[pair_other],
                           pair_separation=self.separation_[pair_row, pair_other],
                           pair_room=self.separation_[pair_row, pair_other] + extra[pair_other], obstacle_now=now,
                           obstacle_next=sweep_end, obstacle_target=target, guard=guard,
                           path_end=path_end, buffer=buffer,
                           obstacle_clear=clear, obstacle_mask=obstacle_mask, static_near=static_near,
                           obstacle_jumps=~np.isfinite(self.obstacle_step_),
                           static_margin=self._route_margin(pos, targets, static_near))

    def _route_margin(self, pos: FloatArray, targets: FloatArray, near: BoolArray) -> FloatArray:
        """Each robot's static margin (n,): the weights' margin, but never more than the least
        clearance on the straight way to its target (sampled every quarter cell, at most 33
        points). A door or corridor narrower than radius + margin, or a goal by a wall, would
        otherwise cost more than a step of progress buys, and the robot would wait before it
        for ever (a local minimum of eq. 3-7 that only the margin made). Only with the hard
        constraints on (``weights.hard > 0``): they keep every robot out of the walls, whereas
        in a purely soft objective the margin is all that does."""
        margin = np.full(len(pos), self.weights.static_margin)
        idx = np.flatnonzero(near)
        if not len(idx) or self.weights.static <= 0 or self.weights.hard <= 0:
            return margin
        seg = targets[idx] - pos[idx]
        length = float(np.linalg.norm(seg, axis=1).max())
        m = int(min(33, max(2, np.ceil(length / (0.25 * self.world_.resolution)) + 1)))
        t = np.linspace(0.0, 1.0, m)
        pts = (pos[idx][:, None, :] + t[None, :, None] * seg[:, None, :]).reshape(-1, 2)
        clear = self.static_.static_clearance(pts, np.repeat(self.radii_[idx], m)).reshape(len(idx), m).min(axis=1)
        margin[idx] = np.clip(clear, 0.0, self.weights.static_margin)
        return margin

    def _steering(self, pos: FloatArray, events: list) -> tuple[FloatArray, FloatArray]:
        """Each robot's steering point for eq. 3 (n, 2) and its preferred velocity (n, 2).

        The point is the goal, or with ``guidance`` the guidance's steering point (the goal
        when in sight, else a visible plan vertex or distance-field cell); a detour waypoint
        replaces it while the robot takes a detour. The coordination's side preference and
        yielding turn it about the robot (same distance, at least one step)."""
        if self.guidance:
            target, is_goal = self.guidance_.targets(pos)
        else:
            target, is_goal = self.goals_.copy(), np.ones(len(pos), bool)
        detour = self._targets(pos, events, target)
        on_detour = ~np.isnan(self.detour_[:, 0])
        target = np.where(on_detour[:, None], detour, target)
        is_goal &= ~on_detour
        pref = velocity_toward(pos, target, self.world_.max_speeds, self.world_.dt, is_goal)
        turned = self.coordination_.preferred(pos, pref)
        dist = np.linalg.norm(target - pos, axis=1)
        # a robot one step from its goal lands on it (nothing to break there; a parked robot
        # may still be asked to back away, and a stalled one to yield)
        landing = is_goal & (dist > 1e-9) & (dist <= self.reach_) & ~self.coordination_.stalled
        turned[landing] = pref[landing]
        changed = np.any(turned != pref, axis=1)
        if changed.any():
            length = np.where(dist > 1e-9, dist, self.reach_)     # a parked robot backs away one step
            unit = turned / np.maximum(np.linalg.norm(turned, axis=1), 1e-300)[:, None]
            target = np.where(changed[:, None], pos + unit * length[:, None], target)
        return target, turned

    def act(self, obs: Observation) -> Decision:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        if n == 0:
            return Decision(pos.copy(), [])
        events: list[dict] = []
        targets, pref = self._steering(pos, events)
        problem = self._problem(obs, targets)
        static = self.static_
        if isinstance(static, StaticGeometry):
            static = static.near(pos, self.reach_ + self.radii_ + self.weights.static_margin + 1e-6)
        choice = solve_step(problem, static, self.weights, self.swarm, self.rng_)
        final = choice.positions.copy()
        violation = choice.violation.copy()
        # sequential resolution by index: robot i must respect the segments of robots j < i.
        # All robots are checked at once against the decisions before them; the first one with
        # a new conflict is solved again alone, and the check resumes after it.
        first = 1
        while first < n:
            checked = problem.after(final)
            idx = np.arange(first, n)
            _, v = objective(checked.rows(idx), static, final[idx][:, None, :], self.weights)
            worse = np.flatnonzero(v[:, 0] > violation[idx] + 1e-12)
            if len(worse) == 0:
                break
            i = int(idx[worse[0]])
            again = solve_step(checked.rows([i]), static, self.weights, self.swarm, self.rng_)
            final[i], violation[i] = again.positions[0], again.violation[0]
            first = i + 1
        self.pressed_ = (violation > 0) | self._near_path(final, problem)
        for i in np.flatnonzero(violation > 0):
            events.append({"robot": int(i), "kind": "no_safe_move", "detail": f"violation {violation[i]:.3g}"})
        adjusted = np.zeros(n, bool)
        if self.layer_ is not None:
            final, adjusted = self.layer_.safe_positions(obs, final)
            events.extend(self.layer_.events(adjusted))
        speeds = np.maximum(self.world_.max_speeds, 1e-12)
        constrained = np.linalg.norm((final - pos) / obs.dt - pref, axis=1) > 0.05 * speeds
        events.extend(self.coordination_.record(obs.step, final, constrained))
        self.previous_positions_ = pos.copy()
        at_goal = np.linalg.norm(final - self.goals_, axis=1) <= 1e-9
        moved = np.any(final != pos, axis=1)
        avoiding = problem.obstacle_mask.any(axis=1) | adjusted
        detour = ~np.isnan(self.detour_[:, 0])
        modes = ["arrived" if at_goal[i] else ("wait" if not moved[i] else
                                               ("avoid" if avoiding[i] else ("detour" if detour[i] else "seek")))
                 for i in range(n)]
        return Decision(final, modes, tuple(events))


@register_controller("pso-reactive")
class ReactivePSOController(PredictivePSOController):
    """The same PSO without prediction (the paper's "classical non-prediction approach"): the
    moving obstacle is taken to stay at its current position.

    It keeps clear of where a moving obstacle *is*, not of where it goes, so it does not
    promise to avoid moving obstacles (``capabilities.moving_obstacles`` is False): an
    obstacle can run it over, which is the effect the paper measures."""

    capabilities = Capabilities(continuous=True, moving_obstacles=False, multi_robot=True, randomized=True)
    predictive = False
