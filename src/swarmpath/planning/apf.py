"""The ``apf`` planner: steepest descent on the artificial potential field (Jaleel & Hassan
2016, section III.1.C, Algorithm 1 step 5), without any repair.

The descent runs on the cells of ``world.grid(radius=robot.radius)``: from the start cell it
moves to the 8-neighbour with the steepest descent ``(U(next) - U(here)) / step length``
(a diagonal step is sqrt 2 cells long and needs both orthogonal neighbours free: no corner
cutting), until it enters the goal cell. It stops at a local minimum when

- no neighbour is lower than the current cell (``"no_descent"``),
- it would enter a cell it has already visited (``"revisit"``; cannot happen with strict
  descent, kept as a guard), or
- the step budget runs out (``"step_budget"``).

The goal cell is a sink: a robot next to it steps in (the goal may lie on a cell border, where
the cells around it have equal attraction).

Statuses: ``EXACT`` with the path when the goal is reached. At a local minimum the plan is
falsy: status ``LOCAL_MINIMUM`` (the descent stopped short of the goal; ``INFEASIBLE`` would
claim no path exists), path ``None``, and ``diagnostics["local_minimum"] = True`` with the stop reason, the stop point and
the partial path (``diagnostics["partial_path"]``, a world polyline from the exact start).
"""
from __future__ import annotations

import time
import weakref
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import ConfigError
from swarmpath.capabilities import Capabilities
from swarmpath.planning.base import Plan, Planner, PlanStatus, RobotPlan
from swarmpath.planning.grid_paths import cells_to_polyline
from swarmpath.planning.potential_field import FieldParameters, PotentialField, potential_field
from swarmpath.registry import register_planner
from swarmpath.types import SeedLike
from swarmpath.world.grid import OccupancyGrid

SQRT2 = float(np.sqrt(2.0))
# The 8 moves (dx, dy), orthogonal first; ties go to the first in this order.
_MOVES = ((1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, 1), (-1, -1), (1, -1))


@dataclass(frozen=True)
class Descent:
    """Result of a steepest descent: ``cells`` (int array (n, 2) of (x, y), start first),
    whether it ``reached`` the goal cell, and why it stopped (``"goal"``, ``"no_descent"``,
    ``"revisit"``, ``"step_budget"``)."""

    cells: NDArray[np.int64]
    reached: bool
    stop_reason: str

    @property
    def steps(self) -> int:
        return len(self.cells) - 1


_FREE: "weakref.WeakKeyDictionary[OccupancyGrid, list[bool]]" = weakref.WeakKeyDictionary()


def _padded_free(grid: OccupancyGrid) -> list[bool]:
    """``~grid.blocked`` with a ring of blocked cells around it, flattened (cached per grid)."""
    hit = _FREE.get(grid)
    if hit is None:
        free = np.zeros((grid.height + 2, grid.width + 2), dtype=bool)
        free[1:-1, 1:-1] = ~grid.blocked
        hit = _FREE[grid] = free.ravel().tolist()
    return hit


def default_step_budget(grid) -> int:
    """Steps allowed to a descent when none is given: four times the grid's perimeter in
    cells (a descent never revisits a cell, so this only bounds pathological fields)."""
    return 4 * (grid.width + grid.height)


