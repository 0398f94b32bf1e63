"""The motion-model protocol: what the simulator, the scenario files and the controllers
need to know about how a moving obstacle moves.

A motion model is one small frozen class in its own module of this package, registered by
name with ``@register_motion("name")`` (the name is the ``motion:`` value of scenario
files). It says

- how the obstacle moves in one step (:meth:`Motion.advance`), from its position, velocity
  and one integer of its own state, with the step's shared context (the static world, the
  run's obstacle random stream, the robots' cells);
- how far it can go in one step at worst (:meth:`Motion.max_step`) and whether it teleports
  instead of travelling (``teleports``): controllers keep out of that reach, and the checker
  sweeps only obstacles that travel;
- which of the forecast classes of grid controllers describes it (``forecast``): ``bounce``
  (straight on, reflected components when blocked), ``bounce8`` (straight on, any of 8
  compass directions when blocked), ``random-walk`` (any of 8 grid steps), ``teleport``
  (reappears anywhere), or ``any-heading`` (anywhere within :meth:`max_step`; the safe
  default for a new model), with the steps on which an any-heading model surely moves as
  ``bounce`` does (:meth:`Motion.steady_steps`: ``turn-every`` between its turns);
- its scenario-file parameters (``parameters``: name -> (type, pydantic Field)), how it is
  built from them (:meth:`from_parameters`), written back (:meth:`to_dict`) and checked
  against a world (:meth:`check`), and an instance for the conformance checks
  (:meth:`example`).

Motions never read robots except through ``keep_clear`` (the paper's obstacles ignore robots).
"""
from __future__ import annotations

import abc
import math
from dataclasses import dataclass, field
from typing import Any, ClassVar, Mapping, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

FORECASTS = ("bounce", "bounce8", "random-walk", "teleport", "any-heading")


class Footprinted(Protocol):
    """What a motion reads of a moving obstacle (``swarmpath.world.moving.MovingObstacle``)."""

    id: str
    start: tuple[float, float]
    velocity: tuple[float, float]

    @property
    def speed(self) -> float: ...


class Terrain(Protocol):
    """What a motion reads of the world (``swarmpath.world.World``): the static geometry."""

    dt: float
    resolution: float

    def obstacle_fits(self, ob: Any, positions: ArrayLike) -> NDArray[np.bool_]: ...

    def grid(self, resolution: float | None = None, radius: float = 0.0) -> Any: ...


@dataclass
class StepContext:
    """What all obstacles of one step share: the world, the run's obstacle stream (used by
    the obstacles in their order, so adding a model never shifts another's draws), the step
    number, the points a redrawn obstacle must not land on (robots and their goals, shape
    (k, 2)), and scratch space that models may fill once per step (e.g. free cells)."""

    terrain: Terrain
    rng: np.random.Generator
    step: int
    keep_clear: FloatArray | None = None
    scratch: dict[str, Any] = field(default_factory=dict)


class Motion(abc.ABC):
    """Base class of motion models (frozen dataclasses registered with ``register_motion``)."""

    kind: ClassVar[str] = ""
    teleports: ClassVar[bool] = False
    #: The model's moves depend on nothing but its own state (no random draws, no robots), so a
    #: controller that replays :meth:`advance` from the obstacle's start knows its future
    #: exactly (``waypoints``); grid controllers then forecast it step by step.
    scripted: ClassVar[bool] = False
    forecast: ClassVar[str] = "any-heading"
    #: The model only ever moves the footprint to a position where it fits (``obstacle_fits``
    #: at the end of each step), so it goes round walls thicker than its step rather than
    #: through them: grid controllers then bound where it can be by the cells it can reach
    #: (:mod:`swarmpath.control.obstacle_reach`). False (the safe default) for new models.
    stays_clear: ClassVar[bool] = False
    #: Scenario-file parameters of this model: name -> (annotation, pydantic FieldInfo).
    parameters: ClassVar[Mapping[str, tuple[Any, Any]]] = {}

    @abc.abstractmethod
    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        """One step of ``ctx.terrain.dt``: the new (position (2,), velocity (2,), counter)."""

    def max_step(self, ob: Footprinted, dt: float, resolution: float) -> float:
        """The longest distance the obstacle's position can move in one step (world units);
        ``inf`` for a model that teleports."""
        return math.inf if self.teleports else ob.speed * dt

    def steady_steps(self, step: int) -> int:
        """For a model of the ``any-heading`` forecast class: how many of the steps after
        step ``step`` (the steps ``step + 1``, ``step + 2``, ...) it surely moves as ``bounce``
        does (straight on at its velocity, reflected where blocked) before it may head
        anywhere. Grid controllers then forecast it as tightly as a bouncer until then. 0
        (default): it may turn on any step."""
        return 0

    @classmethod
    def example(cls) -> "Motion":
        """An instance for the conformance checks (:func:`swarmpath.testing.check_motion`)
        on their 10 x 10 test room; the default instance unless the model needs parameters."""
        return cls()

    @classmethod
    def from_parameters(cls, values: Mapping[str, Any]) -> "Motion":
        """The model from its scenario parameters (``None`` for parameters not given)."""
        return cls(**{k: v for k, v in values.items() if v is not None})

    def to_dict(self) -> dict[str, Any]:
        """The scenario-file form: ``{"motion": kind, **parameters}``."""
        return {"motion": self.kind}

    def check(self, ob: Footprinted, terrain: Terrain, where: str) -> None:
        """Raise :class:`~swarmpath.errors.ScenarioError` when this model cannot run in the
        world (``where`` names the obstacle's field, e.g. ``moving_obstacles[2]``)."""

