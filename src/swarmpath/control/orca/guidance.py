"""Where each robot wants to go next: the preferred velocity of continuous controllers.

:class:`Guidance` steers every robot at a point it can reach in a straight line:

1. its goal, when the straight move to it is free of static geometry (exact swept-disc test,
   :meth:`~swarmpath.world.World.static_hits`);
2. else the farthest visible vertex of its offline plan (``plan.paths[i]``, a polyline in
   world units) among the next few ahead of the last one reached;
3. else (no plan, or the plan's next vertex is out of sight: pushed off the path) the cell
   centre that minimises "distance field of the goal + w * straight distance to it"
   (w = ``straight_weight`` < 1, so that the farthest of the cells along a shortest path
   wins) among the visible cells of a window around the robot: the field (:func:`swarmpath.search.
   distance_field`, exact octile distances on the world's grid inflated for the robot's
   radius) knows the way round walls, doors and maze corridors, the straight part lets the
   robot cut across open space;
4. else the free neighbouring cell of lowest field value (no visibility promised; the
   static half-planes of ORCA keep the robot safe regardless).

Visibility is tested for the robot's radius plus ``clearance`` (less when the goal itself is
closer than that to an obstacle or the workspace's edge). Robots whose goal cell is
blocked in the inflated grid use the grid without inflation. All loops are bounded by the
window size; results depend only on the inputs (deterministic).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.search import distance_field
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


class Guidance:
    """Preferred velocities toward the goals along plans or distance fields.

    Parameters
    ----------
    window : half-width (cells) of the window searched for a visible cell (3 = 7 x 7 cells)
    lookahead : plan vertices tested for visibility beyond the last one reached
    clearance : extra radius (world units) for the visibility tests
    batch : candidate cells tested for visibility per robot and round
    straight_weight : weight (0, 1) of the straight distance to a window cell in its cost
    """

    def __init__(self, *, window: int = 3, lookahead: int = 4, clearance: float = 0.02, batch: int = 25,
                 straight_weight: float = 0.5):
        if window < 1 or lookahead < 1 or batch < 1:
            raise ConfigError(f"guidance: window, lookahead and batch must be >= 1, got {window}, {lookahead}, {batch}")
        if not clearance >= 0:
            raise ConfigError(f"guidance: clearance must be >= 0, got {clearance}")
        self.window = window
        self.lookahead = lookahead
        self.clearance = clearance
        self.batch = batch
        if not 0 < straight_weight < 1:
            raise ConfigError(f"guidance: straight_weight must be in (0, 1), got {straight_weight}")
        self.straight_weight = straight_weight

    # ------------------------------------------------------------------ run state
    def reset(self, world: World, plan: Plan | None = None) -> None:
        """Prepare a run of ``world`` with the offline ``plan`` (or None)."""
        self.world_ = world
        n = world.n_robots
        self.goals_ = world.goals
        self.radii_ = world.radii
        # the radius of the visibility tests: the robot's plus the clearance, but never more
        # than its goal leaves (a goal on the workspace's edge must be visible)
        room = world.static_clearance(world.goals, world.radii) if n else np.zeros(0)
        self.seen_radius_ = self.radii_ + np.clip(room, 0.0, self.clearance)
        self.paths_: list[FloatArray | None] = [None] * n
        if plan is not None:
            for i, path in enumerate(list(plan.paths)[:n]):
                if path is not None and len(path) and np.linalg.norm(np.asarray(path[-1]) - self.goals_[i]) < 1e-6:
                    self.paths_[i] = np.asarray(path, float).reshape(-1, 2)
        self.vertex_ = np.zeros(n, np.int64)          # index of the next plan vertex
        self.open_ = not (len(world.obstacles) or world.static_map is not None)
        self.fields_: dict = {}                        # (radius key, goal cell) -> (grid, field)

    # ------------------------------------------------------------------ fields
    def _field(self, i: int):
        """(grid, field) for robot i's goal; None when no grid cell can hold the goal."""
        r = float(self.radii_[i])
        for radius in (r, 0.0):
            grid = self.world_.grid(radius=radius)
            cell = grid.cell_of(self.goals_[i])
            key = (id(grid), int(cell[0]), int(cell[1]))
            if key in self.fields_:
                return self.fields_[key]
            if grid.is_free(cell):
                out = (grid, distance_field(grid, cell))
                self.fields_[key] = out
                return out
        return None

    def remaining(self, positions: FloatArray) -> FloatArray:
        """An estimate of each robot's remaining path length (world units): the distance
        field at its cell plus the distance to that cell's centre, less the goal's own distance
        to its cell's centre, and never less than the straight distance (so it is 0 exactly at
        the goal); the straight distance in open worlds. Used to detect lack of progress."""
        pos = np.asarray(positions, float)
        straight = np.linalg.norm(pos - self.goals_, axis=1)
        if self.open_:
            return straight
        out = straight.copy()
        for i in range(len(pos)):
            f = self._field(i)
            if f is None:
                continue
            grid, field = f
            c = grid.cell_of(pos[i])
            if grid.contains_cells(c) and np.isfinite(field[c[1], c[0]]):
                offset = float(np.linalg.norm(grid.centers(grid.cell_of(self.goals_[i])) - self.goals_[i]))
                along = field[c[1], c[0]] * grid.resolution + float(np.linalg.norm(grid.centers(c) - pos[i])) - offset
                out[i] = max(float(straight[i]), along)
        return out

    # ------------------------------------------------------------------ targets
    def targets(self, positions: FloatArray) -> tuple[FloatArray, BoolArray]:
        """Each robot's steering point (n, 2) and whether that point is its goal (n,)."""
        pos = np.asarray(positions, float)
        n = len(pos)
        goal = self.goals_
        if n == 0:
            return np.zeros((0, 2)), np.zeros(0, bool)
        if self.open_:
            return goal.copy(), np.ones(n, bool)
        r = self.seen_radius_
        at_goal = np.linalg.norm(pos - goal, axis=1) <= 1e-9
        direct = at_goal.copy()
        rest = np.flatnonzero(~at_goal)
        if len(rest):
            direct[rest] = ~self.world_.static_hits(pos[rest], goal[rest], r[rest])
        target = goal.copy()
        need = np.flatnonzero(~direct)
        if len(need):
            need = self._plan_targets(pos, need, target, r)
        if len(need):
            target[need] = self._field_targets(pos, need, r)
        return target, direct

    def _plan_targets(self, pos: FloatArray, rows: NDArray[np.int64], target: FloatArray, r: FloatArray
                      ) -> NDArray[np.int64]:
        """Set targets from plans where a plan vertex is visible; returns the rows left."""
        left = []
        for i in rows:
            path = self.paths_[i]
            if path is None:
                left.append(i)
                continue
            k0 = int(self.vertex_[i])
            ks = np.arange(k0, min(len(path), k0 + self.lookahead + 1))
            seen = ~self.world_.static_hits(np.repeat(pos[i][None], len(ks), 0), path[ks], np.full(len(ks), r[i]))
            if not seen.any():
                left.append(i)
                continue
            k = int(ks[np.flatnonzero(seen)[-1]])
            self.vertex_[i] = k
            target[i] = path[k]
        return np.asarray(left, np.int64)

    def _candidates(self, p: FloatArray, i: int) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Robot i's window cells with a finite field value: centres (k, 2) in the order of
        preference, their field values (k,), and the lowest-valued neighbouring cell's
        centre as the fallback (or the goal when there is none)."""
        f = self._field(i)
        if f is None:
            return np.zeros((0, 2)), np.zeros(0), self.goals_[i].copy()
        grid, field = f
        h, w = field.shape
        c = grid.cell_of(p)
        off = np.arange(-self.window, self.window + 1)
        ox, oy = np.meshgrid(off, off, indexing="xy")
        cx = (c[0] + ox).ravel()
        cy = (c[1] + oy).ravel()
        inside = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
        cx, cy = cx[inside], cy[inside]
        val = field[cy, cx]
        finite = np.isfinite(val)
        cx, cy, val = cx[finite], cy[finite], val[finite]
        if not len(cx):
            return np.zeros((0, 2)), np.zeros(0), self.goals_[i].copy()
        centre = grid.centers(np.stack([cx, cy], axis=1))
        # cost-to-go through the cell, with the straight part discounted so that among
        # cells on a shortest path the farthest visible one wins (full weight ties them all)
        cost = val * grid.resolution + self.straight_weight * np.linalg.norm(centre - p, axis=1)
        order = np.lexsort((cy, cx, val, cost))
        near = np.max(np.abs(np.stack([cx - c[0], cy - c[1]], axis=1)), axis=1) <= 1
        fallback = centre[np.flatnonzero(near)[np.argmin(val[near])]] if near.any() else centre[order[0]]
        return centre[order], val[order], fallback

    def _field_targets(self, pos: FloatArray, rows: NDArray[np.int64], r: FloatArray) -> FloatArray:
        """Steering points of robots ``rows`` from their goals' distance fields: the best
        visible window cell, tested ``batch`` candidates per robot and round for all robots
        at once; the fallback cell when none is visible."""
        cands = [self._candidates(pos[i], int(i)) for i in rows]
        out = np.array([c[2] for c in cands], float).reshape(-1, 2)
        pending = [k for k, c in enumerate(cands) if len(c[0])]
        start = 0
        while pending:
            seg_a, seg_b, seg_r, owner = [], [], [], []
            for k in pending:
                pts = cands[k][0][start:start + self.batch]
                seg_a.append(np.repeat(pos[rows[k]][None], len(pts), 0))
                seg_b.append(pts)
                seg_r.append(np.full(len(pts), r[rows[k]]))
                owner.append(np.full(len(pts), k))
            own = np.concatenate(owner)
            seen = ~self.world_.static_hits(np.concatenate(seg_a), np.concatenate(seg_b), np.concatenate(seg_r))
            pts = np.concatenate(seg_b)
            still = []
            for k in pending:
                hit = np.flatnonzero(seen & (own == k))
                if len(hit):
                    out[k] = pts[hit[0]]
                elif start + self.batch < len(cands[k][0]):
                    still.append(k)
            pending = still
            start += self.batch
        return out

    # ------------------------------------------------------------------ velocities
    def preferred_velocities(self, positions: FloatArray, speeds: FloatArray, dt: float) -> FloatArray:
        """Preferred velocities (n, 2): full speed toward each robot's steering point, slowing
        only to land exactly on the goal in the last step."""
        pos = np.asarray(positions, float)
        target, is_goal = self.targets(pos)
        return velocity_toward(pos, target, speeds, dt, is_goal)


def velocity_toward(pos: FloatArray, target: FloatArray, speeds: FloatArray, dt: float, stop: BoolArray) -> FloatArray:
    """Velocity (n, 2) of full speed toward ``target``; where ``stop`` is set and the target
    lies within one step, exactly the velocity that lands on it."""
    d = target - pos
    dist = np.linalg.norm(d, axis=1)
    speed = np.where(stop, np.minimum(speeds, dist / dt), speeds)
    unit = d / np.maximum(dist, 1e-300)[:, None]
    return np.where((dist > 0)[:, None], unit * speed[:, None], 0.0)
