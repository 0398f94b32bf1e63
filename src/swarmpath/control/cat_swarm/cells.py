"""The grid a cat swarm controller works on, shared by ``cat-swarm`` and ``cat-swarm-paper``.

- :func:`grid_cells`: the checks (robots move one cell per step and are points or small
  discs), one distance field per goal cell (eq. 12's path lengths; ``cat-swarm-paper``; the
  improved ``cat-swarm`` reads lazy per-goal tables instead and asks for no fields), and
  where each robot's exact goal lies in its cell;
- :meth:`GridCells.candidates`: where each of the 9 candidates of step 6.1-6.2 takes a robot
  and which are allowed statically and within its reach;
- :class:`PathTracker`: each robot's place on its path (the offline plan as grid cells), the
  remaining length, the next cell of the path, and replanning (step 6.6) when a robot leaves
  it: from then on the robot follows its goal's distance field (the shortest path).

These are the parts of Algorithm 4 that do not depend on how a controller avoids others.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.cat_swarm import kernels as K
from swarmpath.control.cell_paths import plan_cells, remaining_lengths
from swarmpath.control.grid_robots import check_grid_robots
from swarmpath.planning.base import Plan
from swarmpath.search import distance_field
from swarmpath.world.grid import OccupancyGrid
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Offset index (into ``kernels.OFFSETS``) of every move (dx + 1, dy + 1).
OFFSET_INDEX = np.zeros((3, 3), np.int64)
for _k, (_dx, _dy) in enumerate(K.OFFSETS):
    OFFSET_INDEX[_dx + 1, _dy + 1] = _k
#: Above this many bytes of float64 distance fields they are stored as float32.
FIELD_BYTES_FLOAT64 = 256 * 2 ** 20


@dataclass(frozen=True)
class GridCells:
    """The static part of a run on the grid (built by :func:`grid_cells` at reset).

    grid : the occupancy grid (inflated by the largest robot radius); goal_cells (n, 2);
    fields (g, height, width) the distance fields of the distinct goal cells (None when not
    asked for), field_index (n,) each robot's field; decimals: rounding of fitness values
    (fewer with float32 fields);
    goal_off_centre (n,) whether the exact goal lies off its cell centre; goal_moves (n, 9)
    the moves a robot standing on its exact goal can make; reach (n,) max_speed * dt.
    """

    grid: OccupancyGrid
    goal_cells: IntArray
    fields: NDArray | None
    field_index: IntArray
    decimals: int
    goal_off_centre: BoolArray
    goal_moves: BoolArray
    reach: FloatArray

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width) of the grid."""
        return self.grid.blocked.shape

    def cells(self, points: FloatArray) -> IntArray:
        """Grid cells (n, 2) of points; a point on the far edge of the grid (a goal on the
        workspace boundary) belongs to the last cell, whose closed square holds it."""
        h, w = self.shape
        cells = self.grid.cell_of(np.asarray(points, float).reshape(-1, 2))
        return np.clip(cells, 0, [w - 1, h - 1])

    def moves(self, cells: IntArray) -> BoolArray:
        """The static validity (..., 9) of the 9 moves from ``cells`` (..., 2) (step 6.3's
        "copies on static obstacles are deleted"; :func:`~.kernels.moves_at`)."""
        return K.moves_at(self.grid.blocked, cells)

    def candidates(self, pos: FloatArray, goals: FloatArray, cells: IntArray, copies: IntArray, *,
                   centre_first: bool = False, hold: BoolArray | None = None
                   ) -> tuple[FloatArray, BoolArray, BoolArray, BoolArray]:
        """Where each candidate takes the robot (n, 9, 2): a cell centre, the exact goal in the
        goal cell; staying settles on the centre (or the goal) of the robot's own cell. With
        ``centre_first`` a move into the goal cell goes to the exact goal only when it is
        within reach, else to the cell's centre (a goal on the cell's far corner, e.g. the
        workspace's corner, is then reached in two steps instead of never). Also which
        candidates are the goal cell (n, 9), which are allowed statically (n, 9), and which
        are allowed and within reach (n, 9; staying always is). Robots ``hold`` (n,) keep to
        the centre of their goal cell (they step onto the goal with the finishing step)."""
        grid = self.grid
        static_ok = self.moves(cells)
        targets = grid.centers(copies)
        in_goal_cell = np.all(copies == self.goal_cells[:, None, :], axis=2)
        to_goal = in_goal_cell
        if centre_first:
            to_goal = in_goal_cell & (np.linalg.norm(goals - pos, axis=1)
                                      <= self.reach * (1 + 1e-9) + 1e-12)[:, None]
        settle = in_goal_cell[:, K.STAY]
        if hold is not None:
            to_goal = to_goal & ~hold[:, None]
            settle = settle & ~hold
        targets = np.where(to_goal[..., None], goals[:, None, :], targets)
        targets[:, K.STAY] = np.where(settle[:, None], goals, grid.centers(cells))
        in_reach = np.linalg.norm(targets - pos[:, None, :], axis=2) <= self.reach[:, None] * (1 + 1e-9) + 1e-12
        valid = static_ok & in_reach
        valid[:, K.STAY] = True  # staying (or settling inside one's own cell) is always possible
        return targets, in_goal_cell, static_ok, valid


