"""The Gymnasium environment ``swarmpath/Navigate-v0``: one robot learns, the others follow a
controller.

``gymnasium.make("swarmpath/Navigate-v0", scenario=NAME_OR_PATH, robot=0, others=None,
**options)``: the agent drives robot ``robot`` (index or id) of the scenario; every other
robot does what the controller ``others`` (a registered name or a Controller; default: the
scenario's controller when it needs no plan or a planner is given, else ``pibt`` on grids and
``orca`` in continuous worlds) proposes, consulted each step as in ``swarmpath run``. The
observation and action spaces are those of one agent of
:class:`~swarmpath.env.parallel.SwarmpathParallelEnv`, and so are the options, the reward and
the info. The episode terminates when the robot arrives (with ``stay_arrived=True``: when
every robot stands on its goal) and is truncated at the step budget.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

from swarmpath.control.base import Controller
from swarmpath.env.core import EnvCore
from swarmpath.env.options import GRID, EnvOptions
from swarmpath.env.registration import register_envs
from swarmpath.env.spaces import action_space, observation_space
from swarmpath.env.worlds import resolve_world
from swarmpath.errors import ConfigError
from swarmpath.registry import CONTROLLERS
from swarmpath.sim.trajectory import Trajectory
from swarmpath.world.world import World


def default_others(core: EnvCore) -> str:
    """The controller of the other robots when none is named (see the module docs)."""
    name = core.world.defaults.get("controller")
    if name in CONTROLLERS:
        caps = CONTROLLERS.get(name).capabilities
        fits = caps.grid_based if core.mode == GRID else caps.continuous
        if fits and (not caps.needs_plan or core.options.planner is not None):
            return name
    return "pibt" if core.mode == GRID else "orca"


class NavigateEnv(gymnasium.Env):
    """One robot of a swarmpath world as a Gymnasium environment (see the module docs)."""

    metadata = {"render_modes": []}

    def __init__(self, scenario: World | str | Path, robot: int | str = 0, others: str | Controller | None = None,
                 *, scen: str | Path | None = None, agents: int | None = None, **options: Any):
        world = resolve_world(scenario, scen, agents)
        self.core = EnvCore(world, EnvOptions.of(options))
        ids = [r.id for r in world.robots]
        if isinstance(robot, str) and robot in ids:
            self.robot = ids.index(robot)
        elif isinstance(robot, (int, np.integer)) and not isinstance(robot, bool) and 0 <= robot < len(ids):
            self.robot = int(robot)
        else:
            raise ConfigError(f"robot must be an index in 0..{len(ids) - 1} or one of the robot ids, got {robot!r}")
        self.agent = ids[self.robot]
        self.others = (others if others is not None else default_others(self.core)) if len(ids) > 1 else None
        self.observation_space = observation_space(self.core)
        self.action_space = action_space(self.core)
        self.render_mode = None
        register_envs()

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[Any, dict]:
        super().reset(seed=seed)
        self.core.reset(seed)
        return self._observation(), self._info()

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict]:
        core = self.core
        i = self.robot
        if core.n > 1:
            proposed = np.asarray(core.expert_decision(self.others).positions, float).copy()
        else:
            proposed = core.stepper.positions.copy()
        rows = np.array([i], np.int64)
        proposed[i] = core.decode([action], rows)[i]
        core.step(proposed)
        return (self._observation(), float(core.last_rewards_[i]), bool(core.terminated_[i]),
                bool(core.truncated_[i]), self._info())

    def expert_action(self, controller: str | Controller) -> Any:
        """The action that reproduces what ``controller`` would do with this robot now."""
        actions, _ = self.core.expert_actions(controller)
        return np.int64(actions[self.robot]) if self.core.mode == GRID else actions[self.robot].copy()

    def trajectory(self) -> Trajectory:
        """The episode so far (all robots) as a swarmpath Trajectory."""
        return self.core.trajectory()

    def _observation(self) -> Any:
        i = self.robot
        if self.core.mode == GRID:
            patch, goal = self.core.observe()
            return {"patch": patch[i], "goal": goal[i]}
        return self.core.observe()[i]

    def _info(self) -> dict:
        info = self.core.info_rows(np.array([self.robot], np.int64))[0]
        if self.core.mode == GRID:
            info["action_mask"] = self.core.action_mask()[self.robot].astype(np.int8)
        return info
