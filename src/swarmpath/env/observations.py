"""What each agent observes, built for all agents at once from the step's state.

Grid worlds (:class:`GridObservations`): an egocentric patch of (2 view + 1)^2 cells around
the robot's cell, ``patch[c, view + dy, view + dx]`` describing cell (x + dx, y + dy) (x =
column, y = row, as the map), with channels

0. static obstacles (the grid the grid controllers use; outside the grid counts as blocked),
1. other robots (their cells),
2. moving obstacles now (cells their footprint overlaps, after this step's move),
3. moving obstacles one step before (with channel 2, their motion),
4. the goal: its cell when inside the patch, else the border cell on the straight line to it;

and a ``goal`` vector (unit direction to the goal, distance over the workspace diagonal;
zeros at the goal).

Continuous worlds (:class:`ContinuousObservations`): one vector of
``6 + 6 neighbours + 6 obstacles + 3 static_points`` numbers in [-1, 1]:

- self: unit direction to the goal (2), distance to it over the workspace diagonal, last
  displacement over the robot's step length (2), at-goal flag;
- the nearest robots the robot senses (:func:`~swarmpath.sim.sensing.sense`, nearest first):
  present flag, offset over the sensing range (2), their last displacement over the robot's
  step length (2), sum of radii over the sensing range;
- the nearest sensed moving obstacles: present flag, offset (2), displacement this step (2),
  footprint extent over the sensing range;
- the nearest static-obstacle cells (cells of the world's grid blocked for a point, and the
  ring of cells around the workspace) within the sensing range: present flag, offset (2).

Absent entries are zeros. Everything is float32.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.control.observation import Observation
from swarmpath.world.grid import OccupancyGrid
from swarmpath.world.shapes import Circle
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
GRID_CHANNELS = ("static", "robots", "moving", "moving_before", "goal")
SELF_FEATURES, ROBOT_FEATURES, OBSTACLE_FEATURES, STATIC_FEATURES = 6, 6, 6, 3


def _diagonal(world: World) -> float:
    w, h = world.bounds.extent
    return float(math.hypot(w, h))


def _goal_vector(pos: FloatArray, goals: FloatArray, diagonal: float) -> FloatArray:
    """Unit direction (2) and distance over ``diagonal`` (1) to each goal, (n, 3)."""
    d = goals - pos
    dist = np.hypot(d[:, 0], d[:, 1])
    unit = np.where((dist > 0)[:, None], d / np.where(dist > 0, dist, 1.0)[:, None], 0.0)
    return np.concatenate([unit, np.minimum(dist / diagonal, 1.0)[:, None]], axis=1)


class FootprintRaster:
    """Cells of a grid that moving obstacles' footprints overlap (open cell squares), for all
    obstacles at once within a fixed window per obstacle."""

    def __init__(self, world: World, grid: OccupancyGrid):
        obs = world.moving_obstacles
        self.grid = grid
        self.m = len(obs)
        res = grid.resolution
        self.circle = np.array([isinstance(o.shape, Circle) for o in obs], bool)
        self.radius = np.array([o.shape.radius if isinstance(o.shape, Circle) else 0.0 for o in obs], float)
        lo = [(-o.shape.radius, -o.shape.radius) if isinstance(o.shape, Circle) else o.shape.min for o in obs]
        hi = [(o.shape.radius, o.shape.radius) if isinstance(o.shape, Circle) else o.shape.max for o in obs]
        self.lo = np.array(lo, float).reshape(-1, 2)
        self.hi = np.array(hi, float).reshape(-1, 2)
        span = float(np.max(self.hi - self.lo, initial=0.0))
        self.window = int(math.ceil(span / res)) + 2
        k = np.arange(self.window)
        self.offsets = np.stack(np.meshgrid(k, k, indexing="xy"), axis=-1).reshape(-1, 2)

    def cells(self, positions: FloatArray) -> NDArray[np.bool_]:
        """Boolean raster (height, width) of the cells the footprints at ``positions`` (m, 2)
        overlap."""
        g = self.grid
        out = np.zeros(g.blocked.shape, bool)
        if self.m == 0:
            return out
        res = g.resolution
        lo = positions + self.lo
        hi = positions + self.hi
        first = np.floor(lo / res).astype(np.int64)
        cells = first[:, None, :] + self.offsets[None]                 # (m, k, 2)
        cell_lo = cells * res
        cell_hi = cell_lo + res
        box = np.all((cell_lo < hi[:, None, :]) & (cell_hi > lo[:, None, :]), axis=2)
        nearest = np.clip(positions[:, None, :], cell_lo, cell_hi)
        gap = np.linalg.norm(nearest - positions[:, None, :], axis=2)
        disc = gap < self.radius[:, None]
        hit = np.where(self.circle[:, None], disc & box, box) & g.contains_cells(cells)
        c = cells[hit]
        out[c[:, 1], c[:, 0]] = True
        return out


class GridObservations:
    """Egocentric patches (see the module docs) on ``grid`` for the robots of ``world``."""

    def __init__(self, world: World, grid: OccupancyGrid, view: int):
        self.world = world
        self.grid = grid
        self.view = view
        self.size = 2 * view + 1
        h, w = grid.blocked.shape
        self.padded = (h + 2 * view, w + 2 * view)
        static = np.ones(self.padded, np.float32)
        static[view:view + h, view:view + w] = grid.blocked
        self.static = static.ravel()
        self.footprints = FootprintRaster(world, grid)
        self.diagonal = _diagonal(world)
        k = np.arange(self.size)
        # flat offsets of a patch's cells from its top-left cell in the padded raster
        self.offsets = (k[:, None] * self.padded[1] + k[None, :]).ravel()

    def _moving_layer(self, positions: FloatArray) -> NDArray[np.float32]:
        v = self.view
        h, w = self.grid.blocked.shape
        layer = np.zeros(self.padded, np.float32)
        layer[v:v + h, v:v + w] = self.footprints.cells(positions)
        return layer.ravel()

    def observe(self, cells: NDArray[np.int64], pos: FloatArray, goals: FloatArray, goal_cells: NDArray[np.int64],
                obstacles_now: FloatArray, obstacles_before: FloatArray
                ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
        """Patches (n, 5, size, size) and goal vectors (n, 3) of robots in ``cells`` (n, 2)."""
        v, n, size = self.view, len(cells), self.size
        wide = self.padded[1]
        # a robot's cell (x, y) is padded cell (x + v, y + v), so its patch starts at (x, y)
        corner = cells[:, 1] * wide + cells[:, 0]
        idx = corner[:, None] + self.offsets[None]                      # (n, size * size)
        patch = np.zeros((n, len(GRID_CHANNELS), size * size), np.float32)
        patch[:, 0] = self.static[idx]
        centre = corner + v * wide + v
        robots = np.bincount(centre, minlength=len(self.static)).astype(np.float32)
        patch[:, 1] = robots[idx]
        patch[:, 1, v * size + v] -= 1.0                                 # not oneself
        np.minimum(patch[:, 1], 1.0, out=patch[:, 1])
        if self.footprints.m:
            patch[:, 2] = self._moving_layer(obstacles_now)[idx]
            patch[:, 3] = self._moving_layer(obstacles_before)[idx]
        rel = goal_cells - cells
        far = np.max(np.abs(rel), axis=1)
        scale = np.where(far > v, v / np.maximum(far, 1), 1.0)
        mark = np.rint(rel * scale[:, None]).astype(np.int64) + v
        patch[np.arange(n), 4, mark[:, 1] * size + mark[:, 0]] = 1.0
        return patch.reshape(n, len(GRID_CHANNELS), size, size), \
            _goal_vector(pos, goals, self.diagonal).astype(np.float32)


class ContinuousObservations:
    """Fixed-size vectors (see the module docs) for the robots of ``world``."""

    def __init__(self, world: World, neighbours: int, obstacles: int, static_points: int, sensing_range: float):
        self.world = world
        self.k_robots = neighbours
        self.k_obstacles = obstacles
        self.k_static = static_points
        self.range = sensing_range
        self.size = SELF_FEATURES + ROBOT_FEATURES * neighbours + OBSTACLE_FEATURES * obstacles + \
            STATIC_FEATURES * static_points
        self.diagonal = _diagonal(world)
        self.reach = world.max_speeds * world.dt
        self.radii = world.radii
        self.extents = np.array([o.extent for o in world.moving_obstacles], float)
        grid = world.grid()
        h, w = grid.blocked.shape
        ring = np.ones((h + 2, w + 2), bool)
        ring[1:-1, 1:-1] = grid.blocked
        cells = np.argwhere(ring)[:, ::-1] - 1                   # (x, y), the ring at -1 and w / h
        self.static_points = grid.centers(cells)
        self.static_tree = cKDTree(self.static_points) if len(cells) and static_points else None

    @staticmethod
    def _nearest(pairs: NDArray[np.int64], dist: FloatArray, n: int, k: int, symmetric: bool
                 ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
        """(owner, slot, other) of the ``k`` nearest partners of every owner among ``pairs``
        (owner, other) with distances; symmetric pairs count for both ends."""
        if symmetric:
            owner = np.concatenate([pairs[:, 0], pairs[:, 1]])
            other = np.concatenate([pairs[:, 1], pairs[:, 0]])
            dist = np.concatenate([dist, dist])
        else:
            owner, other = pairs[:, 0], pairs[:, 1]
        order = np.lexsort((other, dist, owner))
        owner, other = owner[order], other[order]
        first = np.searchsorted(owner, np.arange(n))
        slot = np.arange(len(owner)) - first[owner] if len(owner) else np.zeros(0, np.int64)
        keep = slot < k
        return owner[keep], slot[keep], other[keep]

    def observe(self, obs: Observation, previous: FloatArray) -> NDArray[np.float32]:
        """Vectors (n, size) from the step's Observation and the robots' positions one step
        before (for their displacement)."""
        pos, n, r = obs.positions, obs.n_robots, self.range
        out = np.zeros((n, self.size), np.float64)
        reach = self.reach[:, None]
        out[:, 0:3] = _goal_vector(pos, obs.goals, self.diagonal)
        moved = pos - previous
        out[:, 3:5] = moved / reach
        out[:, 5] = obs.at_goal
        col = SELF_FEATURES
        s = obs.sensed
        if self.k_robots:
            i, slot, j = self._nearest(s.robot_pairs, s.robot_distance, n, self.k_robots, True)
            block = out[:, col:col + ROBOT_FEATURES * self.k_robots].reshape(n, self.k_robots, ROBOT_FEATURES)
            block[i, slot, 0] = 1.0
            block[i, slot, 1:3] = (pos[j] - pos[i]) / r
            block[i, slot, 3:5] = moved[j] / reach[i]
            block[i, slot, 5] = (self.radii[i] + self.radii[j]) / r
            col += ROBOT_FEATURES * self.k_robots
        if self.k_obstacles:
            i, slot, j = self._nearest(s.obstacle_pairs, s.obstacle_distance, n, self.k_obstacles, False)
            block = out[:, col:col + OBSTACLE_FEATURES * self.k_obstacles].reshape(n, self.k_obstacles,
                                                                                   OBSTACLE_FEATURES)
            block[i, slot, 0] = 1.0
            block[i, slot, 1:3] = (obs.obstacle_positions[j] - pos[i]) / r
            block[i, slot, 3:5] = (obs.obstacle_positions[j] - obs.obstacle_previous[j]) / reach[i]
            block[i, slot, 5] = self.extents[j] / r
            col += OBSTACLE_FEATURES * self.k_obstacles
        if self.k_static and self.static_tree is not None:
            d, idx = self.static_tree.query(pos, k=self.k_static, distance_upper_bound=r)
            d, idx = d.reshape(n, -1), idx.reshape(n, -1)
            found = np.isfinite(d)
            block = out[:, col:col + STATIC_FEATURES * self.k_static].reshape(n, self.k_static, STATIC_FEATURES)
            rows, slots = np.nonzero(found)
            block[rows, slots, 0] = 1.0
            block[rows, slots, 1:3] = (self.static_points[idx[rows, slots]] - pos[rows]) / r
        np.clip(out, -1.0, 1.0, out=out)
        return out.astype(np.float32)