def grid_cells(world: World, owner: str, *, fields: bool = True) -> GridCells:
    """Check that ``world`` suits a cell-to-cell controller called ``owner`` and build its
    :class:`GridCells` (raises ConfigError naming the robot that does not fit). ``fields``:
    compute one distance field per goal cell (the whole map per goal); False leaves them to
    the caller (lazy tables)."""
    n = world.n_robots
    reach = world.max_speeds * world.dt
    check_grid_robots(world, owner)
    grid = world.grid(radius=float(world.radii.max(initial=0.0)))
    blocked = grid.blocked
    height, width = blocked.shape
    goals = world.goals
    goal_cells = np.clip(grid.cell_of(np.asarray(goals, float).reshape(-1, 2)), 0, [width - 1, height - 1])
    # one distance field per goal cell (eq. 12 and the replanned paths)
    flat_goal = goal_cells[:, 1] * width + goal_cells[:, 0] if n else np.zeros(0, np.int64)
    unique, field_index = np.unique(flat_goal, return_inverse=True)
    big_fields = len(unique) * blocked.size * 8 > FIELD_BYTES_FLOAT64
    table = None
    if fields:
        table = np.empty((len(unique), height, width), np.float32 if big_fields else np.float64)
        for g, flat in enumerate(unique):
            cell = (int(flat % width), int(flat // width))
            table[g] = distance_field(blocked, cell) if grid.is_free(np.asarray(cell)) else np.inf
    # robots whose exact goal lies off its cell centre reach fewer cells from it
    goal_off_centre = np.linalg.norm(goals - grid.centers(goal_cells), axis=1) > 1e-9
    around = goal_cells[:, None, :] + K.OFFSETS[None]
    inside = grid.contains_cells(around)
    near = np.linalg.norm(grid.centers(around) - goals[:, None, :], axis=2) <= reach[:, None] * (1 + 1e-9)
    goal_moves = inside & near & K.moves_at(blocked, goal_cells) if n else np.zeros((0, 9), bool)
    goal_moves[:, K.STAY] = True
    return GridCells(grid, goal_cells, table, field_index, 3 if big_fields else 6, goal_off_centre, goal_moves,
                     reach)


@dataclass
class PathTracker:
    """Each robot's path as grid cells and its place on it (run state of a controller).

    The paths are concatenated: robot i's cells are ``flat[start[i]:start[i] + length[i]]``
    with the remaining lengths ``rem_flat`` (cells); ``k[i]`` is its index on the path, -1
    once it has left the path (replanned: it follows its goal's distance field)."""

    flat: IntArray
    rem_flat: FloatArray
    start: IntArray
    length: IntArray
    k: IntArray

    @classmethod
    def from_plan(cls, world: World, plan: Plan | None, cells: GridCells) -> PathTracker:
        """The offline plan's paths as cells (a robot without a usable path starts off-path)."""
        n = world.n_robots
        blocked = cells.grid.blocked
        paths = plan.paths if plan is not None else [None] * n
        chunks, rems, starts, lengths = [], [], np.zeros(n, np.int64), np.zeros(n, np.int64)
        total = 0
        start_cells = cells.cells(world.starts)
        for i in range(n):
            p = paths[i] if i < len(paths) else None
            c = plan_cells(p, world.resolution, blocked) if p is not None else None
            if c is not None and (np.any(c[0] != start_cells[i]) or np.any(c[-1] != cells.goal_cells[i])):
                c = None
            starts[i] = total
            if c is not None:
                chunks.append(c)
                rems.append(remaining_lengths(c))
                lengths[i] = len(c)
                total += len(c)
        flat = np.concatenate(chunks) if chunks else np.zeros((1, 2), np.int64)
        rem_flat = np.concatenate(rems) if rems else np.zeros(1)
        return cls(flat, rem_flat, starts, lengths, np.where(lengths > 0, 0, -1).astype(np.int64))

    def index(self, ahead: int = 0) -> tuple[IntArray, BoolArray]:
        """Index into the concatenated paths of each robot's path cell ``ahead`` of its
        current one, and whether that cell exists (robots off their path: False)."""
        k = self.k + ahead
        ok = (self.k >= 0) & (k < self.length)
        idx = np.clip(self.start + np.maximum(k, 0), 0, len(self.flat) - 1)
        return idx, ok

    def remaining(self, cells: IntArray, field_here: FloatArray) -> FloatArray:
        """Remaining path length (cells): along the offline path while the robot is on it,
        else the replanned (shortest) length. A robot found off its path has replanned."""
        idx, ok = self.index()
        on = ok & np.all(self.flat[idx] == cells, axis=1)
        self.k[~on] = -1
        return np.where(on, self.rem_flat[idx], field_here)

    def next_step(self, cells: IntArray, copy_fitness: FloatArray, static_ok: BoolArray, tie: FloatArray) -> IntArray:
        """Offset index of the next cell of each robot's path (0 = stay): the offline path
        while the robot is on it, else the replanned shortest path (distance field)."""
        nxt = K.descent_step(copy_fitness, static_ok, tie)
        on = self.k >= 0
        idx, has_next = self.index(1)
        d = self.flat[idx] - cells
        step_ok = has_next & (np.max(np.abs(d), axis=1) == 1)
        k = np.where(step_ok, OFFSET_INDEX[np.clip(d[:, 0] + 1, 0, 2), np.clip(d[:, 1] + 1, 0, 2)], K.STAY)
        step_ok &= static_ok[np.arange(len(cells)), k]
        at_end = on & ~has_next
        nxt = np.where(at_end, K.STAY, np.where(on & step_ok, k, nxt))
        self.k[on & has_next & ~step_ok] = -1  # the path is broken here: replan
        return nxt

    def advance(self, new_cells: IntArray) -> None:
        """Move each robot's place on its path; leaving the path means replanning."""
        here, on = self.index()
        nxt, has_next = self.index(1)
        advanced = has_next & np.all(self.flat[nxt] == new_cells, axis=1)
        stayed = on & np.all(self.flat[here] == new_cells, axis=1)
        self.k = np.where(advanced, self.k + 1, np.where(stayed, self.k, -1))
