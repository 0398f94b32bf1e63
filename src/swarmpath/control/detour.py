"""Detours around moving obstacles that linger on a robot's way.

The grid controllers rank a robot's moves by its exact distance to its goal on the static map
(lazy tables, :mod:`swarmpath.search.lazy_distance`). An obstacle that stays on the shortest
way (a bouncer shuttling in a slot two cells long, found on the 64 x 64 world with 20
``bounce`` obstacles; a bouncer parked for good in the mouth of a 1-wide aisle) keeps the best
moves out of the candidates for good: the robot waits beside it for ever, and since it never
moves the run ends in a deadlock, though a way round is free.

A robot that has not come closer to its goal for ``DETOUR_AFTER`` steps therefore ranks its
moves by the *detour distance* d': the exact distance to its goal on the map with the cells
where obstacles *linger* taken as blocked (:class:`Lingering`: an obstacle's footprint, grown
by the robots' radius, stood on the cell in about half of the recent steps: a decayed count,
``LINGER_DECAY`` per step, of at least ``LINGER_LEVEL``). Blocked cells keep the static
map's corner rule, so d' is the static distance of that map:

    d'(v) = dist on (static blocked | lingering) from v to the goal

A goal cell where an obstacle lingers gives no detour (the robot waits by it: going round
would lead it nowhere nearer), nor does a map on which the lingering cells cut the robot off
from its goal.

d' is taken on the whole map, not on a window around the robot. A window (13 x 13 cells,
the first version) that moves with the robot saw an obstacle parked six cells away from one
cell and not from the next: from the first the robot turned back to go round, from the second
the shortest way led past the obstacle again, and the robot stepped back and forth for 640
steps (a warehouse with 1-wide aisles and a bouncer parked in an aisle's mouth).

Only lingering counts, not the cells an obstacle may reach next (the look-ahead's D_k): a
random walker's reach moves with it every step, and detours round it sent robots back and
forth (seed 1037 of the 64 x 64 world, a robot shuttling between two cells for 8 steps); an
obstacle passing by leaves a count of 1 on its cells, a bouncer shuttling between two cells
4.7 to 5.3.

The distances come from lazy tables (Reverse Resumable A*, as for the static distances) on
the map with the lingering cells blocked: built again when those cells change, and shared by
the robots that share a goal; the tables of goals no robot asked for on a step are freed.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.hazards import paint
from swarmpath.search.lazy_distance import LazyDistanceTables
from swarmpath.world.move_rules import GRID_MOVES

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Steps without coming closer to its goal after which a robot takes detours round lingering obstacles.
DETOUR_AFTER = 8
#: Each step the lingering count of every cell is multiplied by this, then 1 is added where an
#: obstacle stands.
LINGER_DECAY = 0.9
#: Cells counted at least this are blocked for detours (4: an obstacle on the cell about every
#: other step lately; one that stays for good reaches 10).
LINGER_LEVEL = 4.0


@dataclass
class Lingering:
    """Where moving obstacles have stood lately: per grid cell the count of steps an obstacle's
    footprint (grown by the robots' radius, as in the forecast's boxes) covered it, each older
    step weighted ``LINGER_DECAY`` less (created in a controller's ``reset``, updated every
    step); and the detour distances d' on the map with the cells counted ``LINGER_LEVEL`` or
    more blocked."""

    level: FloatArray
    static: BoolArray
    connectivity: int = 8
    _mask: BoolArray | None = field(default=None, init=False, repr=False)
    _tables: LazyDistanceTables | None = field(default=None, init=False, repr=False)
    _handles: dict = field(default_factory=dict, init=False, repr=False)

    @classmethod
    def start(cls, static: BoolArray, connectivity: int = 8) -> "Lingering":
        """Nothing counted yet on the map ``static`` (h, w), bool ``blocked[y, x]``."""
        static = np.asarray(static, bool)
        return cls(np.zeros(static.shape), static, connectivity)

    def update(self, forecast, positions: FloatArray) -> None:
        """Count the obstacles (``forecast``'s footprints) standing at ``positions`` (m, 2)."""
        p = np.asarray(positions, float).reshape(-1, 2)
        here = paint(self.level.shape, forecast.cover_ranges(p + forecast.keep_lo, p + forecast.keep_hi))
        self.level *= LINGER_DECAY
        self.level += here

    def blocked(self) -> BoolArray:
        """The map of the detours (h, w): static obstacles and the cells where obstacles linger."""
        return self.static | (self.level >= LINGER_LEVEL)

    def detour_distances(self, goal_cells: IntArray, cells: IntArray) -> FloatArray:
        """d' (k, c) from ``cells`` (k, c, 2) (x, y) to the goal of each of k robots
        (``goal_cells`` (k, 2)): inf on blocked cells, off the map, where the lingering cells
        cut the cell off from the goal, and for a goal cell where an obstacle lingers."""
        goal_cells = np.asarray(goal_cells, np.int64).reshape(-1, 2)
        cells = np.asarray(cells, np.int64).reshape(len(goal_cells), -1, 2)
        mask = self.blocked()
        if self._mask is None or not np.array_equal(mask, self._mask):
            self._mask, self._handles = mask, {}
            self._tables = LazyDistanceTables(mask, connectivity=self.connectivity)
        tables = self._tables
        asked: dict[tuple[int, int], int] = {}
        handles = np.full(len(goal_cells), -1, np.int64)
        h, w = mask.shape
        for r, key in enumerate(map(tuple, goal_cells.tolist())):
            if not (0 <= key[0] < w and 0 <= key[1] < h) or mask[key[1], key[0]]:
                continue                            # no detour to a goal an obstacle lingers on
            if key not in asked:
                handle = self._handles.pop(key, None)
                asked[key] = tables.acquire(key) if handle is None else handle
            handles[r] = asked[key]
        for handle in self._handles.values():       # goals no robot asked for this step
            tables.release(handle)
        self._handles = asked
        out = np.full(cells.shape[:2], np.inf)
        rows = np.flatnonzero(handles >= 0)
        if len(rows):
            c = cells.shape[1]
            out[rows] = tables.distances(np.repeat(handles[rows], c), cells[rows].reshape(-1, 2)).reshape(-1, c)
        return out


#: Added to the distance of a move with no detour when others have one (cells).
NO_DETOUR = 1e3


def detour_ranking(lingering: Lingering, cells: IntArray, goal_cells: IntArray, distance: FloatArray) -> FloatArray:
    """The distances (k, 9) a held-back robot ranks its moves (``GRID_MOVES`` order) by, k
    robots in ``cells`` (k, 2) with goals ``goal_cells`` (k, 2): d' of the cell a move reaches
    (:meth:`Lingering.detour_distances`) where it is finite, the static ``distance`` (k, 9) plus
    ``NO_DETOUR`` where it is not but another move's is; a robot none of whose moves has a
    finite d' keeps ``distance`` (it waits: its goal is blocked, or the lingering cells cut it
    off). Where nothing lingers on any way home, d' is the static distance. NaN and inf
    (impossible moves) stay."""
    cells = np.asarray(cells, np.int64).reshape(-1, 2)
    if not len(cells) or not np.any(lingering.level >= LINGER_LEVEL):
        return np.asarray(distance, float)                      # nothing lingers: d' is the distance
    d = lingering.detour_distances(goal_cells, cells[:, None, :] + GRID_MOVES[None])
    some = np.isfinite(d).any(axis=1)[:, None]
    out = np.where(np.isfinite(d), d, distance + NO_DETOUR)
    out = np.where(np.isfinite(distance), out, distance)
    return np.where(some, out, distance)
