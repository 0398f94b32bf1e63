"""Where moving obstacles are and can be next: cell sets for grid controllers.

Moving obstacles move first in every step (phase 1) and do not react to robots, so a robot
must choose its cell at step t so that the obstacle's sweep from its position at t to its
position at t + 1 misses it. The controller knows the obstacles' footprints and motion models
(``world.moving_obstacles``) and sees their last two positions; from them we list every
position an obstacle can take next: one for a straight move, every free direction when it
bounces or walks at random, anything within its speed when the model may turn to any angle.

Footprints are handled through their bounding boxes on the grid, grown by the robots'
radius. A cell is *covered* when its centre lies inside the grown box: robots (points or
discs) rest on cell centres, so one resting on an uncovered centre is clear of the footprint.
The squares a box overlaps (the rule for point robots until 2026-11) take whole rows of cells
beside an obstacle a hair off the grid. A move between two clear centres can pass a footprint
beside it (checked by :meth:`ObstacleForecast.crossings`), and a robot resting off a centre is
checked where it rests (:meth:`ObstacleForecast.sweep_hits`). A footprint's move
covers the cells its swept region covers, row by row (:func:`sweep_cell_ranges`), not the
sweep's bounding box: a diagonal sweep is a hexagon.

Everything is vectorised over obstacles; boxes are painted with a 2-D difference array.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.obstacle_reach import WallAwareReach, centre_cells, reach_rule
from swarmpath.world.motions import FORECASTS, Motion, StepContext
from swarmpath.world.move_rules import GRID_MOVES, footprint_hits
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
#: Steps ahead a scripted obstacle's positions are listed (the deepest look-ahead asks 7).
SCRIPT_STEPS = 12
#: How far (world units) inside a box a cell centre must lie to count as covered by it: half the
#: checker's tolerance (``geometry.EPS``), so an uncovered centre is surely clear.
CENTRE_SLACK = 0.5e-9


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


def centre_cell_ranges(lo: FloatArray, hi: FloatArray, resolution: float, margin: int = 0) -> IntArray:
    """Cell ranges [x0, x1) x [y0, y1) of the cells whose centres lie inside the open boxes
    (lo, hi) (shape (k, 2) each), grown by ``margin`` cells: int array (k, 4). A centre within
    ``CENTRE_SLACK`` of a box's edge counts as outside: a disc there only touches the footprint
    (the checker allows contact within ``geometry.EPS``)."""
    x0y0 = np.floor((lo + CENTRE_SLACK) / resolution - 0.5).astype(np.int64) + 1 - margin
    x1y1 = np.ceil((hi - CENTRE_SLACK) / resolution - 0.5).astype(np.int64) + margin
    return np.concatenate([x0y0, x1y1], axis=-1)


def sweep_cell_ranges(a: FloatArray, b: FloatArray, lo: FloatArray, hi: FloatArray, resolution: float,
                      centres: bool = False, margin: int = 0) -> tuple[IntArray, IntArray]:
    """The cells a box footprint (offsets ``lo``, ``hi`` (k, 2) from its position) covers while it
    sweeps from ``a`` to ``b`` (k, 2): cell ranges (q, 4) as :func:`box_cell_ranges` (the open
    squares the swept region overlaps; with ``centres``, as :func:`centre_cell_ranges`: the
    centres it holds), and the sweep each range comes from (q,).

    Why not the sweep's bounding box: a box moving diagonally sweeps a hexagon, and the two
    corners of its bounding box lie outside it. For a bounce8 obstacle off the grid going
    diagonally those corners are whole cells, often the only way out of a nook beside its
    path (64 x 64 acceptance world, seed 2691: a robot on its goal in a dead end saw its way
    out covered and was caught when the obstacle turned). A sweep along an axis is its
    box; a diagonal sweep is listed row by row: for the cell row y (its open strip, or its
    centre line), the t in [0, 1] at which the box a + t (b - a) + [lo, hi] meets the row,
    and the x extent of the box over those t (it moves linearly, so the ends of that t
    interval bound it). With ``margin`` > 0 the bounding boxes are returned, grown."""
    a = np.asarray(a, float).reshape(-1, 2)
    b = np.asarray(b, float).reshape(-1, 2)
    lo = np.asarray(lo, float) + np.zeros_like(a)
    hi = np.asarray(hi, float) + np.zeros_like(a)
    ranges_of = centre_cell_ranges if centres else box_cell_ranges
    boxes = ranges_of(np.minimum(a, b) + lo, np.maximum(a, b) + hi, resolution, margin)
    d = b - a
    # a sweep along an axis covers its box; a diagonal one may leave out cells of it (with the
    # square rule only corner cells, when the box spans two cells or more each way)
    diagonal = (np.abs(d) > 1e-9 * max(resolution, 1.0)).all(axis=1) & (margin == 0)
    if not centres:
        diagonal &= ((boxes[:, 2:] - boxes[:, :2]) >= 2).all(axis=1)
    if not diagonal.any():
        return boxes, np.arange(len(a))
    straight = np.flatnonzero(~diagonal)
    k = np.flatnonzero(diagonal)
    y0, y1 = boxes[k, 1], boxes[k, 3]
    row = y0[:, None] + np.arange(int(np.max(y1 - y0)))[None, :]                 # (s, rows)
    valid = row < y1[:, None]
    ay, dy = a[k, 1, None], d[k, 1, None]
    # where the row is met: the strip (y, y + 1) for squares, the centre line for centres
    if centres:
        top = bottom = (row + 0.5) * resolution
    else:
        bottom, top = row * resolution, (row + 1) * resolution
    # box bottom  ay + lo_y + t dy < top  and  box top  ay + hi_y + t dy > bottom
    t_a = (top - ay - lo[k, 1, None]) / dy
    t_b = (bottom - ay - hi[k, 1, None]) / dy
    up = dy > 0
    t_lo = np.minimum(np.maximum(np.where(up, t_b, t_a), 0.0), 1.0)
    t_hi = np.minimum(np.maximum(np.where(up, t_a, t_b), 0.0), 1.0)
    valid &= t_lo < t_hi
    ax, dx = a[k, 0, None], d[k, 0, None]
    x_lo = ax + lo[k, 0, None] + np.minimum(t_lo * dx, t_hi * dx)
    x_hi = ax + hi[k, 0, None] + np.maximum(t_lo * dx, t_hi * dx)
    # the columns by the same rule as the boxes (the row's y is set above, not taken from here)
    span = ranges_of(np.stack([x_lo, np.zeros_like(x_lo)], axis=-1), np.stack([x_hi, np.zeros_like(x_hi)], axis=-1),
                     resolution)
    x0, x1 = span[..., 0], span[..., 2]
    keep = valid & (x0 < x1)
    cells = np.stack([x0[keep], row[keep], x1[keep], row[keep] + 1], axis=1)
    owner = np.broadcast_to(k[:, None], row.shape)[keep]
    return np.concatenate([boxes[straight], cells]), np.concatenate([straight, owner])


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


def paint_windows(ranges: IntArray, origins: IntArray, size: int, skip: BoolArray | None = None) -> BoolArray:
    """Boolean windows (r, size, size): window w is True where the union of the cell ranges
    (k, 4) covers cell ``origins[w] + (dx, dy)`` (``[w, dy, dx]``); ``skip`` (r, k) leaves
    range k out of window w. Only the ranges that overlap a window are painted into it (a
    difference array per window), so the cost grows with windows x ranges, not with the
    grid."""
    r = len(origins)
    out = np.zeros((r, size + 1, size + 1), np.int32)
    if len(ranges) and r:
        o = np.asarray(origins, np.int64)
        chunk = max(1, 1_000_000 // len(ranges))  # bound the (windows x ranges) temporaries
        for s0 in range(0, r, chunk):
            oo = o[s0:s0 + chunk]
            x0 = np.clip(ranges[None, :, 0] - oo[:, None, 0], 0, size)
            y0 = np.clip(ranges[None, :, 1] - oo[:, None, 1], 0, size)
            x1 = np.clip(ranges[None, :, 2] - oo[:, None, 0], 0, size)
            y1 = np.clip(ranges[None, :, 3] - oo[:, None, 1], 0, size)
            ok = (x0 < x1) & (y0 < y1)
            if skip is not None:
                ok &= ~np.asarray(skip, bool)[s0:s0 + chunk]
            win = np.nonzero(ok)[0] + s0
            x0, y0, x1, y1 = x0[ok], y0[ok], x1[ok], y1[ok]
            np.add.at(out, (win, y0, x0), 1)
            np.add.at(out, (win, y0, x1), -1)
            np.add.at(out, (win, y1, x0), -1)
            np.add.at(out, (win, y1, x1), 1)
    return out.cumsum(1).cumsum(2)[:, :size, :size] > 0


class ObstacleForecast:
    """Predicts the moving obstacles of one world, step by step (created in a controller's
    ``reset``; holds no run state beyond a memo of exact static checks and the step number
    given to :meth:`at_step`)."""

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
        # a cell is covered when its centre lies in the grown box: robots rest on centres, and
        # their moves between centres are checked on their own (crossings)
        self.robot_radius = float(robot_radius)
        self.code = np.array([motion_code(o) for o in obs], np.int64)
        self.base_code = self.code.copy()
        # any-heading models that move as bounce does on known steps (turn-every between turns)
        self.steady_models = np.array([j for j, o in enumerate(obs) if self.code[j] == ANY_HEADING
                                       and type(o.motion).steady_steps is not Motion.steady_steps], np.int64)
        self.steady = np.full(self.m, np.iinfo(np.int64).max)   # steps the code holds (at_step)
        # scripted models (waypoints): replayed from their start, their future known exactly
        self.scripted = np.array([j for j, o in enumerate(obs) if self.code[j] == ANY_HEADING
                                  and getattr(o.motion, "scripted", False)], np.int64)
        self._replay: dict[int, tuple[int, FloatArray, FloatArray, int]] = {}   # j: (step, p, v, counter)
        self.script: dict[int, FloatArray] = {}     # j: positions now and SCRIPT_STEPS steps ahead
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
        # boxes of uncertain heading cut to the cells the obstacle can reach round the walls
        # (obstacle_reach.py), for models that only move to where their footprint fits; a
        # footprint wider than a point in every direction never has its centre in a blocked cell
        solid = np.all((-self.lo > 1e-6) & (self.hi > 1e-6), axis=1)
        self.stays_clear = np.array([bool(getattr(o.motion, "stays_clear", False)) for o in obs], bool) & solid
        free = centre_cells(world, self.resolution, self.shape) if self.stays_clear.any() else None
        self.reach_cut = WallAwareReach(free) if free is not None else None
        self.keep_extent = np.max(np.abs(np.concatenate([self.keep_lo, self.keep_hi], axis=1)), axis=1, initial=0.0)
        self.least_extent = np.min(np.concatenate([-self.lo, self.hi], axis=1), axis=1, initial=np.inf)

    def cover_ranges(self, lo: FloatArray, hi: FloatArray, margin: int = 0) -> IntArray:
        """The cells (ranges (k, 4)) that open boxes (lo, hi) (k, 2) of footprints grown by the
        robots' radius cover: the cells whose centres they hold (:func:`centre_cell_ranges`).
        A robot (point or disc) resting on a centre outside the grown box is clear of the
        footprint; a move between two clear centres, which can pass a footprint beside it, is
        checked on its own (:meth:`crossings`), as is a robot resting off a centre
        (:meth:`off_centre_hits`).

        Why not the squares a box overlaps (the rule for point robots until 2026-11): a
        bounce8 obstacle going diagonally rests off the grid, and its one-cell box then
        overlaps four squares, its step six; running along a wall a hair off the row centre it
        shut the row beside it too, so a robot on its goal at the edge could only flee ahead
        of it (64 x 64 acceptance world, seed 3046: chased 18 cells, the run cut off at the
        budget)."""
        return centre_cell_ranges(lo, hi, self.resolution, margin)

    def sweep_ranges(self, a: FloatArray, b: FloatArray, lo: FloatArray, hi: FloatArray, margin: int = 0
                     ) -> tuple[IntArray, IntArray]:
        """The cells (ranges (q, 4), and the sweep of each (q,)) that footprints of box offsets
        ``lo``, ``hi`` (k, 2), grown by the robots' radius already, cover while sweeping from
        ``a`` to ``b`` (k, 2): :func:`sweep_cell_ranges` with this forecast's cover rule (the
        centres they hold)."""
        return sweep_cell_ranges(a, b, lo, hi, self.resolution, True, margin)

    def at_step(self, step: int, positions: FloatArray | None = None) -> None:
        """The obstacles have made their move of step ``step``: an any-heading model that
        declares steady steps (:meth:`~swarmpath.world.motions.base.Motion.steady_steps`,
        ``turn-every`` between its turns) is forecast as ``bounce`` while its next move is a
        steady one, for as many steps as it stays steady (the look-ahead grows its boxes by its
        reach from there). A scripted model (``Motion.scripted``: waypoints) seen at
        ``positions`` where its replay says it is, is forecast along its script, exactly, for
        ``SCRIPT_STEPS`` steps. Without a call, such models count as any-heading on every step."""
        for j in self.steady_models.tolist():
            ahead = int(self.world.moving_obstacles[j].motion.steady_steps(int(step)))
            self.code[j] = BOUNCE if ahead >= 1 else ANY_HEADING
            self.steady[j] = ahead if ahead >= 1 else np.iinfo(np.int64).max
        if positions is not None and len(self.scripted):
            self._follow_scripts(int(step), np.asarray(positions, float).reshape(self.m, 2))

    def _follow_scripts(self, step: int, positions: FloatArray) -> None:
        """Replay each scripted obstacle's model from its start up to ``step`` (its state is
        the model's own, not observed), check it stands where observed, and list its positions
        for the next ``SCRIPT_STEPS`` steps. An obstacle the replay does not match (a run
        started elsewhere) stays any-heading."""
        self.script = {}
        for j in self.scripted.tolist():
            ob = self.world.moving_obstacles[j]
            at, p, v, counter = self._replay.get(j, (0, np.asarray(ob.start, float), np.asarray(ob.velocity, float), 0))
            if at > step:
                at, p, v, counter = 0, np.asarray(ob.start, float), np.asarray(ob.velocity, float), 0
            if step - at > 100_000:
                continue   # a budget on the replay: such an obstacle stays any-heading
            while at < step:
                at += 1
                p, v, counter = ob.motion.advance(ob, p, v, counter, StepContext(self.world, None, at))
            self._replay[j] = (at, p, v, counter)
            if not np.allclose(p, positions[j], rtol=0, atol=1e-9):
                continue
            future = [p]
            q, w, c = p, v, counter
            for k in range(1, SCRIPT_STEPS + 1):
                q, w, c = ob.motion.advance(ob, q, w, c, StepContext(self.world, None, step + k))
                future.append(q)
            self.script[j] = np.asarray(future, float)

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
        # a bouncer that did not move last step had every sign of its heading blocked (the
        # reflections it tries are the same four each step): it stands for good
        vague = code == ANY_HEADING
        extra[vague] = self.speed[vague]
        for j, future in self.script.items():   # scripted: exactly its next position
            cand[j, 1] = future[1]
            possible[j] = False
            possible[j, 1] = True
            extra[j] = 0.0
        return cand, possible, extra

    def danger(self, positions: FloatArray, previous: FloatArray, *, margin: int = 0) -> BoolArray:
        """Cells (height, width) a robot must not end this step in: covered by an obstacle
        now (phase 2 of this step) or by its sweep to any possible next position (phase 1 of
        the next step), grown by ``margin`` cells."""
        if self.m == 0:
            return np.zeros(self.shape, bool)
        return paint(self.shape, self._danger_ranges(positions, previous, margin))

    def _danger_ranges(self, positions: FloatArray, previous: FloatArray, margin: int) -> IntArray:
        return self._owned_danger(positions, previous, margin)[0]

    def _owned_danger(self, positions: FloatArray, previous: FloatArray, margin: int) -> tuple[IntArray, IntArray]:
        p = np.asarray(positions, float).reshape(self.m, 2)
        cand, possible, extra = self.next_positions(p, previous)
        j, s = np.nonzero(possible)
        q = cand[j, s]
        ranges, sweep = self.sweep_ranges(p[j], q, self.keep_lo[j] - extra[j, None], self.keep_hi[j] + extra[j, None],
                                          margin)
        owners = j[sweep]
        if self.reach_cut is not None and np.any(extra > 0):
            # a model that may turn to any angle: its grown box, cut to one step round the walls
            d = p - np.asarray(previous, float).reshape(self.m, 2)
            reach = np.where(extra > 0, np.maximum(extra, np.hypot(d[:, 0], d[:, 1])), 0.0)
            ranges, owners = self._cut_to_reach(ranges, owners, p, np.ones(self.m, np.int64), reach, margin)
        return ranges, owners

    def _cut_to_reach(self, ranges: IntArray, owners: IntArray, starts: FloatArray, steps: IntArray,
                      reach: FloatArray, margin: int) -> tuple[IntArray, IntArray]:
        """Ranges (q, 4) of obstacles ``owners`` (q,) whose position is uncertain (``reach`` (m,)
        > 0: world units per step per axis at most, for ``steps`` (m,) steps from ``starts``
        (m, 2)) cut to the cells they can reach round the walls
        (:class:`~swarmpath.control.obstacle_reach.WallAwareReach`); the others unchanged."""
        cut = self.stays_clear[owners] & (reach[owners] > 0) & (steps[owners] > 0)
        if cut.any() and self._sat_shape == self.shape and abs(self._sat_res - self.resolution) < 1e-12:
            # a box without a blocked cell holds no wall to go round: its cut is the whole box
            h, w = self.shape
            x0, x1 = np.clip(ranges[:, 0], 0, w), np.clip(ranges[:, 2], 0, w)
            y0, y1 = np.clip(ranges[:, 1], 0, h), np.clip(ranges[:, 3], 0, h)
            sat = self._sat
            cut &= sat[y1, x1] - sat[y0, x1] - sat[y1, x0] + sat[y0, x0] > 0
        if not cut.any():
            return ranges, owners
        res = self.resolution
        j = owners[cut]
        # one rule per obstacle (its boxes of every row and step share it)
        ob, row = np.unique(j, return_inverse=True)
        rules = np.array([reach_rule(r / res, r / res * (np.sqrt(2) if walker else 1.0), rho / res, e / res, walker,
                                     margin)
                          for r, rho, e, walker in zip(reach[ob].tolist(), self.least_extent[ob].tolist(),
                                                       self.keep_extent[ob].tolist(),
                                                       (self.code[ob] == RANDOM_WALK).tolist())], np.int64)[row]
        hops, jumps, dils = rules[:, 0], rules[:, 1].astype(bool), rules[:, 2]
        cells = np.floor(starts[j] / res).astype(np.int64)
        kept, kept_owners = self.reach_cut.cut(ranges[cut], j, cells, hops, steps[j], dils, jumps)
        return np.concatenate([ranges[~cut], kept]), np.concatenate([owners[~cut], kept_owners])

    def step_ranges(self, positions: FloatArray, previous: FloatArray, steps: int, *, margin: int = 0
                    ) -> list[IntArray]:
        """The cell ranges (k, 4) whose union is D_k, for k = 1 ... ``steps`` (see
        :meth:`coverage`): what :func:`paint` (the whole grid) or :func:`paint_windows` (the
        cells around some robots) turns into cell sets."""
        return [r for r, _ in self.owned_step_ranges(positions, previous, steps, margin=margin)]

    def owned_step_ranges(self, positions: FloatArray, previous: FloatArray, steps: int, *, margin: int = 0
                          ) -> list[tuple[IntArray, IntArray]]:
        """:meth:`step_ranges` with the obstacle each range comes from: per step k, (ranges
        (q, 4), obstacle (q,)); a caller leaves some obstacles out by their rows."""
        if self.m == 0:
            return [(np.zeros((0, 4), np.int64), np.zeros(0, np.int64)) for _ in range(steps)]
        out = [self._owned_danger(positions, previous, margin)]
        if steps < 2:
            return out
        m = self.m
        p = np.asarray(positions, float).reshape(m, 2)
        d = p - np.asarray(previous, float).reshape(m, 2)
        moving = np.hypot(d[:, 0], d[:, 1]) > _MOVING
        # a bouncer that stood still stands on (next_positions): straight on at zero speed
        straight = (np.isin(self.code, (BOUNCE, BOUNCE8)) & moving) | ((self.code == BOUNCE) & ~moving)
        ahead = p[:, None, :] + d[:, None, :] * np.arange(1, steps + 1)[None, :, None]
        ok = self.fits(np.repeat(np.arange(m), steps), ahead.reshape(-1, 2)).reshape(m, steps)
        free_all = np.where(ok.all(axis=1), steps, np.argmin(ok, axis=1))
        # a model steady for s more steps goes straight at most s steps, then anywhere
        free_all = np.where(straight, np.minimum(free_all, self.steady), 0)
        reach = np.where(self.code == RANDOM_WALK, self.walk_step, np.maximum(self.speed, np.hypot(*d.T)))
        reach = np.where(self.code == REDRAW, 0.0, reach)
        # a moving bounce or bounce8 obstacle turns only where it is blocked: its runs are
        # listed exactly (few branches); the others are bounded by boxes
        runs, exact = self._bounce_runs(p, d, straight & ~ok.all(axis=1) & (self.steady >= steps), steps)
        scripted = np.array([j for j in self.script if len(self.script[j]) > steps], np.int64)
        boxed = np.flatnonzero(~exact)
        for k in range(2, steps + 1):
            free = np.minimum(free_all, k)
            sure = free >= k
            grow = np.where(sure, 0.0, (k - free) * reach)[:, None]
            a = np.where(sure[:, None], p + (k - 1) * d, p + free[:, None] * d)
            b = np.where(sure[:, None], p + k * d, a)
            if len(scripted):   # scripted obstacles: the sweep of their k-th step, exactly
                grow[scripted] = 0.0
                a[scripted] = [self.script[j][k - 1] for j in scripted.tolist()]
                b[scripted] = [self.script[j][k] for j in scripted.tolist()]
            boxes, sweep = self.sweep_ranges(a[boxed], b[boxed], self.keep_lo[boxed] - grow[boxed],
                                             self.keep_hi[boxed] + grow[boxed], margin)
            owners = boxed[sweep]
            if self.reach_cut is not None:
                # the boxes grown for an uncertain heading, cut to the cells reachable round walls
                unsure = np.where(grow[:, 0] > 0, k - free, 0)
                boxes, owners = self._cut_to_reach(boxes, owners, a, unsure, np.where(unsure > 0, reach, 0.0), margin)
            if exact.any():
                j, a, b = runs[k - 1]
                more, sweep = self.sweep_ranges(a, b, self.keep_lo[j], self.keep_hi[j], margin)
                boxes = np.concatenate([boxes, more])
                owners = np.concatenate([owners, j[sweep]])
            out.append((boxes, owners))
        return out

    def bounce_successors(self, which: IntArray, pos: FloatArray, vel: FloatArray
                          ) -> tuple[IntArray, FloatArray, FloatArray]:
        """One step of the bounce and bounce8 models
        (:func:`swarmpath.world.motions._straight.straight_step`) from the states (``which``
        (k,) obstacles at ``pos`` (k, 2) with step ``vel`` (k, 2), world units per step):
        straight on where the footprint fits; where it does not, bounce8 takes one step in any
        other compass direction at the same speed that fits and bounce the first reflection
        that fits (x flipped, y flipped, both); with none, they stand with the heading
        reversed. Returns (parent (q,), position (q, 2), step (q, 2)): every state one step
        on, with the index of the state it comes from (a bounce8 turn has several)."""
        j = np.asarray(which, np.int64)
        eight = self.code[j] == BOUNCE8
        # straight on, and the 8 compass directions at the same speed, checked together
        speed = np.hypot(vel[:, 0], vel[:, 1])
        turns = UNIT_DIRECTIONS[None] * speed[:, None, None]                      # (k, 8, 2)
        dest = pos[:, None, :] + np.concatenate([vel[:, None, :], turns], axis=1)   # (k, 9, 2)
        free = self.fits(np.repeat(j, 9), dest.reshape(-1, 2)).reshape(len(j), 9)
        ok = free[:, 0]
        hit = np.flatnonzero(~ok & eight)
        other = free[hit, 1:] & (np.abs(turns[hit] - vel[hit, None, :]).max(axis=2) > 1e-9)
        r, c = np.nonzero(other)
        flip = np.flatnonzero(~ok & ~eight)
        flips = vel[flip, None, :] * BOUNCE_FLIPS[None]                              # (f, 3, 2)
        flip_to = pos[flip, None, :] + flips
        fits = self.fits(np.repeat(j[flip], 3), flip_to.reshape(-1, 2)).reshape(len(flip), 3)
        first = np.argmax(fits, axis=1)
        reflected = fits.any(axis=1)
        f = flip[reflected]
        boxed = np.concatenate([hit[~other.any(axis=1)], flip[~reflected]])
        parent = np.concatenate([np.flatnonzero(ok), hit[r], f, boxed])
        new_pos = np.concatenate([dest[ok, 0], dest[hit[r], 1 + c], flip_to[reflected, first[reflected]], pos[boxed]])
        new_vel = np.concatenate([vel[ok], turns[hit[r], c], flips[reflected, first[reflected]], -vel[boxed]])
        return parent, new_pos, new_vel

    def _bounce_runs(self, p: FloatArray, d: FloatArray, which: BoolArray, steps: int, cap: int = 256
                     ) -> tuple[list[tuple[IntArray, FloatArray, FloatArray]], BoolArray]:
        """Every way the moving bounce and bounce8 obstacles ``which`` can go in the next
        ``steps`` steps, as the models move them (:meth:`bounce_successors`, step by step). Returns
        per step k (1 ... steps) the moves (obstacle, from, to) and a mask of the obstacles
        listed; an obstacle with more than ``cap`` distinct states at some step is left to
        the boxes (the mask is False for it)."""
        exact = which.copy()
        if not exact.any():
            return [], exact
        runs: list[tuple[IntArray, FloatArray, FloatArray]] = []
        j = np.flatnonzero(which)
        pos, vel = p[j], d[j]
        for _ in range(steps):
            parent, new_pos, new_vel = self.bounce_successors(j, pos, vel)
            new_j, start = j[parent], pos[parent]
            runs.append((new_j, start, new_pos))
            j, pos, vel = new_j, new_pos, new_vel
            count = np.bincount(j, minlength=len(p))
            if count.max(initial=0) > 48:   # branches that met again: keep one of each state
                key = np.ascontiguousarray(np.column_stack([j, np.round(np.column_stack([pos, vel]) * 1e6)])
                                           .astype(np.int64))
                _, first = np.unique(key.view(np.dtype((np.void, key.dtype.itemsize * 5))).ravel(),
                                     return_index=True)
                first.sort()
                j, pos, vel = j[first], pos[first], vel[first]
                count = np.bincount(j, minlength=len(p))
            over = count > cap
            if over.any():
                exact &= ~over
                keep = ~over[j]
                j, pos, vel = j[keep], pos[keep], vel[keep]
        return [(rj[exact[rj]], a[exact[rj]], b[exact[rj]]) for rj, a, b in runs], exact

    def coverage(self, positions: FloatArray, previous: FloatArray, steps: int, *, margin: int = 0
                 ) -> list[BoolArray]:
        """[D_1, ..., D_steps]: the cells (height, width) an obstacle may cover in phase 1 of
        each of the next ``steps`` steps. D_1 is :meth:`danger`. For k >= 2, D_k holds the
        sweep from step k - 1 to step k: the bouncing models go straight on while their way
        is free (``f`` free steps). A moving bounce or bounce8 obstacle turns only where it is
        blocked (bounce8 to any other compass direction that is free, bounce to its first
        reflection that fits) and goes straight on again: its runs are listed exactly
        (:meth:`_bounce_runs`). One that stands (after a full stop) may set off any way, so
        from step f on it lies within (k - f) steps of travel of where it is; random walkers
        lie within k steps of travel of where they are now. Those boxes are cut to the cells
        such an obstacle can reach round the walls when its model keeps to where it fits
        (:mod:`swarmpath.control.obstacle_reach`).

        Whole-grid arrays: a controller that needs the cells around its robots only asks
        :meth:`windows` (the cost then follows the robots, not the map)."""
        return [paint(self.shape, r) for r in self.step_ranges(positions, previous, steps, margin=margin)]

    def windows(self, positions: FloatArray, previous: FloatArray, steps: int, origins: IntArray, size: int, *,
                margin: int = 0) -> BoolArray:
        """D_1 ... D_steps of :meth:`coverage` on square windows of the grid only: bool array
        (steps, r, size, size), window w holding cells ``origins[w] + (0 ... size - 1)`` (x and
        y; ``out[k - 1, w, dy, dx]`` is D_k at cell ``origins[w] + (dx, dy)``). Cells outside
        the grid are never covered. Exactly the whole-grid sets on those cells."""
        h, w = self.shape
        out = np.zeros((steps, len(origins), size, size), bool)
        for k, r in enumerate(self.step_ranges(positions, previous, steps, margin=margin)):
            clipped = np.stack([np.clip(r[:, 0], 0, w), np.clip(r[:, 1], 0, h), np.clip(r[:, 2], 0, w),
                                np.clip(r[:, 3], 0, h)], axis=1) if len(r) else r
            out[k] = paint_windows(clipped, origins, size)
        return out

    def influence(self, steps: int) -> float:
        """How far (world units, Chebyshev) from an obstacle's position anything it may do in
        the next ``steps`` steps can reach; robots farther away need no forecast."""
        if self.m == 0:
            return 0.0
        extent = float(np.max(np.abs(np.concatenate([self.keep_lo, self.keep_hi]))))
        fastest = float(np.max(np.maximum(self.speed, self.walk_step), initial=0.0))
        return extent + (steps + 1) * fastest

    def sweep_hits(self, points: FloatArray, positions: FloatArray, previous: FloatArray) -> BoolArray:
        """Whether a robot of the forecast's radius resting at ``points`` (..., 2) may be hit in
        phase 1 of the next step: some obstacle's footprint sweeping from where it stands now
        to one of its possible next positions (:meth:`next_positions`, grown by their
        uncertainty) reaches it, exactly as the checker decides
        (:func:`~swarmpath.world.move_rules.footprint_hits`). For disc robots resting off a cell
        centre (an exact goal), which the centre cover does not speak for."""
        pts = np.asarray(points, float)
        flat = pts.reshape(-1, 2)
        hit = np.zeros(len(flat), bool)
        if self.m == 0 or len(flat) == 0:
            return hit.reshape(pts.shape[:-1])
        p = np.asarray(positions, float).reshape(self.m, 2)
        cand, possible, extra = self.next_positions(p, previous)
        reach = np.max(np.abs(np.concatenate([self.keep_lo, self.keep_hi], axis=1)), axis=1) + extra \
            + np.max(np.abs(cand - p[:, None, :]), axis=(1, 2))
        for j in range(self.m):
            near = np.flatnonzero(np.max(np.abs(flat - p[j]), axis=1) <= reach[j] + self.resolution)
            if len(near) == 0:
                continue
            shape = self.world.moving_obstacles[j].placed((0.0, 0.0))
            r = np.full(len(near), self.robot_radius + extra[j])
            for q in cand[j, possible[j]]:
                hit[near] |= footprint_hits(shape, flat[near] - p[j], flat[near] - q, r)
        return hit.reshape(pts.shape[:-1])

    def off_centre_hits(self, points: FloatArray, centres: FloatArray, positions: FloatArray,
                        previous: FloatArray) -> BoolArray:
        """:meth:`sweep_hits` for the entries of ``points`` (..., 2) that lie off their cell
        centres ``centres`` (same shape); False for the others, which the cover speaks for."""
        pts = np.asarray(points, float)
        odd = np.abs(pts - np.asarray(centres, float)).max(axis=-1) > 1e-9
        out = np.zeros(odd.shape, bool)
        if odd.any():
            out[odd] = self.sweep_hits(pts[odd], positions, previous)
        return out

    def crossings(self, starts: FloatArray, ends: FloatArray, positions: FloatArray) -> BoolArray:
        """Whether each move starts[r] -> ends[r, c] (shapes (k, 2) and (k, c, 2)) meets an
        obstacle where it stands now: for point robots, passes through the interior of its
        bounding box (exact for boxes); for disc robots, comes closer to its footprint than the
        radius (the checker's phase-2 rule, :func:`~swarmpath.world.move_rules.footprint_hits`:
        the box grown by the radius would also forbid moves that start in its corners, away
        from the footprint). Used for every robot near an obstacle: the cover speaks for the
        centres only (:meth:`cover_ranges`), and a move between two clear centres can pass a
        footprint beside it."""
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
            if self.robot_radius > 0:
                shape = self.world.moving_obstacles[j].placed((0.0, 0.0))
                hit = footprint_hits(shape, a - p[j], b - p[j], np.full(len(a), self.robot_radius))
            else:
                hit = segment_crosses_open_box(a, b, p[j] + self.keep_lo[j], p[j] + self.keep_hi[j])
            bad[near] |= hit.reshape(len(near), c)
        return bad


# ---------------------------------------------------------------------------------- look-ahead
# Which cells keep a robot clear of every moving obstacle for several steps, whatever the
# obstacles do: backward induction over D_1 ... D_K on small windows around the robots that
# an obstacle can reach at all (a controller's cost follows the robots near obstacles, never
# the map's area).

def window_moves(blocked: BoolArray, connectivity: int = 8) -> BoolArray:
    """The 9 grid moves (``move_rules.GRID_MOVES`` order, stay first) from every inner cell of
    ``blocked`` (..., s + 2, s + 2), a window with a one-cell ring (outside the grid:
    blocked): bool array (..., s, s, 9). Staying needs a free cell; a move a free target, a
    diagonal also both orthogonal neighbours free (no corner cutting), and none with
    4-connectivity. On a whole grid padded with blocked cells it is
    :func:`swarmpath.control.pibt.core.static_moves`."""
    b = np.asarray(blocked, bool)
    s0, s1 = b.shape[-2] - 2, b.shape[-1] - 2
    free = ~b
    here = free[..., 1:1 + s0, 1:1 + s1]
    out = np.zeros(b.shape[:-2] + (s0, s1, 9), bool)
    for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
        if connectivity == 4 and dx and dy:
            continue
        ok = here & free[..., 1 + dy:1 + dy + s0, 1 + dx:1 + dx + s1]
        if dx and dy:
            ok &= free[..., 1:1 + s0, 1 + dx:1 + dx + s1] & free[..., 1 + dy:1 + dy + s0, 1:1 + s1]
        out[..., a] = ok
    return out


def escape_cells(unsafe: BoolArray, moves: BoolArray) -> BoolArray:
    """Cells with a way out, shape (..., h, w): some allowed move (``moves`` (..., h, w, 9),
    staying included) reaches a cell that is not ``unsafe`` (..., h, w); cells beyond the
    array count as unsafe. A robot that ends its step on such a cell can still get clear next
    step, wherever the obstacles go (``unsafe`` = what they may cover the step after)."""
    u = np.asarray(unsafe, bool)
    h, w = u.shape[-2:]
    pad = np.ones(u.shape[:-2] + (h + 2, w + 2), bool)
    pad[..., 1:-1, 1:-1] = u
    out = np.zeros(u.shape, bool)
    for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
        out |= moves[..., a] & ~pad[..., 1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
    return out


def standing_cells(covered, k: int) -> BoolArray:
    """Cells an obstacle may stand on after k steps from now (k >= 1), shape (..., h, w), as
    far as ``covered`` = [D_1, ..., D_K] tells: the step-k sweep ends where the step-(k+1)
    sweep starts, so D_k and D_(k+1) (D_K alone for k = K). A bouncer on a straight run
    stands on one cell of its two-cell sweeps, not on the cell it has just left."""
    here = np.asarray(covered[k - 1], bool)
    return here & np.asarray(covered[k], bool) if k < len(covered) else here


def moves_past(moves: BoolArray, standing: BoolArray) -> BoolArray:
    """``moves`` (..., h, w, 9) without the diagonals that pass a cell of ``standing``
    (..., h, w): a diagonal crosses the shared corner of its two orthogonal neighbours, and an
    obstacle standing on either touches it (the checker's phase 2: the robot moves while the
    obstacles stand where their step ended). Corners beyond the array count as clear: a move
    that needs one ends beyond the array too.

    With cells counted by their centres this misses no crossing of a box footprint at least
    a cell wide by a point robot: such a box touching a move's path holds the centre of its
    start, its end or a corner cell (an interval of length 1 meeting [c + 1/2, c + 3/2] holds
    one of its ends), and start and end are in no D set. A smaller obstacle off the grid can
    slip between centres; the step being decided is checked exactly
    (:meth:`ObstacleForecast.crossings`). For disc robots (cells covered by their centres
    grown by the radius) it would also leave out diagonals the disc clears, so the
    controllers use it for point robots only (:class:`HazardWindows`)."""
    s = np.asarray(standing, bool)
    h, w = s.shape[-2:]
    pad = np.zeros(s.shape[:-2] + (h + 2, w + 2), bool)
    pad[..., 1:-1, 1:-1] = s
    out = np.array(moves, bool, copy=True)
    for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
        if dx and dy:
            out[..., a] &= ~pad[..., 1:1 + h, 1 + dx:1 + dx + w] & ~pad[..., 1 + dy:1 + dy + h, 1:1 + w]
    return out


def safe_tier(covered, moves: BoolArray, depth: int, corners: bool = True) -> tuple[BoolArray, BoolArray]:
    """Cells where a robot may end this step and still keep clear of every moving obstacle
    for ``depth`` steps whatever the obstacles do, shape (..., h, w). ``covered`` = [D_1,
    ..., D_K] (K >= depth, each (..., h, w)) are the cells obstacles may cover in each of the
    next K steps. Backward induction: S_depth = not D_depth, S_k = not D_k and one allowed
    move away from S_(k+1), the move made while the obstacles stand where step k left them
    (with ``corners``, for point robots: no diagonal past one, :func:`moves_past`). Returns
    (S_1, S_2) (S_2: where the robot must be able to go next step; all True for depth 1).

    Why the diagonals: a robot waiting beside a bouncer's line, a walker on its other side,
    was ranked safe because a diagonal led on past the bouncer's next cell; the step after,
    that diagonal crossed the bouncer and the robot was cornered (64 x 64 acceptance world,
    pibt seed 3299)."""
    safe = ~np.asarray(covered[depth - 1], bool)
    after = np.ones_like(safe)
    for k in range(depth - 1, 0, -1):
        after = safe
        ways = moves_past(moves, standing_cells(covered, k)) if corners else moves
        safe = ~np.asarray(covered[k - 1], bool) & escape_cells(~safe, ways)
    return safe, after


def dead_end_cells(moves: BoolArray, budget: int = 64) -> BoolArray:
    """Cells (height, width) of dead ends: peeled from the free cells, a cell with at most one
    move (``moves`` (height, width, 9), index 0 the stay) into the cells not yet peeled at a
    time, ``budget`` rounds at most (dead-end corridors longer than that are cut off there).
    A robot in such a cell can only leave the way it came: an obstacle at the mouth corners
    it, so robots next to one look further ahead (:data:`DEAD_END_EXTRA`)."""
    moves = np.asarray(moves, bool)
    h, w = moves.shape[:2]
    free = moves[..., 0].copy()
    alive = free.copy()
    for _ in range(budget):
        padded = np.pad(alive, 1)
        ways = np.zeros((h, w), np.int64)
        for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
            if a:
                ways += moves[..., a] & padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
        peel = alive & (ways <= 1)
        if not peel.any():
            break
        alive &= ~peel
    return free & ~alive


#: How far (cells, Chebyshev) from an obstacle :func:`pocket_cells` looks for pockets it closes.
POCKET_REACH = 6


def pocket_cells(moves: BoolArray, reach: int = POCKET_REACH, batch: int = 4096) -> BoolArray:
    """Cells (height, width) of pockets: free cells that an obstacle standing on one free
    cell m cuts off from everything more than ``reach`` cells from m, because the robot may
    not end a step next to it (the 3 x 3 cells around m are closed). ``moves`` (height,
    width, 9) are the grid moves, index 0 the stay (free cells).

    Dead ends shorter than ``reach`` are pockets (longer ones: :func:`dead_end_cells`); the
    others are wider: a 2 x 3 nook at the map's edge, a room with a door two cells wide. A robot inside one is shut in by a
    single obstacle at the mouth, however wide the pocket is, so robots next to one look
    further ahead (:data:`DEAD_END_EXTRA`). Moves without corner cutting connect exactly the
    4-connected cells, so each window (2 ``reach`` + 1 cells wide around m, the 3 x 3 around
    m removed) is labelled 4-connected; its parts that touch no edge of the window are
    pockets. All windows are labelled at once, ``batch`` at a time (one labelled stack, no
    links between windows)."""
    from scipy import ndimage

    free = np.asarray(moves, bool)[..., 0]
    h, w = free.shape
    size = 2 * reach + 1
    padded = np.pad(free, reach, constant_values=False)
    ys, xs = np.nonzero(free)
    off = np.arange(size)
    structure = np.zeros((3, 3, 3), bool)
    structure[1] = [[False, True, False], [True, True, True], [False, True, False]]
    ring = np.ones((size, size), bool)
    ring[1:-1, 1:-1] = False
    out = np.zeros((h, w), bool)
    for start in range(0, len(ys), batch):
        y, x = ys[start:start + batch], xs[start:start + batch]
        win = padded[(y[:, None] + off)[:, :, None], (x[:, None] + off)[:, None, :]]
        win[:, reach - 1:reach + 2, reach - 1:reach + 2] = False
        labels, count = ndimage.label(win, structure)
        if count == 0:
            continue
        open_ = np.zeros(count + 1, bool)
        open_[labels[:, ring]] = True
        k, i, j = np.nonzero(~open_[labels])
        out[y[k] + i - reach, x[k] + j - reach] = True
    return out & free


def trap_cells(moves: BoolArray) -> BoolArray:
    """Cells (height, width) where a single obstacle can shut a robot in: the dead ends
    (:func:`dead_end_cells`) and the pockets (:func:`pocket_cells`) of the grid moves
    ``moves`` (height, width, 9). Robots with a candidate among them look
    :data:`DEAD_END_EXTRA` steps further."""
    return dead_end_cells(moves) | pocket_cells(moves)


#: Extra look-ahead steps for a robot with a candidate (its own cell included) in a dead end.
DEAD_END_EXTRA = 2


def next_to_dead_end(dead_end: BoolArray, dest: IntArray, allowed: BoolArray) -> IntArray:
    """Indices of the robots with an ``allowed`` candidate (r, 9) whose cell ``dest`` (r, 9, 2)
    lies in a dead end (``dead_end`` from :func:`dead_end_cells`): those that look
    :data:`DEAD_END_EXTRA` steps further."""
    h, w = dead_end.shape
    inside = np.clip(dest, 0, [w - 1, h - 1])
    return np.flatnonzero((dead_end[inside[..., 1], inside[..., 0]] & allowed).any(axis=1))


def stay_depth(covered, shape: tuple[int, ...] | None = None) -> NDArray[np.int64]:
    """For every cell, for how many of the next K steps it stays clear of every obstacle
    (0 ... K), shape of one D_k: how long a robot could wait there. With K = 0 steps (an
    empty list) every cell gets 0; ``shape`` gives the shape then."""
    if len(covered) == 0:
        if shape is None:
            raise ValueError("stay_depth: give the grid's shape when there are no steps")
        return np.zeros(shape, dtype=np.int64)
    clear = np.ones(np.shape(covered[0]), dtype=bool)
    depth = np.zeros(np.shape(covered[0]), dtype=np.int64)
    for d in covered:
        clear &= ~np.asarray(d, bool)
        depth += clear
    return depth


def warning_levels(covered, cells: IntArray, decay: float) -> FloatArray:
    """A soft warning for ``cells`` (..., 2) in [0, 1]: decay ** (k - 1) when an obstacle may
    cover a cell within one cell of it k steps from now (k = 1, 2, ...), the largest value
    where several apply. ``covered[k]`` is a grid (h, w) (cells clipped into it) or a batch
    of windows (r, h, w), then ``cells`` (r, ..., 2) are window coordinates of window r.
    Robots step out of an obstacle's way early instead of being cornered."""
    first = np.asarray(covered[0])
    h, w = first.shape[-2:]
    ring = np.asarray(cells)[..., None, :] + GRID_MOVES
    x = np.clip(ring[..., 0], 0, w - 1)
    y = np.clip(ring[..., 1], 0, h - 1)
    rows = () if first.ndim == 2 else (np.arange(first.shape[0]).reshape((-1,) + (1,) * (x.ndim - 1)),)
    out = np.zeros(np.shape(cells)[:-1])
    for k in range(len(covered) - 1, -1, -1):
        near = np.asarray(covered[k])[rows + (y, x)].any(axis=-1)
        out = np.where(near, decay ** k, out)
    return out


