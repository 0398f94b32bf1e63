"""The modified cat swarm of Jaleel & Hassan (2016, section III.2.C, Algorithm 4) as small pure
functions over arrays. The controller (:mod:`swarmpath.control.cat_swarm`) wires them to the
simulator; docs/papers/jaleel-hassan-2016.md (online phase) explains every interpretation.

Grid conventions: cells are (x, y) integer pairs, ``blocked[y, x]``; the 9 candidate offsets
are ``OFFSETS`` (index 0 = the present position, then the 8 directions).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Offsets of the candidate cells: the present cell, then E, NE, N, NW, W, SW, S, SE.
OFFSETS = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], dtype=np.int64)
#: Octile length of each offset (0, 1 or sqrt 2).
STEP_COST = np.linalg.norm(OFFSETS, axis=1)
#: Whether each offset is a diagonal move.
DIAGONAL = np.all(OFFSETS != 0, axis=1)
STAY = 0


def mixture_counts(n_robots: int, mixture_ratio: float) -> tuple[int, int]:
    """Eq. 10-11: robots in seek mode = round(MR * N) (halves rounded up), the rest trace.
    MR = 0.4 and N = 12 give (5, 7); N = 2 gives (1, 1), as the paper wants."""
    n_seek = int(np.floor(mixture_ratio * n_robots + 0.5))
    n_seek = min(max(n_seek, 0), n_robots)
    return n_seek, n_robots - n_seek


def mixture_split(remaining: FloatArray, groups: IntArray, mixture_ratio: float, tiebreak: FloatArray) -> BoolArray:
    """Seek flags (eq. 10-11 and the paragraph after them): in every group, the
    ``round(MR * size)`` robots with the LONGEST remaining path get seek mode (flag 1), the
    others trace mode (flag 0); equal lengths are ordered by ``tiebreak`` (random keys).

    remaining, tiebreak : (n,) ; groups : (n,) group label of each robot (>= 0).
    Returns a bool array (n,)."""
    n = len(remaining)
    if n == 0:
        return np.zeros(0, dtype=bool)
    order = np.lexsort((tiebreak, -np.asarray(remaining, float), groups))
    g_sorted = groups[order]
    starts = np.flatnonzero(np.r_[True, g_sorted[1:] != g_sorted[:-1]])
    sizes = np.diff(np.r_[starts, n])
    rank = np.arange(n) - np.repeat(starts, sizes)
    n_seek = np.floor(mixture_ratio * sizes + 0.5).astype(np.int64)
    seek = np.zeros(n, dtype=bool)
    seek[order] = rank < np.repeat(n_seek, sizes)
    return seek


def conflict_groups(edges: IntArray, members: BoolArray) -> IntArray:
    """Groups of robots in conflict with each other: connected components of the conflict
    graph (``edges`` (e, 2) robot pairs) among the robots flagged in ``members`` (n,).
    Returns one group label per member, in the order of ``np.flatnonzero(members)`` (the
    groups of :func:`mixture_split`)."""
    index = np.flatnonzero(members)
    local = -np.ones(len(members), np.int64)
    local[index] = np.arange(len(index))
    e = edges[members[edges[:, 0]] & members[edges[:, 1]]]
    graph = coo_matrix((np.ones(len(e)), (local[e[:, 0]], local[e[:, 1]])), shape=(len(index), len(index)))
    return connected_components(graph, directed=False)[1].astype(np.int64)


def seek_copies(cells: IntArray, *, srd: int = 1) -> IntArray:
    """Step 6.1-6.2 of Algorithm 4: the seeking memory pool. Every robot is copied SMP = 8
    times; each copy changes both coordinates (CDC = 2) by -SRD, 0 or +SRD cells (the eight
    directions). Slot 0 holds the present position, the candidate SPC adds (the controller
    decides whether it may win).

    cells : (n, 2) -> copies (n, 9, 2)"""
    return cells[:, None, :] + OFFSETS[None] * srd


def move_table(blocked: BoolArray) -> BoolArray:
    """Static validity of the 9 moves from every cell, shape (height, width, 9): the target is
    inside the grid and free, and a diagonal move does not cut a blocked corner (both
    orthogonal neighbours free). Step 6.3's "copies on static obstacles are deleted"."""
    h, w = blocked.shape
    pad = np.ones((h + 2, w + 2), dtype=bool)
    pad[1:-1, 1:-1] = blocked
    free = ~pad
    out = np.zeros((h, w, len(OFFSETS)), dtype=bool)
    for k, (dx, dy) in enumerate(OFFSETS):
        ok = free[1 + dy:1 + dy + h, 1 + dx:1 + dx + w].copy()
        if dx and dy:
            ok &= free[1:1 + h, 1 + dx:1 + dx + w] & free[1 + dy:1 + dy + h, 1:1 + w]
        out[..., k] = ok & ~blocked
    return out


def moves_at(blocked: BoolArray, cells: IntArray) -> BoolArray:
    """:func:`move_table` at given cells only, shape (..., 9) for ``cells`` (..., 2): the same
    values without building the table of the whole grid (a robot needs its own 9 moves)."""
    b = np.asarray(blocked, bool)
    h, w = b.shape
    c = np.asarray(cells, np.int64)

    def free(x, y):
        x, y = np.broadcast_arrays(x, y)
        ok = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        out = np.zeros(ok.shape, bool)
        out[ok] = ~b[y[ok], x[ok]]
        return out

    x, y = c[..., 0, None], c[..., 1, None]
    dx, dy = OFFSETS[:, 0], OFFSETS[:, 1]
    ok = free(x + dx, y + dy) & free(x, y)
    return ok & (~DIAGONAL | (free(x + dx, y) & free(x, y + dy)))


