"""LaCAM: configuration-space search with PIBT as the successor generator.

Okumura, "LaCAM: Search-Based Algorithm for Quick Multi-Agent Pathfinding", AAAI 2023
(Algorithm 1), with two refinements of "Improving LaCAM for Scalable Eventually Optimal
Multi-Agent Pathfinding" (IJCAI 2023): a known configuration is pushed back on the stack
(re-insertion, section 4.1) instead of being dropped, and PIBT may emulate swaps
(``swap``, from LaCAM3's PIBT).

A high-level node holds one configuration (every robot's cell), its parent, the robots'
PIBT priorities and order, and a queue of low-level nodes: constraints "robot ``who`` makes
move ``where``" that are added lazily, one robot deeper each time a constraint is popped.
Each pop asks PIBT for a successor configuration that satisfies the popped constraint. The
stack is searched depth first; the first configuration with every robot on its goal ends
the search. With re-insertion and the complete constraint tree the search is complete: it
either finds a solution or exhausts the (finite) configuration space.

Budgets: a node limit (high-level nodes created), a wall-clock limit and optionally a work
limit (PIBT calls times robots: the same on any machine), all checked every iteration.
"""
from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.pibt.core import GridGraph, decision_order, pibt_step
from swarmpath.search.lazy_distance import LazyDistanceTables

IntArray = NDArray[np.int64]

#: Random restarts: a pop that yields no new configuration sends the search back to its start
#: with chance ``RESTART / (depth + 1)`` at a node of that depth (see :func:`lacam_search`).
RESTART = 0.3


@dataclass(eq=False)
class HighNode:
    """A configuration ``cells`` (n,) flat int32, its parent, the PIBT ``priority`` (n,) and
    ``order`` (robots in decreasing priority), and the low-level constraint queue ``tree``
    of (who, move, parent constraint, depth) tuples (None is the empty root constraint)."""

    cells: NDArray[np.int32]
    parent: "HighNode | None"
    priority: NDArray[np.float64]
    order: NDArray[np.int32]
    depth: int
    tree: deque = field(default_factory=lambda: deque([None]))


@dataclass(frozen=True)
class SearchResult:
    """``configs`` (T + 1, n) flat cells from start to goal, or None; ``reason`` when None
    ("timeout", "node_limit", "exhausted"); statistics."""

    configs: NDArray[np.int32] | None
    reason: str
    nodes: int
    iterations: int
    pibt_calls: int
    time_s: float


def next_priorities(priority: NDArray[np.float64], base: NDArray[np.float64], at_goal: NDArray[np.bool_]
                    ) -> NDArray[np.float64]:
    """PIBT's priorities along a branch of the search (AIJ 2022, section 3.2): +1 away from
    the goal, back to the fractional part ``base`` at the goal."""
    return np.where(at_goal, base, priority + 1.0)


def restarting(rng: np.random.Generator, restart: float, depth: int) -> bool:
    """Whether a pop at a node of ``depth`` that yielded no new configuration sends the search
    back to its start: chance ``restart / (depth + 1)`` (no draw when ``restart`` is 0)."""
    return bool(restart) and rng.random() * (depth + 1) < restart


def _constraint_moves(low) -> tuple[list[int], list[int]]:
    """(robots, moves) of a low-level node, root first (the order they were added)."""
    who, where = [], []
    while low is not None:
        w, m, low, _ = low
        who.append(w)
        where.append(m)
    return who[::-1], where[::-1]