@dataclass(frozen=True)
class HazardWindows:
    """The moving-obstacle look-ahead of the robots an obstacle can reach within the next
    ``steps`` steps, on a square window around each (built by :func:`hazard_windows`).

    rows (r,) : those robots' indices; origin (r, 2) : cell (x, y) of each window's corner;
    covered (steps, r, s, s) : D_1 ... D_steps (:meth:`ObstacleForecast.coverage`) on the
    windows; moves (r, s, s, 9) : the static grid moves from each window cell; corners : the
    look-ahead leaves out diagonals past a cell an obstacle may stand on (:func:`moves_past`;
    point robots).

    Why only point robots: cells covered by their centres, grown by a disc robot's radius,
    leave out diagonals that the disc would clear as well, and that cost a disc robot the
    diagonal out of a bouncer's column on seed 1 of the 64 x 64 acceptance world with discs
    (cat-swarm, caught; docs/algorithms/pibt.md)."""

    rows: IntArray
    origin: IntArray
    covered: BoolArray
    moves: BoolArray
    corners: bool = True

    def local(self, cells: IntArray) -> IntArray:
        """Window coordinates of grid cells (r, ..., 2), one leading row per window."""
        c = np.asarray(cells, np.int64)
        return c - self.origin.reshape((-1,) + (1,) * (c.ndim - 2) + (2,))

    def at(self, grid, cells: IntArray) -> BoolArray:
        """The value of ``grid`` (r, s, s) (one of ``covered`` or a tier) at grid cells
        (r, ..., 2), which must lie inside each row's window."""
        c = self.local(cells)
        rows = np.arange(len(self.rows)).reshape((-1,) + (1,) * (c.ndim - 2))
        return grid[rows, c[..., 1], c[..., 0]]

    def tiers(self, allowed: BoolArray, dest: IntArray, depth: int | IntArray, exits: BoolArray | None = None,
              spare: bool = True, fallback: BoolArray | None = None
              ) -> tuple[BoolArray, BoolArray, IntArray, IntArray]:
        """Keep each robot to the most cautious tier that leaves it a candidate: for d =
        ``depth`` (one for all, or (r,) per robot) down to 2, the candidates (``allowed`` (r,
        9), reaching cells ``dest`` (r, 9, 2)) from which the robot can keep clear for d
        steps; a robot with none keeps its candidates for the next d. ``exits`` (r, 9, 9): the
        moves a robot can make after each candidate (default: the static moves of the
        candidate's cell; less from an exact goal off its cell centre). With ``spare``
        (default) a robot in a tier keeps to the candidates that leave two ways on (moves the
        step after, standing included) when it has any: two robots fleeing the same obstacle
        toward one way out used to be cornered, one of them (on 3 of 30 seeds of the 64 x 64
        acceptance world, for pibt and cat-swarm alike; none with the spare way).

        ``fallback`` (r,) marks robots that keep all their candidates, ranked instead of cut:
        a robot an obstacle may reach where it stands must leave, and when the cells of its
        deepest tier are taken by other robots a shallower one beats staying.

        Returns (allowed, threatened, rank, ways): threatened robots must leave their cell to
        stay in their tier; rank (r, 9) orders the candidates from the most cautious (0): two
        steps per tier below the robot's ``depth``, one more for a single way on in its tier
        (with ``spare``); ways (r, 9): how many ways on each candidate leaves in its tier (0
        outside every tier from 2 up)."""
        r = len(self.rows)
        allowed = np.asarray(allowed, bool).copy()
        threatened = np.zeros(r, bool)
        undecided = np.ones(r, bool)
        if exits is None:
            exits = self.at(self.moves, dest)
        if self.corners and len(self.covered) >= 2:
            # next step's moves are made while the obstacles stand where that step left them
            exits = exits & self.at(moves_past(self.moves, standing_cells(self.covered, 1)), dest)
        around = np.asarray(dest)[..., None, :] + GRID_MOVES            # (r, 9, 9, 2)
        base = allowed.copy()
        depth = np.broadcast_to(np.asarray(depth, np.int64), (r,))
        top = int(depth.max(initial=0))
        # candidates in no tier from 2 up rank as tier 1 (clear of the next step only)
        rank = np.broadcast_to(2 * (np.maximum(depth, 1) - 1)[:, None], base.shape).copy()
        ranked = np.zeros(base.shape, bool)
        way_count = np.zeros(base.shape, np.int64)
        for d in range(top, 1, -1):
            _, then = safe_tier(self.covered, self.moves, d, self.corners)
            ways = np.sum(exits & self.at(then, around), axis=-1)
            strict = base & ~self.at(self.covered[0], dest) & (ways > 0)
            fresh = strict & ~ranked & (depth >= d)[:, None]
            rank = np.where(fresh, 2 * (depth[:, None] - d) + (spare & (ways < 2)), rank)
            way_count = np.where(fresh, ways, way_count)
            ranked |= fresh
            if spare:
                # two ways on rather than one where some candidate has them: another robot
                # fleeing the same obstacle may take a single way out first
                wide = strict & (ways >= 2)
                strict = np.where(wide.any(axis=1)[:, None], wide, strict)
            usable = strict.any(axis=1) & undecided & (depth >= d)
            allowed = np.where(usable[:, None], strict, allowed)
            threatened |= usable & ~strict[:, 0]
            undecided &= ~usable
        if fallback is not None:
            allowed = np.where(np.asarray(fallback, bool)[:, None], base, allowed)
        return allowed, threatened, rank, way_count


