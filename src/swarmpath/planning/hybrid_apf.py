"""The ``hybrid-apf`` planner: Algorithm 1 of Jaleel & Hassan 2016 (section III.1.D).

For each robot: descend the potential field (the ``apf`` planner's steepest descent). If the
descent reaches the goal, that is the path. Otherwise, from the stop point SS (the local
minimum) run A* on the same grid to the goal, smooth the A* part with a B-spline that stays
collision-free (:func:`swarmpath.search.smoothing.smooth_path`) and return APF part + smoothed
part. The junction is the centre of the stop cell; the smoothed part starts there exactly.

Path points: the APF part moves between centres of 8-adjacent cells; the smoothed part is
resampled so consecutive points are at most one cell (``resolution``) apart. Every step is
therefore at most sqrt 2 cells long, which a grid controller moving one cell (diagonal
included) per step can follow vertex by vertex.
"""
from __future__ import annotations

import time

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.planning.apf import _check_budget, apf_robot
from swarmpath.capabilities import Capabilities
from swarmpath.planning.base import Plan, Planner, PlanStatus, RobotPlan
from swarmpath.planning.grid_paths import cells_to_polyline
from swarmpath.planning.potential_field import FieldParameters
from swarmpath.registry import register_planner
from swarmpath.search import astar
from swarmpath.search.smoothing import dedupe, smooth_path
from swarmpath.types import SeedLike


def hybrid_robot(world, robot, params: FieldParameters, max_steps: int | None = None, smooth: bool = True,
                 degree: int = 3) -> RobotPlan:
    """Algorithm 1 for one robot (see the module docstring). Diagnostics: ``time_s``,
    ``local_minima`` (0 or 1), ``fallback_used`` (A* repair ran), ``expansions`` (A*),
    ``apf_steps``, ``stop_reason``, ``stop_point``, ``smoothing_refinements``,
    ``smoothing_kept_points``, ``smoothing_fallback``, ``apf_length``, ``repair_length``."""
    t0 = time.perf_counter()
    outcome = apf_robot(world, robot, params, max_steps)
    apf = outcome.plan
    if apf.status in (PlanStatus.INVALID_START, PlanStatus.INVALID_GOAL):
        return apf
    d = apf.diagnostics
    diag: dict = {"apf_steps": d["steps"], "stop_reason": d["stop_reason"], "local_minima": d["local_minima"],
                  "fallback_used": False, "expansions": 0}
    if apf:
        diag["apf_length"] = apf.length
        diag["time_s"] = time.perf_counter() - t0
        return RobotPlan(robot.id, PlanStatus.EXACT, apf.path, diag)
    grid = outcome.field.grid
    stop_cell = outcome.descent.cells[-1]
    goal_cell = grid.cell_of(robot.goal)
    result = astar(grid, stop_cell, goal_cell)
    partial = d["partial_path"]
    diag.update({"fallback_used": True, "expansions": result.expansions, "stop_point": d["stop_point"],
                 "apf_length": float(np.linalg.norm(np.diff(partial, axis=0), axis=1).sum())})
    if not result:
        diag["partial_path"] = partial
        diag["time_s"] = time.perf_counter() - t0
        return RobotPlan(robot.id, PlanStatus.INFEASIBLE, None, diag)
    repair = cells_to_polyline(grid, result.cells, grid.centers(stop_cell), robot.goal)
    if smooth:
        sm = smooth_path(world, repair, robot.radius, degree=degree, max_step=grid.resolution)
        repair = sm.path
        diag.update({"smoothing_refinements": sm.refinements, "smoothing_kept_points": sm.kept_points,
                     "smoothing_fallback": sm.fallback})
    diag["repair_length"] = float(np.linalg.norm(np.diff(repair, axis=0), axis=1).sum())
    path = dedupe(np.concatenate([partial, repair[1:]]))
    diag["time_s"] = time.perf_counter() - t0
    return RobotPlan(robot.id, PlanStatus.EXACT, path, diag)


@register_planner("hybrid-apf")
class HybridAPFPlanner(Planner):
    """APF descent, repaired by A* + B-spline from a local minimum (Algorithm 1).

    Parameters (world units; paper values as defaults): ``attractive_gain`` zeta,
    ``quadratic_range`` d*_goal, ``repulsive_gain`` eta, ``influence_range`` Q*; ``max_steps``
    the descent's step budget (None: four times the grid perimeter); ``smooth`` whether the
    A* part is smoothed; ``degree`` the B-spline degree."""

    capabilities = Capabilities(continuous=True, multi_robot=False)

    def __init__(self, attractive_gain: float = 0.5, quadratic_range: float = 15.0, repulsive_gain: float = 1.0,
                 influence_range: float = 1.0, max_steps: int | None = None, smooth: bool = True,
                 degree: int = 3):
        self.attractive_gain = attractive_gain
        self.quadratic_range = quadratic_range
        self.repulsive_gain = repulsive_gain
        self.influence_range = influence_range
        self.max_steps = max_steps
        self.smooth = smooth
        self.degree = degree
        self._params()
        _check_budget(max_steps)
        if not (isinstance(degree, (int, np.integer)) and 1 <= degree <= 5):
            raise ConfigError(f"degree must be a whole number from 1 to 5, got {degree!r}")

    def _params(self) -> FieldParameters:
        return FieldParameters(self.attractive_gain, self.quadratic_range, self.repulsive_gain, self.influence_range)

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        t0 = time.perf_counter()
        params = self._params()
        robots = tuple(hybrid_robot(world, r, params, self.max_steps, self.smooth, self.degree)
                       for r in world.robots)
        diag = {"local_minima": sum(int(r.diagnostics.get("local_minima", 0)) for r in robots),
                "fallbacks": sum(int(bool(r.diagnostics.get("fallback_used", False))) for r in robots),
                "expansions": sum(int(r.diagnostics.get("expansions", 0)) for r in robots)}
        return Plan("hybrid-apf", robots, time.perf_counter() - t0, diag)
