"""The environments' engine, free of Gymnasium and PettingZoo: episodes of one world over the
simulator's step loop (:class:`~swarmpath.sim.stepper.WorldStepper`), with actions,
observations, rewards, terminations and experts for all robots at once, as arrays.

The environment's step t+1 is the simulator's step t+1 cut where the agents decide: when
:meth:`EnvCore.step` has moved the robots of step t it moves the obstacles of step t+1
and builds the observations the agents act on, so an agent sees what a controller sees at
``act()`` (obstacles already moved). The random streams are the simulator's:
``make_rng(seed, "obstacles")`` for the obstacles, ``make_rng(seed, "controller")`` for each
expert.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.base import Controller
from swarmpath.control.grid_robots import check_grid_robots
from swarmpath.env.actions import ContinuousActions, GridActions
from swarmpath.env.experts import ExpertPool, expert_name
from swarmpath.env.observations import (
    GRID_CHANNELS,
    ContinuousObservations,
    GridObservations,
)
from swarmpath.env.options import CONTINUOUS, GRID, EnvOptions
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import PLANNERS
from swarmpath.sim.simulator import default_max_steps
from swarmpath.sim.stepper import GOAL_TOLERANCE, StepOutcome, WorldStepper
from swarmpath.sim.trajectory import ALL_REACHED, TRUNCATED, Trajectory
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]


def choose_mode(world: World, mode: str | None) -> str:
    """``mode``, or grid when every robot can move cell to cell (at most half a cell wide,
    reaching a neighbouring cell in a step), else continuous. An explicit grid mode on a world
    whose robots cannot is refused with the robot named."""
    if mode == GRID:
        check_grid_robots(world, "the grid environment")
        return GRID
    if mode == CONTINUOUS:
        return CONTINUOUS
    try:
        check_grid_robots(world, "the grid environment")
    except ConfigError:
        return CONTINUOUS
    return GRID


class EnvCore:
    """Episodes of ``world`` with ``options`` for all robots at once (see the module docs).

    Robots are indexed as ``world.robots``; ``live`` marks the robots that are still agents
    (not terminated or truncated)."""

    def __init__(self, world: World, options: EnvOptions):
        if not isinstance(world, World):
            raise ConfigError(f"the environment needs a World, got {type(world).__name__}")
        if world.n_robots == 0:
            raise ConfigError(f"world {world.name!r} has no robots, so no agents")
        if options.planner is not None:
            PLANNERS.get(options.planner)
        self.world = world
        self.options = options
        self.mode = choose_mode(world, options.mode)
        self.n = world.n_robots
        self.stepper = WorldStepper(world, sensing=options.sensing, record=options.record)
        self.reach = world.max_speeds * world.dt
        self.goals = world.goals
        self.rewards = options.rewards
        w = options.rewards
        self._weights = np.array([w.progress, w.arrival, w.step, w.robot_contact, w.static_contact,
                                  w.moving_contact, w.invalid_move])
        if self.mode == GRID:
            self.grid_actions = GridActions(world, options.connectivity)
            self.grid_obs = GridObservations(world, self.grid_actions.grid, options.view)
        else:
            self.continuous_actions = ContinuousActions(world, options.goal_snap)
            self.continuous_obs = ContinuousObservations(world, options.neighbours, options.obstacles,
                                                         options.static_points,
                                                         options.sensing.range * world.resolution)
        self.experts = ExpertPool()
        self.episode_ = -1
        self.next_seed_ = options.seed
        self._plans: dict[int, Plan | None] = {}
        self._cells_step: tuple[int, int] = (-1, -1)

    # ------------------------------------------------------------------ shapes
    @property
    def n_actions(self) -> int:
        """Grid: the number of discrete actions (9 or 5)."""
        return self.grid_actions.n_actions

    @property
    def patch_shape(self) -> tuple[int, int, int]:
        size = self.grid_obs.size
        return (len(GRID_CHANNELS), size, size)

    @property
    def vector_size(self) -> int:
        return self.continuous_obs.size

    # ------------------------------------------------------------------ episodes
    def plan_for(self, seed: int) -> Plan | None:
        """The offline plan of the episode ``seed`` (``options.planner``; None without), as
        ``swarmpath run`` makes it: the planner's ``plan(world, rng=seed)``."""
        if self.options.planner is None:
            return None
        if seed not in self._plans:
            plan = PLANNERS.get(self.options.planner)().plan(self.world, rng=seed)
            if len(self._plans) >= 4:
                self._plans.pop(next(iter(self._plans)))
            self._plans[seed] = plan if plan.robots else None
        return self._plans[seed]

    def reset(self, seed: int | None = None) -> None:
        """Start an episode: of ``seed``, else of the seed after the last one (``options.seed``
        first)."""
        if seed is None:
            seed = self.next_seed_
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ConfigError(f"seed must be a non-negative whole number, got {seed!r}")
        self.seed_ = int(seed)
        self.next_seed_ = self.seed_ + 1
        self.episode_ += 1
        self.plan_ = self.plan_for(self.seed_)
        self.max_steps_ = self.options.max_steps or default_max_steps(self.world, self.plan_)
        self.stepper.reset(self.seed_)
        self.live_ = np.ones(self.n, bool)
        self.terminated_ = np.zeros(self.n, bool)
        self.truncated_ = np.zeros(self.n, bool)
        self.contact_totals_ = np.zeros((self.n, 3), np.int64)
        d = self.stepper.positions - self.goals
        self.dist_ = np.hypot(d[:, 0], d[:, 1])
        self.last_counts_ = np.zeros((self.n, 3), np.int64)
        self.last_rejected_ = np.zeros(self.n, bool)
        self.last_rewards_ = np.zeros(self.n)
        self.experts_used_: set[str] = set()
        self.stepper.begin_step()

    @property
    def step_count(self) -> int:
        return self.stepper.step

    @property
    def done(self) -> bool:
        return not self.live_.any()

    # ------------------------------------------------------------------ actions
    def decode(self, actions: Any, rows: NDArray[np.int64]) -> FloatArray:
        """Proposed next positions (n, 2): robots ``rows`` take ``actions`` (one per row), all
        others stay where they are."""
        pos = self.stepper.positions
        proposed = pos.copy()
        if len(rows) == 0:
            return proposed
        if self.mode == GRID:
            a = np.asarray(actions)
            if a.shape != (len(rows),) or not np.issubdtype(a.dtype, np.integer):
                a = self._grid_actions(actions, len(rows))
            if a.min() < 0 or a.max() >= self.n_actions:
                bad = a[(a < 0) | (a >= self.n_actions)][0]
                raise ConfigError(f"grid action {int(bad)} is not in 0..{self.n_actions - 1}")
            proposed[rows] = self.grid_actions.decode(pos[rows], a.astype(np.int64), rows, self.cells()[rows])
            return proposed
        try:
            v = np.asarray(actions, dtype=float).reshape(len(rows), 2)
        except (TypeError, ValueError):
            raise ConfigError("continuous actions must be pairs of numbers (a velocity in [-1, 1]^2)") from None
        full = np.zeros((self.n, 2))
        full[rows] = v
        decoded = self.continuous_actions.decode(pos, full)
        proposed[rows] = decoded[rows]
        return proposed

    @staticmethod
    def _grid_actions(actions: Any, k: int) -> NDArray[np.int64]:
        out = np.zeros(k, np.int64)
        for i, a in enumerate(actions):
            value = np.asarray(a)
            if value.shape not in ((), (1,)) or not np.issubdtype(value.dtype, np.integer):
                raise ConfigError(f"a grid action is one whole number, got {a!r}")
            out[i] = int(value.reshape(-1)[0])
        return out

    def expert_decision(self, controller: str | Controller):
        """The expert's Decision for the current step."""
        self.experts_used_.add(expert_name(controller))
        return self.experts.decision(controller, world=self.world, plan=self.plan_, seed=self.seed_,
                                     episode=self.episode_, observation=self.stepper.observation())

    def expert_actions(self, controller: str | Controller) -> tuple[Any, NDArray[np.bool_]]:
        """Every robot's action (grid (n,) ints, continuous (n, 2) velocities) reproducing the
        expert's proposal, and whether exactly."""
        proposed = np.asarray(self.expert_decision(controller).positions, float)
        pos = self.stepper.positions
        if self.mode == GRID:
            return self.grid_actions.encode(pos, proposed)
        return self.continuous_actions.encode(pos, proposed)

    # ------------------------------------------------------------------ observations
    def observe(self) -> Any:
        """Observations of every robot: grid (patches (n, 5, s, s), goal vectors (n, 3)),
        continuous vectors (n, size)."""
        st = self.stepper
        if self.mode == GRID:
            ga = self.grid_actions
            return self.grid_obs.observe(self.cells(), st.positions, self.goals, ga.goal_cells,
                                         st.obstacle_positions, st.obstacle_previous)
        return self.continuous_obs.observe(st.observation(), st.previous_positions)

    def action_mask(self) -> NDArray[np.bool_]:
        """Grid: the statically possible actions (n, n_actions)."""
        return self.grid_actions.mask(self.stepper.positions, self.cells())

    def cells(self) -> NDArray[np.int64]:
        """Grid: the robots' cells now (n, 2), computed once per step."""
        st = self.stepper
        if self._cells_step != (self.episode_, st.step):
            self._cells = self.grid_actions.cells(st.positions)
            self._cells_step = (self.episode_, st.step)
        return self._cells

    # ------------------------------------------------------------------ stepping
    def step(self, proposed: FloatArray) -> StepOutcome:
        """Move the robots to ``proposed`` (n, 2) (validated and checked by the simulator's
        pieces), reward, terminate and truncate; then the next step's obstacles move."""
        if self.done:
            raise ConfigError("the episode is over: call reset()")
        st = self.stepper
        dist_before = self.dist_
        was_at_goal = dist_before <= GOAL_TOLERANCE
        outcome = st.end_step(proposed)
        d = st.positions - self.goals
        self.dist_ = np.hypot(d[:, 0], d[:, 1])
        at_goal = self.dist_ <= GOAL_TOLERANCE
        reward = self._weights[0] * (dist_before - self.dist_) / self.reach
        reward += self._weights[1] * (at_goal & ~was_at_goal)
        reward += self._weights[2] * ~at_goal
        reward += outcome.counts @ self._weights[3:6]
        reward += self._weights[6] * outcome.rejected
        self.last_rewards_ = reward
        self.last_counts_ = outcome.counts
        self.last_rejected_ = outcome.rejected
        self.contact_totals_ += outcome.counts
        live = self.live_
        if self.options.stay_arrived:
            terminated = live & bool(at_goal.all())
        else:
            terminated = live & at_goal
        truncated = live & ~terminated & (st.step >= self.max_steps_)
        self.terminated_ = terminated
        self.truncated_ = truncated
        self.live_ = live & ~terminated & ~truncated
        st.begin_step()
        return outcome

    # ------------------------------------------------------------------ records
    def trajectory(self) -> Trajectory:
        """The episode so far as a Trajectory (all robots at their goals: "all_reached")."""
        at_goal = self.stepper.at_goal()
        status = ALL_REACHED if bool(at_goal.all()) else TRUNCATED
        opts = self.options
        meta = {"controller": "swarmpath.env" if not self.experts_used_ else "swarmpath.env+" + "+".join(
                    sorted(self.experts_used_)),
                "planner": opts.planner, "max_steps": self.max_steps_, "env_mode": self.mode,
                "env_options": {"connectivity": opts.connectivity, "stay_arrived": opts.stay_arrived,
                                "goal_snap": opts.goal_snap, "view": opts.view}}
        paths = list(self.plan_.paths) if self.plan_ is not None else []
        return self.stepper.trajectory(status, meta=meta, planned_paths=paths)

    def info_rows(self, rows: NDArray[np.int64]) -> list[dict]:
        """Info of robots ``rows`` for the last step: contacts by kind this step and in the
        episode, whether the move was rejected, whether the robot is at its goal, its distance."""
        st = self.stepper
        dist = self.dist_[rows]
        step = st.step
        columns = zip(dist.tolist(), (dist <= GOAL_TOLERANCE).tolist(), self.last_counts_[rows].tolist(),
                      self.contact_totals_[rows].sum(axis=1).tolist(), self.last_rejected_[rows].tolist())
        return [{"step": step, "at_goal": at, "distance": d, "robot_robot": c[0], "robot_static": c[1],
                 "robot_moving": c[2], "contacts_total": total, "invalid_move": bad}
                for d, at, c, total, bad in columns]
