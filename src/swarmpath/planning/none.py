"""The ``none`` planner: no offline plan, for controllers that plan online by themselves."""
from __future__ import annotations

from swarmpath.planning.base import Plan, Planner
from swarmpath.registry import register_planner
from swarmpath.types import SeedLike


@register_planner("none")
class NoPlanner(Planner):
    """Returns an empty plan; the run then simulates without one."""

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        return Plan("none", (), 0.0)
