"""Robots in danger close together choose their moves jointly.

PIBT lets robots decide one at a time. When two or three robots beside one another must
get away from a moving obstacle, the first to decide takes its best cell, and that may be
the only safe cell of the next one, which is left with a risky move or with staying. Among
such a group the order decides who is exposed, not the risk.

:func:`joint_escapes` finds, for each group of robots in danger that stand within two
cells of one another (farther apart their moves cannot conflict), the combination of moves
of least total cost that the checker's rule allows (no shared cell, no swap, no diagonal
crossing: the conflict table of :func:`swarmpath.control.pibt.core.conflict_table`). The
cost of a move is the controller's own ranking key (look-ahead tier, walker risk, distance
to goal), so the joint choice changes nothing for a robot alone; for a group it is the
choice a single planner of the whole group would make with the same keys. A depth-first
search with a lower bound (each robot's cheapest move) and a budget of visited nodes keeps
it bounded; a group over budget keeps PIBT's own order.

The controller then ranks each robot's chosen move first and makes it a claimed cell for
every other robot, so PIBT's pushes do not take it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from swarmpath.control.pibt.core import claims_on_moves, move_cells

#: depth-first search nodes visited per group before giving up (the group keeps PIBT's order)
JOINT_BUDGET = 20_000

#: largest group searched jointly
JOINT_MAX_GROUP = 6


def danger_groups(cells: NDArray[np.int64], members: NDArray[np.int64]) -> list[NDArray[np.int64]]:
    """The robots ``members`` split into groups whose cells are within two cells
    (Chebyshev) of one another, chained; only groups of two or more are returned. Pairs come
    from a k-d tree, so thousands of robots in danger cost no k x k matrix."""
    members = np.asarray(members, np.int64)
    if len(members) < 2:
        return []
    c = np.asarray(cells, np.int64)[members]
    pairs = cKDTree(c).query_pairs(2.0 + 1e-9, p=np.inf, output_type="ndarray")
    if len(pairs) == 0:
        return []
    k = len(members)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(k, k))
    _, label = connected_components(graph, directed=False)
    size = np.bincount(label)
    return [members[np.flatnonzero(label == g)] for g in np.flatnonzero(size >= 2)]


def best_joint_moves(cells: NDArray[np.int64], cost: NDArray[np.float64], allowed: NDArray[np.bool_],
                     table: NDArray[np.uint8], budget: int = JOINT_BUDGET) -> NDArray[np.int64] | None:
    """The moves (k,) of least total ``cost`` (k, 9) for the robots on ``cells`` (k, 2), each
    among its ``allowed`` (k, 9) moves, no two conflicting by ``table`` (25, 9, 9); None if
    no combination exists or the search visits more than ``budget`` nodes."""
    k = len(cells)
    options = [np.flatnonzero(allowed[i] & np.isfinite(cost[i])) for i in range(k)]
    if any(len(o) == 0 for o in options):
        return None
    options = [o[np.argsort(cost[i, o], kind="stable")] for i, o in enumerate(options)]
    order = np.argsort([len(o) for o in options], kind="stable")
    floor = np.array([cost[i, options[i][0]] for i in range(k)])
    rest = np.concatenate([np.cumsum(floor[order][::-1])[::-1][1:], [0.0]])   # bound of the robots after
    offset = np.asarray(cells, np.int64)[None, :, :] - np.asarray(cells, np.int64)[:, None, :]
    near = np.abs(offset).max(axis=2) <= 2
    index = (offset[..., 1] + 2) * 5 + (offset[..., 0] + 2)
    chosen = np.full(k, -1, np.int64)
    best: list = [np.inf, None]
    visits = 0

    def search(depth: int, total: float) -> bool:
        nonlocal visits
        if depth == k:
            if total < best[0]:
                best[0], best[1] = total, chosen.copy()
            return True
        i = order[depth]
        for a in options[i]:
            visits += 1
            if visits > budget:
                return False
            t = total + cost[i, a]
            if t + rest[depth] >= best[0]:
                break                      # options are sorted: the rest cost no less
            if any(chosen[j] >= 0 and near[i, j] and table[index[i, j], a, chosen[j]] for j in order[:depth]):
                continue
            chosen[i] = a
            finished = search(depth + 1, t)
            chosen[i] = -1
            if not finished:
                return False
        return True

    if not search(0, 0.0):
        return None
    return best[1]


def joint_escapes(cells: NDArray[np.int64], cost: NDArray[np.float64], allowed: NDArray[np.bool_],
                  members: NDArray[np.int64], table: NDArray[np.uint8],
                  budget: int = JOINT_BUDGET) -> NDArray[np.int64]:
    """For every group of robots in ``members`` standing within two cells of one another
    (:func:`danger_groups`, at most :data:`JOINT_MAX_GROUP` robots), the joint moves of least
    total ``cost`` (:func:`best_joint_moves`). Returns (n,) move indices, -1 for robots
    outside such groups or in groups without an answer within ``budget``."""
    out = np.full(len(cells), -1, np.int64)
    for group in danger_groups(cells, members):
        if len(group) > JOINT_MAX_GROUP:
            continue
        moves = best_joint_moves(cells[group], cost[group], allowed[group], table, budget)
        if moves is not None:
            out[group] = moves
    return out


def prefer_joint_escapes(dist: NDArray[np.float64], cells: NDArray[np.int64], allowed: NDArray[np.bool_],
                         members: NDArray[np.int64], table: NDArray[np.uint8], shape: tuple[int, int],
                         claim_weight: float) -> NDArray[np.float64]:
    """``dist`` (n, 9) with the joint moves of :func:`joint_escapes` ranked first for the
    robots in ``members`` (the others' keys unchanged but for the claims): each chosen move's
    key becomes one less than the robot's least, and every other robot's move onto a chosen
    cell (staying included: a robot that stays keeps its cell) costs ``claim_weight`` more.
    ``shape`` (height, width) of the grid."""
    cost = np.where(np.isnan(dist), np.inf, dist)
    moves = joint_escapes(cells, cost, allowed, members, table)
    chosen = np.flatnonzero(moves >= 0)
    if len(chosen) == 0:
        return dist
    out = dist.copy()
    out[chosen, moves[chosen]] = np.nanmin(np.where(allowed[chosen], out[chosen], np.nan), axis=1) - 1.0
    flat = move_cells(cells, shape)
    hit = claims_on_moves(flat, flat[chosen, moves[chosen]]) > 0
    hit[chosen] = False
    out += claim_weight * hit
    return out
