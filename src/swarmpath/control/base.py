"""The controller interface: online, per-step policies that choose robots' next positions.

``reset(world, plan, rng)`` prepares a run; ``act(observation)`` returns the next position of
every robot as a :class:`Decision` (which may also name each robot's behaviour). A controller
never moves obstacles and never decides whether a collision happened: the simulator does.
"""
from __future__ import annotations

import abc
from dataclasses import dataclass, field
from typing import ClassVar, Sequence

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.observation import Observation
from swarmpath.planning.base import Plan
from swarmpath.world.world import World


@dataclass(frozen=True)
class Decision:
    """Next positions (n, 2) plus, optionally, each robot's behaviour this step (e.g. "seek",
    "trace", "prey", "wait") and notable events (dicts with "robot" and "kind")."""

    positions: NDArray[np.float64]
    modes: Sequence[str] | None = None
    events: Sequence[dict] = field(default_factory=tuple)


class Controller(abc.ABC):
    """Base class of controllers (register subclasses with ``@register_controller``).

    Constructors store hyperparameters only; everything a run creates is set in ``reset``
    (names with a trailing underscore), so one configured controller runs many worlds and
    seeds."""

    capabilities: ClassVar[Capabilities] = Capabilities()
    registered_name: ClassVar[str] = ""

    @abc.abstractmethod
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        """Prepare a run of ``world`` with the offline ``plan`` (None without a planner)."""

    @abc.abstractmethod
    def act(self, obs: Observation) -> Decision:
        """The next positions of all robots, shape (n_robots, 2), as a :class:`Decision`."""
