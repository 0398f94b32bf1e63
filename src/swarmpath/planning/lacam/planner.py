"""The ``lacam`` planner: a timed, collision-free joint plan for all robots of a static world.

The world is planned on its occupancy grid ``world.grid(radius=largest robot radius)`` with
the checker's robot-robot rule (``move_rules.grid_conflict_table`` for that radius), so a plan
executed by the ``follow`` controller has no contact. Every robot's path has one vertex per
step (``times = arange(len(path))``), all paths the same length (makespan + 1, padded with
the goal); the first vertex is the exact start, the last the exact goal. When a start or goal
lies off its cell's centre, one extra step first moves every such robot to its cell centre
(the others wait), and one last step moves robots from their goal cell's centre to the exact
goal.

Before searching, robots whose start or goal is not a free cell get ``INVALID_START`` /
``INVALID_GOAL``, robots whose goal is cut off from their start ``INFEASIBLE`` (checked with
the lazy distance tables); then no joint plan exists and every other robot is ``INFEASIBLE``
too, with the reason in its diagnostics. Moving obstacles are ignored (capabilities say so).
"""
from __future__ import annotations

import time

import numpy as np

from swarmpath.capabilities import Capabilities
from swarmpath.control.pibt.core import GridGraph, check_connectivity, static_moves
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan, Planner, PlanStatus, RobotPlan
from swarmpath.planning.lacam.search import RESTART, lacam_search
from swarmpath.registry import register_planner
from swarmpath.rng import make_rng
from swarmpath.search.lazy_distance import LazyDistanceTables, choose_landmarks
from swarmpath.types import SeedLike