def cornered_penalty(allowed: BoolArray, rank: IntArray, ways: IntArray) -> IntArray:
    """For robots with no candidate in their deepest look-ahead tier (obstacles closing in:
    the best ``rank`` among ``allowed`` (r, 9) is above 0): 9 minus the ways on each candidate
    leaves (``ways`` from :meth:`HazardWindows.tiers`), so that among equally safe cells such a
    robot takes the one with the most ways on, not the one nearest its goal; 0 for the other
    robots. A robot waiting by a wall or in a corner as obstacles close in was cornered
    within three steps (64 x 64 acceptance world, pibt: 5 of 100 seeds with a contact instead of 7)."""
    best = np.where(allowed, rank, np.iinfo(np.int64).max).min(axis=1)
    return np.where((best > 0)[:, None], 9 - np.asarray(ways), 0)


def hazard_windows(forecast: ObstacleForecast, positions: FloatArray, previous: FloatArray, robots: FloatArray,
                   cells: IntArray, padded_blocked: BoolArray, pad: int, steps: int, radius: int, *,
                   connectivity: int = 8, margin: int = 0) -> HazardWindows | None:
    """:class:`HazardWindows` for the robots (at ``robots`` (n, 2), world units, in ``cells``
    (n, 2)) that an obstacle (at ``positions``, one step earlier ``previous``) can reach within
    ``steps`` steps plus ``radius`` cells; None when there is none. Each window holds the
    cells within ``radius`` cells (Chebyshev) of its robot: what candidates (1 cell away) and
    a ``radius``-step look-ahead read. ``padded_blocked`` is the static grid padded with
    ``pad`` >= radius + 1 blocked cells on every side."""
    if forecast.m == 0 or len(cells) == 0:
        return None
    from scipy.spatial import cKDTree

    obstacles = np.asarray(positions, float).reshape(forecast.m, 2)
    reach = forecast.influence(steps) + (radius + 1) * forecast.resolution
    count = cKDTree(obstacles).query_ball_point(np.asarray(robots, float), reach, p=np.inf, return_length=True)
    rows = np.flatnonzero(np.asarray(count) > 0)
    if len(rows) == 0:
        return None
    size = 2 * radius + 1
    origin = np.asarray(cells, np.int64)[rows] - radius
    covered = forecast.windows(obstacles, previous, steps, origin, size, margin=margin)
    off = np.arange(size + 2)
    ys = origin[:, 1, None] - 1 + pad + off[None]
    xs = origin[:, 0, None] - 1 + pad + off[None]
    patches = padded_blocked[ys[:, :, None], xs[:, None, :]]
    return HazardWindows(rows, origin, covered, window_moves(patches, connectivity), forecast.robot_radius == 0)
