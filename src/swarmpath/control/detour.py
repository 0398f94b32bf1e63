"""Detours around moving obstacles that linger on a robot's way.

The grid controllers rank a robot's moves by its exact distance to its goal on the static map
(lazy tables, :mod:`swarmpath.search.lazy_distance`). An obstacle that stays on the shortest
way (a bouncer shuttling in a slot two cells long, found on the 64 x 64 world with 20
``bounce`` obstacles) keeps the best moves out of the candidates for good: the robot waits
beside it for ever, and since it never moves the run ends in a deadlock, though a way round,
one or two cells longer, is free.

A robot that has not come closer to its goal for ``DETOUR_AFTER`` steps therefore ranks its
moves by the *detour distance*: on a square window of ``DETOUR_RADIUS`` cells around it, the
cells where obstacles *linger* are taken as blocked (:class:`Lingering`: an obstacle's
footprint, grown by the robots' radius, stood on the cell in about half of the recent steps:
a decayed count, ``LINGER_DECAY`` per step, of at least ``LINGER_LEVEL``), and the cost from a
cell to the goal is the shortest way inside the window, over free cells, to a cell on the
window's rim (plus that cell's exact distance to the goal) or to the goal itself:

    d'(v) = min over exits e of  path_window(v, e) + dist(e, goal)

with exits the free, unblocked cells on the rim, and the goal cell when it lies in the window
unblocked (dist 0). Where nothing lingers, d' equals dist wherever the shortest way leaves
through the rim. A goal cell where an obstacle lingers gives no detour (the robot waits by
it: going round would lead it nowhere nearer), nor does a window the obstacles seal.

Only lingering counts, not the cells an obstacle may reach next (the look-ahead's D_k): a
random walker's reach moves with it every step, and detours round it sent robots back and
forth (seed 1037 of the 64 x 64 world, a robot shuttling between two cells for 8 steps); an
obstacle passing by leaves a count of 1 on its cells, a bouncer shuttling between two cells
4.7 to 5.3.

Computed for all such robots at once by value iteration on their windows (Bellman-Ford:
every cell takes the least of its moves' cost plus the value where the move ends, until
nothing changes, at most one sweep per window cell), with the moves of the static grid
(no corner cutting).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.hazards import paint
from swarmpath.world.move_rules import GRID_MOVES

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Steps without coming closer to its goal after which a robot takes detours round lingering obstacles.
DETOUR_AFTER = 8
#: Half the side of the window a detour is searched on (cells).
DETOUR_RADIUS = 6
#: Each step the lingering count of every cell is multiplied by this, then 1 is added where an
#: obstacle stands.
LINGER_DECAY = 0.9
#: Cells counted at least this are blocked for detours (4: an obstacle on the cell about every
#: other step lately; one that stays for good reaches 10).
LINGER_LEVEL = 4.0
MOVE_COST = np.linalg.norm(GRID_MOVES, axis=1)
STAY = 0  # GRID_MOVES[0] is (0, 0)


def window_cells(grid: NDArray, origins: IntArray, size: int) -> tuple[NDArray, BoolArray]:
    """The values of ``grid`` (h, w, ...) on square windows (r, size, size, ...), window w
    starting at cell ``origins[w]`` (x, y), and which window cells lie on the grid (r, size,
    size); off the grid the values are those of the nearest grid cell."""
    h, w = grid.shape[:2]
    off = np.arange(size)
    xs = origins[:, 0, None] + off[None]
    ys = origins[:, 1, None] + off[None]
    inside = ((ys >= 0) & (ys < h))[:, :, None] & ((xs >= 0) & (xs < w))[:, None, :]
    return grid[np.clip(ys, 0, h - 1)[:, :, None], np.clip(xs, 0, w - 1)[:, None, :]], inside


def window_moves(moves: BoolArray, origins: IntArray, size: int) -> BoolArray:
    """The static moves (``moves`` (h, w, 9), see ``static_moves``) of the cells of square
    windows (r, size, size, 9), window w starting at cell ``origins[w]`` (x, y); cells off the
    grid have no move."""
    got, inside = window_cells(moves, origins, size)
    return got & inside[..., None]


def detour_distances(covered: BoolArray, moves: BoolArray, exit_cost: FloatArray, dest: IntArray,
                     max_sweeps: int | None = None) -> FloatArray:
    """The detour distance d' of every candidate of r robots on their windows.

    ``covered`` (r, s, s): cells counted as blocked (the obstacles' reach); ``moves`` (r, s,
    s, 9): the static moves from each window cell; ``exit_cost`` (r, s, s): the cost to the
    goal from each exit cell (inf elsewhere: not an exit); ``dest`` (r, c, 2): window
    coordinates (x, y) of the candidates' cells. Returns (r, c): d' at each candidate's cell,
    inf where the window offers no way out or the cell is covered or off the window."""
    r, s = covered.shape[:2]
    value = np.where(covered, np.inf, exit_cost)
    free = ~covered
    pad = 1
    sweeps = max_sweeps if max_sweeps is not None else s * s
    for _ in range(sweeps):
        padded = np.pad(value, ((0, 0), (pad, pad), (pad, pad)), constant_values=np.inf)
        best = value.copy()
        for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
            if dx == 0 and dy == 0:
                continue
            there = padded[:, pad + dy:pad + dy + s, pad + dx:pad + dx + s]
            cand = np.where(moves[..., a] & free, there + MOVE_COST[a], np.inf)
            np.minimum(best, cand, out=best)
        if np.array_equal(best, value):
            break
        value = best
    d = np.asarray(dest, np.int64)
    inside = (d[..., 0] >= 0) & (d[..., 0] < s) & (d[..., 1] >= 0) & (d[..., 1] < s)
    rows = np.arange(r)[:, None]
    out = value[rows, np.clip(d[..., 1], 0, s - 1), np.clip(d[..., 0], 0, s - 1)]
    return np.where(inside, out, np.inf)


def detour_exits(covered: BoolArray, origins: IntArray, goal_cells: IntArray, rim_cost: FloatArray) -> FloatArray:
    """Exit costs (r, s, s) of the windows (``origins`` (r, 2): each window's corner cell):
    ``rim_cost`` (r, q) (the exact goal distances of the rim cells, in :func:`rim_cells`
    order) on the rim's uncovered cells, 0 on the goal cell when it lies in the window
    uncovered, inf elsewhere. A window whose goal cell is covered has no exit."""
    r, s = covered.shape[:2]
    out = np.full((r, s, s), np.inf)
    (dy, dx), _ = rim_cells(origins, s)
    out[:, dy, dx] = rim_cost
    g = np.asarray(goal_cells, np.int64) - origins
    in_window = np.all((g >= 0) & (g < s), axis=1)
    rows = np.flatnonzero(in_window)
    out[rows, g[rows, 1], g[rows, 0]] = 0.0
    sealed = in_window.copy()
    sealed[rows] = covered[rows, g[rows, 1], g[rows, 0]]
    out[sealed] = np.inf
    out[covered] = np.inf
    return out


def rim_cells(origins: IntArray, size: int) -> tuple[tuple[IntArray, IntArray], IntArray]:
    """The rim of each window: ((dy, dx) window coordinates (q,) each, grid cells (r, q, 2))."""
    rim = np.zeros((size, size), bool)
    rim[0, :] = rim[-1, :] = rim[:, 0] = rim[:, -1] = True
    dy, dx = np.nonzero(rim)
    cells = np.asarray(origins, np.int64)[:, None, :] + np.stack([dx, dy], axis=1)[None]
    return (dy, dx), cells


@dataclass
class Lingering:
    """Where moving obstacles have stood lately: per grid cell the count of steps an obstacle's
    footprint (grown by the robots' radius, as in the forecast's boxes) covered it, each older
    step weighted ``LINGER_DECAY`` less (created in a controller's ``reset``, updated every
    step)."""

    level: FloatArray

    @classmethod
    def start(cls, shape: tuple[int, int]) -> "Lingering":
        return cls(np.zeros(shape))

    def update(self, forecast, positions: FloatArray) -> None:
        """Count the obstacles (``forecast``'s footprints) standing at ``positions`` (m, 2)."""
        p = np.asarray(positions, float).reshape(-1, 2)
        here = paint(self.level.shape, forecast.cover_ranges(p + forecast.keep_lo, p + forecast.keep_hi))
        self.level *= LINGER_DECAY
        self.level += here

    def windows(self, origins: IntArray, size: int) -> BoolArray:
        """Cells counted at least ``LINGER_LEVEL`` on square windows (r, size, size) starting at
        cells ``origins`` (r, 2) (x, y); cells off the grid are not counted."""
        got, inside = window_cells(self.level, origins, size)
        return (got >= LINGER_LEVEL) & inside


def detour_costs(lingering: Lingering, cells: IntArray, goal_cells: IntArray, moves: BoolArray, goal_distance,
                 radius: int = DETOUR_RADIUS) -> tuple[FloatArray, BoolArray]:
    """d' (k, 9) of the 9 moves (``GRID_MOVES`` order) of k robots in ``cells`` (k, 2) with
    goals ``goal_cells`` (k, 2), on windows of ``radius`` cells around them, the cells where
    obstacles linger blocked. ``moves``: the static moves of the grid (h, w, 9);
    ``goal_distance(rows, cells)``: exact goal distances of robots ``rows`` (q,) from ``cells``
    (q, 2), inf off the grid or blocked. inf where there is no detour. Also returns which
    windows (k,) hold a lingering cell at all: on the others d' is the static distance at best."""
    cells = np.asarray(cells, np.int64).reshape(-1, 2)
    k = len(cells)
    if k == 0:
        return np.zeros((0, 9)), np.zeros(0, bool)
    size = 2 * radius + 1
    origins = cells - radius
    covered = lingering.windows(origins, size)
    touched = covered.any(axis=(1, 2))
    wm = window_moves(moves, origins, size)
    covered |= ~wm[..., STAY]   # static obstacles and cells off the grid
    _, rim = rim_cells(origins, size)
    q = rim.shape[1]
    rows = np.repeat(np.arange(k), q)
    rim_cost = np.asarray(goal_distance(rows, rim.reshape(-1, 2)), float).reshape(k, q)
    exits = detour_exits(covered, origins, goal_cells, rim_cost)
    dest = radius + GRID_MOVES[None].repeat(k, axis=0)
    return detour_distances(covered, wm, exits, dest), touched


#: Added to the distance of a move with no detour when others have one (cells).
NO_DETOUR = 1e3


def detour_ranking(lingering: Lingering, cells: IntArray, goal_cells: IntArray, moves: BoolArray,
                   distance: FloatArray, goal_distance) -> FloatArray:
    """The distances (k, 9) a held-back robot ranks its moves by: d' (:func:`detour_costs`)
    where a move has a detour, the static ``distance`` (k, 9) plus ``NO_DETOUR`` where it has
    none but another move has; a robot none of whose moves has a detour keeps ``distance``
    (it waits: its goal is blocked, or the window is sealed), and so does a robot near which
    nothing lingers. NaN and inf (impossible moves) stay."""
    d, touched = detour_costs(lingering, cells, goal_cells, moves, goal_distance)
    some = (np.isfinite(d).any(axis=1) & touched)[:, None]
    out = np.where(np.isfinite(d), d, distance + NO_DETOUR)
    out = np.where(np.isfinite(distance), out, distance)
    return np.where(some, out, distance)