@register_planner("lacam")
class LaCAMPlanner(Planner):
    """LaCAM (Okumura, AAAI 2023) with re-insertion (IJCAI 2023), PIBT swaps and random
    restarts (both from LaCAM3).

    Parameters
    ----------
    connectivity : int
        8 (octile moves without corner cutting) or 4.
    time_limit : float
        Wall-clock budget of the search in seconds (10).
    node_limit : int
        Budget of high-level nodes (configurations) created (1,000,000).
    swap : bool
        LaCAM3's swap emulation inside PIBT (True).
    restart : float
        Random restarts: a search step that yields no new configuration goes back to the
        start with chance ``restart / (depth + 1)`` (0.3; 0: none; see
        :func:`~swarmpath.planning.lacam.search.lacam_search`).
    landmarks : int or "auto"
        Landmark cells of the distance tables' differential heuristic ("auto": 8 when there is
        a robot per 4,096 free cells or more, else 0; 0: octile only).
    """

    capabilities = Capabilities(grid_based=True, multi_robot=True, randomized=True)

    def __init__(self, connectivity: int = 8, time_limit: float = 10.0, node_limit: int = 1_000_000,
                 swap: bool = True, landmarks: int | str = "auto", restart: float = RESTART):
        self.restart = restart
        self.connectivity = connectivity
        self.landmarks = landmarks
        self.time_limit = time_limit
        self.node_limit = node_limit
        self.swap = swap

    def _check(self) -> None:
        check_connectivity(self.connectivity, "lacam")
        if not self.time_limit > 0:
            raise ConfigError(f"lacam: time_limit must be > 0 seconds, got {self.time_limit!r}")
        if isinstance(self.restart, bool) or not isinstance(self.restart, (int, float)) \
                or not 0 <= self.restart < float("inf"):
            raise ConfigError(f"lacam: restart must be a finite number >= 0, got {self.restart!r}")
        if int(self.node_limit) < 1:
            raise ConfigError(f"lacam: node_limit must be >= 1, got {self.node_limit!r}")

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        self._check()
        t0 = time.perf_counter()
        gen = make_rng(rng, "lacam")
        n = world.n_robots
        res = world.resolution
        radius = float(world.radii.max(initial=0.0))
        grid = world.grid(radius=radius)
        h, w = grid.blocked.shape
        starts_xy = np.clip(grid.cell_of(world.starts), 0, [w - 1, h - 1]) if n else np.zeros((0, 2), np.int64)
        goals_xy = np.clip(grid.cell_of(world.goals), 0, [w - 1, h - 1]) if n else np.zeros((0, 2), np.int64)
        status: list[PlanStatus | None] = [None] * n
        reasons: list[str] = [""] * n
        if radius > res / 2 + 1e-12:
            for i in range(n):
                status[i] = PlanStatus.INVALID_START
                reasons[i] = f"lacam plans robots of radius up to half a cell ({res / 2:g}); the largest is {radius:g}"
        else:
            self._check_cells(grid, world, starts_xy, "start", PlanStatus.INVALID_START, status, reasons)
            self._check_cells(grid, world, goals_xy, "goal", PlanStatus.INVALID_GOAL, status, reasons)
        tables = LazyDistanceTables(grid.blocked, connectivity=self.connectivity,
                                    landmarks=choose_landmarks(self.landmarks, world.n_robots, grid.blocked))
        handles = np.full(n, -1, np.int64)
        ok = np.flatnonzero([st is None for st in status])
        if len(ok):
            handles[ok] = tables.acquire_many(goals_xy[ok])
            cut = ok[~np.isfinite(tables.distances(handles[ok], starts_xy[ok]))]
            for i in cut.tolist():
                status[i] = PlanStatus.INFEASIBLE
                reasons[i] = "the goal is cut off from the start on the grid"
        diag = {"connectivity": self.connectivity, "grid": [w, h], "radius": radius}
        bad = [i for i in range(n) if status[i] is not None]
        if bad:
            first = world.robots[bad[0]].id
            robots = tuple(RobotPlan(r.id, status[i] or PlanStatus.INFEASIBLE, None,
                                     {"reason": reasons[i] or f"no joint plan: robot {first!r} cannot be planned"})
                           for i, r in enumerate(world.robots))
            return Plan("lacam", robots, time.perf_counter() - t0, {**diag, "reason": f"robot {first!r}: "
                                                                           f"{reasons[bad[0]]}"})
        graph = GridGraph.build(grid.blocked, self.connectivity, radius, res)
        moves = static_moves(grid.blocked, self.connectivity).reshape(h * w, 9)
        flat = lambda c: (c[:, 1] * w + c[:, 0]).astype(np.int32)  # noqa: E731
        budget = self.time_limit - (time.perf_counter() - t0)
        result = lacam_search(graph, tables, handles, flat(starts_xy), flat(goals_xy), moves, gen,
                              time_limit=max(budget, 0.0), node_limit=int(self.node_limit), swap=self.swap,
                              restart=float(self.restart))
        diag.update({"nodes": result.nodes, "iterations": result.iterations, "pibt_calls": result.pibt_calls,
                     "search_time_s": result.time_s, "expanded_cells": sum(tables.expanded(hd) for hd in set(handles))})
        if result.configs is None:
            why = {"timeout": f"time limit of {self.time_limit:g} s reached",
                   "node_limit": f"node limit of {self.node_limit} reached",
                   "exhausted": "every reachable configuration explored: no joint plan"}[result.reason]
            st = PlanStatus.INFEASIBLE if result.reason == "exhausted" else PlanStatus.TIMEOUT
            robots = tuple(RobotPlan(r.id, st, None, {"reason": why}) for r in world.robots)
            return Plan("lacam", robots, time.perf_counter() - t0, {**diag, "reason": why})
        paths = self._world_paths(world, grid, result.configs)
        makespan = len(paths[0]) - 1 if n else 0
        robots = tuple(RobotPlan(r.id, PlanStatus.EXACT, paths[i], {"makespan": makespan},
                                 np.arange(len(paths[i]), dtype=np.int64)) for i, r in enumerate(world.robots))
        diag["makespan"] = makespan
        diag["sum_of_costs"] = sum_of_costs(result.configs, flat(goals_xy))
        return Plan("lacam", robots, time.perf_counter() - t0, diag)

    @staticmethod
    def _check_cells(grid, world, cells, which: str, bad_status: PlanStatus, status: list, reasons: list) -> None:
        """Cells must be inside the grid, free, and distinct (one robot per cell)."""
        seen: dict[tuple[int, int], int] = {}
        free = grid.is_free(cells)
        for i, c in enumerate(cells.tolist()):
            if status[i] is not None:
                continue
            if not free[i]:
                status[i] = bad_status
                reasons[i] = f"{which} cell {tuple(c)} is blocked on the grid for radius {world.radii.max():g}"
            elif tuple(c) in seen:
                status[i] = bad_status
                reasons[i] = f"{which} cell {tuple(c)} is also robot {world.robots[seen[tuple(c)]].id!r}'s"
            else:
                seen[tuple(c)] = i

    @staticmethod
    def _world_paths(world, grid, configs: np.ndarray) -> list[np.ndarray]:
        """World paths (T + 1 [+ 2], 2) per robot from flat cell configurations (T + 1, n)."""
        w = grid.width
        cells = np.stack([configs % w, configs // w], axis=-1)          # (T + 1, n, 2)
        centres = grid.centers(cells)
        starts, goals = world.starts, world.goals
        head = [starts[None]]
        if np.any(np.linalg.norm(centres[0] - starts, axis=1) > 1e-9):
            head.append(centres[:1])          # settle on the start cells' centres first
        tail = []
        if np.any(np.linalg.norm(centres[-1] - goals, axis=1) > 1e-9):
            tail.append(goals[None])          # and end on the exact goals
        allp = np.concatenate(head + [centres[1:]] + tail, axis=0)
        return [np.ascontiguousarray(allp[:, i]) for i in range(allp.shape[1])]


def sum_of_costs(configs: np.ndarray, goals: np.ndarray) -> int:
    """Sum over robots of the step after which each stays on its goal cell: configurations
    (T + 1, n) and goals (n,) as flat cells (the usual MAPF sum of costs, waits included)."""
    off = configs != goals[None, :]
    if not off.any():
        return 0
    t = off.shape[0]
    last = t - np.argmax(off[::-1], axis=0)          # one past the last step off the goal
    return int(np.where(off.any(axis=0), last, 0).sum())


def arrival_step(path: np.ndarray, goal) -> int:
    """The step after which a timed path stays on ``goal`` (its cost in sum-of-costs terms)."""
    at = np.linalg.norm(np.asarray(path) - np.asarray(goal, float), axis=1) <= 1e-9
    if not at[-1]:
        return len(path) - 1
    k = len(at) - 1
    while k > 0 and at[k - 1]:
        k -= 1
    return int(k)
