"""PIBT, the maths: priorities, candidate moves and one configuration step.

Priority Inheritance with Backtracking (Okumura, Machida, Defago, Tamura, "Priority
inheritance with backtracking for iterative multi-agent path finding", Artificial
Intelligence 310, 2022). At every step each robot ranks its candidate cells (stay and the 4
or 8 neighbours) by the exact distance to its goal; robots decide in decreasing priority; a
robot that wants the cell of a robot that has not decided yet makes that robot move first
(priority inheritance) or, if it cannot, tries its next cell (backtracking). The loop of one
step runs in C (``_pibt.c``); this module prepares its inputs:

- :func:`update_priorities`: section 3.2 of the paper: a robot's priority grows by one every
  step it is away from its goal and drops back to its fractional part (a distinct random
  number in [0, 1)) when it is at the goal;
- :func:`decision_order`: robots in decreasing priority;
- :func:`static_moves`: which of the 9 grid moves (``move_rules.GRID_MOVES``) leave each cell
  through free cells without corner cutting;
- :func:`pibt_step`: one step, with the checker's conflict table
  (:func:`swarmpath.world.move_rules.grid_conflict_table`) and optional forced moves (LaCAM's
  constraints).

Cells are flat indices ``y * width + x`` of the occupancy grid.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.pibt import _pibt
from swarmpath.errors import ConfigError
from swarmpath.world.move_rules import GRID_MOVES, grid_conflict_table

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Index of "stay" among the 9 grid moves.
STAY = 0
#: Whether each of the 9 grid moves is diagonal.
DIAGONAL_MOVE = np.all(GRID_MOVES != 0, axis=1)
#: Flags returned per robot by :func:`pibt_step`.
PUSHED, STUCK = 1, 2


def check_connectivity(connectivity: int, who: str) -> None:
    """4 or 8; anything else raises :class:`ConfigError` naming ``connectivity``."""
    if connectivity not in (4, 8):
        raise ConfigError(f"{who}: connectivity must be 4 or 8, got {connectivity!r}")


def static_moves(blocked: NDArray[np.bool_], connectivity: int = 8) -> BoolArray:
    """Which grid moves are possible from each cell: bool array (height, width, 9) in
    ``GRID_MOVES`` order. Staying is possible on a free cell; a move needs a free target
    inside the grid, a diagonal also both orthogonal neighbours free (no corner cutting), and
    none with 4-connectivity."""
    b = np.asarray(blocked, bool)
    h, w = b.shape
    free = np.zeros((h + 2, w + 2), bool)
    free[1:-1, 1:-1] = ~b
    out = np.zeros((h, w, 9), bool)
    for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
        if connectivity == 4 and dx and dy:
            continue
        ok = free[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] & ~b
        if dx and dy:
            ok &= free[1:1 + h, 1 + dx:1 + dx + w] & free[1 + dy:1 + dy + h, 1:1 + w]
        out[:, :, a] = ok
    return out


def update_priorities(priority: FloatArray, at_goal: BoolArray, base: FloatArray) -> FloatArray:
    """Section 3.2: +1 for every robot away from its goal, back to ``base`` (its fractional
    part, distinct random numbers in [0, 1)) for robots at their goal. Shapes (n,)."""
    return np.where(at_goal, base, priority + 1.0)


def decision_order(priority: FloatArray, urgent: BoolArray | None = None,
                   options: NDArray[np.int64] | None = None) -> NDArray[np.int32]:
    """Robots in decreasing priority (ties by index); ``urgent`` robots (standing where a
    moving obstacle may be next step, or that must leave to stay clear of one) decide before
    all others, and with ``options`` (n,) (how many candidates each robot has left) the most
    constrained urgent robot first: a robot with one way out takes it before a robot with
    two takes that cell from it."""
    if urgent is None:
        return np.argsort(-priority, kind="stable").astype(np.int32)
    urgent = np.asarray(urgent, bool)
    if options is None:
        return np.lexsort((-priority, ~urgent)).astype(np.int32)
    return np.lexsort((-priority, np.where(urgent, options, 0), ~urgent)).astype(np.int32)


def escape_claims(cells: IntArray, allowed: BoolArray, rank: NDArray[np.int64], must: BoolArray,
                  shape: tuple[int, int]) -> IntArray:
    """How many robots need each move's cell to get away (n, 9): for every move of a robot
    that need not leave (``~must``), the number of robots that must leave their cell
    (``must``: a moving obstacle may be there next step) and rank that cell among their best
    ways out (``allowed`` (n, 9) candidates of the lowest ``rank`` (n, 9), staying excluded).
    0 for staying, for moves off the grid ``shape`` (height, width) and for robots in ``must``.

    Why: PIBT lets a pushed robot take its best free cell, and that may be the one way out of
    a robot that decides after it (64 x 64 acceptance world, seed 3091: a robot on its goal in
    a pocket and the robot beside it both had to leave south; the robots below, pushed
    aside, took the cell one of them needed, and a walker caught it). A pushed robot that
    ranks such cells after its others leaves them to the robots that need them."""
    cells = np.asarray(cells, np.int64).reshape(-1, 2)
    allowed = np.asarray(allowed, bool)
    must = np.asarray(must, bool)
    n = len(cells)
    if n == 0 or not must.any():
        return np.zeros((n, 9), np.int64)
    flat = move_cells(cells, shape)
    ways = allowed & (flat >= 0)
    ways[:, STAY] = False
    best = np.where(ways, rank, np.iinfo(np.int64).max).min(axis=1, keepdims=True)
    need = ways & (rank == best) & must[:, None]
    out = claims_on_moves(flat, flat[need])
    out[:, STAY] = 0
    out[must] = 0
    return out


def move_cells(cells: IntArray, shape: tuple[int, int]) -> IntArray:
    """The flat cell ``y * width + x`` (n, 9) each move of the robots on ``cells`` (n, 2)
    reaches, -1 off the grid ``shape`` (height, width)."""
    h, w = shape
    dest = np.asarray(cells, np.int64).reshape(-1, 1, 2) + GRID_MOVES[None]       # (n, 9, 2)
    inside = (dest[..., 0] >= 0) & (dest[..., 0] < w) & (dest[..., 1] >= 0) & (dest[..., 1] < h)
    return np.where(inside, dest[..., 1] * w + dest[..., 0], -1)


def claims_on_moves(flat: IntArray, claimed: IntArray) -> IntArray:
    """How many entries of ``claimed`` (flat cells, repeats counted) each move's cell ``flat``
    (n, 9) of :func:`move_cells` is (n, 9); 0 off the grid. Sorts the few claimed cells
    instead of building a map-sized array."""
    cells, count = np.unique(np.asarray(claimed, np.int64), return_counts=True)
    if len(cells) == 0:
        return np.zeros(np.shape(flat), np.int64)
    at = np.minimum(np.searchsorted(cells, flat), len(cells) - 1)
    return np.where((flat >= 0) & (cells[at] == flat), count[at], 0)


def conflict_table(radius: float, resolution: float) -> NDArray[np.uint8]:
    """The checker's rule for two robots of ``radius`` as a C-contiguous uint8 table (25, 9, 9)
    (:func:`swarmpath.world.move_rules.grid_conflict_table`). Using the largest radius of a
    world for every pair is conservative: a conflict of smaller discs is one of larger discs."""
    return np.ascontiguousarray(grid_conflict_table(radius, radius, resolution), np.uint8)


@dataclass(frozen=True)
class StepResult:
    """One PIBT step: ``moves`` (n,) indices into ``GRID_MOVES``; ``flags`` (n,) with bits
    :data:`PUSHED` (moved by priority inheritance or pulled by a swap) and :data:`STUCK`
    (every candidate failed); ``ok`` False when forced moves cannot be met; ``conflicts``
    robot pairs whose moves still conflict by the table (0 without forced moves); ``calls``
    recursive PIBT calls; ``swaps`` robots pulled by the swap emulation."""

    moves: NDArray[np.int8]
    flags: NDArray[np.uint8]
    ok: bool
    conflicts: int
    calls: int
    swaps: int


@dataclass(frozen=True)
class GridGraph:
    """What one PIBT step needs of the map: ``blocked`` (height, width) as C-contiguous uint8,
    the connectivity, and the conflict table (:func:`conflict_table`)."""

    blocked: NDArray[np.uint8]
    connectivity: int
    table: NDArray[np.uint8]

    @classmethod
    def build(cls, blocked: NDArray[np.bool_], connectivity: int, radius: float, resolution: float) -> GridGraph:
        return cls(np.ascontiguousarray(blocked, np.uint8), connectivity, conflict_table(radius, resolution))

    @property
    def height(self) -> int:
        return int(self.blocked.shape[0])

    @property
    def width(self) -> int:
        return int(self.blocked.shape[1])


def pibt_step(graph: GridGraph, cells: NDArray[np.int32], dist: FloatArray, allowed: BoolArray, tie: FloatArray,
              order: NDArray[np.int32], *, goals: NDArray[np.int32], slots: NDArray[np.int64] | None = None,
              tables=None, swap: bool = False, yield_way: bool = False, forced: NDArray[np.int8] | None = None,
              forced_order: NDArray[np.int32] | None = None) -> StepResult:
    """One step of PIBT (Algorithm 1 of the paper) for all robots.

    Parameters
    ----------
    graph : GridGraph
        The map, its connectivity and the conflict table.
    cells : ndarray of shape (n,), int32
        Each robot's flat cell ``y * width + x`` (distinct).
    dist : ndarray of shape (n, 9)
        Cost to goal of the cell each move reaches (the ranking key).
    allowed : ndarray of shape (n, 9), bool
        Candidate moves (static, in reach, away from moving obstacles). A robot whose stay is
        not allowed tries to leave; if it cannot, it stays anyway.
    tie : ndarray of shape (n, 9)
        Random keys breaking ties of equal cost among equally occupied cells.
    order : ndarray of shape (n,), int32
        Robots in the order they decide (decreasing priority).
    goals : ndarray of shape (n,), int32
        Each robot's goal cell (flat).
    slots, tables : each robot's table in a :class:`~swarmpath.search.lazy_distance.LazyDistanceTables`'
        C object (``tables._c``; slot -1: none, then the octile distance to the goal is used);
        only read by the swap emulation.
    swap : bool
        LaCAM3's swap emulation (Okumura, AAMAS 2024): a robot that must pass another one in a
        corridor moves away and pulls it.
    yield_way : bool
        A robot pushed off its goal ranks first the cells that are not closer to the pusher's
        goal than its own cell (it steps out of the pusher's way instead of ahead of it), an
        ordering choice left open by the paper (any order keeps Theorem 1). It ends the
        ping-pong of two robots whose goals lie one behind the other in a corridor.
    forced, forced_order : LaCAM's constraints: ``forced[i]`` the move robot i must make (-1:
        free), placed in ``forced_order`` before PIBT runs.
    """
    n = len(cells)
    moves = np.zeros(n, np.int8)
    flags = np.zeros(n, np.uint8)
    if forced is None:
        forced = np.full(n, -1, np.int8)
        forced_order = np.zeros(0, np.int32)
    if slots is None:
        slots = np.full(n, -1, np.int64)
    ok, bad, calls, swaps = _pibt.step(
        graph.width, graph.height, graph.connectivity == 8, graph.blocked, np.ascontiguousarray(cells, np.int32),
        np.ascontiguousarray(dist, np.float64), np.ascontiguousarray(allowed, np.uint8),
        np.ascontiguousarray(tie, np.float64), np.ascontiguousarray(order, np.int32), graph.table,
        np.ascontiguousarray(forced, np.int8), np.ascontiguousarray(forced_order, np.int32),
        np.ascontiguousarray(goals, np.int32), np.ascontiguousarray(slots, np.int64), tables, bool(swap),
        bool(yield_way), moves, flags)
    return StepResult(moves, flags, bool(ok), int(bad), int(calls), int(swaps))


#: Steps of PIBT :func:`pibt_step_escaping` may run, at most, to find a way out for robots
#: still standing in danger after its reordered tries (one per way out tried).
ESCAPE_TRIES = 16


def pibt_step_escaping(graph: GridGraph, cells: NDArray[np.int32], dist: FloatArray, allowed: BoolArray,
                       tie: FloatArray, order: NDArray[np.int32], *, danger: BoolArray,
                       rank: NDArray[np.int64] | None = None, rounds: int = 3, **kwargs) -> StepResult:
    """:func:`pibt_step`, retried when a robot that must leave its cell (its stay is not
    allowed: a moving obstacle may reach it) could not, or when a robot in ``danger`` (n,)
    got a worse ``rank`` (n, 9; the look-ahead's, lower is more cautious) than its best
    candidate's: the robots that failed decide first in the next try, up to ``rounds`` tries;
    the try with the fewest robots left standing in danger, then the fewest in danger on a
    worse cell, then the fewest others failed, wins (the first on ties). A robot still
    standing in danger then tries each of its ways out (best first) as its only candidate,
    deciding first; the first try that leaves fewer robots worse off wins (at most
    :data:`ESCAPE_TRIES` tries).

    PIBT decides greedily in priority order, so a robot with two ways out may take the one
    a neighbour needed, or cross its diagonal; letting the robot that was left without a way
    out (or with a worse one) choose first resolves such pairs: three robots side by side
    fleeing an obstacle onto three cells, the middle one deciding last. Without moving
    obstacles every stay is allowed and this is one :func:`pibt_step`."""
    res = pibt_step(graph, cells, dist, allowed, tie, order, **kwargs)
    ok = np.asarray(allowed, bool)
    must = ~ok[:, STAY]
    danger = np.asarray(danger, bool)
    if rank is not None:
        rank = np.asarray(rank)
        best_rank = np.where(ok, rank, np.iinfo(np.int64).max).min(axis=1)
        rows = np.arange(len(cells))

    def failed(r: StepResult) -> NDArray[np.bool_]:
        f = must & (r.moves == STAY)
        if rank is not None:
            f |= danger & (rank[rows, r.moves.astype(np.int64)] > best_rank)
        return f

    def cost(r: StepResult) -> tuple[int, int, int]:
        # robots left standing in danger weigh most, then robots in danger on a worse cell
        f = failed(r)
        stood = must & (r.moves == STAY)
        return int(np.sum(stood & danger)), int(np.sum(f & danger)), int(np.sum(f))

    best, best_cost = res, cost(res)
    o = np.asarray(order, np.int32)
    last = res
    for _ in range(rounds):
        # the robots that failed in the last try go first, in the order they had
        stuck = failed(last)
        if not stuck.any():
            break
        front = o[stuck[o]]
        front = np.concatenate([front[danger[front]], front[~danger[front]]])
        o = np.concatenate([front, o[~stuck[o]]]).astype(np.int32)
        last = pibt_step(graph, cells, dist, allowed, tie, o, **kwargs)
        c = cost(last)
        if c < best_cost:
            best, best_cost = last, c
    # a robot still left standing in danger tries each of its ways out in turn, deciding first
    # with that one cell as its only candidate: reordering alone misses two robots fleeing side
    # by side whose best ways out cross (each one's diagonal is the other's only way; both
    # straight on is the answer neither ranks first)
    tries = 0
    for i in np.flatnonzero(must & danger & (best.moves == STAY)):
        ways = np.flatnonzero(ok[i])
        ways = ways[ways != STAY]
        for a in ways[np.argsort(np.asarray(dist)[i, ways], kind="stable")]:
            if tries == ESCAPE_TRIES:
                return best
            tries += 1
            only = ok.copy()
            only[i] = False
            only[i, a] = True
            first = np.concatenate([[i], o[o != i]]).astype(np.int32)
            r = pibt_step(graph, cells, dist, only, tie, first, **kwargs)
            c = cost(r)
            if c < best_cost:
                best, best_cost = r, c
                break
    return best
