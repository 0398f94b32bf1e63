"""Where moving obstacles are and can be next: cell sets for grid controllers.

Moving obstacles move first in every step (phase 1) and do not react to robots, so a robot
must choose its cell at step t so that the obstacle's sweep from its position at t to its
position at t + 1 misses it. The controller knows the obstacles' footprints and motion models
(``world.moving_obstacles``) and sees their last two positions; from them we list every
position an obstacle can take next: one for a straight move, every free direction when it
bounces or walks at random, anything within its speed when the model may turn to any angle.

Footprints are handled through their bounding boxes on the grid: a cell is *covered* when
the open box overlaps the cell's open square. A point robot anywhere in the closed square of
an uncovered cell (centre or corner) is strictly outside the footprint, and a move between
the centres of two uncovered 8-adjacent cells stays outside it (the move lies in the two
closed squares and, for a diagonal, their common corner).

Everything is vectorised over obstacles; boxes are painted with a 2-D difference array.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.world.motions import FORECASTS
from swarmpath.world.moving import MovingObstacle
from swarmpath.world.shapes import Circle

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

GRID_DIRECTIONS = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float)
UNIT_DIRECTIONS = GRID_DIRECTIONS / np.linalg.norm(GRID_DIRECTIONS, axis=1, keepdims=True)
BOUNCE_FLIPS = np.array([[-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]])
#: Forecast classes of motion models (``Motion.forecast``), as codes.
BOUNCE, BOUNCE8, RANDOM_WALK, REDRAW, ANY_HEADING = (FORECASTS.index(name) for name in FORECASTS)
_MOVING = 1e-9
N_SLOTS = 10  # 0: stay, 1: straight on, 2-9: the 8 directions (or the 3 bounce reflections)


def footprint_box(ob: MovingObstacle) -> tuple[FloatArray, FloatArray]:
    """(lo, hi) of the footprint's bounding box relative to the obstacle's position."""
    if isinstance(ob.shape, Circle):
        r = ob.shape.radius
        return np.array([-r, -r]), np.array([r, r])
    return np.asarray(ob.shape.min, float), np.asarray(ob.shape.max, float)


def motion_code(ob: MovingObstacle) -> int:
    """How predictable the obstacle's motion model says it is (``Motion.forecast``): straight
    with reflections (bounce), straight with a random new direction (bounce8), a random grid
    step every time (random-walk), a jump that avoids robots' cells (teleport), or any heading
    within its one-step reach (any-heading: turn-every, waypoints, and new models)."""
    return FORECASTS.index(ob.motion.forecast)


def box_cell_ranges(lo: FloatArray, hi: FloatArray, resolution: float, margin: int = 0) -> IntArray:
    """Cell ranges [x0, x1) x [y0, y1) of the cells whose open squares overlap the open boxes
    (lo, hi) (shape (k, 2) each), grown by ``margin`` cells: int array (k, 4)."""
    x0y0 = np.floor(lo / resolution + 1e-6).astype(np.int64) - margin
    x1y1 = np.ceil(hi / resolution - 1e-6).astype(np.int64) + margin
    return np.concatenate([x0y0, x1y1], axis=-1)


def paint(shape: tuple[int, int], ranges: IntArray) -> BoolArray:
    """Boolean grid (height, width): True in the union of the cell ranges (k, 4)."""
    h, w = shape
    out = np.zeros((h + 1, w + 1), np.int32)
    if len(ranges):
        x0 = np.clip(ranges[:, 0], 0, w)
        y0 = np.clip(ranges[:, 1], 0, h)
        x1 = np.clip(ranges[:, 2], 0, w)
        y1 = np.clip(ranges[:, 3], 0, h)
        ok = (x0 < x1) & (y0 < y1)
        x0, y0, x1, y1 = x0[ok], y0[ok], x1[ok], y1[ok]
        np.add.at(out, (y0, x0), 1)
        np.add.at(out, (y0, x1), -1)
        np.add.at(out, (y1, x0), -1)
        np.add.at(out, (y1, x1), 1)
    return out.cumsum(0).cumsum(1)[:h, :w] > 0


class ObstacleForecast:
    """Predicts the moving obstacles of one world, step by step (created in a controller's
    ``reset``; holds no run state beyond a memo of exact static checks)."""

    def __init__(self, world, grid, robot_radius: float = 0.0):
        self.world = world
        obs = world.moving_obstacles
        self.m = len(obs)
        self.shape = grid.blocked.shape
        self.resolution = grid.resolution
        boxes = [footprint_box(o) for o in obs]
        self.lo = np.array([b[0] for b in boxes], float).reshape(-1, 2)
        self.hi = np.array([b[1] for b in boxes], float).reshape(-1, 2)
        # what robots must keep out of: the footprint grown by the robots' radius
        self.keep_lo = self.lo - robot_radius
        self.keep_hi = self.hi + robot_radius
        self.code = np.array([motion_code(o) for o in obs], np.int64)
        # one step of travel; for models that may head anywhere, their declared worst case
        self.speed = np.array([o.max_step(world.dt, world.resolution) if c == ANY_HEADING else o.speed * world.dt
                               for o, c in zip(obs, self.code)], float)
        self.walk_step = np.array([(o.speed or world.resolution) for o in obs], float) * world.dt
        # summed-area table of the world's blocked cells: a footprint whose covered cells are
        # all free surely fits (a cell is blocked when anything static or the boundary
        # overlaps its open square); only footprints next to blocked cells need exact checks
        b = np.pad(world.grid().blocked.astype(np.int64), ((1, 0), (1, 0)))
        self._sat = b.cumsum(0).cumsum(1)
        self._sat_shape = world.grid().blocked.shape
        self._sat_res = world.grid().resolution
        self._memo: dict[tuple[int, int, int], bool] = {}
        # obstacles with the same footprint fit at the same places: check them together
        # a world of raster cells only (and box footprints) is checked exactly and vectorised
        sm = world.static_map
        self._raster_only = (sm is not None and not world.obstacles
                             and all(not isinstance(o.shape, Circle) for o in obs))
        keys = [tuple(np.r_[lo, hi].round(12)) for lo, hi in boxes]
        first: dict[tuple, int] = {}
        self.shape_of = np.array([first.setdefault(k, j) for j, k in enumerate(keys)], np.int64)

    # ------------------------------------------------------------------ static fit
    def fits(self, which: IntArray, positions: FloatArray) -> BoolArray:
        """Whether obstacle ``which[r]``'s footprint fits at ``positions[r]`` (as the motion
        models decide: inside the workspace, off static obstacles). Shapes (k,), (k, 2)."""
        which = np.asarray(which, np.int64)
        pos = np.asarray(positions, float).reshape(-1, 2)
        if len(pos) == 0:
            return np.zeros(0, bool)
        if self._raster_only:  # exactly World.obstacle_fits, for all obstacles at once
            sm = self.world.static_map
            lo, hi = pos + self.lo[which], pos + self.hi[which]
            cs = sm.cell_size
            x0 = np.floor(lo[:, 0] / cs + 1e-9).astype(int)
            y0 = np.floor(lo[:, 1] / cs + 1e-9).astype(int)
            x1 = np.ceil(hi[:, 0] / cs - 1e-9).astype(int)
            y1 = np.ceil(hi[:, 1] / cs - 1e-9).astype(int)
            return self.world.bounds.boxes_inside(lo, hi) & (sm.count_blocked(x0, y0, x1, y1) == 0)
        h, w = self._sat_shape
        r = box_cell_ranges(pos + self.lo[which], pos + self.hi[which], self._sat_res)
        inside = (r[:, 0] >= 0) & (r[:, 1] >= 0) & (r[:, 2] <= w) & (r[:, 3] <= h)
        x0, x1 = np.clip(r[:, 0], 0, w), np.clip(r[:, 2], 0, w)
        y0, y1 = np.clip(r[:, 1], 0, h), np.clip(r[:, 3], 0, h)
        s = self._sat
        out = inside & (s[y1, x1] - s[y0, x1] - s[y1, x0] + s[y0, x0] == 0)
        unsure = np.flatnonzero(~out)
        if len(unsure) == 0:
            return out
        shapes = self.shape_of[which[unsure]]
        keys = [(int(j), round(x * 1e6), round(y * 1e6))
                for j, (x, y) in zip(shapes.tolist(), pos[unsure].tolist())]
        todo: dict[int, list[int]] = {}
        for k, key in zip(unsure.tolist(), keys):
            hit = self._memo.get(key)
            if hit is None:
                todo.setdefault(key[0], []).append(k)
            else:
                out[k] = hit
        if len(self._memo) > 200_000:
            self._memo.clear()
        for j, rows in todo.items():
            found = self.world.obstacle_fits(self.world.moving_obstacles[j], pos[rows])
            out[rows] = found
            for k, f in zip(rows, found.tolist()):
                self._memo[(j, round(pos[k, 0] * 1e6), round(pos[k, 1] * 1e6))] = f
        return out

    # ------------------------------------------------------------------ next step
    def next_positions(self, positions: FloatArray, previous: FloatArray) -> tuple[FloatArray, BoolArray, FloatArray]:
        """Every position each obstacle can take at the next step: candidates (m, 10, 2), a
        mask (m, 10) of those possible, and an extra radius of uncertainty (m,) (world units;
        > 0 for models that may turn to any angle).

        ``positions`` are the obstacles now, ``previous`` one step earlier: their difference
        is the current velocity times dt. Bounces are predicted with the same static geometry
        the motion models use."""
        m = self.m
        p = np.asarray(positions, float).reshape(m, 2)
        d = p - np.asarray(previous, float).reshape(m, 2)
        step = np.hypot(d[:, 0], d[:, 1])
        moving = step > _MOVING
        code = self.code
        cand = np.repeat(p[:, None, :], N_SLOTS, axis=1)
        cand[:, 1] = p + d
        b8 = code == BOUNCE8
        size = np.where(moving, step, self.speed)
        cand[b8, 2:] = p[b8, None] + UNIT_DIRECTIONS[None] * size[b8, None, None]
        rw = code == RANDOM_WALK
        cand[rw, 2:] = p[rw, None] + GRID_DIRECTIONS[None] * self.walk_step[rw, None, None]
        bo = code == BOUNCE
        cand[bo, 2:5] = p[bo, None] + d[bo, None] * BOUNCE_FLIPS[None]
        which = np.repeat(np.arange(m), N_SLOTS)
        ok = self.fits(which, cand.reshape(-1, 2)).reshape(m, N_SLOTS)
        possible = np.zeros((m, N_SLOTS), bool)
        possible[:, 0] = True
        extra = np.zeros(m)
        straight = (b8 | bo) & moving
        ahead = straight & ok[:, 1]
        possible[ahead, 1] = True
        possible[ahead, 0] = False
        turn8 = (b8 & ~ahead) | rw
        possible[turn8, 2:] = ok[turn8, 2:]
        turn3 = bo & moving & ~ahead
        possible[turn3, 2:5] = ok[turn3, 2:5]
        vague = (code == ANY_HEADING) | (bo & ~moving)
        extra[vague] = self.speed[vague]
        return cand, possible, extra

    def danger(self, positions: FloatArray, previous: FloatArray, *, margin: int = 0) -> BoolArray:
        """Cells (height, width) a robot must not end this step in: covered by an obstacle
        now (phase 2 of this step) or by its sweep to any possible next position (phase 1 of
        the next step), grown by ``margin`` cells."""
        if self.m == 0:
            return np.zeros(self.shape, bool)
        p = np.asarray(positions, float).reshape(self.m, 2)
        cand, possible, extra = self.next_positions(p, previous)
        j, s = np.nonzero(possible)
        q = cand[j, s]
        lo = np.minimum(p[j], q) + self.keep_lo[j] - extra[j, None]
        hi = np.maximum(p[j], q) + self.keep_hi[j] + extra[j, None]
        return paint(self.shape, box_cell_ranges(lo, hi, self.resolution, margin))

    def coverage(self, positions: FloatArray, previous: FloatArray, steps: int, *, margin: int = 0
                 ) -> list[BoolArray]:
        """[D_1, ..., D_steps]: the cells (height, width) an obstacle may cover in phase 1 of
        each of the next ``steps`` steps. D_1 is :meth:`danger`. For k >= 2, D_k holds the
        sweep from step k - 1 to step k: the bouncing models go straight on while their way
        is free (``f`` free steps) and may take any direction from the first blocked step
        on, so from step f on they lie within (k - f) steps of travel of where the straight
        run ends; random walkers lie within k steps of travel of where they are now."""
        out = [self.danger(positions, previous, margin=margin)]
        if steps < 2 or self.m == 0:
            return out + [np.zeros(self.shape, bool) for _ in range(steps - 1)]
        m = self.m
        p = np.asarray(positions, float).reshape(m, 2)
        d = p - np.asarray(previous, float).reshape(m, 2)
        moving = np.hypot(d[:, 0], d[:, 1]) > _MOVING
        straight = np.isin(self.code, (BOUNCE, BOUNCE8)) & moving
        ahead = p[:, None, :] + d[:, None, :] * np.arange(1, steps + 1)[None, :, None]
        ok = self.fits(np.repeat(np.arange(m), steps), ahead.reshape(-1, 2)).reshape(m, steps)
        free_all = np.where(ok.all(axis=1), steps, np.argmin(ok, axis=1))
        free_all = np.where(straight, free_all, 0)
        reach = np.where(self.code == RANDOM_WALK, self.walk_step, np.maximum(self.speed, np.hypot(*d.T)))
        reach = np.where(self.code == REDRAW, 0.0, reach)
        for k in range(2, steps + 1):
            free = np.minimum(free_all, k)
            sure = free >= k
            grow = np.where(sure, 0.0, (k - free) * reach)[:, None]
            a = np.where(sure[:, None], p + (k - 1) * d, p + free[:, None] * d)
            b = np.where(sure[:, None], p + k * d, a)
            lo = np.minimum(a, b) + self.keep_lo - grow
            hi = np.maximum(a, b) + self.keep_hi + grow
            out.append(paint(self.shape, box_cell_ranges(lo, hi, self.resolution, margin)))
        return out

    def influence(self, steps: int) -> float:
        """How far (world units, Chebyshev) from an obstacle's position anything it may do in
        the next ``steps`` steps can reach; robots farther away need no forecast."""
        if self.m == 0:
            return 0.0
        extent = float(np.max(np.abs(np.concatenate([self.keep_lo, self.keep_hi]))))
        fastest = float(np.max(np.maximum(self.speed, self.walk_step), initial=0.0))
        return extent + (steps + 1) * fastest

    def crossings(self, starts: FloatArray, ends: FloatArray, positions: FloatArray) -> BoolArray:
        """Whether each move starts[r] -> ends[r, c] (shapes (k, 2) and (k, c, 2)) passes
        through the interior of an obstacle's bounding box (grown by the robots' radius)
        where it stands now (exact for point robots; used for robots whose cell an obstacle
        already covers or that rest off a cell centre)."""
        from swarmpath.world.geometry import segment_crosses_open_box

        k, c = ends.shape[:2]
        bad = np.zeros((k, c), bool)
        if self.m == 0 or k == 0:
            return bad
        p = np.asarray(positions, float).reshape(self.m, 2)
        reach = np.max(np.abs(np.concatenate([self.keep_lo, self.keep_hi])), initial=0.0) + 2 * self.resolution * 1.5
        for j in range(self.m):
            near = np.flatnonzero(np.max(np.abs(starts - p[j]), axis=1) <= reach)
            if len(near) == 0:
                continue
            a = np.repeat(starts[near], c, axis=0)
            b = ends[near].reshape(-1, 2)
            lo, hi = p[j] + self.keep_lo[j], p[j] + self.keep_hi[j]
            bad[near] |= segment_crosses_open_box(a, b, lo, hi).reshape(len(near), c)
        return bad
