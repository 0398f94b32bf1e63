"""One ORCA step for all robots: the half-planes of every robot (static geometry, moving
obstacles, neighbours), the batched linear programs, and the exact check that makes each
straight move of one step contact-free under the simulator's own rules.

:class:`ORCASolver` is shared by the ``orca`` controller and :class:`SafetyLayer`; it holds
per-run geometry (built in :meth:`ORCASolver.reset`) and no per-step state: callers pass the
robots' current velocities.

Lines per robot, in three tiers (see :func:`swarmpath.control.orca.lp.solve_orca_lp`):

- hard (velocity 0 always permitted): every static feature within reach, through its
  closest point, horizon ``obstacle_time_horizon`` (RVO2's obstacle lines, linearised); the
  rim of a circular workspace; each moving obstacle's current footprint, which stands still
  during the robots' move (phase 2), horizon ``dt``;
- firm: the end of the step keeps clear of the obstacle's next move (phase 1 of the next
  step: the predicted sweep, or the one-step reach disc when the model may turn), horizon
  ``dt``, allowed to demand a flight away;
- soft: ORCA's non-reciprocal lines for moving obstacles (responsibility 1, their
  predicted velocity, horizon ``time_horizon``) and the reciprocal lines of up to
  ``max_neighbours`` robots within ``neighbour_distance`` (responsibility 1/2).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.control.orca import kernels
from swarmpath.control.orca.halfplanes import (
    clearance_halfplanes,
    halfplane_below,
    orca_halfplanes_robots,
)
from swarmpath.control.orca.making_way import make_way
from swarmpath.control.orca.obstacles import (
    ObstacleForecast,
    RedrawGuard,
    footprint_offsets,
    teleports,
)
from swarmpath.control.orca.static_features import StaticFeatures, closest_on_segments
from swarmpath.errors import ConfigError
from swarmpath.world import geometry as g
from swarmpath.world.move_rules import NO_CONFLICT, move_conflicts
from swarmpath.world.shapes import Circle
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]

#: Fractions of the chosen move tried, in order, when the exact check rejects it.
SCALES = (1.0, 0.5, 0.25, 0.0)
#: Directions of the ring of escape moves tried exactly when the lines leave a robot exposed.
ESCAPE_DIRECTIONS = 32
#: Directions of the look-ahead moves that decide whether an end position is viable.
VIABLE_DIRECTIONS = 16
#: Slack of the exact checks beyond the simulator's own (world units).
CHECK_SLACK = 1e-7
#: Up to this many neighbours (self included) the C grid search finds them (it keeps them in
#: a sorted list, one insertion per candidate); beyond, cKDTree does.
MAX_GRID_NEIGHBOURS = 64


def tidy_moves(pos: FloatArray, p1: FloatArray, goals: FloatArray, step_len: FloatArray,
               snap: float = 1e-6) -> FloatArray:
    """End positions (n, 2) of moves pos -> p1 made exact: an end within ``snap`` of the goal
    is the goal (the simulator's arrival test is exact), a move shorter than 1e-12 is no move,
    and no move exceeds ``step_len`` (n,) (rounding of v * dt)."""
    found = kernels.tidy_moves(pos, p1, goals, step_len, snap)     # the C loop, or the numpy reference
    if found is not None:
        return found
    p1 = p1.copy()
    near_goal = np.linalg.norm(p1 - goals, axis=1) <= snap
    p1[near_goal] = goals[near_goal]
    step = np.linalg.norm(p1 - pos, axis=1)
    dust = step < 1e-12
    p1[dust] = pos[dust]
    too_far = step > step_len
    if too_far.any():
        p1[too_far] = pos[too_far] + (p1[too_far] - pos[too_far]) * (step_len[too_far] / step[too_far])[:, None]
    return p1


def _segment_point_distance(a: FloatArray, b: FloatArray, p: FloatArray) -> FloatArray:
    """Distance from points p to segments a-b (broadcast over leading axes, last axis 2)."""
    ab = b - a
    ap = p - a
    denom = (ab * ab).sum(-1)
    t = np.clip((ap * ab).sum(-1) / np.where(denom > 0, denom, 1.0), 0.0, 1.0)
    q = ap - t[..., None] * ab
    return np.sqrt((q * q).sum(-1))


@dataclass(frozen=True)
class ORCAParams:
    """ORCA's hyperparameters (RVO2's names in brackets).

    time_horizon : tau of robot-robot and moving-obstacle lines [timeHorizon], time units
    obstacle_time_horizon : tau of static lines [timeHorizonObst]; at least one step is used
    neighbour_distance : robots farther apart than this are ignored [neighborDist], world units
    max_neighbours : at most this many nearest robots give lines [maxNeighbors]
    safety_margin : added to every combined radius and static clearance (world units); near
        a goal closer to a wall than this, that robot's static margin shrinks to half the gap
    obstacle_margin : extra room asked of moving obstacles in the (soft) ORCA lines only, so
        that a robot keeps space to escape in (world units)
    """

    time_horizon: float = 4.0
    obstacle_time_horizon: float = 2.0
    neighbour_distance: float = 8.0
    max_neighbours: int = 10
    safety_margin: float = 0.02
    obstacle_margin: float = 0.0

    def __post_init__(self) -> None:
        for name in ("time_horizon", "obstacle_time_horizon", "neighbour_distance"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"{name} must be > 0, got {getattr(self, name)}")
        if self.max_neighbours < 0:
            raise ConfigError(f"max_neighbours must be >= 0, got {self.max_neighbours}")
        if not self.safety_margin >= 0:
            raise ConfigError(f"safety_margin must be >= 0, got {self.safety_margin}")
        if not self.obstacle_margin >= 0:
            raise ConfigError(f"obstacle_margin must be >= 0, got {self.obstacle_margin}")


@dataclass(frozen=True)
class SafeMoves:
    """Result of :meth:`ORCASolver.make_safe`: end positions (n, 2), the fraction of the
    proposed move kept (n,), and robots whose end position could not be kept out of a moving
    obstacle's next move (n,) (cornered)."""

    positions: FloatArray
    scale: FloatArray
    exposed: BoolArray


