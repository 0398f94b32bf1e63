"""The last resort of a cornered robot: the move a moving obstacle is least likely to hit.

A grid controller keeps robots out of every cell a moving obstacle *may* enter next step
(D_1 of :class:`~swarmpath.control.hazards.ObstacleForecast`), and its look-ahead keeps them
from being cornered. Obstacles never react, so a robot can still end up with every move,
staying included, inside D_1: a walker coming down the corridor of a dead end, two obstacles
closing in on a robot by a wall. Such a robot used to stay where it was (event ``no_escape``);
a random walker that lingers then hits it sooner or later.

The worst case no longer separates the moves, but their chances still differ. The motion
models say how an obstacle chooses among the moves they allow: a random walker takes each free
direction with the same chance; a bouncer goes straight on, or turns at random where it
cannot; a model that may head anywhere is taken as its whole reach. So for each move of a
cornered robot we count the expected number of obstacles whose next sweep covers the cell the
move ends in (:func:`hit_chances`; covered as in D_1), and the robot takes the move with the smallest count; among
equal ones, the move with the most ways on to cells no obstacle can reach the step after
(:func:`ways_clear`), then the one nearest its goal. A move into or through an obstacle where
it stands now is never taken. Robots that have a sure move are not affected.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.hazards import HazardWindows, ObstacleForecast, moves_past, standing_cells
from swarmpath.world.move_rules import GRID_MOVES

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]

#: Chances closer than this count as equal (then ways on and the distance to the goal decide).
CHANCE_RESOLUTION = 1e-6


def move_weights(possible: BoolArray, extra: FloatArray) -> FloatArray:
    """The chance of each next position (m, 10) of :meth:`ObstacleForecast.next_positions`
    (``possible`` (m, 10)): the same for every possible one, except that an obstacle whose
    model must move (a random walker with a free direction, a bouncer turning) does not stay.
    ``extra`` (m,) > 0 marks models that may head anywhere: their one position stands for
    their whole reach."""
    p = np.asarray(possible, bool).copy()
    must_move = p[:, 1:].any(axis=1) & ~(np.asarray(extra) > 0)
    p[must_move, 0] = False
    count = p.sum(axis=1, keepdims=True)
    return np.where(p, 1.0 / np.maximum(count, 1), 0.0)


def hit_chances(forecast: ObstacleForecast, positions: FloatArray, previous: FloatArray, cells: IntArray,
                skip: BoolArray | None = None) -> tuple[FloatArray, BoolArray]:
    """For robots ending their step in grid ``cells`` (k, c, 2): the expected number of moving
    obstacles (at ``positions`` (m, 2), one step earlier ``previous``) whose sweep to their
    next position covers the cell, shape (k, c), each next position weighted by
    :func:`move_weights`, leaving out the obstacles ``skip`` (m,) marks; and whether an
    obstacle (any) covers the cell where it stands now (k, c): a contact in this very step. A
    cell is covered as in the forecast's D_1: the swept footprint, grown by the robots' radius
    (:meth:`~swarmpath.control.hazards.ObstacleForecast.sweep_ranges`), holds the cell's
    centre."""
    cells = np.asarray(cells, np.int64)
    k, c = cells.shape[:2]
    if forecast.m == 0 or k == 0:
        return np.zeros((k, c)), np.zeros((k, c), bool)
    p = np.asarray(positions, float).reshape(forecast.m, 2)
    cand, possible, extra = forecast.next_positions(p, previous)
    weight = move_weights(possible, extra)
    if skip is not None:
        weight[np.asarray(skip, bool)] = 0.0
    j, s = np.nonzero(weight)
    q = cand[j, s]
    sweeps, of = forecast.sweep_ranges(p[j], q, forecast.keep_lo[j] - extra[j, None],
                                       forecast.keep_hi[j] + extra[j, None])       # (w', 4), sweep of each
    here = forecast.cover_ranges(p + forecast.keep_lo, p + forecast.keep_hi)       # (m, 4)
    x, y = cells[..., 0, None], cells[..., 1, None]

    def inside(r: IntArray) -> BoolArray:
        return (x >= r[:, 0]) & (x < r[:, 2]) & (y >= r[:, 1]) & (y < r[:, 3])

    covers = np.zeros((len(sweeps), len(q)))
    covers[np.arange(len(sweeps)), of] = 1.0    # a diagonal sweep is several rows of cells
    swept = (inside(sweeps).astype(float) @ covers) > 0
    return swept @ weight[j, s], inside(here).any(axis=-1)


def ways_clear(hz: HazardWindows, local_rows: IntArray, dest: IntArray) -> IntArray:
    """For the robots ``local_rows`` (r,) of ``hz`` (indices into ``hz.rows``) with candidate
    cells ``dest`` (r, 9, 2): how many static moves (staying included) lead from each
    candidate to a cell no obstacle may cover the step after next (D_2; with windows of one
    step only, all static moves), shape (r, 9)."""
    rows = np.asarray(local_rows, np.int64)
    size = hz.covered.shape[-1]
    c = np.asarray(dest, np.int64) - hz.origin[rows, None, :]
    ways = hz.moves[rows]
    if hz.corners and hz.covered.shape[0] >= 2:
        # the moves of the step after are made while the obstacles stand where it left them
        ways = moves_past(ways, standing_cells(hz.covered[:, rows], 1))
    moves = ways[np.arange(len(rows))[:, None], np.clip(c[..., 1], 0, size - 1), np.clip(c[..., 0], 0, size - 1)]
    if hz.covered.shape[0] < 2:
        return moves.sum(axis=-1)
    around = c[..., None, :] + GRID_MOVES                                  # (r, 9, 9, 2)
    inside = np.all((around >= 0) & (around < size), axis=-1)
    bx = np.clip(around[..., 0], 0, size - 1)
    by = np.clip(around[..., 1], 0, size - 1)
    clear = inside & ~hz.covered[1][rows[:, None, None], by, bx]
    return np.sum(moves & clear, axis=-1)


def last_resort(forecast: ObstacleForecast, positions: FloatArray, previous: FloatArray, starts: FloatArray,
                targets: FloatArray, dest: IntArray, feasible: BoolArray, ways: IntArray,
                walker_risk: FloatArray | None = None, walkers: BoolArray | None = None
                ) -> tuple[BoolArray, FloatArray]:
    """The moves cornered robots may take, and their order. ``starts`` (r, 2) where the robots
    are, ``targets`` (r, 9, 2) where each move ends (move 0: stay) and ``dest`` (r, 9, 2) its
    grid cell, ``feasible`` (r, 9) the moves the static map and the robot's reach allow,
    ``ways`` (r, 9) from :func:`ways_clear`. ``walker_risk`` (r, 9), with ``walkers`` (m,)
    marking the obstacles it accounts for: the exact chance of each move being caught by those
    random walkers (:mod:`swarmpath.control.evasion`), which then replaces their hit chance.

    Returns (allowed (r, 9), cost (r, 9)). A move is allowed unless it ends in or passes
    through an obstacle where it stands now; staying, unless an obstacle covers the robot now.
    The cost is the hit chance of :func:`hit_chances` (plus ``walker_risk``; rounded to
    :data:`CHANCE_RESOLUTION`) plus ``(9 - ways) * CHANCE_RESOLUTION / 10``: the least likely
    hit first, then the most ways on. The caller adds the distance to the goal below both.

    Why the walkers' exact chance: a move that is safe this step can be a dead end the walker
    closes the next; the evasion value weighs that, the one-step chance does not."""
    positions = np.asarray(positions, float)
    chance, now = hit_chances(forecast, positions, previous, dest, skip=walkers if walker_risk is not None else None)
    if walker_risk is not None:
        chance = chance + np.asarray(walker_risk, float)
    allowed = np.asarray(feasible, bool) & ~now
    allowed &= ~forecast.crossings(np.asarray(starts, float), np.asarray(targets, float), positions)
    allowed[:, 0] = ~now[:, 0]
    cost = np.round(chance / CHANCE_RESOLUTION) * CHANCE_RESOLUTION + (9 - np.asarray(ways)) * CHANCE_RESOLUTION / 10
    return allowed, cost


def no_escape_events(stood: BoolArray, cornered: BoolArray) -> list[dict]:
    """The ``no_escape`` events of one step: robots ``stood`` (n,) in a cell an obstacle may
    reach next step because the other robots left them no way out, and robots ``cornered``
    (n,) that had no move outside D_1 at all and took the one of :func:`last_resort`."""
    stood = np.asarray(stood, bool) & ~np.asarray(cornered, bool)
    return ([{"robot": int(i), "kind": "no_escape",
              "detail": "a moving obstacle may reach this cell and no move leads out"} for i in np.flatnonzero(stood)]
            + [{"robot": int(i), "kind": "no_escape",
                "detail": "every move ends where a moving obstacle may be next; took the least likely"}
               for i in np.flatnonzero(cornered)])