def fitness_eq12(fields: NDArray, field_index: IntArray, copies: IntArray) -> FloatArray:
    """Eq. 12: the fitness of a copy is the length of the path from the copy to its robot's
    goal. ``fields[g]`` (height, width) is the grid distance field of goal g (cells, octile,
    the same cost A* finds), ``field_index`` (n,) the field of each robot, ``copies`` (n, k, 2)
    cells (clipped into the grid here; mask invalid copies separately). Returns (n, k)."""
    h, w = fields.shape[1:]
    x = np.clip(copies[..., 0], 0, w - 1)
    y = np.clip(copies[..., 1], 0, h - 1)
    return fields[field_index[:, None], y, x].astype(np.float64)


def tie_break_eq13(copy_points: FloatArray, goals: FloatArray) -> FloatArray:
    """Eq. 13 (used when fitness values tie): prefer the copy whose way to the goal is most
    direct, i.e. that moves forward and not backward. The paper's formula (sum of Euclidean
    segment lengths over the number of points of the copy's path) is lost in the text; we use
    the straight-line distance from the copy to the goal. copy_points (n, k, 2), goals (n, 2)
    -> (n, k)."""
    return np.linalg.norm(copy_points - goals[:, None, :], axis=-1)


def rank_copies(fitness: FloatArray, tie: FloatArray, valid: BoolArray, *, decimals: int = 6,
                safety: NDArray | None = None) -> IntArray:
    """Step 6.4-6.5: candidate indices of every robot from best to worst: smallest fitness
    first, ties by eq. 13, then by index; invalid (deleted) copies last. With ``safety``
    (n, k), larger safety comes before everything else. (n, k) -> (n, k)."""
    f = np.where(valid, np.round(fitness, decimals), np.inf)
    t = np.where(valid, tie, np.inf)
    order = np.argsort(t, axis=1, kind="stable")
    for key in (f, None if safety is None else -np.asarray(safety, float)):
        if key is None:
            continue
        key = np.where(valid, key, np.inf)
        nxt = np.argsort(np.take_along_axis(key, order, axis=1), axis=1, kind="stable")
        order = np.take_along_axis(order, nxt, axis=1)
    return order


def descent_step(copy_fitness: FloatArray, static_ok: BoolArray, tie: FloatArray) -> IntArray:
    """The next cell of each robot's replanned shortest path (step 6.6's "replanning"): the
    neighbour minimising step cost + distance-to-goal (``copy_fitness`` (n, 9) = eq. 12 of the
    9 candidates, index 0 the present cell), ties by eq. 13. Returns the offset index (n,)
    (0 when the robot is at its goal or walled in)."""
    cost = copy_fitness + STEP_COST[None]
    valid = static_ok.copy()
    valid[:, STAY] = False
    order = rank_copies(cost, tie, valid)
    best = order[:, 0]
    here = copy_fitness[:, STAY]
    best_cost = np.take_along_axis(cost, best[:, None], axis=1)[:, 0]
    stuck = ~valid[np.arange(len(copy_fitness)), best] | ~(best_cost < here + 1e-3) | (here <= 0)
    return np.where(stuck, STAY, best)


def linear_next(previous: FloatArray, current: FloatArray) -> FloatArray:
    """Algorithm 2's "next objects position" of a moving obstacle: where its last move takes
    it again, current + (current - previous) (the paper's blocks keep their direction until
    they hit something). previous, current (m, 2) -> (m, 2)."""
    current = np.asarray(current, float).reshape(-1, 2)
    return current + (current - np.asarray(previous, float).reshape(-1, 2))


def conflict_lists(robot_points: FloatArray, object_points: FloatArray, object_owner: IntArray,
                   limit: float) -> tuple[IntArray, IntArray]:
    """Algorithm 2 (steps 2-5, each with Algorithm 3): the object positions in every robot's
    short or medium list. The distances (eq. 9) from the robot's current and next position
    (Rc, Rn) to every object's current and next position (C-Object, N-Object) are classified;
    a position within ``limit`` (the upper bound of the medium class) is listed.

    robot_points : (n, 2, 2) each robot's (Rc, Rn)
    object_points : (k, 2) the objects' current and next positions, one row each
    object_owner : (k,) the robot a row belongs to (-1 for a moving obstacle), so that a
        robot never lists itself
    Returns (robot (e,), object row (e,)): each listed pair once, sorted.
    """
    n = len(robot_points)
    if n == 0 or len(object_points) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    tree = cKDTree(np.asarray(object_points, float))
    hits = tree.query_ball_point(np.asarray(robot_points, float).reshape(-1, 2), limit)
    robot = np.repeat(np.arange(2 * n) // 2, [len(h) for h in hits]).astype(np.int64)
    row = np.fromiter((j for h in hits for j in h), np.int64, count=len(robot))
    keep = object_owner[row] != robot
    pairs = np.unique(np.stack([robot[keep], row[keep]], axis=1), axis=0).reshape(-1, 2)
    return pairs[:, 0], pairs[:, 1]


def near_listed(points: FloatArray, robot: IntArray, listed: FloatArray, clearance: float) -> NDArray[np.bool_]:
    """Which points of each robot lie closer than ``clearance`` to an object position in its
    lists (step 6.3: "distance less than one" deletes a copy; step 7: a tracing robot waits).

    points : (n, k, 2) per robot (its copies, or k = 1: its position); robot (e,), listed
    (e, 2): the listed object positions and whose lists they are in. Returns (n, k)."""
    out = np.zeros(points.shape[:2], dtype=bool)
    if len(robot):
        close = np.linalg.norm(points[robot] - listed[:, None, :], axis=-1) < clearance
        np.logical_or.at(out, robot, close)
    return out
