"""The simulator: steps the world, asks the controller for moves, and checks every move.

Each step (:class:`~swarmpath.sim.stepper.WorldStepper`, which environments drive too):
(1) moving obstacles move by their motion model; (2) robots sense; (3) the controller returns
next positions; (4) the moves are validated (finite, within the robot's ``max_speed * dt``;
an invalid move is recorded and the robot stays) and contacts decided by the independent
checker (:mod:`swarmpath.sim.collisions`); (5) everything is recorded. A run ends when
every robot is at its goal, when the step budget is spent ("truncated"), or when the robots
that have not arrived stopped making progress ("deadlock").

The budget a caller gives is a hard limit. The default one (:func:`default_max_steps`) counts
journeys, not crowds: in a narrow map robots queue, and a run can still be bringing robots
home when it is spent (400 robots in a 1-wide 129 x 129 maze arrive around step 10,100 of a
9,824-step budget; 50 robots in a 1-wide 33 x 33 maze need up to 3.4 times the budget). So
past the default budget the run goes on while robots still make progress (some robot away
from its goal comes closer to it than it has been since it last left it, the
:class:`~swarmpath.sim.progress.ProgressWatch` rule): it ends once none has for
:data:`PROGRESS_GRACE` of the budget, and at :data:`MAX_EXTENSION` times the budget at the
latest.
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Callable

import numpy as np

from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import SensingConfig
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.rng import make_rng
from swarmpath.sim.journeys import journey_lower_bounds
from swarmpath.sim.progress import ProgressWatch, distinct_positions, unreachable_goals
from swarmpath.sim.stepper import GOAL_TOLERANCE, WorldStepper
from swarmpath.sim.trajectory import ALL_REACHED, DEADLOCK, TRUNCATED, Trajectory
from swarmpath.world.world import World

#: Behaviour names a run may use (trajectories store them as int8 indices).
MAX_MODE_NAMES = 127
#: Past the default budget a run goes on while robots make progress: until none has for this
#: share of the budget (two longest journeys) ...
PROGRESS_GRACE = 0.5
#: ... and at this many times the budget at the latest. Arrivals alone were too rare a sign: in
#: a 1-wide maze, 50 robots following LaCAM's plan, the number at home made no new high for 800
#: steps of a 900-step budget while the run was on its way to finish at 3.4 times the budget.
MAX_EXTENSION = 8


def default_max_steps(world, plan=None) -> int:
    """A step budget that leaves room for detours: 200 plus four times the longest journey
    (planned length, else twice the straight line or the length round the static obstacles
    it is at least, :func:`~swarmpath.sim.journeys.journey_lower_bounds`, whichever is
    longer) in steps at the robot's speed; a timed plan's journey lasts at least until its
    last step (a crowded plan waits).

    Why the obstacles: in a maze the way round is many times the straight line. On a 33 x 33
    maze of 1-wide corridors with 25 robots the longest journey is 224 cells against 64 for
    twice the straight line; the budget was 384 steps, below the 431 of a complete plan."""
    longest = 0.0
    bounds = None
    for k, r in enumerate(world.robots):
        length = None
        steps = 0.0
        if plan is not None and k < len(plan.robots) and plan.robots[k].path is not None:
            length = plan.robots[k].length
            times = plan.robots[k].times
            steps = float(times[-1]) if times is not None and len(times) else 0.0
        if length is None:
            if bounds is None:
                bounds = journey_lower_bounds(world)
            length = max(2 * math.dist(r.start, r.goal), float(bounds[k]))
        longest = max(longest, length / (r.max_speed * world.dt), steps)
    return int(200 + 4 * math.ceil(longest))


class Simulator:
    """Runs ``controller`` on ``world`` (with an optional offline ``plan``) for one seed."""

    def __init__(self, world: World, controller: Controller, plan: Plan | None = None, *, seed: int = 0,
                 max_steps: int | None = None, sensing: SensingConfig | None = None, deadlock_window: int = 60,
                 progress_window: int | None = None, progress: Callable[[int, int], None] | None = None):
        if not isinstance(world, World):
            raise ConfigError(f"the simulator needs a World, got {type(world).__name__}")
        if not isinstance(controller, Controller):
            raise ConfigError(f"the simulator needs a Controller, got {type(controller).__name__}")
        if plan is not None and not isinstance(plan, Plan):
            raise ConfigError(f"plan must be a Plan or None, got {type(plan).__name__}")
        if world.n_robots == 0:
            raise ConfigError(f"world {world.name!r} has no robots to simulate")
        for name, value, low in (("max_steps", max_steps, 1), ("deadlock_window", deadlock_window, 2),
                                 ("progress_window", progress_window, 1), ("seed", seed, 0)):
            if value is None and name in ("max_steps", "progress_window"):
                continue
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
                raise ConfigError(f"{name} must be a whole number >= {low}, got {value!r}")
        self.world = world
        self.controller = controller
        self.plan = plan
        self.seed = int(seed)
        budget = default_max_steps(world, plan)
        self.max_steps = int(max_steps) if max_steps is not None else budget
        #: the default budget stretches while robots make progress (module docstring)
        self.soft_budget = max_steps is None
        self.sensing = sensing or SensingConfig()
        self.deadlock_window = int(deadlock_window)
        self.progress_window = int(progress_window) if progress_window is not None else budget
        self.progress = progress

    def run(self) -> Trajectory:
        """Run the controller until every robot is home, the budget is spent, or no robot
        makes progress; returns the frozen record of the run."""
        world = self.world
        n = world.n_robots
        goals = world.goals
        t0 = time.perf_counter()
        self.controller.reset(world, self.plan, make_rng(self.seed, "controller"))
        reset_time = time.perf_counter() - t0

        watch = ProgressWatch(goals, world.starts, self.progress_window, GOAL_TOLERANCE)
        hopeless = np.zeros(n, dtype=bool)
        if getattr(self.controller, "capabilities", None) is not None and self.controller.capabilities.grid_based:
            hopeless = unreachable_goals(world, world.radii)
        stepper = WorldStepper(world, sensing=self.sensing)
        stepper.reset(self.seed)
        events = stepper.events_
        for i in np.flatnonzero(hopeless):
            events.append({"step": 0, "kind": "goal_unreachable", "robot": int(i),
                           "detail": "no path in the static world from the start to the goal"})
        modes: list[list[int]] = []
        mode_names: dict[str, int] = {}
        status = TRUNCATED
        act_time = 0.0
        budget = self.max_steps
        step = 0
        while step < budget:
            step += 1
            stepper.begin_step()
            t_act = time.perf_counter()
            decision = self.controller.act(stepper.observation())
            act_time += time.perf_counter() - t_act
            if not isinstance(decision, Decision):
                try:
                    decision = Decision(np.asarray(decision, float))
                except (TypeError, ValueError):
                    raise ConfigError(f"controller returned {type(decision).__name__}, not a Decision or an "
                                      "array of positions") from None
            if np.shape(decision.positions) != (n, 2):
                raise ConfigError(f"controller returned positions of shape {np.shape(decision.positions)}, "
                                  f"expected {(n, 2)}")
            stepper.end_step(decision.positions)
            if decision.modes is not None:
                modes.append(self._mode_indices(decision.modes, mode_names, n))
            elif modes:
                modes.append([mode_names.setdefault("", len(mode_names))] * n)
            for ev in decision.events:
                events.append({"step": step, **ev})
            arrived = stepper.at_goal()
            if step == budget and self.soft_budget:
                budget = self._stretched(step, watch.last_progress)
            if self.progress is not None:
                self.progress(step, budget)
            if np.all(arrived):
                status = ALL_REACHED
                break
            if np.all(arrived | hopeless):
                status = DEADLOCK
                events.append({"step": step, "kind": "deadlock", "detail": "every robot not at its goal has a goal "
                               "it cannot reach (see the goal_unreachable events)"})
                break
            if watch.update(step, stepper.positions):
                status = DEADLOCK
                events.append({"step": step, "kind": "deadlock",
                               "detail": f"no robot came closer to its goal in {self.progress_window} steps"})
                break
            if step % self.deadlock_window == 0 and self._stalled(stepper.positions_, goals):
                status = DEADLOCK
                events.append({"step": step, "kind": "deadlock",
                               "detail": f"no robot visited more than two positions in {self.deadlock_window} "
                                         "steps while some are away from their goals"})
                break
        sim_time = time.perf_counter() - t0
        names = sorted(mode_names, key=mode_names.get)
        traj = stepper.trajectory(
            status, planned_paths=list(self.plan.paths) if self.plan is not None else [],
            meta={"controller": getattr(self.controller, "registered_name", type(self.controller).__name__),
                  "planner": self.plan.planner if self.plan is not None else None,
                  "sim_time_s": sim_time, "controller_time_s": act_time + reset_time,
                  "controller_reset_s": reset_time, "max_steps": budget})
        return dataclasses.replace(traj, modes=np.asarray(modes, np.int8) if modes else None, mode_names=names)

    def _stretched(self, step: int, last_progress: int) -> int:
        """The budget at ``step``, the end of the current one: :data:`PROGRESS_GRACE` of the
        default budget past the last step of progress, when that is later, up to
        :data:`MAX_EXTENSION` times the default budget."""
        grace = max(1, math.ceil(PROGRESS_GRACE * self.max_steps))
        return max(step, min(last_progress + grace, MAX_EXTENSION * self.max_steps))

    @staticmethod
    def _mode_indices(names, mode_names: dict[str, int], n: int) -> list[int]:
        """Indices of a step's behaviour names (one per robot) in the run's list of names."""
        if isinstance(names, str) or len(names) != n:
            raise ConfigError(f"controller returned modes for {len(names)} robots, expected {n}")
        out = [mode_names.setdefault(str(m), len(mode_names)) for m in names]
        if len(mode_names) > MAX_MODE_NAMES:
            raise ConfigError(f"controller reported more than {MAX_MODE_NAMES} distinct behaviour names (modes)")
        return out

    def _stalled(self, positions: list, goals: np.ndarray) -> bool:
        """True when some robot is away from its goal and no robot at all visited more than two
        positions in the window: the ones left wait or shuttle, and nobody clears their way.

        Robots already home count too. In a crowd robots wait for a long time while others
        step aside and back (400 robots in a 1-wide maze following LaCAM's plan: the 13 robots
        still away each moved once in 60 steps while robots that were home let others through,
        and a rule on the robots away alone ended a run that was to finish 250 steps later)."""
        window = np.asarray(positions[-self.deadlock_window:])
        unfinished = np.linalg.norm(window[-1] - goals, axis=1) > GOAL_TOLERANCE
        if not unfinished.any():
            return False
        return bool(np.all(distinct_positions(window) <= 2))

