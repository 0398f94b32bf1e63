"""The turn game: keeping clear of a turning bounce8 obstacle by watching it turn.

The look-ahead tiers of :mod:`swarmpath.control.hazards` ask whether a robot can keep clear
of D_1 ... D_K, the cells the obstacles *may* cover in each of the next K steps (K = 3 by
default). That is an open-loop question: the robot must pick its whole path now, as if it
would not see where the obstacles went. A bounce8 obstacle about to meet a wall may turn any
of seven ways, and the union of its seven runs covers nearly every cell of a nook beside that
wall; and the tiers look three steps ahead, while a robot in a nook needs four or five to get
out. In the 64 x 64 acceptance world such robots waited on their goals until the obstacle had
turned their way, then had no move left (seeds 1606 and 1673).

The robot sees each turn one step after it is made, so the true question is a game: is there
a move now such that, whichever way the obstacle turns, the robot has a move then that keeps
it clear, and so on? A bounce8 obstacle is deterministic until it meets something, so the
game tree is small: one branch per step while its way is free, up to seven where it turns.
For each moving bounce8 obstacle that will meet something within ``depth`` steps (the others
go straight, and the open-loop runs are exact for them), backward induction over its tree on
a square region around it gives, for every cell, how many steps a robot arriving there next
step can keep clear, playing best:

    V(s, c) = min over branches b of s:  0                          if c in C_l or sweep(s -> b)
                                         1 + max_a V(b, c + a)      otherwise (1 at the last level),

where s is the obstacle's state (position and step) at level l, C_l the open-loop cover of
every *other* obstacle at step l + 1 (D_(l+1) without this obstacle's ranges, from
``ObstacleForecast.owned_step_ranges``), sweep(s -> b) the cells its move covers (as in D_1:
the swept footprint grown by the robots' radius), and a the robot's static moves (staying
included). The other obstacles are taken at their worst, so each obstacle's value is sound on
its own, and a robot near two turning obstacles takes the better of the two.

A robot near such an obstacle then ranks its candidates by that value (``depth`` steps clear
first) instead of the open-loop tiers, and among equal values by the ways on: a candidate from
which, whichever way the obstacle turns, at least two moves keep the value ranks before one
with a single such move (another robot may stand on it; the tiers' spare way). It keeps to the
best when it has a choice. Without the spare way a robot fled along the map's edge into a
cell whose only way on was a nook another robot stood in (seed 1090).

Each obstacle's tree has a budget (:data:`TURN_GAME_BUDGET` nodes): an obstacle with more
(turning again and again in a pocket) leaves its robots to the tiers. ``depth`` is 4
(:data:`TURN_GAME_DEPTH`): 3 leaves seed 1606 cornered; 4 and 5 both get seeds 1606 and 1673
through, and each level can multiply the tree by seven (docs/algorithms/pibt.md).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.hazards import BOUNCE8, ObstacleForecast, paint_windows
from swarmpath.world.move_rules import GRID_MOVES

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]

#: Steps the game plays ahead.
TURN_GAME_DEPTH = 4
#: Game-tree nodes one obstacle may expand in one step; beyond it the open-loop tiers stand.
TURN_GAME_BUDGET = 400


def turning_obstacles(forecast: ObstacleForecast, positions: FloatArray, previous: FloatArray,
                      depth: int) -> IntArray:
    """The moving bounce8 obstacles whose straight run meets something within ``depth``
    steps (there they turn at random): the ones the game tree follows."""
    p = np.asarray(positions, float).reshape(forecast.m, 2)
    d = p - np.asarray(previous, float).reshape(forecast.m, 2)
    moving = np.hypot(d[:, 0], d[:, 1]) > 1e-9
    j = np.flatnonzero((forecast.code == BOUNCE8) & moving)
    if len(j) == 0:
        return j
    ahead = p[j, None, :] + d[j, None, :] * np.arange(1, depth + 1)[None, :, None]
    fits = forecast.fits(np.repeat(j, depth), ahead.reshape(-1, 2)).reshape(len(j), depth)
    return j[~fits.all(axis=1)]


def _region_moves(moves: BoolArray, origin: IntArray, size: int) -> BoolArray:
    """The static moves (size, size, 9) of the cells ``origin + (0 ... size - 1)``; none
    outside the grid."""
    h, w = moves.shape[:2]
    out = np.zeros((size, size, 9), bool)
    x0, y0 = max(origin[0], 0), max(origin[1], 0)
    x1, y1 = min(origin[0] + size, w), min(origin[1] + size, h)
    if x0 < x1 and y0 < y1:
        out[y0 - origin[1]:y1 - origin[1], x0 - origin[0]:x1 - origin[0]] = moves[y0:y1, x0:x1]
    return out


def _move_index(moves: BoolArray) -> IntArray:
    """For a region's static moves (s, s, 9): the flat index (s, s, 9) of each move's cell in
    the region padded by one cell, the padding's corner (0) where the move is not allowed."""
    s = moves.shape[0]
    ys, xs = np.mgrid[0:s, 0:s]
    idx = (ys[..., None] + 1 + GRID_MOVES[:, 1]) * (s + 2) + xs[..., None] + 1 + GRID_MOVES[:, 0]
    return np.where(moves, idx, 0).astype(np.int32)