def lacam_search(graph: GridGraph, tables: LazyDistanceTables, handles: IntArray, starts: NDArray[np.int32],
                 goals: NDArray[np.int32], moves: NDArray[np.bool_], rng: np.random.Generator, *,
                 time_limit: float, node_limit: int, work_limit: int | None = None, swap: bool = True,
                 restart: float = RESTART) -> SearchResult:
    """Algorithm 1 of the LaCAM paper with re-insertion of known configurations.

    Parameters
    ----------
    graph : GridGraph
        Map, connectivity and conflict table (the checker's rule).
    tables, handles : lazy distance tables and each robot's handle (n,).
    starts, goals : ndarray of shape (n,), int32
        Flat start and goal cells (distinct; every goal reachable from its start).
    moves : ndarray of shape (height * width, 9), bool
        Static moves from each cell (:func:`~swarmpath.control.pibt.core.static_moves`).
    rng : numpy Generator
        Tie-breaking of PIBT and the order of the constraint tree's children.
    time_limit, node_limit : the budget (seconds, high-level nodes).
    work_limit : int or None
        A budget that does not depend on the machine: robot moves PIBT may generate (its calls
        times the robots). The time per call grows with the robots, so this is close to a
        time limit, but the same on every machine and under any load. None: no such limit.
    restart : float
        Random restarts. A pop that yields no new configuration (PIBT fails under the
        constraint, or finds a known configuration) pushes the start configuration instead,
        with chance ``restart / (depth + 1)``. LaCAM3 (Okumura, AAMAS 2024) pushes the start
        in place of a known configuration with a fixed chance (0.1 in its code) so that a
        depth-first search stuck in a bad region of a crowd starts over; a fixed chance never
        lets it reach the depth of a long plan (1-wide mazes: 10,000 steps), while one over the
        depth costs each pop about ``restart`` pops of walking down again, whatever the depth.
        Measured (400 agents): room-32-32-4, 8-connected, 2 of 6 seeds found no plan in 30 s
        without restarts, 0 of 8 with (at most 4.5 s); 1-wide 129 x 129 maze, 2 of 16 searches
        found none in 60 s without, 0 of 16 with. 0: none.
    """
    t0 = time.perf_counter()
    n = len(starts)
    width = graph.width
    goal_key = goals.tobytes()
    base = rng.random(n) if n else np.zeros(0)
    xy = lambda c: np.stack([c % width, c // width], axis=1)  # noqa: E731
    d0 = tables.distances(handles, xy(starts.astype(np.int64)))
    # initial priorities: farther robots first (LaCAM's code: distance / number of cells)
    prio0 = d0 / max(1, graph.blocked.size) + base * 1e-6
    root = HighNode(starts.copy(), None, prio0, decision_order(prio0), 0)
    explored: dict[bytes, HighNode] = {starts.tobytes(): root}
    stack: list[HighNode] = [root]
    iterations = calls = 0
    calls_allowed = np.inf if work_limit is None else max(1, int(work_limit) // max(1, n))
    last: HighNode | None = None
    # PIBT's random tie-breaking keys: a window at a random offset of one pool of keys,
    # cheaper than a fresh draw of 9 n keys for every call (8 us with 400 robots)
    ties = rng.random(max(1 << 16, 36 * n))
    goal_node: HighNode | None = None
    reason = "exhausted"
    goal_cells_xy = xy(goals.astype(np.int64))
    while stack:
        if len(explored) >= node_limit:
            reason = "node_limit"
            break
        if calls >= calls_allowed:
            reason = "work_limit"
            break
        if time.perf_counter() - t0 > time_limit:
            reason = "timeout"
            break
        iterations += 1
        node = stack[-1]
        if node.cells.tobytes() == goal_key:
            goal_node = node
            break
        if not node.tree:
            stack.pop()
            continue
        low = node.tree.popleft()
        depth = 0 if low is None else low[3]
        if depth < n:
            i = int(node.order[depth])
            options = np.flatnonzero(moves[node.cells[i]])
            for a in rng.permutation(options).tolist():
                node.tree.append((i, a, low, depth + 1))
        who, where = _constraint_moves(low)
        cells = node.cells
        if node is not last:
            # the stack's top stays the same while its successors are known or fail, often for
            # dozens of pops in a crowd: what depends on the node alone is computed once
            last = node
            cxy = xy(cells.astype(np.int64))
            dist = tables.neighbour_costs(handles, cxy)
            allowed = moves[cells].view(np.uint8) if moves.dtype == np.bool_ else moves[cells]
        forced = np.full(n, -1, np.int8)
        if who:
            forced[who] = where
        # NaN marks impossible moves, which are not allowed: PIBT never compares them
        at = int(rng.integers(len(ties) - 9 * n + 1))
        res = pibt_step(graph, cells, dist, allowed, ties[at:at + 9 * n].reshape(n, 9), node.order,
                        goals=goals, slots=handles, tables=tables._c, swap=swap, yield_way=True,
                        forced=forced, forced_order=np.asarray(who, np.int32))
        calls += 1
        if not res.ok or res.conflicts:
            if restarting(rng, restart, node.depth):
                stack.append(root)
            continue
        dxy = graph_moves_xy(res.moves)
        new_xy = cxy + dxy
        new_cells = (new_xy[:, 1] * width + new_xy[:, 0]).astype(np.int32)
        key = new_cells.tobytes()
        known = explored.get(key)
        if known is not None:
            # re-insertion (IJCAI 2023, section 4.1), or now and then a restart
            stack.append(root if restarting(rng, restart, node.depth) else known)
            continue
        at_goal = np.all(new_xy == goal_cells_xy, axis=1)
        prio = next_priorities(node.priority, base, at_goal)
        child = HighNode(new_cells, node, prio, decision_order(prio), node.depth + 1)
        explored[key] = child
        stack.append(child)
    elapsed = time.perf_counter() - t0
    if goal_node is None:
        return SearchResult(None, reason, len(explored), iterations, calls, elapsed)
    configs = []
    h: HighNode | None = goal_node
    while h is not None:
        configs.append(h.cells)
        h = h.parent
    return SearchResult(np.asarray(configs[::-1], np.int32).reshape(-1, n), "solved", len(explored), iterations,
                        calls, elapsed)


def graph_moves_xy(move_index: NDArray[np.int8]) -> IntArray:
    """Cell offsets (n, 2) of move indices into ``move_rules.GRID_MOVES``."""
    from swarmpath.world.move_rules import GRID_MOVES

    return GRID_MOVES[np.asarray(move_index, np.int64)]
