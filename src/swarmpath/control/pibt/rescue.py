"""Completing a stalled run: when grid robots in a static world stop making progress, LaCAM
plans the rest from where they stand, and the robots follow that plan.

PIBT moves every robot one step at a time by local rules, and it is not complete: its
guarantee (the robot of highest priority reaches its goal) needs every pair of neighbouring
cells to lie on a cycle, which a dead end breaks. On a dense map a robot whose goal lies at
the bottom of a one-cell dead end, behind a robot already home in its mouth, pushes that robot
deeper in instead of out, and the two shuttle for ever (random-32-32-20, random scenario 1,
300 agents: 299 home, then a deadlock; the swarm controllers on the same core stall the same
way). LaCAM (:mod:`swarmpath.planning.lacam`) searches configurations with PIBT as its
successor generator and is complete: from the robots' current cells it finds a joint plan
whenever one exists, given the time.

So the grid controllers watch their progress, and when it stops they hand the rest of the run
to LaCAM (:class:`StallRescue`). Each robot away from its goal keeps a record: the least
distance to its goal since it last left it. Progress has stopped when

- for ``after`` steps no robot away from its goal has beaten its record (every robot stuck);
- one robot has shuttled ``after`` times (stepped back onto the cell it left the step before)
  without beating its record: pushed to and fro while the others still move. The simulator
  calls a deadlock when every robot has kept to two cells for 60 steps. A robot
  merely waiting in a queue does not count: in a crowd of 10,000 one always waits that long,
  and a search for all of them would only spend its budget; or
- for ``2 * after`` steps the sum of the distances of the robots away from their goals has not
  fallen below its least value so far (robots pushed on and off their goals start fresh
  records without the run getting anywhere).

The plan is collision-free under the checker's rules (the same conflict table as the core's),
so following it ends the run with every robot home and no contact.

It applies only where LaCAM's plan is the whole truth: no moving obstacles (they would cross a
plan made without them), every goal on its cell's centre and on a free cell, every robot on a
cell centre when the rescue starts, and every robot fast enough for the grid's moves (a
diagonal needs sqrt(2) cells a step). Otherwise the controller carries on by its own rules. A
search that runs out of its budget leaves the controller in charge; it tries again after
another stall, at most ``attempts`` times in a run. The budget is ``work_limit`` robot moves
(PIBT calls times robots) for all the run's searches together: the same on every machine and
under any load, so a run's outcome depends on its seed alone (a wall-clock limit made two runs
of one seed differ), and a run no plan can finish spends it once, not once per attempt (three
failed searches of 100 robots in a 1-wide maze took 160 s).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.pibt.core import GridGraph, static_moves
from swarmpath.control.progress import progress_update
from swarmpath.planning.lacam.search import lacam_search
from swarmpath.search.lazy_distance import LazyDistanceTables

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Steps without any robot beating its own record after which a run counts as stalled.
RESCUE_AFTER = 24
#: Budget of a run's LaCAM searches together: robot moves PIBT may generate (calls times
#: robots). About 5 to 50 s on one core; configurations take at most 16 bytes per robot move.
RESCUE_WORK = 100_000_000
#: Searches a run may start at most.
RESCUE_ATTEMPTS = 3


def planned_decision(positions: FloatArray, planned: FloatArray, goals: FloatArray, events: list[dict]):
    """The Decision of a step of the rescue's plan: robots to ``planned`` (n, 2), modes
    "arrived" (on its goal), "rescue" (moving) or "wait"."""
    from swarmpath.control.base import Decision

    arrived = np.linalg.norm(planned - goals, axis=1) <= 1e-9
    moved = np.any(np.abs(planned - positions) > 1e-12, axis=1)
    modes = np.where(arrived, "arrived", np.where(moved, "rescue", "wait")).astype(object)
    return Decision(planned, modes.tolist(), events)


def check_rescue(after, work_limit, controller: str) -> None:
    """Raise :class:`~swarmpath.errors.ConfigError` naming the setting unless ``after`` and
    ``work_limit`` are whole numbers >= 0 and >= 1."""
    from swarmpath.errors import ConfigError

    if isinstance(after, bool) or not isinstance(after, (int, np.integer)) or after < 0:
        raise ConfigError(f"{controller}: rescue_after must be a whole number >= 0, got {after!r}")
    if isinstance(work_limit, bool) or not isinstance(work_limit, (int, np.integer)) or work_limit < 1:
        raise ConfigError(f"{controller}: rescue_work must be a whole number >= 1 (robot moves), got {work_limit!r}")


class StallRescue:
    """Watches a grid controller's progress and, once it stalls, plans the rest with LaCAM.

    Built by :meth:`build` (None where the rescue does not apply). Each step the controller
    calls :meth:`next_positions` first (the plan's next step while one is being followed),
    and otherwise :meth:`update` with the robots' distances to their goals, which returns the
    first step of a fresh plan when the run has stalled and LaCAM found one.
    """

    def __init__(self, grid, graph: GridGraph, tables: LazyDistanceTables, moves: BoolArray, goal_cells: IntArray,
                 rng: np.random.Generator, *, after: int, work_limit: int, attempts: int,
                 swap: bool):
        self.grid = grid
        self.graph = graph
        self.tables = tables
        self.moves = np.asarray(moves, bool).reshape(-1, 9)
        self.goal_cells = np.asarray(goal_cells, np.int64)
        self.rng = rng
        self.after = int(after)
        self.work_left = int(work_limit)        # the run's searches share one budget
        self.attempts = int(attempts)
        self.swap = swap
        n = len(self.goal_cells)
        self.best = np.full(n, np.inf)          # each robot's record since it last left its goal
        self.came_closer = np.zeros(n, np.int64)  # steps since it last beat it (progress.py)
        self.shuttled = np.zeros(n, np.int64)   # A-B-A steps of each robot since it last beat it
        self.last = np.full((n, 2), -1, np.int64)    # each robot's cell one step ago
        self.before = np.full((n, 2), -1, np.int64)  # and two steps ago
        self.since = 0                          # steps since some robot away from its goal beat it
        self.best_sum = np.inf
        self.since_sum = 0
        self.plan: IntArray | None = None       # (T + 1, n, 2) cells being followed
        self.at = 0
        self.tried = 0

    @classmethod
    def build(cls, world, grid, graph: GridGraph, tables: LazyDistanceTables, connectivity: int,
              rng: np.random.Generator, *, after: int = RESCUE_AFTER, work_limit: int = RESCUE_WORK,
              attempts: int = RESCUE_ATTEMPTS, swap: bool = True
              ) -> "StallRescue | None":
        """The rescue for ``world`` on ``grid`` (the controller's own grid, conflict ``graph``
        and distance ``tables``, moves of ``connectivity``), or None where it does not apply
        (``after`` = 0, moving obstacles, a goal off its cell's centre or on a blocked cell,
        a robot too slow for the grid's moves)."""
        n = world.n_robots
        if not after or n == 0 or world.moving_obstacles:
            return None
        h, w = grid.blocked.shape
        goal_cells = np.clip(grid.cell_of(world.goals), 0, [w - 1, h - 1])
        if np.any(np.linalg.norm(grid.centers(goal_cells) - world.goals, axis=1) > 1e-9):
            return None
        if not np.all(grid.is_free(goal_cells)):
            return None
        step = world.resolution * (np.sqrt(2) if connectivity == 8 else 1.0)
        if np.any(world.max_speeds * world.dt < step * (1 - 1e-9)):
            return None
        moves = static_moves(grid.blocked, connectivity)
        return cls(grid, graph, tables, moves, goal_cells, rng, after=after, work_limit=work_limit,
                   attempts=attempts, swap=swap)

    # ------------------------------------------------------------------ following
    @property
    def following(self) -> bool:
        return self.plan is not None

    def next_positions(self, positions: FloatArray) -> FloatArray | None:
        """The plan's next positions (n, 2) while one is followed and the robots stand where
        it says; None otherwise (a robot off the plan drops it)."""
        if self.plan is None:
            return None
        here = self.grid.centers(self.plan[self.at])
        if self.at + 1 >= len(self.plan) or np.any(np.abs(np.asarray(positions) - here) > 1e-9):
            self.plan = None
            return None
        self.at += 1
        return self.grid.centers(self.plan[self.at])

    # ------------------------------------------------------------------ watching
    def update(self, positions: FloatArray, cells: IntArray, remaining: FloatArray, at_goal: BoolArray
               ) -> tuple[FloatArray | None, list[dict]]:
        """Record this step's progress (``remaining`` (n,): each robot's distance to its goal,
        ``at_goal`` (n,)); when the run has stalled, plan the rest from ``cells`` (n, 2, the
        robots' cells, all on their centres ``positions``). Returns the plan's first step's
        positions (n, 2) or None, and the events of a search (``rescue`` or ``rescue_failed``)."""
        remaining = np.where(np.isfinite(remaining), remaining, np.inf)
        away = ~np.asarray(at_goal, bool)
        had_record = np.isfinite(self.best)
        self.best, came_closer = progress_update(self.best, self.came_closer, remaining, ~away)
        self.came_closer = came_closer
        # a robot that has just left its goal starts a record; that is no progress
        improved = away & had_record & (came_closer == 0)
        c = np.asarray(cells, np.int64)
        shuttle = np.all(c == self.before, axis=1) & np.any(c != self.last, axis=1)   # A, B, A again
        self.shuttled = np.where(improved | ~away, 0, self.shuttled + shuttle)
        self.before, self.last = self.last, c.copy()
        self.since = 0 if improved.any() or not away.any() else self.since + 1
        total = float(np.sum(np.where(away & np.isfinite(remaining), remaining, 0.0)))
        if total < self.best_sum - 1e-6:
            self.best_sum, self.since_sum = total, 0
        else:
            self.since_sum += 1
        stalled = away.any() and (self.since >= self.after or self.since_sum >= 2 * self.after
                                  or bool(np.any(self.shuttled[away] >= self.after)))
        # no search either with a goal cut off from its robot: LaCAM has no plan to find
        if not stalled or self.tried >= self.attempts or self.work_left <= 0 \
                or not np.all(np.isfinite(remaining)):
            return None, []
        if np.any(np.abs(self.grid.centers(cells) - np.asarray(positions)) > 1e-9):
            return None, []
        self.tried += 1
        self.since = self.since_sum = 0
        self.shuttled[:] = 0
        self.best_sum = np.inf
        # the events say how much work the search did, not how long it took: a run's record is
        # the same on any machine (seconds would differ between two runs of one seed)
        configs, reason, work = self._search(np.asarray(cells, np.int64))
        if configs is None:
            return None, [{"robot": -1, "kind": "rescue_failed",
                           "detail": f"no progress: LaCAM found no plan for the rest ({reason}, "
                                     f"{work:,} robot moves tried)"}]
        self.plan, self.at = configs, 0
        event = {"robot": -1, "kind": "rescue",
                 "detail": f"no progress: LaCAM planned the remaining {len(configs) - 1} steps of "
                           f"{int(away.sum())} robots away from their goals ({work:,} robot moves tried)"}
        return self.next_positions(positions), [event]

    def _search(self, cells: IntArray) -> tuple[IntArray | None, str, int]:
        """LaCAM from ``cells`` (n, 2) to the goals: cells (T + 1, n, 2), or None and why; and
        the robot moves the search generated (PIBT calls times robots)."""
        w = self.graph.width
        handles = self.tables.acquire_many(self.goal_cells)
        try:
            flat = lambda c: (c[:, 1] * w + c[:, 0]).astype(np.int32)  # noqa: E731
            result = lacam_search(self.graph, self.tables, handles, flat(cells), flat(self.goal_cells), self.moves,
                                  # the work limit binds first: a search creates at most one
                                  # configuration per call, and a call moves every robot
                                  self.rng, time_limit=np.inf, node_limit=self.work_left,
                                  work_limit=self.work_left, swap=self.swap)
        finally:
            for hd in handles.tolist():
                self.tables.release(hd)
        work = int(result.pibt_calls) * len(cells)
        self.work_left -= work
        if result.configs is None:
            return None, result.reason, work
        configs = result.configs.astype(np.int64)
        return np.stack([configs % w, configs // w], axis=-1), "solved", work


__all__ = ["RESCUE_AFTER", "RESCUE_ATTEMPTS", "RESCUE_WORK", "StallRescue", "check_rescue",
           "planned_decision"]
