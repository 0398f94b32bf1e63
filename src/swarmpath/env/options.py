"""The environments' options: what the agents control and see, how they are rewarded, when an
episode ends. One frozen dataclass each, checked once, so a bad option fails at construction
with one line naming it (a :class:`~swarmpath.errors.ConfigError`)."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

from swarmpath.control.observation import SensingConfig
from swarmpath.errors import ConfigError

GRID, CONTINUOUS = "grid", "continuous"


def _number(name: str, value: Any, *, low: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError(f"{name} must be a finite number, got {value!r}")
    if low is not None and value < low:
        raise ConfigError(f"{name} must be >= {low:g}, got {value!r}")
    return float(value)


def _whole(name: str, value: Any, low: int, high: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < low or (high is not None and value > high):
        bound = f"in [{low}, {high}]" if high is not None else f">= {low}"
        raise ConfigError(f"{name} must be a whole number {bound}, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class Rewards:
    """Reward weights; an agent's reward each step is the sum of

    - ``progress`` times the straight-line distance to its goal gained this step, in units of
      its step length ``max_speed * dt`` (so in [-1, 1] per step);
    - ``arrival`` on the step it reaches its goal (exactly, as the simulator's test);
    - ``step`` on every step it ends away from its goal (a time cost, usually negative);
    - ``robot_contact``, ``static_contact``, ``moving_contact`` per contact of that kind the
      checker finds for it this step (robot-robot contacts count for both robots);
    - ``invalid_move`` when its move was rejected (too long, or not finite).
    """

    progress: float = 1.0
    arrival: float = 10.0
    step: float = -0.01
    robot_contact: float = -1.0
    static_contact: float = -1.0
    moving_contact: float = -1.0
    invalid_move: float = -0.5

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            _number(f"rewards.{f.name}", getattr(self, f.name))

    @classmethod
    def of(cls, value: "Rewards | Mapping[str, float] | None") -> "Rewards":
        """``value`` itself, the defaults (None), or the defaults with the weights a dict gives."""
        if value is None:
            return cls()
        if isinstance(value, cls):
            return value
        if not isinstance(value, Mapping):
            raise ConfigError(f"rewards must be a Rewards or a dict of weights, got {type(value).__name__}")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(value) - names)
        if unknown:
            raise ConfigError(f"unknown reward weight {unknown[0]!r}; choose from: {', '.join(sorted(names))}")
        return cls(**dict(value))


@dataclass(frozen=True)
class EnvOptions:
    """Options of :func:`swarmpath.env.parallel_env` and ``swarmpath/Navigate-v0``.

    Parameters
    ----------
    mode : {"grid", "continuous"} or None
        Grid: 9 discrete moves (5 with ``connectivity=4``) between cell centres. Continuous:
        a velocity in [-1, 1]^2 times the robot's ``max_speed``. None: grid when every robot
        is at most half a cell wide and reaches a neighbouring cell in a step, else continuous.
    connectivity : {8, 4}
        Grid moves: stay and 8 neighbours, or stay and 4.
    view : int
        Grid: the egocentric patch reaches ``view`` cells each side ((2 view + 1)^2 cells).
    neighbours, obstacles, static_points : int
        Continuous: how many nearest robots, moving obstacles and static-obstacle cells the
        observation vector holds (within the sensing range).
    sensing : SensingConfig
        The range and distance classes of the controllers' Observation (the simulator's
        default); the continuous observation sees as far as this range.
    max_steps : int or None
        Step budget of an episode (None: the simulator's default for the world).
    stay_arrived : bool
        False: an agent is terminated when it reaches its goal and parks there (it stays put,
        other robots can still run into it). True: agents keep acting after they arrive and
        all terminate together when every robot stands on its goal at once (the simulator's
        "all reached").
    goal_snap : float or None
        Continuous: a move that ends within this distance (world units) of the robot's goal,
        with the goal itself in reach, ends on the goal (arrival is exact). None: a tenth of
        each robot's step length. 0 turns snapping off.
    rewards : Rewards or dict
        Reward weights (:class:`Rewards`).
    planner : str or None
        An offline planner whose plan the experts receive (as with ``swarmpath run
        --planner``); None: no plan.
    record : bool
        Record the episode as a Trajectory (True; False saves a little time per step).
    seed : int
        Seed of the first episode when ``reset()`` is called without one.
    """

    mode: str | None = None
    connectivity: int = 8
    view: int = 5
    neighbours: int = 6
    obstacles: int = 4
    static_points: int = 8
    sensing: SensingConfig = field(default_factory=SensingConfig)
    max_steps: int | None = None
    stay_arrived: bool = False
    goal_snap: float | None = None
    rewards: Rewards = field(default_factory=Rewards)
    planner: str | None = None
    record: bool = True
    seed: int = 0

    def __post_init__(self) -> None:
        if self.mode not in (None, GRID, CONTINUOUS):
            raise ConfigError(f"mode must be 'grid', 'continuous' or None, got {self.mode!r}")
        if self.connectivity not in (4, 8) or isinstance(self.connectivity, bool):
            raise ConfigError(f"connectivity must be 4 or 8, got {self.connectivity!r}")
        _whole("view", self.view, 1, 64)
        for name in ("neighbours", "obstacles", "static_points"):
            _whole(name, getattr(self, name), 0, 64)
        if not isinstance(self.sensing, SensingConfig):
            raise ConfigError(f"sensing must be a SensingConfig, got {type(self.sensing).__name__}")
        if self.max_steps is not None:
            _whole("max_steps", self.max_steps, 1, 10**9)
        for name in ("stay_arrived", "record"):
            if not isinstance(getattr(self, name), bool):
                raise ConfigError(f"{name} must be True or False, got {getattr(self, name)!r}")
        if self.goal_snap is not None:
            _number("goal_snap", self.goal_snap, low=0.0)
        object.__setattr__(self, "rewards", Rewards.of(self.rewards))
        if self.planner is not None and not isinstance(self.planner, str):
            raise ConfigError(f"planner must be a registered name or None, got {type(self.planner).__name__}")
        _whole("seed", self.seed, 0)

    @classmethod
    def of(cls, options: Mapping[str, Any]) -> "EnvOptions":
        """Options from keyword arguments; an unknown name is refused with the known ones."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(options) - names)
        if unknown:
            raise ConfigError(f"unknown environment option {unknown[0]!r}; choose from: {', '.join(sorted(names))}")
        return cls(**dict(options))
