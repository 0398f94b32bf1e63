"""The controller interface: online, per-step policies that choose robots' next positions.

``reset(world, plan, rng)`` prepares a run; ``act(observation)`` returns the next position of
every robot (or a :class:`Decision` that also names each robot's behaviour). A controller
never moves obstacles and never decides whether a collision happened: the simulator does.
"""
from __future__ import annotations

import abc
from dataclasses import dataclass, field
from typing import ClassVar, Sequence

import numpy as np
from numpy.typing import NDArray

from swarmpath.planning.base import Capabilities


@dataclass(frozen=True)
class Decision:
    """Next positions (n, 2) plus, optionally, each robot's behaviour this step (e.g. "seek",
    "trace", "prey", "wait") and notable events (dicts with "robot" and "kind")."""

    positions: NDArray[np.float64]
    modes: Sequence[str] | None = None
    events: Sequence[dict] = field(default_factory=tuple)


class Controller(abc.ABC):
    """Base class of controllers (register subclasses with ``@register_controller``)."""

    capabilities: ClassVar[Capabilities] = Capabilities()
    registered_name: ClassVar[str] = ""

    @abc.abstractmethod
    def reset(self, world, plan, rng: np.random.Generator) -> None:
        """Prepare a run of ``world`` with the offline ``plan`` (None without a planner)."""

    @abc.abstractmethod
    def act(self, observation) -> "Decision | NDArray[np.float64]":
        """Next positions of all robots, shape (n_robots, 2), or a :class:`Decision`."""