class ORCASolver:
    """ORCA for all robots of a world (built by :meth:`reset`, used every step)."""

    def __init__(self, params: ORCAParams | None = None):
        self.params = params or ORCAParams()
        self._rows_cache: IntArray | None = None

    def reset(self, world: World) -> None:
        """Precompute the world's static features, radii, speeds and margins."""
        p = self.params
        self.world = world
        self.dt = float(world.dt)
        self.features = StaticFeatures(world)
        self.radii = world.radii
        self.speeds = world.max_speeds
        self.step_len = self.speeds * self.dt
        self.tau = float(p.time_horizon)
        self.tau_static = max(float(p.obstacle_time_horizon), self.dt)
        self.goals = world.goals
        n = world.n_robots
        # a static margin a robot can live with at its goal
        if n:
            room = world.static_clearance(world.goals, self.radii)
            self.static_margin = np.clip(0.5 * room, 0.0, p.safety_margin)
        else:
            self.static_margin = np.zeros(0)
        self.points = self.radii == 0
        self.resolution = float(world.resolution)
        self.redraw = RedrawGuard(world) if any(teleports(o) for o in world.moving_obstacles) else None
        self.has_static = bool(len(world.obstacles) or world.static_map is not None)
        shapes = [o.shape for o in world.moving_obstacles]
        self.obstacle_is_circle = np.array([isinstance(sh, Circle) for sh in shapes], bool)
        self.obstacle_radius = np.array([sh.radius if isinstance(sh, Circle) else 0.0 for sh in shapes], float)
        self.obstacle_lo = np.array([(0.0, 0.0) if isinstance(sh, Circle) else sh.min for sh in shapes],
                                    float).reshape(-1, 2)
        self.obstacle_hi = np.array([(0.0, 0.0) if isinstance(sh, Circle) else sh.max for sh in shapes],
                                    float).reshape(-1, 2)

    # ------------------------------------------------------------------ contact distances
    def combined_radius(self, i: IntArray, j: IntArray) -> FloatArray:
        """Distance robots i and j keep (plus the margin): the sum of radii, or a cell
        diagonal for two point robots (then they can never share or swap grid cells)."""
        rsum = self.radii[i] + self.radii[j]
        both = self.points[i] & self.points[j]
        return np.where(both, np.sqrt(2.0) * self.resolution, rsum) + self.params.safety_margin

    # ------------------------------------------------------------------ lines
    def lines(self, pos: FloatArray, vel: FloatArray, forecast: ObstacleForecast | None,
              fixed: BoolArray | None = None) -> tuple[FloatArray, IntArray, IntArray, IntArray]:
        """Every robot's lines, packed (see :func:`kernels.pack_lines`). A neighbour that is
        ``fixed`` (n,) (it will not move) leaves the whole avoidance to the other robot."""
        n = len(pos)
        p = self.params
        owners, pts, dirs, tiers = [], [], [], []

        def add(owner, lp, ld, tier):
            if len(owner):
                owners.append(np.asarray(owner, np.int64))
                pts.append(lp)
                dirs.append(ld)
                tiers.append(np.full(len(owner), tier, np.int64))

        clearance = self.radii + self.static_margin
        # hard: static features and the workspace
        reach = clearance + self.speeds * self.tau_static + 1e-9
        # a robot near its goal looks one step ahead only: with a longer horizon a goal close
        # to a wall is approached by ever shorter steps and never reached
        tau = np.where(np.linalg.norm(pos - self.goals, axis=1) <= self.speeds * self.tau_static, self.dt,
                       self.tau_static) if n else np.zeros(0)
        owner, offset = self.features.closest(pos, reach)
        if len(owner):
            add(owner, *clearance_halfplanes(offset, clearance[owner], tau[owner], floor=0.0), 0)
        owner, normal, room = self.features.bound_lines(pos, clearance, self.step_len, reach - clearance)
        if len(owner):
            add(owner, *halfplane_below(normal, np.maximum(room, 0.0) / tau[owner]), 0)
        # moving obstacles: hard (this step's footprint), firm (next move), soft (ORCA)
        if forecast is not None and len(forecast.now):
            self._obstacle_lines(pos, vel, forecast, add)
        # robots: reciprocal ORCA lines of the nearest neighbours
        if n > 1 and p.max_neighbours > 0:
            i, j = self.neighbours(pos)
            if len(i):
                # the C loop, or its numpy reference (the same bits)
                resp = np.full(n, 0.5) if fixed is None else np.where(fixed, 1.0, 0.5)
                found = kernels.robot_halfplanes(pos, vel, self.radii, resp, i, j, np.sqrt(2.0) * self.resolution,
                                                 p.safety_margin, self.tau, self.dt)
                if found is None:
                    c = 0.5 if fixed is None else np.where(fixed[j], 1.0, 0.5)
                    found = orca_halfplanes_robots(pos[j] - pos[i], vel[i] - vel[j], vel[i],
                                                   self.combined_radius(i, j), self.tau, self.dt, c)
                add(i, *found, 2)
        if owners:
            def joined(parts):
                return parts[0] if len(parts) == 1 else np.concatenate(parts)

            return kernels.pack_lines(joined(owners), joined(pts), joined(dirs), joined(tiers), n)
        return kernels.pack_lines(np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros((0, 2)),
                                  np.zeros(0, np.int64), n)

    def _obstacle_lines(self, pos, vel, fc: ObstacleForecast, add) -> None:
        p = self.params
        r = self.radii + p.safety_margin
        dist = np.linalg.norm(pos[:, None, :] - fc.now[None], axis=-1)               # (n, m)
        grown = fc.extent[None] + fc.reach[None] + np.linalg.norm(fc.next - fc.now, axis=1)[None]
        near = dist <= r[:, None] + grown + 2 * self.step_len[:, None] + 1e-9
        i, j = np.nonzero(near)
        if len(i):
            # hard: the footprint standing at `now` during this move
            off = footprint_offsets(self.world, fc.now, pos, i, j)
            add(i, *clearance_halfplanes(off, r[i], self.dt, floor=0.0), 0)
            # firm: the end disc clear of the next move (jumping obstacles: see RedrawGuard)
            keep = ~fc.jumping[j]
            ii, jj = i[keep], j[keep]
            q = closest_on_segments(pos[ii], fc.now[jj], fc.next[jj])
            add(ii, *clearance_halfplanes(q - pos[ii], r[ii] + fc.extent[jj] + fc.reach[jj], self.dt, floor=None), 1)
        # soft: ORCA with full responsibility, for obstacles within the neighbour distance
        seen = (dist <= p.neighbour_distance + fc.extent[None]) & ~fc.jumping[None]
        i, j = np.nonzero(seen)
        if len(i):
            lp_, ld_ = orca_halfplanes_robots(fc.now[j] - pos[i], vel[i] - fc.velocity[j], vel[i],
                                              r[i] + fc.extent[j] + fc.reach[j] + p.obstacle_margin, self.tau,
                                              self.dt, 1.0)
            add(i, lp_, ld_, 2)

    def neighbours(self, pos: FloatArray) -> tuple[IntArray, IntArray]:
        """(i, j) pairs: for each robot i its up to ``max_neighbours`` nearest robots j within
        ``neighbour_distance``, nearest first, exactly as scipy's cKDTree finds them: the C
        grid search (:func:`kernels.nearest`) where distances are distinct, cKDTree for the
        robots with tied distances (whose order is its tree's) and as the reference."""
        p = self.params
        n = len(pos)
        k = min(p.max_neighbours + 1, n)
        found = kernels.nearest(pos, k, p.neighbour_distance) if k <= MAX_GRID_NEIGHBOURS else None
        if found is not None:
            idx, tied = found
            if tied.any():
                rows = np.flatnonzero(tied)
                dist, ix = cKDTree(pos).query(pos[rows], k=k, distance_upper_bound=p.neighbour_distance)
                dist = dist.reshape(len(rows), k)
                ix = ix.reshape(len(rows), k)
                idx[rows] = np.where(np.isfinite(dist) & (ix < n), ix, -1)
            ii = self._rows(n, k)
            ok = (idx >= 0) & (idx != ii)
            return ii[ok], idx[ok]
        dist, idx = cKDTree(pos).query(pos, k=k, distance_upper_bound=p.neighbour_distance)
        dist = dist.reshape(len(pos), k)
        idx = idx.reshape(len(pos), k)
        ii = np.repeat(np.arange(len(pos)), k).reshape(len(pos), k)
        ok = np.isfinite(dist) & (idx != ii) & (idx < len(pos))
        return ii[ok].astype(np.int64), idx[ok].astype(np.int64)

    def _rows(self, n: int, k: int) -> IntArray:
        """The (n, k) array of row indices (robot i in row i), kept between steps."""
        rows = self._rows_cache
        if rows is None or rows.shape != (n, k):
            rows = np.repeat(np.arange(n, dtype=np.int64), k).reshape(n, k)
            self._rows_cache = rows
        return rows

    # ------------------------------------------------------------------ velocities
    def velocities(self, pos: FloatArray, vel: FloatArray, preferred: FloatArray,
                   forecast: ObstacleForecast | None, fixed: BoolArray | None = None) -> tuple[FloatArray, IntArray]:
        """New velocities (n, 2) and LP statuses (n,) (0 all lines held, 1 robot lines
        relaxed, 2 obstacle lines relaxed, 3 none possible); ``fixed`` robots (n,) get 0."""
        lines, n_lines, n_hard, n_firm = self.lines(pos, vel, forecast, fixed)
        v, status = kernels.solve_lines(lines, n_lines, n_hard, n_firm, preferred, self.speeds)
        if fixed is not None:
            v[fixed] = 0.0
        return v, status

    # ------------------------------------------------------------------ exact checks
    def static_unsafe(self, a: FloatArray, b: FloatArray, rows: IntArray) -> BoolArray:
        """Moves a -> b of robots ``rows`` that enter static geometry or leave the workspace
        (the simulator's test, with a hair of slack for discs: a point robot may stand on the
        workspace's edge, where any slack would forbid every move)."""
        moved = np.any(a != b, axis=1)
        out = np.zeros(len(rows), bool)
        if moved.any():
            k = np.flatnonzero(moved)
            r = self.radii[rows[k]]
            out[k] = self.world.static_hits(a[k], b[k], r + CHECK_SLACK * (r > 0))
        return out

    def obstacle_unsafe(self, a: FloatArray, b: FloatArray, rows: IntArray, fc: ObstacleForecast | None
                        ) -> tuple[BoolArray, BoolArray]:
        """(hard, soft) per move: hard = the swept disc enters a footprint standing at
        ``now`` (phase 2); soft = the end disc lies where an obstacle's next move may reach
        (phase 1 of the next step; redraw jumps are tested by :meth:`redraw_unsafe`)."""
        hard, soft, _ = self._obstacle_check(a, b, rows, fc)
        return hard, soft

    def _obstacle_check(self, a: FloatArray, b: FloatArray, rows: IntArray, fc: ObstacleForecast | None
                        ) -> tuple[BoolArray, BoolArray, FloatArray]:
        """:meth:`obstacle_unsafe` plus the depth (world units) by which each end disc enters
        the worst next move (<= 0: clear)."""
        k = len(rows)
        if fc is None or not len(fc.now) or k == 0:
            return np.zeros(k, bool), np.zeros(k, bool), np.full(k, -np.inf)
        r = (self.radii[rows] + CHECK_SLACK)[:, None]                               # (k, 1)
        A, B = a[:, None, :], b[:, None, :]
        o = fc.now[None]                                                             # (1, m, 2)
        # phase 2 (hard): discs as points grown by their radius, boxes exactly; a robot the
        # obstacle already reached (phase 1) may move, but not deeper in
        gap = np.full((k, len(fc.now)), np.inf)
        now = np.full((k, len(fc.now)), np.inf)
        c = self.obstacle_is_circle
        if c.any():
            gap[:, c] = _segment_point_distance(A, B, o[:, c]) - self.obstacle_radius[c]
            now[:, c] = np.sqrt(((A - o[:, c]) ** 2).sum(-1)) - self.obstacle_radius[c]
        if (~c).any():
            lo = o[:, ~c] + self.obstacle_lo[~c]
            hi = o[:, ~c] + self.obstacle_hi[~c]
            gap[:, ~c] = g.segment_box_distance(A, B, lo, hi)
            now[:, ~c] = g.point_box_distance(A, lo, hi)
        hard = np.any(gap < np.minimum(r, now - CHECK_SLACK), axis=1)
        # next move (soft): the end disc clear of the sweep now -> next grown by the reach
        d = _segment_point_distance(fc.now[None], fc.next[None], b[:, None, :])     # (k, m)
        need = fc.extent + fc.reach + r
        over = np.where(fc.jumping[None], -np.inf, need - d)
        depth = over.max(axis=1)
        return hard, depth > 0, depth

    def make_safe(self, p0: FloatArray, p1: FloatArray, forecast: ObstacleForecast | None,
                  fixed: BoolArray | None = None) -> SafeMoves:
        """The largest fraction in :data:`SCALES` of each move p0 -> p1 that passes the exact
        checks: static geometry and moving footprints always (a shorter piece of a safe move
        is safe, and standing still is), the next move of moving obstacles when some
        fraction can, then every pair of robots by the simulator's move rules
        (:func:`swarmpath.world.move_rules.move_conflicts`): both robots of a conflicting
        pair step down a fraction until no pair conflicts (at worst both stand, and two
        standing robots never conflict). Every loop is bounded by the number of fractions.
        ``fixed`` robots (n,) stand still and are never moved to make way."""
        if fixed is not None:
            p1 = np.where(np.asarray(fixed, bool)[:, None], p0, p1)
        n = len(p0)
        scales = np.asarray(SCALES)
        last = len(scales) - 1
        d = p1 - p0
        first_ok = np.full(n, -1)              # first fraction passing every check
        first_hard = np.full(n, last)          # first fraction passing the hard checks
        # the whole moves first, then every shorter fraction of the robots that failed, at once
        todo = np.arange(n)
        for levels in ([0], list(range(1, last + 1))):
            if not len(todo):
                break
            if levels == [0]:       # the whole moves: their ends are p1 itself
                rows = todo
                a, b = p0[rows], p1[rows]
            else:
                rows = np.tile(todo, len(levels))
                lv = np.repeat(np.asarray(levels), len(todo))
                a = p0[rows]
                b = np.where((lv == 0)[:, None], p1[rows], a + scales[lv][:, None] * d[rows])
            hard = self.static_unsafe(a, b, rows)
            ob_hard, soft = self.obstacle_unsafe(a, b, rows, forecast)
            hard |= ob_hard
            if self.redraw is not None:
                soft |= self.redraw.danger(b, self.radii[rows] + CHECK_SLACK)
            hard = hard.reshape(len(levels), len(todo))
            good = ~hard & ~soft.reshape(len(levels), len(todo))
            for k, level in enumerate(levels):
                newly = ~hard[k] & (first_hard[todo] == last)
                first_hard[todo[newly]] = level
                ok = good[k] & (first_ok[todo] < 0)
                first_ok[todo[ok]] = level
            todo = todo[first_ok[todo] < 0]
        level = np.where(first_ok >= 0, first_ok, first_hard)
        exposed = first_ok < 0
        if forecast is not None and len(forecast.now):
            # robots near obstacles whose chosen end leaves no clear move for the step after
            # next (not viable) look for a better end too
            near = np.flatnonzero(~exposed & self.threatened(p0, forecast))
            if len(near):
                ends = p0[near] + scales[level[near]][:, None] * d[near]
                stuck = near[~self._viable(ends, near, forecast)]
                exposed_or_stuck = exposed.copy()
                exposed_or_stuck[stuck] = True
            else:
                exposed_or_stuck = exposed
        else:
            exposed_or_stuck = exposed
        held = np.zeros(n, bool)
        if forecast is not None and len(forecast.now):
            # robots held still only by the obstacles' next moves (a moving fraction passes the
            # hard checks; e.g. a slow robot between the cells a redraw obstacle may take)
            # look for a sideways move that keeps clear and gets closer to a full step in the
            # direction of their proposal
            held = (first_ok == last) & (first_hard < last) & np.any(d != 0, axis=1)
            exposed_or_stuck = exposed_or_stuck | held
        if fixed is not None:
            exposed_or_stuck = exposed_or_stuck & ~fixed
        if exposed_or_stuck.any() and forecast is not None:
            # the linearised lines can miss an escape: try a ring of moves exactly
            rows = np.flatnonzero(exposed_or_stuck)
            aim = p1.copy()
            if held.any():
                length = np.maximum(np.linalg.norm(d[held], axis=1), 1e-300)
                aim[held] = p0[held] + d[held] * (self.step_len[held] / length)[:, None]
            ends, clear = self._escape(p0, p1, rows, forecast, aim)
            p1 = p1.copy()
            p1[rows] = ends
            d = p1 - p0
            level[rows] = 0
            exposed[rows] = ~clear
        level = self._robot_pairs(p0, d, level, self.threatened(p0, forecast))
        s = scales[level]
        out = p0 + s[:, None] * d
        full = level == 0
        out[full] = p1[full]
        if forecast is not None and len(forecast.now) and len(p0) > 1:
            # a robot that a neighbour's move cut short may now stand in an obstacle's next
            # move: it looks again for a clear move, moving neighbours out of its way if need
            # be (making_way.py)
            soft = self._soft_unsafe(p0, out, np.arange(len(p0)), forecast)
            rows = np.flatnonzero(soft & ~exposed & (True if fixed is None else ~fixed))
            if len(rows):
                out, freed, pushed = make_way(self, p0, p1, out, rows, forecast, fixed=fixed)
                s = s.copy()
                s[rows[freed]] = 1.0
                s[pushed] = 0.0
                exposed = exposed.copy()
                exposed[rows[~freed]] = True
        return SafeMoves(out, s, exposed)

    def _soft_unsafe(self, a: FloatArray, b: FloatArray, rows: IntArray, fc: ObstacleForecast) -> BoolArray:
        """Moves a -> b of robots ``rows`` whose end lies in an obstacle's next move (a redraw
        jump included)."""
        _, soft = self.obstacle_unsafe(a, b, rows, fc)
        if self.redraw is not None:
            soft = soft | self.redraw.danger(b, self.radii[rows] + CHECK_SLACK)
        return soft

    def _escape(self, p0: FloatArray, p1: FloatArray, rows: IntArray, fc: ObstacleForecast,
                aim: FloatArray | None = None) -> tuple[FloatArray, BoolArray]:
        """For robots ``rows`` that no fraction of their move keeps clear of the obstacles'
        next moves: among ``ESCAPE_DIRECTIONS`` directions at full and half step, the grid
        cell centres within a step, standing still and the move itself, the end position that
        passes every check and lies closest
        to the proposed one (or to ``aim`` (n, 2) where given), else the one (passing the hard
        checks) that enters the next moves least. Returns the end positions (k, 2) and which
        of them are clear (k,)."""
        aim = p1 if aim is None else aim
        k = len(rows)
        ang = 2 * np.pi * np.arange(ESCAPE_DIRECTIONS) / ESCAPE_DIRECTIONS
        ring = np.stack([np.cos(ang), np.sin(ang)], axis=1)
        frac = np.array([1.0, 0.5])
        offsets = (frac[:, None, None] * ring[None]).reshape(-1, 2)                     # (c, 2)
        step = self.step_len[rows]
        cand = p0[rows][:, None, :] + offsets[None] * step[:, None, None]               # (k, c, 2)
        cand = np.concatenate([p1[rows][:, None, :], p0[rows][:, None, :], cand, self._cell_centres(p0[rows], step)],
                              axis=1)
        c = cand.shape[1]
        flat_rows = np.repeat(rows, c)
        a = np.repeat(p0[rows], c, axis=0)
        b = cand.reshape(-1, 2)
        hard = self.static_unsafe(a, b, flat_rows)
        ob_hard, soft, depth = self._obstacle_check(a, b, flat_rows, fc)
        hard |= ob_hard
        if self.redraw is not None:
            jump = self.redraw.danger(b, self.radii[flat_rows] + CHECK_SLACK)
            soft |= jump
            depth = np.where(jump, np.maximum(depth, 0.0), depth)
        hard = hard.reshape(k, c)
        clear = ~hard & ~soft.reshape(k, c)
        depth = depth.reshape(k, c)
        dist = np.linalg.norm(cand - aim[rows][:, None, :], axis=2)
        viable = np.zeros((k, c), bool)
        if fc.next2 is not None and clear.any():
            kk, cc = np.nonzero(clear)
            viable[kk, cc] = self._viable(cand[kk, cc], rows[kk], fc)
        score = np.where(clear, dist + np.where(viable, 0.0, 1e3), np.where(hard, np.inf, 1e6 + depth))
        best = np.argmin(score, axis=1)
        pick = np.arange(k)
        ends = cand[pick, best]
        ok = clear[pick, best]
        # nothing passes even the hard checks (cannot happen: standing is hard-safe unless
        # already overlapped): keep the original move
        none = ~np.isfinite(score[pick, best])
        ends[none] = p1[rows][none]
        return ends, ok

    def _cell_centres(self, pos: FloatArray, step: FloatArray) -> FloatArray:
        """The centres of the grid cells around each position (k, 2), (k, c, 2), those out of
        one step's reach replaced by the position itself: where a redraw obstacle cannot land
        beside a robot, the spots a ring of directions may miss."""
        res = self.resolution
        span = int(np.ceil(float(step.max(initial=0.0)) / res)) if len(step) else 0
        off = np.arange(-span, span + 1)
        ox, oy = np.meshgrid(off, off, indexing="xy")
        cells = np.floor(pos / res)[:, None, :] + np.stack([ox.ravel(), oy.ravel()], axis=1)[None]
        centres = (cells + 0.5) * res
        far = np.linalg.norm(centres - pos[:, None, :], axis=2) > step[:, None]
        return np.where(far[..., None], pos[:, None, :], centres)

    def _viable(self, ends: FloatArray, rows: IntArray, fc: ObstacleForecast) -> BoolArray:
        """Whether from each end position (k, 2) of robots ``rows`` some move of the step
        after next (a ring of ``VIABLE_DIRECTIONS`` full steps, or standing) keeps the end
        disc clear of every obstacle's move after next and stays inside the free space (its
        end disc; a heuristic look-ahead, the exact checks are made when that step comes)."""
        if fc.next2 is None or not len(ends):
            return np.ones(len(ends), bool)
        ang = 2 * np.pi * np.arange(VIABLE_DIRECTIONS) / VIABLE_DIRECTIONS
        ring = np.concatenate([np.zeros((1, 2)), np.stack([np.cos(ang), np.sin(ang)], axis=1)])
        moves = ends[:, None, :] + ring[None] * self.step_len[rows][:, None, None]            # (k, q, 2)
        k, q, _ = moves.shape
        r = self.radii[rows][:, None, None]
        keep = ~fc.jumping
        d = _segment_point_distance(fc.next[keep][None, None], fc.next2[keep][None, None], moves[:, :, None, :])
        need = fc.extent[keep] + fc.reach2[keep] + r                                             # (k, 1, m')
        clear = np.all(d >= need, axis=2) if keep.any() else np.ones((k, q), bool)
        inside = self.world.static_clearance(moves.reshape(-1, 2), np.repeat(self.radii[rows], q)) >= 0
        return np.any(clear & inside.reshape(k, q), axis=1)

    def threatened(self, pos: FloatArray, fc: ObstacleForecast | None) -> BoolArray:
        """Robots within two steps' travel of a moving obstacle's next move (n,)."""
        if fc is None or not len(fc.now):
            return np.zeros(len(pos), bool)
        d = _segment_point_distance(fc.now[None], fc.next[None], pos[:, None, :])          # (n, m)
        reach = self.radii[:, None] + fc.extent + fc.reach + 2 * self.step_len[:, None]
        return np.any(d < reach, axis=1)

    def _robot_pairs(self, p0: FloatArray, d: FloatArray, level: IntArray, threatened: BoolArray) -> IntArray:
        """Lower the fractions of robots in conflicting pairs until no pair conflicts: in
        each conflicting pair the robot of lower priority steps down (priority: threatened
        by a moving obstacle first, then the smaller index), the other only when the first
        cannot (it already stands). Only pairs with a robot changed in the last round are
        tested again."""
        n = len(p0)
        if n < 2:
            return level
        scales = np.asarray(SCALES)
        last = len(scales) - 1
        # two robots whose starts lie farther apart than twice the longest move plus this
        # cannot conflict
        extra = 2 * float(self.radii.max(initial=0.0)) + 1e-6 + (2 * self.resolution if self.points.any() else 0.0)
        # the C loop (it finds the pairs within that reach on a grid), or the numpy reference
        found = kernels.robot_pairs(p0, d, self.radii + CHECK_SLACK * (self.radii > 0), threatened, level, scales,
                                    self.resolution, extra)
        if found is not None:
            return found
        reach = 2 * float(np.linalg.norm(d, axis=1).max(initial=0.0)) + 2 * float(self.radii.max(initial=0.0)) \
            + 1e-6 + (2 * self.resolution if self.points.any() else 0.0)
        pairs = cKDTree(p0).query_pairs(reach, output_type="ndarray")
        if not len(pairs):
            return level
        i, j = pairs[:, 0], pairs[:, 1]
        ri = self.radii[i] + CHECK_SLACK * (self.radii[i] > 0)
        rj = self.radii[j] + CHECK_SLACK * (self.radii[j] > 0)
        moving = np.any(d != 0, axis=1)
        level = level.copy()
        bad = np.zeros(len(i), bool)
        test = np.arange(len(i))
        for _ in range(last * n + 1):       # every round lowers some robot's fraction
            a, b = i[test], j[test]
            a1 = p0[a] + scales[level[a]][:, None] * d[a]
            b1 = p0[b] + scales[level[b]][:, None] * d[b]
            bad[test] = move_conflicts(p0[a], a1, p0[b], b1, ri[test], rj[test], self.resolution) != NO_CONFLICT
            if not bad.any():
                break
            can = (level < last) & moving
            bi, bj = i[bad], j[bad]
            # j has the lower priority unless i is the unthreatened one of a mixed pair
            j_first = threatened[bi] | ~threatened[bj]
            lose = np.where(j_first, bj, bi)
            keep = np.where(j_first, bi, bj)
            lose = np.where(can[lose], lose, keep)
            lower = np.zeros(n, bool)
            lower[lose] = True
            lower &= can
            if not lower.any():
                break
            level[lower] += 1
            test = np.flatnonzero(lower[i] | lower[j])
        return level
