"""One run of the simulator's step loop, driven from outside: the state an environment steps.

:class:`~swarmpath.sim.simulator.Simulator` runs its loop to the end with a controller inside
it; an environment needs the same loop cut open, because the agents' actions arrive between
two calls. :class:`WorldStepper` holds that loop's state and runs its parts in the
simulator's order and with the simulator's pieces, so that the same proposals give the same
trajectory bit for bit:

1. :meth:`WorldStepper.begin_step`: the moving obstacles move
   (:func:`~swarmpath.world.moving.advance_obstacles`, with the run's ``"obstacles"`` stream
   and the robots' positions and goals to keep clear);
2. :meth:`WorldStepper.observation`: what the robots sense
   (:class:`~swarmpath.control.observation.Observation` filled by
   :func:`~swarmpath.sim.sensing.sense`), built once per step and only when asked for;
3. the caller decides the next positions (agents' actions, a controller);
4. :meth:`WorldStepper.end_step`: moves longer than ``max_speed * dt`` (or not finite) are
   rejected, the robot stays and an ``invalid_move`` event is recorded (:func:`validate_moves`); the independent checker
   (:func:`~swarmpath.sim.collisions.step_contacts`) decides the contacts; everything is
   recorded for :meth:`WorldStepper.trajectory`.

Nothing here knows about Gymnasium or PettingZoo: the simulator drives this object, and so do
the environments of :mod:`swarmpath.env`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.observation import Observation, SensingConfig
from swarmpath.errors import ConfigError
from swarmpath.rng import make_rng
from swarmpath.sim.collisions import ROBOT_MOVING, ROBOT_ROBOT, ROBOT_STATIC, Contact, step_contacts
from swarmpath.sim.sensing import sense
from swarmpath.sim.trajectory import ALL_REACHED, Termination, Trajectory
from swarmpath.world.moving import ObstacleState, advance_obstacles, initial_obstacle_state
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
#: A robot is at its goal when its position is this close to it (world units).
GOAL_TOLERANCE = 1e-9
#: Contact kinds in the order of the per-robot count columns of :class:`StepOutcome`.
CONTACT_KINDS = (ROBOT_ROBOT, ROBOT_STATIC, ROBOT_MOVING)


def validate_moves(proposed: FloatArray, pos: FloatArray, speeds: FloatArray, step: int,
                   events: list) -> tuple[FloatArray, NDArray[np.bool_]]:
    """The simulator's move validation: proposed positions (n, 2) whose move from ``pos`` is
    not finite or longer than ``speeds`` (n,) (with the simulator's tolerance) are replaced
    by ``pos`` and recorded as ``invalid_move`` events. Returns (positions, rejected mask)."""
    proposed = np.asarray(proposed, dtype=float)
    if proposed.shape != pos.shape:
        raise ConfigError(f"proposed positions have shape {proposed.shape}, expected {pos.shape}")
    new = proposed.copy()
    bad_value = ~np.all(np.isfinite(new), axis=1)
    length = np.linalg.norm(np.where(bad_value[:, None], 0.0, new - pos), axis=1)
    too_far = length > speeds * (1 + 1e-9) + 1e-12
    rejected = bad_value | too_far
    for i in np.flatnonzero(rejected):
        detail = "not a finite position" if bad_value[i] else f"step {length[i]:.6g} > max {speeds[i]:.6g}"
        events.append({"step": step, "kind": "invalid_move", "robot": int(i), "detail": detail})
        new[i] = pos[i]
    return new, rejected


@dataclass(frozen=True)
class StepOutcome:
    """What one step did: ``contacts`` (the checker's list), ``counts`` (n, 3) contacts per
    robot and kind (robot-robot, robot-static, robot-moving; a robot-robot contact counts for
    both robots) and ``rejected`` (n,) moves refused by the validation."""

    step: int
    contacts: list[Contact]
    counts: NDArray[np.int64]
    rejected: NDArray[np.bool_]


class WorldStepper:
    """The step loop of one run of ``world``, one part at a time (see the module docs).

    Parameters
    ----------
    world : World
        The world to step.
    sensing : SensingConfig, optional
        Distance classes and range of the Observation (the simulator's default).
    record : bool
        Keep every position, contact and event for :meth:`trajectory` (True).
    """

    def __init__(self, world: World, *, sensing: SensingConfig | None = None, record: bool = True):
        if not isinstance(world, World):
            raise ConfigError(f"the stepper needs a World, got {type(world).__name__}")
        self.world = world
        self.sensing = sensing or SensingConfig()
        self.record = record

    # ------------------------------------------------------------------ the loop
    def reset(self, seed: int) -> None:
        """Start a run of ``seed``: robots at their starts, obstacles at step 0, and the
        obstacles' random stream ``make_rng(seed, "obstacles")``."""
        world = self.world
        self.seed_ = int(seed)
        self.goals_ = world.goals
        self.speeds_ = world.max_speeds * world.dt
        self.obstacle_rng_ = make_rng(self.seed_, "obstacles")
        self.state_: ObstacleState = initial_obstacle_state(world)
        self.step_ = 0
        self.pos_ = world.starts.copy()
        self.previous_pos_ = self.pos_.copy()
        self.obstacles_before_ = self.state_.positions.copy()
        self.moved_ = False                   # begin_step() done for step step_ + 1
        self.observation_: Observation | None = None
        self.positions_: list[FloatArray] = [self.pos_]
        self.obstacle_positions_: list[FloatArray] = [self.state_.positions.copy()]
        self.contacts_: list[Contact] = []
        self.events_: list[dict] = []

    def begin_step(self) -> None:
        """Step ``step + 1`` begins: the moving obstacles move (robots' positions and goals
        kept clear, as in the simulator)."""
        if self.moved_:
            raise ConfigError("begin_step() called twice for the same step")
        n = self.world.n_robots
        keep_clear = np.concatenate([self.pos_, self.goals_]) if n else None
        self.state_ = advance_obstacles(self.world, self.state_, self.obstacle_rng_, keep_clear)
        self.moved_ = True
        self.observation_ = None

    def observation(self) -> Observation:
        """The controllers' view of the current step (after the obstacles moved), the
        simulator's Observation; built on first request and kept for the step."""
        if not self.moved_:
            raise ConfigError("observation() needs begin_step() first")
        if self.observation_ is None:
            pos, after = self.pos_, self.state_.positions
            self.observation_ = Observation(
                self.step_ + 1, self.world.dt, pos.copy(), self.goals_, self.at_goal(), after.copy(),
                self.obstacles_before_.copy(), sense(pos, after, self.sensing, self.world.resolution))
        return self.observation_

    def end_step(self, proposed: FloatArray) -> StepOutcome:
        """Finish the step with the robots' proposed next positions (n, 2): validate them,
        decide the contacts, record."""
        if not self.moved_:
            raise ConfigError("end_step() needs begin_step() first")
        step = self.step_ + 1
        events: list[dict] = []
        new, rejected = validate_moves(proposed, self.pos_, self.speeds_, step, events)
        after = self.state_.positions
        contacts = step_contacts(self.world, step, self.pos_, new, self.obstacles_before_, after)
        counts = np.zeros((self.world.n_robots, 3), np.int64)
        for c in contacts:
            k = CONTACT_KINDS.index(c.kind)
            counts[c.robot, k] += 1
            if c.kind == ROBOT_ROBOT:
                counts[c.other, k] += 1
        self.previous_pos_ = self.pos_
        self.pos_ = new
        self.obstacles_before_ = after.copy()
        self.step_ = step
        self.moved_ = False
        self.observation_ = None
        if self.record:
            self.positions_.append(new)
            self.obstacle_positions_.append(self.obstacles_before_)
            self.contacts_.extend(contacts)
            self.events_.extend(events)
        return StepOutcome(step, contacts, counts, rejected)

    # ------------------------------------------------------------------ state
    @property
    def step(self) -> int:
        """Steps completed."""
        return self.step_

    @property
    def positions(self) -> FloatArray:
        """Robots' positions now (n, 2); do not modify."""
        return self.pos_

    @property
    def previous_positions(self) -> FloatArray:
        """Robots' positions one step before (n, 2) (the starts at step 0)."""
        return self.previous_pos_

    @property
    def obstacle_positions(self) -> FloatArray:
        """Moving obstacles' positions (m, 2): after this step's move once :meth:`begin_step`
        ran, else after the last completed step."""
        return self.state_.positions

    @property
    def obstacle_previous(self) -> FloatArray:
        """Moving obstacles' positions after the last completed step (m, 2)."""
        return self.obstacles_before_

    def at_goal(self) -> NDArray[np.bool_]:
        """Robots at their goals (the simulator's exact test), shape (n,)."""
        return np.linalg.norm(self.pos_ - self.goals_, axis=1) <= GOAL_TOLERANCE

    def trajectory(self, status: Termination | str | None = None, *, meta: dict | None = None,
                   planned_paths: list | None = None) -> Trajectory:
        """The run so far as a :class:`~swarmpath.sim.trajectory.Trajectory` (status: every
        robot at its goal, else the one given, else truncated)."""
        if not self.record:
            raise ConfigError("this environment does not record (record=False): no trajectory")
        world = self.world
        n = world.n_robots
        if status is None:
            status = ALL_REACHED if n and bool(np.all(self.at_goal())) else "truncated"
        k = len(self.positions_)
        return Trajectory(
            scenario=world.name, seed=self.seed_, dt=world.dt, resolution=world.resolution,
            robot_ids=[r.id for r in world.robots], radii=world.radii, goals=self.goals_,
            positions=np.asarray(self.positions_, float).reshape(k, n, 2),
            obstacle_ids=[o.id for o in world.moving_obstacles],
            obstacle_positions=np.asarray(self.obstacle_positions_, float).reshape(k, -1, 2),
            contacts=list(self.contacts_), events=list(self.events_),
            planned_paths=list(planned_paths or []), status=status, world=world.to_dict(),
            static_map=world.static_map.blocked if world.static_map is not None else None,
            meta={"max_steps": None, **(meta or {})},
        )
