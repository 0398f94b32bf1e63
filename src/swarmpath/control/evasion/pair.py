"""Two random walkers closing in on one robot together: the chance of being caught within two
steps, played out jointly, on top of the one-walker values beyond.

The walker value (:mod:`~swarmpath.control.evasion.walker`) plays one walker at a time, and the
controllers combine several walkers near a robot as independent, 1 - prod(1 - risk). That
misses the one danger two walkers make together: each alone can be escaped (its value is 0),
but a robot between them, two cells from each, is left with no cell two cells from both when
both step toward it. On the 64 x 64 acceptance world a robot waiting beside its goal stepped
between two walkers on that rating (each 0), both closed in, and every move it had left was
rated 1 in 8 (seed 6067 of ``random_grid_with_movers``, step 115).

For a robot with two walkers within :data:`PAIR_RADIUS` cells this plays the first two steps
as one game against both (expectimax, the walkers stepping independently, each as its model
says):

    risk(a) = sum_{d1, d2} P1(w1, d1) P2(w2, d2) x ( 1                           if d1 or d2 sweeps over r + a
                                                     min_b J(r + a, w1 + d1, w2 + d2, b)  otherwise )
    J(r, w1, w2, b) = sum_{e1, e2} P1(w1, e1) P2(w2, e2) x ( 1                   if e1 or e2 sweeps over r + b
                                                             L(r + b, w1 + e1, w2 + e2)   otherwise )
    L(r, w1, w2) = 1 - (1 - V1_(h-2)(r, w1 - r)) (1 - V2_(h-2)(r, w2 - r))

with a and b over the robot's static moves that do not enter or cross either walker where it
stands, "sweeps over" the checker's own geometry (the walker value's hit tables), and the
walker values V of the remaining h - 2 steps at the leaves (h the horizon), walkers beyond their
radius counted as escaped as there. With h = 2 it is exact for both walkers together. Other
robots and other obstacles are not in the state, as in the walker value.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.evasion.walker import WalkerEvasion
from swarmpath.world.move_rules import GRID_MOVES

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Two walkers both within this many cells (Chebyshev) of a robot are played together.
PAIR_RADIUS = 3

_A = np.arange(9)


def _inside(cells: IntArray, shape: tuple[int, int]) -> NDArray[np.bool_]:
    h, w = shape
    return (cells[..., 0] >= 0) & (cells[..., 0] < w) & (cells[..., 1] >= 0) & (cells[..., 1] < h)


def _chances(table: WalkerEvasion, cells: IntArray) -> FloatArray:
    """P(w, d) (..., 9) of the walkers of ``table`` on ``cells`` (..., 2); 0 off the map."""
    h, w = table.shape
    out = table.model.chances[np.clip(cells[..., 1], 0, h - 1), np.clip(cells[..., 0], 0, w - 1)].astype(float)
    return np.where(_inside(cells, table.shape)[..., None], out, 0.0)


def _sweeps(table: WalkerEvasion, d, rest: IntArray) -> NDArray[np.bool_]:
    """Whether the walker's step ``d`` sweeps over a robot resting at ``rest`` (..., 2), its
    offset from the walker's start."""
    R = table.R
    near = np.abs(rest).max(axis=-1) <= R + 1
    c = np.clip(rest + R + 1, 0, 2 * R + 2)
    return near & table.model.hit[d, c[..., 1], c[..., 0]].astype(bool)


def _blocks(table: WalkerEvasion, a, offset: IntArray) -> NDArray[np.bool_]:
    """Whether robot move ``a`` enters or crosses the walker standing at ``offset`` (..., 2)
    from the robot."""
    R = table.R
    near = np.abs(offset).max(axis=-1) <= R
    c = np.clip(offset + R, 0, 2 * R)
    return near & table.model.forbid[a, c[..., 1], c[..., 0]].astype(bool)


def _leaf(table: WalkerEvasion, k: int, robot: IntArray, offset: IntArray) -> FloatArray:
    """V_k of ``table`` for the robot on ``robot`` + GRID_MOVES[a] + GRID_MOVES[b] and the walker
    at ``offset`` from there (shape (9, 9, 9, 9, 2), dimensions a, d, b, e of
    :func:`_escape_next`); 0 beyond the walker's radius."""
    R = table.R
    cells = (robot + GRID_MOVES[:, None, :] + GRID_MOVES[None, :, :]).reshape(-1, 2)
    V = table.values(k, cells).reshape(9, 9, 2 * R + 1, 2 * R + 1).astype(float)
    near = np.abs(offset).max(axis=-1) <= R
    c = np.clip(offset + R, 0, 2 * R)
    return np.where(near, V[_A[:, None, None, None], _A[None, None, :, None], c[..., 1], c[..., 0]], 0.0)


