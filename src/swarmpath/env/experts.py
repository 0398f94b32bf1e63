"""Experts: registered controllers consulted on the environment's state, as the simulator would.

An expert is reset once per episode, when first consulted, with the world, the episode's
plan and the run's ``make_rng(seed, "controller")`` stream, and acts at most once per step on
the step's :class:`~swarmpath.control.observation.Observation` (asking twice in a step gives
the same :class:`~swarmpath.control.base.Decision`). Consulted at every step from the first,
it sees exactly what it would see in ``swarmpath run`` with the same seed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import CONTROLLERS
from swarmpath.rng import make_rng
from swarmpath.world.world import World


def expert_name(controller: str | Controller) -> str:
    """The registered name of a controller (or of its class), for records."""
    if isinstance(controller, str):
        return controller
    return getattr(controller, "registered_name", "") or type(controller).__name__


@dataclass
class _Entry:
    controller: Controller
    episode: int = -1
    step: int = -1
    decision: Decision | None = None


class ExpertPool:
    """The experts of one environment, by registered name or by controller object."""

    def __init__(self) -> None:
        self._entries: dict[object, _Entry] = {}

    def _entry(self, controller: str | Controller) -> _Entry:
        if isinstance(controller, str):
            key: object = controller
            if key not in self._entries:
                self._entries[key] = _Entry(CONTROLLERS.get(controller)())
        elif isinstance(controller, Controller):
            key = ("object", id(controller))
            entry = self._entries.get(key)
            if entry is None or entry.controller is not controller:
                self._entries[key] = _Entry(controller)
        else:
            raise ConfigError(f"an expert is a registered controller name or a Controller, got "
                              f"{type(controller).__name__}")
        return self._entries[key]

    def decision(self, controller: str | Controller, *, world: World, plan: Plan | None, seed: int, episode: int,
                 observation: Observation) -> Decision:
        """The expert's decision for the step of ``observation`` (reset first if this is its
        first consultation in ``episode``)."""
        entry = self._entry(controller)
        ctrl = entry.controller
        if entry.episode != episode:
            caps = getattr(ctrl, "capabilities", None)
            if plan is None and caps is not None and caps.needs_plan:
                raise ConfigError(f"expert {expert_name(controller)!r} needs an offline plan; create the "
                                  "environment with planner=... (e.g. planner='astar')")
            ctrl.reset(world, plan, make_rng(seed, "controller"))
            entry.episode, entry.step, entry.decision = episode, -1, None
        if entry.step != observation.step:
            decision = ctrl.act(observation)
            if not isinstance(decision, Decision):
                try:
                    decision = Decision(np.asarray(decision, float))
                except (TypeError, ValueError):
                    raise ConfigError(f"expert {expert_name(controller)!r} returned {type(decision).__name__}, "
                                      "not a Decision or an array of positions") from None
            positions = np.asarray(decision.positions, float)
            if positions.shape != observation.positions.shape:
                raise ConfigError(f"expert {expert_name(controller)!r} returned positions of shape "
                                  f"{positions.shape}, expected {observation.positions.shape}")
            entry.step, entry.decision = observation.step, decision
            return decision
        return entry.decision  # type: ignore[return-value]  # set at this step