def _best_move(value: NDArray[np.int8], index: IntArray, count: bool = False
               ) -> NDArray[np.int8] | tuple[NDArray[np.int8], NDArray[np.int8]]:
    """For every cell of ``value`` (n, s, s): the largest value one static move away
    (staying included; ``index`` (n, s, s, 9) from :func:`_move_index`, one per region);
    cells beyond the region count 0. With ``count``, also how many moves reach that value."""
    n, s = value.shape[0], value.shape[-1]
    pad = np.zeros((n, s + 2, s + 2), value.dtype)
    pad[:, 1:-1, 1:-1] = value
    flat = np.take_along_axis(pad.reshape(n, (s + 2) * (s + 2)), index.reshape(n, s * s * 9), axis=1)
    each = flat.reshape(n, s, s, 9)
    best = each.max(axis=-1)
    if not count:
        return best
    return best, np.sum((each == best[..., None]) & (index > 0), axis=-1).astype(np.int8)


class TurnGame:
    """The turn game of one run's controller: :meth:`clear_steps` for the turning obstacles,
    :meth:`ranks` for the robots near them. Keeps the move tables of the regions it has played
    on (bounded; the static moves never change).

    Parameters
    ----------
    forecast : the controller's :class:`~swarmpath.control.hazards.ObstacleForecast`
    moves : bool (h, w, 9), the robots' static moves
    depth : steps played ahead; budget : game-tree nodes per obstacle and step
    """

    def __init__(self, forecast: ObstacleForecast, moves: BoolArray, depth: int = TURN_GAME_DEPTH,
                 budget: int = TURN_GAME_BUDGET):
        self.forecast = forecast
        self.moves = np.asarray(moves, bool)
        self.depth = depth
        self.budget = budget
        self._indices: dict[tuple[int, int, int], IntArray] = {}

    def _index(self, origin: IntArray, size: int) -> IntArray:
        """:func:`_move_index` of the region at ``origin``, kept (the static moves never change)."""
        key = (int(origin[0]), int(origin[1]), size)
        found = self._indices.get(key)
        if found is None:
            if len(self._indices) > 1024:   # 16 KiB each at depth 4
                self._indices.clear()
            found = self._indices[key] = _move_index(_region_moves(self.moves, origin, size))
        return found

    def clear_steps(self, positions: FloatArray, previous: FloatArray, turning: IntArray,
                    owned: list[tuple[IntArray, IntArray]], near_lo: IntArray, near_hi: IntArray
                    ) -> tuple[IntArray, NDArray[np.int8], NDArray[np.int8], BoolArray]:
        """V of the module docstring for each obstacle of ``turning`` (t,) (at ``positions``,
        one step earlier ``previous``): (origins (t, 2), values (t, s, s), ways (t, s, s), solved
        (t,)) on a square region of cells ``origin + (0 ... s - 1)`` around each, a value being
        the steps (0 ... depth) a robot arriving in that cell next step can keep clear of every moving
        obstacle, reacting to that obstacle's turns, and ways the fewest moves that keep that
        value the step after, whichever way the obstacle goes. ``owned``: the forecast's
        :meth:`~swarmpath.control.hazards.ObstacleForecast.owned_step_ranges` for ``depth``
        steps. Exact on the cells within depth steps of the robots near each obstacle, whose
        cells lie in the box ``near_lo[t] ... near_hi[t]`` (t, 2): a branch whose obstacle can
        no longer come near them is not followed, and states met twice at one level are
        valued once. An obstacle whose tree has more than the budget of nodes is not solved.

        The trees are built level by level (all states of a level, of every obstacle, in one
        call of the motion model) and valued backwards level by level, every level's nodes at
        once."""
        fc, depth = self.forecast, self.depth
        turning = np.asarray(turning, np.int64)
        t = len(turning)
        p = np.asarray(positions, float).reshape(fc.m, 2)
        q = np.asarray(previous, float).reshape(fc.m, 2)
        res = fc.resolution
        step = np.hypot(*(p[turning] - q[turning]).T)
        keep_lo, keep_hi = fc.keep_lo[turning], fc.keep_hi[turning]
        extent = np.max(np.abs(np.concatenate([keep_lo, keep_hi], axis=1)), axis=1)
        radius = int(np.ceil(np.max((depth * step + extent) / res))) + depth + 1
        size = 2 * radius + 1
        origin = np.floor(p[turning] / res).astype(np.int64) - radius                      # (t, 2)
        covered = np.stack([paint_windows(r, origin, size, skip=o[None, :] == turning[:, None]) for r, o in owned],
                           axis=1)                                                          # (t, depth, s, s)
        index = np.stack([self._index(o, size) for o in origin])                            # (t, s, s, 9)
        # the value with the obstacle out of the way, level by level
        free = [np.where(covered[:, depth - 1], 0, 1).astype(np.int8)]
        for level in range(depth - 2, -1, -1):
            free.insert(0, np.where(covered[:, level], 0, 1 + _best_move(free[0], index)).astype(np.int8))
        lo_w = (np.asarray(near_lo) - depth) * res
        hi_w = (np.asarray(near_hi) + 1 + depth) * res
        # forward: the states of each level (deduplicated), and the edges parent -> child
        tag = np.arange(t)
        pos, vel = p[turning], p[turning] - q[turning]
        expand = [np.ones(t, bool)]
        edges: list[tuple[IntArray, IntArray, IntArray, FloatArray, FloatArray]] = []   # (parent, child, tag, a, b)
        nodes = np.ones(t, np.int64)
        for level in range(depth):
            live = np.flatnonzero(expand[-1])
            parent, new_pos, new_vel = fc.bounce_successors(turning[tag[live]], pos[live], vel[live])
            parent = live[parent]
            new_tag = tag[parent]
            nodes += np.bincount(new_tag, minlength=t)
            key = np.column_stack([new_tag, np.round(np.column_stack([new_pos, new_vel]) * 1e6)]).astype(np.int64)
            _, first, child = np.unique(key, axis=0, return_index=True, return_inverse=True)
            child = child.ravel()
            edges.append((parent, child, new_tag, pos[parent], new_pos))
            pos, vel, tag = new_pos[first], new_vel[first], new_tag[first]
            gap = np.max(np.maximum(lo_w[tag] - pos, pos - hi_w[tag]), axis=1)
            expand.append((gap <= (depth - level - 1) * step[tag] + extent[tag] + res) & (nodes[tag] <= self.budget))
        # backward: V of level l's states from their children's, all at once
        ys = np.arange(size)[:, None]
        xs = np.arange(size)[None, :]
        value = np.zeros((0, size, size), np.int8)
        for level in range(depth - 1, -1, -1):
            parent, child, g, a, b = edges[level]
            # the cells each edge's sweep covers: a box per cell row (fc.sweep_ranges), painted
            rows, edge = fc.sweep_ranges(a, b, keep_lo[g], keep_hi[g])
            x0, y0 = rows[:, 0] - origin[g[edge], 0], rows[:, 1] - origin[g[edge], 1]
            x1, y1 = rows[:, 2] - origin[g[edge], 0], rows[:, 3] - origin[g[edge], 1]
            hit = covered[g, level].copy()
            row_hit = ((xs[None] >= x0[:, None, None]) & (xs[None] < x1[:, None, None])
                       & (ys[None] >= y0[:, None, None]) & (ys[None] < y1[:, None, None]))
            np.logical_or.at(hit, edge, row_hit)
            if level + 1 < depth:
                later = np.where(expand[level + 1][child, None, None], value[child], free[level + 1][g])
                best, count = _best_move(later, index[g], count=True)
                v = np.where(hit, 0, 1 + best).astype(np.int8)
            else:
                v = np.where(hit, 0, 1).astype(np.int8)
                count = np.full(v.shape, 9, np.int8)
            value = np.full((len(expand[level]), size, size), depth - level, np.int8)
            np.minimum.at(value, parent, v)
        # ways on at the root: the moves after each branch that keep the value, the fewest
        ways = np.full((t, size, size), 9, np.int8)
        np.minimum.at(ways, parent, np.where(v > 0, count, 0).astype(np.int8))
        return origin, value[:t], ways, nodes <= self.budget

    def ranks(self, positions: FloatArray, previous: FloatArray, cells: IntArray, base: BoolArray, dest: IntArray,
              allowed: BoolArray, threatened: BoolArray, rank: IntArray, fallback: BoolArray | None = None
              ) -> tuple[BoolArray, BoolArray, IntArray]:
        """Re-rank the candidates of some robots (in grid ``cells`` (r, 2); ``base``
        (r, 9) their candidates before the look-ahead tiers, reaching ``dest`` (r, 9, 2);
        ``allowed``, ``threatened``, ``rank`` what the tiers made of them) that a turning bounce8
        obstacle can reach: by :meth:`clear_steps`, the best of the obstacles near: rank 2 *
        (depth - steps clear), plus 1 with fewer than two ways on (as the tiers' spare way),
        keeping to the best-ranked candidates (all of them, ranked, for the robots
        ``fallback`` marks); threatened when staying is not among those.
        The other robots keep the tiers' answer. Returns the new (allowed, threatened, rank)."""
        allowed, threatened, rank = allowed.copy(), threatened.copy(), rank.copy()
        fc, depth = self.forecast, self.depth
        turning = turning_obstacles(fc, positions, previous, depth)
        if len(turning) == 0 or len(cells) == 0:
            return allowed, threatened, rank
        cells = np.asarray(cells, np.int64)
        dest = np.asarray(dest, np.int64)
        base = np.asarray(base, bool)
        best = np.full(base.shape, -1, np.int64)
        res = fc.resolution
        p = np.asarray(positions, float).reshape(fc.m, 2)
        centre = np.floor(p[turning] / res).astype(np.int64)
        near = np.abs(cells[None, :, :] - centre[:, None, :]).max(axis=2) <= depth + 2      # (t, r)
        some = near.any(axis=1)
        if not some.any():
            return allowed, threatened, rank
        turning, near = turning[some], near[some]
        big = np.iinfo(np.int64).max // 4
        near_lo = np.where(near[..., None], cells[None], big).min(axis=1)
        near_hi = np.where(near[..., None], cells[None], -big).max(axis=1)
        owned = fc.owned_step_ranges(p, previous, depth)
        origin, values, ways, solved = self.clear_steps(p, previous, turning, owned, near_lo, near_hi)
        size = values.shape[-1]
        for k in np.flatnonzero(solved).tolist():
            rows = np.flatnonzero(near[k])
            c = dest[rows] - origin[k]
            inside = np.all((c >= 0) & (c < size), axis=-1)
            cy, cx = np.clip(c[..., 1], 0, size - 1), np.clip(c[..., 0], 0, size - 1)
            # steps clear first, then two ways on rather than one (another robot may take one)
            key = np.where(inside, 2 * values[k, cy, cx].astype(np.int64) + (ways[k, cy, cx] >= 2), 0)
            best[rows] = np.maximum(best[rows], key)
        rows = np.flatnonzero((best >= 0).any(axis=1) & base.any(axis=1))
        if len(rows) == 0:
            return allowed, threatened, rank
        new = np.where(base[rows], 2 * depth + 1 - np.maximum(best[rows], 0), rank[rows])
        keep = base[rows] & (new == np.where(base[rows], new, np.iinfo(np.int64).max).min(axis=1, keepdims=True))
        rank[rows] = new
        keep_all = np.zeros(len(rows), bool) if fallback is None else np.asarray(fallback, bool)[rows]
        allowed[rows] = np.where(keep_all[:, None], base[rows], keep)
        threatened[rows] = ~keep[:, 0]
        return allowed, threatened, rank
