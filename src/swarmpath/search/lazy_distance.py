"""Lazy per-goal distance tables: exact grid distances to a goal, expanded only as far as the
queries need.

PIBT and LaCAM ask "how far is this cell from robot i's goal?" for the cells around every
robot at every step. A full distance field per goal (:func:`~swarmpath.search.distance_field`)
costs the whole map per robot: 10,000 robots on a 512 x 512 map would need 20 GB. Here each
goal gets a *lazy* table, a Reverse Resumable A* (Silver 2005, "Cooperative pathfinding",
section 4) run backward from the goal: cells are closed in order of g + h toward the cell
last queried, the search stops as soon as the queried cell is closed and resumes from its open
list on the next query. With a consistent heuristic (octile, Manhattan) every closed cell has
its exact distance, whatever target the open list was keyed to; memory grows with what was
expanded (8 x 8 tiles), not with the map.

Costs are those of :mod:`swarmpath.search.astar` and :func:`~swarmpath.search.distance_field`:
8-connected octile (1 and sqrt 2) without corner cutting, or 4-connected unit costs. Inside,
a cost is a pair of integers (straight moves, diagonal moves), so equal costs compare equal
exactly; the double returned is ``straight + sqrt(2) * diagonal``.

Robots with the same goal share one table (reference counted); :meth:`LazyDistanceTables.release`
frees a table when its last robot lets go of it (it arrived, or the run ended). The search
runs in C (``_lazydist.c``).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError
from swarmpath.search import _lazydist
from swarmpath.search.distance_field import distance_field
from swarmpath.search.grid_input import blocked_array, check_cell, check_connectivity

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The 9 grid moves in :data:`swarmpath.world.move_rules.GRID_MOVES` order (stay first).
GRID_MOVES = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], np.int64)


class LazyDistanceTables:
    """Lazy distance tables of one grid, one per goal cell, shared by robots with that goal.

    Parameters
    ----------
    grid : OccupancyGrid or bool array of shape (height, width)
        ``blocked[y, x]``.
    connectivity : int
        8 (octile, no corner cutting) or 4 (unit costs).
    landmarks : int
        Number of landmark cells for the differential heuristic (ALT: Goldberg & Harrelson,
        "Computing the shortest path: A* search meets graph theory", SODA 2005): exact costs
        from k cells spread over the map (farthest-point choice) bound the cost between any
        two cells from below, ``|d(L, v) - d(L, t)|``, far more tightly than the octile
        distance on cluttered maps, so each table expands fewer cells. 0 (default) uses the
        octile/Manhattan distance only; the landmarks cost k full distance fields up front
        (8 bytes per cell each).

    Creating a table (:meth:`acquire`) costs nothing: the first query starts the search.
    """

    def __init__(self, grid: ArrayLike, *, connectivity: int = 8, landmarks: int = 0):
        self.blocked = blocked_array(grid)
        self.connectivity = connectivity
        diagonal = check_connectivity(connectivity)
        if not isinstance(landmarks, (int, np.integer)) or not 0 <= landmarks <= 64:
            raise ConfigError(f"landmarks must be a whole number in [0, 64], got {landmarks!r}")
        self.height, self.width = self.blocked.shape
        lm = landmark_fields(self.blocked, int(landmarks), connectivity) if landmarks else None
        self.landmark_cells = lm[1] if lm is not None else np.zeros((0, 2), np.int64)
        self._c = _lazydist.LazyTables(np.ascontiguousarray(self.blocked).view(np.uint8), self.width, self.height,
                                       diagonal, None if lm is None else lm[0])
        self._by_goal: dict[tuple[int, int], int] = {}   # goal cell -> slot
        self._users: dict[int, int] = {}                 # slot -> reference count
        self._goal_of: dict[int, tuple[int, int]] = {}

    # ------------------------------------------------------------------ tables
    def acquire(self, goal: ArrayLike) -> int:
        """The table of ``goal`` (a free cell (x, y)), created on first use; every call adds a
        user that :meth:`release` must give back. Returns the table's handle."""
        x, y = check_cell(self.blocked, goal, "goal")
        slot = self._by_goal.get((x, y))
        if slot is None:
            slot = int(self._c.add(x, y))
            self._by_goal[(x, y)] = slot
            self._goal_of[slot] = (x, y)
            self._users[slot] = 0
        self._users[slot] += 1
        return slot

    def acquire_many(self, goals: ArrayLike) -> IntArray:
        """Handles (k,) of the tables of ``goals`` (cells of shape (k, 2)), one user each."""
        g = np.asarray(goals, np.int64).reshape(-1, 2)
        return np.array([self.acquire(c) for c in g.tolist()], np.int64)

    def release(self, handle: int) -> None:
        """Give back one use of a table; the last user frees its memory."""
        handle = int(handle)
        if handle not in self._users:
            raise ConfigError(f"handle {handle} is not a live distance table")
        self._users[handle] -= 1
        if self._users[handle] == 0:
            self._c.remove(handle)
            del self._users[handle], self._by_goal[self._goal_of.pop(handle)]

    def goal(self, handle: int) -> tuple[int, int]:
        """The goal cell (x, y) of a live table."""
        return self._goal_of[int(handle)]

    @property
    def live(self) -> int:
        """Number of tables in use."""
        return len(self._users)

    # ------------------------------------------------------------------ queries
    def distance(self, handle: int, cell: ArrayLike) -> float:
        """Exact cost from ``cell`` (x, y) to the table's goal, ``inf`` when the cell is blocked,
        outside the grid or cut off from the goal."""
        x, y = (int(v) for v in np.asarray(cell).reshape(2))
        return float(self._c.get(int(handle), x, y))

    def distances(self, handles: ArrayLike, cells: ArrayLike) -> FloatArray:
        """Costs (k,) from ``cells[r]`` (shape (k, 2)) to the goal of table ``handles[r]``."""
        c = np.asarray(cells, np.int64).reshape(-1, 2)
        h = np.ascontiguousarray(np.broadcast_to(np.asarray(handles, np.int64), (len(c),)))
        flat = self._flat(c)
        out = np.empty(len(c), np.float64)
        self._c.get_many(h, flat, out)
        return out

    def neighbour_costs(self, handles: ArrayLike, cells: ArrayLike) -> FloatArray:
        """Costs (k, 9) to the goal of table ``handles[r]`` from the cell each of the 9 grid
        moves (:data:`GRID_MOVES`) reaches from ``cells[r]``; NaN where the move is impossible
        (outside, blocked, corner cutting, or diagonal with 4-connectivity). Staying on a
        blocked cell gives ``inf``."""
        c = np.asarray(cells, np.int64).reshape(-1, 2)
        h = np.ascontiguousarray(np.asarray(handles, np.int64).reshape(len(c)))
        out = np.empty((len(c), 9), np.float64)
        self._c.neighbour_costs(h, self._flat(c), out)
        return out

    def field(self, handle: int) -> FloatArray:
        """The whole distance field (height, width) of a table: every cell queried. For tests
        and small maps; it expands the table completely."""
        ys, xs = np.mgrid[0:self.height, 0:self.width]
        cells = np.stack([xs.ravel(), ys.ravel()], axis=1)
        return self.distances(np.full(len(cells), int(handle)), cells).reshape(self.height, self.width)

    # ------------------------------------------------------------------ statistics
    def expanded(self, handle: int) -> int:
        """Cells closed so far by a table's search."""
        return int(self._c.expanded(int(handle)))

    def is_closed(self, handle: int, cell: ArrayLike) -> bool:
        """Whether a table already knows the exact cost of ``cell`` (no search on query)."""
        x, y = (int(v) for v in np.asarray(cell).reshape(2))
        return bool(self._c.is_closed(int(handle), x, y))

    def memory_bytes(self) -> int:
        """Bytes held by all live tables (directories, tiles, open lists)."""
        return int(self._c.memory_bytes())

    def _flat(self, cells: IntArray) -> IntArray:
        inside = (cells[:, 0] >= 0) & (cells[:, 0] < self.width) & (cells[:, 1] >= 0) & (cells[:, 1] < self.height)
        return np.ascontiguousarray(np.where(inside, cells[:, 1] * self.width + cells[:, 0], -1), np.int64)