def steepest_descent(field: PotentialField, start_cell, goal_cell, max_steps: int | None = None) -> Descent:
    """Steepest descent of ``field.total`` over the 8 neighbours from ``start_cell`` (x, y)
    until ``goal_cell`` (see the module docstring for the rules and the stop reasons)."""
    grid = field.grid
    h, w = grid.height, grid.width
    budget = default_step_budget(grid) if max_steps is None else int(max_steps)
    # Pad with one ring of blocked cells so that neighbour lookups need no bounds checks.
    u = np.full((h + 2, w + 2), np.inf)
    u[1:-1, 1:-1] = field.total
    uf = u.ravel()
    ff = _padded_free(grid)
    stride = w + 2
    moves = [(dx, dy, dx + dy * stride, SQRT2 if dx and dy else 1.0) for dx, dy in _MOVES]
    x, y = int(start_cell[0]), int(start_cell[1])
    gx, gy = int(goal_cell[0]), int(goal_cell[1])
    goal_idx = (gy + 1) * stride + gx + 1
    here = (y + 1) * stride + x + 1
    cells = [(x, y)]
    visited = {here}
    reason = "goal"
    while here != goal_idx:
        if len(cells) - 1 >= budget:
            reason = "step_budget"
            break
        best, best_slope = -1, 0.0
        u_here = uf[here]
        for dx, dy, off, length in moves:
            nxt = here + off
            if not ff[nxt]:
                continue
            if dx and dy and not (ff[here + dx] and ff[here + dy * stride]):
                continue  # no corner cutting
            if nxt == goal_idx:
                best = nxt
                break
            slope = (uf[nxt] - u_here) / length
            if slope < best_slope:
                best, best_slope = nxt, slope
        if best < 0:
            reason = "no_descent"
            break
        if best in visited:
            reason = "revisit"
            break
        visited.add(best)
        here = best
        cells.append((here % stride - 1, here // stride - 1))
    return Descent(np.asarray(cells, dtype=np.int64), reason == "goal", reason)


@dataclass(frozen=True)
class APFOutcome:
    """One robot's APF descent with its field, for the hybrid planner and the figures."""

    plan: RobotPlan
    field: PotentialField | None
    descent: Descent | None


def apf_robot(world, robot, params: FieldParameters, max_steps: int | None = None) -> APFOutcome:
    """Plan one robot with the plain APF descent (see the module docstring)."""
    t0 = time.perf_counter()
    grid = world.grid(radius=robot.radius)
    start, goal = grid.cell_of(robot.start), grid.cell_of(robot.goal)
    if not grid.is_free(start):
        return APFOutcome(RobotPlan(robot.id, PlanStatus.INVALID_START, None,
                                    {"reason": f"start cell {tuple(start)} is blocked"}), None, None)
    if not grid.is_free(goal):
        return APFOutcome(RobotPlan(robot.id, PlanStatus.INVALID_GOAL, None,
                                    {"reason": f"goal cell {tuple(goal)} is blocked"}), None, None)
    field = potential_field(world, robot.goal, radius=robot.radius, params=params)
    descent = steepest_descent(field, start, goal, max_steps)
    diag: dict = {"steps": descent.steps, "stop_reason": descent.stop_reason,
                  "local_minimum": not descent.reached, "local_minima": int(not descent.reached)}
    if descent.reached:
        path = cells_to_polyline(grid, descent.cells, robot.start, robot.goal)
        diag["time_s"] = time.perf_counter() - t0
        return APFOutcome(RobotPlan(robot.id, PlanStatus.EXACT, path, diag), field, descent)
    partial = cells_to_polyline(grid, descent.cells, robot.start, grid.centers(descent.cells[-1]))
    stop = grid.centers(descent.cells[-1])
    diag.update({"stop_point": stop, "stop_cell": descent.cells[-1].copy(), "partial_path": partial,
                 "distance_to_goal": float(np.linalg.norm(stop - np.asarray(robot.goal, float))),
                 "time_s": time.perf_counter() - t0})
    return APFOutcome(RobotPlan(robot.id, PlanStatus.LOCAL_MINIMUM, None, diag), field, descent)


def _check_budget(max_steps: int | None) -> None:
    if max_steps is not None and not (isinstance(max_steps, (int, np.integer)) and max_steps >= 1):
        raise ConfigError(f"max_steps must be a whole number >= 1 or None, got {max_steps!r}")


@register_planner("apf")
class APFPlanner(Planner):
    """Plain artificial potential field planner: steepest descent per robot, no repair.

    Parameters (world units; paper values as defaults): ``attractive_gain`` zeta,
    ``quadratic_range`` d*_goal, ``repulsive_gain`` eta, ``influence_range`` Q*;
    ``max_steps`` the descent's step budget (None: four times the grid perimeter)."""

    capabilities = Capabilities(grid_based=True, multi_robot=False)

    def __init__(self, attractive_gain: float = 0.5, quadratic_range: float = 15.0, repulsive_gain: float = 1.0,
                 influence_range: float = 1.0, max_steps: int | None = None):
        self.attractive_gain = attractive_gain
        self.quadratic_range = quadratic_range
        self.repulsive_gain = repulsive_gain
        self.influence_range = influence_range
        self.max_steps = max_steps
        self._params()
        _check_budget(max_steps)

    def _params(self) -> FieldParameters:
        return FieldParameters(self.attractive_gain, self.quadratic_range, self.repulsive_gain, self.influence_range)

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        t0 = time.perf_counter()
        params = self._params()
        robots = tuple(apf_robot(world, r, params, self.max_steps).plan for r in world.robots)
        minima = sum(int(r.diagnostics.get("local_minimum", False)) for r in robots)
        return Plan("apf", robots, time.perf_counter() - t0, {"local_minima": minima})
