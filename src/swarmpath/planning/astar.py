"""The ``astar`` planner: an independent shortest grid path for each robot (octile,
8-connected, no corner cutting) on the world's grid inflated for the robot's radius."""
from __future__ import annotations

import time

from swarmpath.capabilities import Capabilities
from swarmpath.planning.base import Plan, Planner, PlanStatus, RobotPlan
from swarmpath.planning.grid_paths import cells_to_polyline
from swarmpath.registry import register_planner
from swarmpath.search import astar
from swarmpath.types import SeedLike


@register_planner("astar")
class AStarPlanner(Planner):
    """Decoupled A*: robots are planned independently, ignoring each other."""

    capabilities = Capabilities(grid_based=True, multi_robot=False)

    def __init__(self, connectivity: int = 8):
        self.connectivity = connectivity

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        t0 = time.perf_counter()
        robots = []
        total_expansions = 0
        for robot in world.robots:
            robots.append(plan_robot_astar(world, robot, self.connectivity))
            total_expansions += robots[-1].diagnostics.get("expansions", 0)
        return Plan("astar", tuple(robots), time.perf_counter() - t0, {"expansions": total_expansions})


def plan_robot_astar(world, robot, connectivity: int = 8) -> RobotPlan:
    """One robot's A* plan on ``world.grid(radius=robot.radius)``, as a world polyline."""
    t0 = time.perf_counter()
    grid = world.grid(radius=robot.radius)
    start, goal = grid.cell_of(robot.start), grid.cell_of(robot.goal)
    if not grid.is_free(start):
        return RobotPlan(robot.id, PlanStatus.INVALID_START, None, {"reason": f"start cell {tuple(start)} is blocked"})
    if not grid.is_free(goal):
        return RobotPlan(robot.id, PlanStatus.INVALID_GOAL, None, {"reason": f"goal cell {tuple(goal)} is blocked"})
    result = astar(grid, start, goal, connectivity=connectivity)
    diag = {"expansions": result.expansions, "time_s": time.perf_counter() - t0,
            "grid_cost": result.cost * grid.resolution}
    if not result:
        return RobotPlan(robot.id, PlanStatus.INFEASIBLE, None, diag)
    return RobotPlan(robot.id, PlanStatus.EXACT, cells_to_polyline(grid, result.cells, robot.start, robot.goal), diag)