#: Landmarks pay off when the robots' tables together will expand a sizeable share of the map:
#: with fewer than one goal per this many free cells they cost more than they save.
FREE_CELLS_PER_GOAL_FOR_LANDMARKS = 4096


def choose_landmarks(requested: int | str, n_goals: int, blocked: ArrayLike, default: int = 8) -> int:
    """The number of landmarks to build: ``requested`` when it is a number; for ``"auto"``,
    ``default`` when there is at least one goal per :data:`FREE_CELLS_PER_GOAL_FOR_LANDMARKS`
    free cells, else 0 (one robot on a 4000 x 4000 map must not pay for eight full distance
    fields at reset)."""
    if requested == "auto":
        free = int(np.count_nonzero(~np.asarray(blocked, bool)))
        return default if n_goals * FREE_CELLS_PER_GOAL_FOR_LANDMARKS >= free else 0
    if isinstance(requested, bool) or not isinstance(requested, (int, np.integer)):
        raise ConfigError(f"landmarks must be a whole number or 'auto', got {requested!r}")
    return int(requested)


def landmark_fields(blocked: NDArray[np.bool_], k: int, connectivity: int = 8) -> tuple[FloatArray, IntArray] | None:
    """Exact cost fields from ``k`` landmark cells chosen by farthest-point selection (the
    first farthest from the first free cell in scan order, each next one farthest from all
    chosen so far): (fields of shape (height * width, k), landmark cells (k, 2) as x, y), or
    None on a grid without a free cell. Deterministic."""
    free = np.flatnonzero(~blocked.ravel())
    if len(free) == 0 or k == 0:
        return None
    h, w = blocked.shape
    probe = distance_field(blocked, (int(free[0] % w), int(free[0] // w)), connectivity=connectivity).ravel()
    nearest = np.where(np.isfinite(probe), probe, -1.0)
    fields, cells = [], []
    for _ in range(k):
        v = int(np.argmax(nearest))
        if nearest[v] <= 0 and fields:
            break
        cell = (v % w, v // w)
        f = distance_field(blocked, cell, connectivity=connectivity).ravel()
        fields.append(f)
        cells.append(cell)
        nearest = np.minimum(nearest, np.where(np.isfinite(f), f, np.inf)) if len(fields) > 1 else \
            np.where(np.isfinite(f), f, -1.0)
    return np.ascontiguousarray(np.stack(fields, axis=1)), np.asarray(cells, np.int64)
