"""The PettingZoo Parallel environment over the simulator: one agent per robot.

``parallel_env(scenario, **options)`` builds it from a World, a scenario file, a built-in
scenario name, or a MovingAI ``.map`` with ``scen=`` (and ``agents=``). Agents are the robots'
ids; actions, observations, rewards and options are described in :mod:`swarmpath.env.options`,
:mod:`swarmpath.env.actions` and :mod:`swarmpath.env.observations`. Each agent's info holds
the checker's contacts of the step by kind (``robot_robot``, ``robot_static``,
``robot_moving``), its episode total (``contacts_total``), ``invalid_move``, ``at_goal``,
``distance`` and, on grids, the ``action_mask`` of statically possible moves.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from pettingzoo import ParallelEnv

from swarmpath.control.base import Controller
from swarmpath.env.core import EnvCore
from swarmpath.env.options import GRID, EnvOptions
from swarmpath.env.registration import register_envs
from swarmpath.env.spaces import action_space, observation_space
from swarmpath.env.worlds import resolve_world
from swarmpath.errors import ConfigError
from swarmpath.sim.trajectory import Trajectory
from swarmpath.world.world import World


class SwarmpathParallelEnv(ParallelEnv):
    """Many robots, one PettingZoo agent each, stepping the simulator's world model and
    collision checker (see the module docs)."""

    metadata = {"name": "swarmpath_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(self, world: World, options: EnvOptions | None = None):
        self.core = EnvCore(world, options or EnvOptions())
        self.possible_agents: list[str] = [r.id for r in world.robots]
        self.agents: list[str] = []
        self.render_mode = None
        self._index = {a: k for k, a in enumerate(self.possible_agents)}
        self._observation_spaces = {a: observation_space(self.core) for a in self.possible_agents}
        self._action_spaces = {a: action_space(self.core) for a in self.possible_agents}
        #: For each live agent, whether the last expert_actions() call reproduced the
        #: expert's proposal exactly.
        self.expert_exact: dict[str, bool] = {}
        register_envs()

    # ------------------------------------------------------------------ spaces
    def observation_space(self, agent: str):
        return self._observation_spaces[agent]

    def action_space(self, agent: str):
        return self._action_spaces[agent]

    @property
    def world(self) -> World:
        return self.core.world

    @property
    def mode(self) -> str:
        """"grid" or "continuous"."""
        return self.core.mode

    # ------------------------------------------------------------------ the API
    def reset(self, seed: int | None = None, options: dict | None = None) -> tuple[dict, dict]:
        """Start an episode of ``seed`` (``swarmpath run --seed`` of the same number gives the
        same obstacles and experts); without a seed, the seed after the last one."""
        self.core.reset(seed)
        self.agents = list(self.possible_agents)
        self._rows = rows = np.arange(self.core.n)
        return self._observations(rows), self._infos(rows)

    def step(self, actions: dict[str, Any]) -> tuple[dict, dict, dict, dict, dict]:
        if not self.agents:
            return {}, {}, {}, {}, {}
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ConfigError(f"no action for agent {missing[0]!r} ({len(missing)} live agents without one)")
        unknown = [a for a in actions if a not in self._index]
        if unknown:
            raise ConfigError(f"action for unknown agent {unknown[0]!r}")
        core = self.core
        agents = self.agents
        rows = self._rows
        core.step(core.decode([actions[a] for a in agents], rows))
        obs = self._observations(rows)
        rewards = dict(zip(agents, core.last_rewards_[rows].tolist()))
        terminated = dict(zip(agents, core.terminated_[rows].tolist()))
        truncated = dict(zip(agents, core.truncated_[rows].tolist()))
        infos = self._infos(rows)
        if not core.live_[rows].all():
            self.agents = [a for a, alive in zip(agents, core.live_[rows].tolist()) if alive]
            self._rows = np.array([self._index[a] for a in self.agents], np.int64)
        return obs, rewards, terminated, truncated, infos

    def close(self) -> None:
        pass

    # ------------------------------------------------------------------ experts and records
    def expert_actions(self, controller: str | Controller) -> dict[str, Any]:
        """The action of every live agent that reproduces what ``controller`` (a registered
        name or a Controller) would do now; see :attr:`expert_exact`. Consulted from the
        first step on, the rollout of these actions is ``swarmpath run`` with the same seed."""
        actions, exact = self.core.expert_actions(controller)
        rows = [self._index[a] for a in self.agents]
        self.expert_exact = {a: bool(exact[k]) for a, k in zip(self.agents, rows)}
        if self.core.mode == GRID:
            return {a: np.int64(actions[k]) for a, k in zip(self.agents, rows)}
        return {a: actions[k].copy() for a, k in zip(self.agents, rows)}

    def trajectory(self) -> Trajectory:
        """The episode so far as a swarmpath Trajectory (replay, validators, metrics)."""
        return self.core.trajectory()

    # ------------------------------------------------------------------ helpers
    def _observations(self, rows: np.ndarray) -> dict[str, Any]:
        agents = [self.possible_agents[k] for k in rows.tolist()]
        every = len(rows) == self.core.n
        if self.core.mode == GRID:
            patch, goal = self.core.observe()
            if not every:
                patch, goal = patch[rows], goal[rows]
            return {a: {"patch": p, "goal": g} for a, p, g in zip(agents, patch, goal)}
        vectors = self.core.observe()
        return dict(zip(agents, vectors if every else vectors[rows]))

    def _infos(self, rows: np.ndarray) -> dict[str, dict]:
        agents = [self.possible_agents[k] for k in rows.tolist()]
        infos = self.core.info_rows(rows)
        if self.core.mode == GRID:
            for info, mask in zip(infos, self.core.action_mask()[rows].astype(np.int8)):
                info["action_mask"] = mask
        return dict(zip(agents, infos))


def parallel_env(scenario: World | str | Path, *, scen: str | Path | None = None, agents: int | None = None,
                 **options: Any) -> SwarmpathParallelEnv:
    """A PettingZoo ParallelEnv of ``scenario`` (a World, a scenario file, a built-in name, or
    a MovingAI ``.map`` with ``scen`` and optionally the first ``agents`` rows) with the
    options of :class:`~swarmpath.env.options.EnvOptions` as keywords."""
    return SwarmpathParallelEnv(resolve_world(scenario, scen, agents), EnvOptions.of(options))
