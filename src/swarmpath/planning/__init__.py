"""Offline planners: one path per robot before the robots move (registered by name)."""
from swarmpath.planning.base import Capabilities, Plan, Planner, PlanStatus, RobotPlan

__all__ = ["Capabilities", "Plan", "Planner", "PlanStatus", "RobotPlan", "plan"]


def plan(world, planner: str = "astar", *, seed: int = 0, **hyperparameters) -> Plan:
    """Plan ``world`` with the registered planner ``planner`` (front door)."""
    from swarmpath.registry import PLANNERS

    return PLANNERS.get(planner)(**hyperparameters).plan(world, rng=seed)
