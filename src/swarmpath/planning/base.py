"""What every offline planner returns: one path per robot with a status and diagnostics.

A planner is configured by its constructor (hyperparameters only) and run by
``plan(world, rng=...)``; the same configured planner can plan many worlds and seeds.
"""
from __future__ import annotations

import abc
import enum
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Mapping

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.types import SeedLike


class PlanStatus(enum.Enum):
    """Why a robot's plan is what it is (OMPL's PlannerStatus in spirit)."""

    EXACT = "exact"                  # a path to the goal
    APPROXIMATE = "approximate"      # a path that ends near, not at, the goal
    TIMEOUT = "timeout"              # the budget ran out before a path was found
    LOCAL_MINIMUM = "local_minimum"  # the method stopped short of the goal (a potential field's minimum)
    INVALID_START = "invalid_start"  # the start is blocked or outside the planner's grid
    INVALID_GOAL = "invalid_goal"    # the goal is blocked or outside the planner's grid
    INFEASIBLE = "infeasible"        # no path exists


_STATUS_WORDS = {
    PlanStatus.EXACT: "a path to the goal",
    PlanStatus.APPROXIMATE: "a path that ends near the goal",
    PlanStatus.TIMEOUT: "the planner's budget ran out before it found a path",
    PlanStatus.LOCAL_MINIMUM: "stuck in a local minimum short of the goal",
    PlanStatus.INVALID_START: "the start is blocked or off the planner's grid",
    PlanStatus.INVALID_GOAL: "the goal is blocked or off the planner's grid",
    PlanStatus.INFEASIBLE: "no path exists",
}


@dataclass(frozen=True)
class RobotPlan:
    """The plan of one robot: ``path`` of shape (n_points, 2) in world units, or None.

    ``times`` (n_points,) makes the plan timed: the robot stands on ``path[k]`` at step
    ``times[k]`` (non-decreasing integers, a repeated vertex is a wait). Multi-robot planners
    that coordinate robots in time (``lacam``) return timed plans; untimed polylines leave it
    None and are followed at the robot's speed."""

    robot_id: str
    status: PlanStatus
    path: NDArray[np.float64] | None = None
    diagnostics: Mapping[str, Any] = field(default_factory=dict)
    times: NDArray[np.int64] | None = None

    def __bool__(self) -> bool:
        return self.path is not None and self.status in (PlanStatus.EXACT, PlanStatus.APPROXIMATE)

    @property
    def reason(self) -> str:
        """Why the plan is what it is, in words (for tables and JSON)."""
        given = self.diagnostics.get("reason") if isinstance(self.diagnostics, Mapping) else None
        if given:
            return str(given)
        if self.status is PlanStatus.LOCAL_MINIMUM and "stop_point" in self.diagnostics:
            x, y = (float(v) for v in self.diagnostics["stop_point"])
            return f"stuck in a local minimum at ({x:g}, {y:g})"
        return _STATUS_WORDS[self.status]

    @property
    def length(self) -> float | None:
        """Euclidean length of the path (world units), None without a path."""
        if self.path is None:
            return None
        return float(np.linalg.norm(np.diff(self.path, axis=0), axis=1).sum())


@dataclass(frozen=True)
class Plan:
    """Plans of all robots of a world, in the world's robot order."""

    planner: str
    robots: tuple[RobotPlan, ...]
    wall_time_s: float
    diagnostics: Mapping[str, Any] = field(default_factory=dict)

    def __bool__(self) -> bool:
        return bool(self.robots) and all(bool(r) for r in self.robots)

    @property
    def paths(self) -> list[NDArray[np.float64] | None]:
        return [r.path for r in self.robots]

    def __len__(self) -> int:
        return len(self.robots)

    def __getitem__(self, i: int) -> RobotPlan:
        return self.robots[i]

    def save(self, path: str | Path) -> Path:
        """Write the plan to ``path`` as JSON (format: swarmpath.planning.plan_io)."""
        from swarmpath.planning.plan_io import write_plan

        return write_plan(self, path)

    @classmethod
    def load(cls, path: str | Path) -> "Plan":
        """Read a plan written by :meth:`save` (a malformed file raises ConfigError)."""
        from swarmpath.planning.plan_io import read_plan

        return read_plan(path, plan_type=cls, robot_type=RobotPlan, status_type=PlanStatus)


class Planner(abc.ABC):
    """Base class of offline planners (register subclasses with ``@register_planner``)."""

    capabilities: ClassVar[Capabilities] = Capabilities()
    registered_name: ClassVar[str] = ""

    @abc.abstractmethod
    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        """One :class:`RobotPlan` per robot of ``world``, in the world's robot order."""