def _escape_next(table: WalkerEvasion, robot: IntArray, walker: IntArray) -> FloatArray:
    """For one walker on ``walker`` and the robot on ``robot``, after robot move a and walker
    step d: E (9, 9, 9) [a, d, b] = sum_e P(w + d, e) x (1 - sweeps) x (1 - V_(h-2)) over the
    walker's next step e, for the robot's next move b: the chance that this walker neither
    sweeps over the robot next step nor catches it later (its own value). Two walkers step
    independently, so J = S1 S2 - E1 E2 (S the sums of their next chances, 1 where they can
    stand)."""
    G = GRID_MOVES
    a, d, b, e = (_A[:, None, None, None], _A[None, :, None, None], _A[None, None, :, None], _A[None, None, None, :])
    o_next = (walker - robot) + G[d] - G[a]                                     # (9, 9, 1, 1, 2)
    chance = _chances(table, walker + G[_A])[None, :, None, :]                  # (1, 9, 1, 9) [d, e]
    caught = _sweeps(table, e, G[b] - o_next)                                   # (9, 9, 9, 9)
    k = table.horizon - 2
    later = _leaf(table, k, robot, o_next + G[e] - G[b]) if k > 0 else 0.0
    return np.sum(chance * np.where(caught, 0.0, 1.0 - later), axis=-1)        # (9, 9, 9)


def pair_move_risk(first: WalkerEvasion, second: WalkerEvasion, moves: NDArray[np.bool_], robot, walker_1,
                   walker_2) -> FloatArray:
    """The chance (9,) that each of the robot's moves (``GRID_MOVES`` order) ends in a contact
    with either walker within the horizon of ``first`` (module docstring), for a robot on grid
    cell ``robot`` and walkers (just moved) on cells ``walker_1`` (of the kind ``first`` models)
    and ``walker_2`` (of ``second``); ``moves`` (height, width, 9) are the robots' static moves.
    A move the static map forbids, or into or through a walker where it stands, scores 1.

    The next step's sum over both walkers' steps factors, since they step independently:
    with X_i = (1 - sweeps_i) (1 - V_i), sum P1 P2 (1 - X1 X2) = S1 S2 - (sum P1 X1)(sum P2 X2)."""
    r = np.asarray(robot, np.int64).reshape(2)
    w1 = np.asarray(walker_1, np.int64).reshape(2)
    w2 = np.asarray(walker_2, np.int64).reshape(2)
    h, w = moves.shape[:2]
    G = GRID_MOVES
    o1, o2 = w1 - r, w2 - r
    # dimensions: a (robot now), d1, d2 (walkers now), b (robot next)
    a = _A[:, None, None]
    d1, d2 = _A[None, :, None], _A[None, None, :]
    caught_now = _sweeps(first, d1, G[a] - o1) | _sweeps(second, d2, G[a] - o2)           # (9, 9, 9)
    chance_now = _chances(first, w1)[None, :, None] * _chances(second, w2)[None, None, :]
    e1 = _escape_next(first, r, w1)                                                        # (9, 9, 9) [a, d1, b]
    e2 = _escape_next(second, r, w2)                                                       # [a, d2, b]
    s1 = _chances(first, w1 + G[_A]).sum(axis=-1)                                          # (9,) [d1]
    s2 = _chances(second, w2 + G[_A]).sum(axis=-1)
    after_next = (s1[None, :, None, None] * s2[None, None, :, None]
                  - e1[:, :, None, :] * e2[:, None, :, :])                                # (9, 9, 9, 9)
    cell_next = r + G[:, None, None, :]                                                     # (9, 1, 1, 2)
    can = _inside(cell_next, (h, w))[..., None] & moves[np.clip(cell_next[..., 1], 0, h - 1),
                                                          np.clip(cell_next[..., 0], 0, w - 1)]
    o1_next = (o1 + G[d1] - G[a])[..., None, :]                                            # (9, 9, 1, 1, 2)
    o2_next = (o2 + G[d2] - G[a])[..., None, :]                                            # (9, 1, 9, 1, 2)
    can = can & ~_blocks(first, _A, o1_next) & ~_blocks(second, _A, o2_next)
    best_next = np.where(can, after_next, np.inf).min(axis=-1)
    best_next = np.minimum(best_next, 1.0)                                                  # no move left: 1
    risk = np.sum(chance_now * np.where(caught_now, 1.0, best_next), axis=(1, 2))
    allowed = moves[r[1], r[0]] if _inside(r, (h, w)) else np.zeros(9, bool)
    allowed = allowed & ~_blocks(first, _A, o1[None]) & ~_blocks(second, _A, o2[None])
    return np.where(allowed, np.minimum(risk, 1.0), 1.0)
