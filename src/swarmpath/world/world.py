"""The World: an immutable, validated description of one planning problem.

It holds the workspace bounds, static obstacles (shapes and/or a raster map), danger zones,
moving obstacles (initial state + motion model) and robots (start, goal, radius, speed). It
answers the exact geometric questions the simulator and the validators ask about static
obstacles, and hands out cached occupancy grids for grid planners and controllers.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scipy.spatial import cKDTree

from swarmpath.errors import ScenarioError
from swarmpath.world import limits
from swarmpath.world.bounds import Bounds, CircleBounds, RectBounds
from swarmpath.world.entities import DangerZone, Robot
from swarmpath.world.geometry import EPS
from swarmpath.world.grid import OccupancyGrid, rasterize
from swarmpath.world.limits import preview
from swarmpath.world.moving import MovingObstacle
from swarmpath.world.shapes import Circle, Polygon, Rect, Shape
from swarmpath.world.static_map import StaticMap

FloatArray = NDArray[np.float64]


def _finite(*values: Any) -> bool:
    """Whether every value is a real finite number (not a bool, not NaN or infinite)."""
    try:
        return all(not isinstance(v, bool) and math.isfinite(float(v)) for v in values)
    except (TypeError, ValueError):
        return False


def _fmt(p: ArrayLike) -> str:
    x, y = (float(v) for v in p)
    return f"({x:g}, {y:g})"


@dataclass(frozen=True, eq=False)
class World:
    """One planning problem. Construct it directly, from a scenario file
    (:func:`swarmpath.world.load_scenario`) or from MovingAI files
    (:func:`swarmpath.world.world_from_movingai`). Invalid worlds raise :class:`ScenarioError`
    naming the field."""

    bounds: Bounds
    obstacles: tuple[Shape, ...] = ()
    static_map: StaticMap | None = None
    danger_zones: tuple[DangerZone, ...] = ()
    moving_obstacles: tuple[MovingObstacle, ...] = ()
    robots: tuple[Robot, ...] = ()
    resolution: float = 1.0
    dt: float = 1.0
    name: str = "world"
    defaults: Mapping[str, str] = field(default_factory=dict)
    _grids: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        for name in ("obstacles", "danger_zones", "moving_obstacles", "robots"):
            object.__setattr__(self, name, tuple(getattr(self, name)))
        object.__setattr__(self, "defaults", dict(self.defaults))
        self._validate()

    # ------------------------------------------------------------------ validation
    def _validate(self) -> None:
        for name in ("resolution", "dt"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
                    and math.isfinite(value) and value > 0):
                raise ScenarioError(f"must be a finite number > 0, got {preview(value)}", field=name)
        b = self.bounds
        if isinstance(b, RectBounds):
            if not (_finite(b.width, b.height) and b.width > 0 and b.height > 0):
                raise ScenarioError(f"width and height must be finite and > 0, got {preview(b.width)} x "
                                    f"{preview(b.height)}", field="bounds")
        elif isinstance(b, CircleBounds):
            if not (_finite(*b.center, b.radius) and b.radius > 0):
                raise ScenarioError(f"center and radius must be finite, radius > 0, got {preview(b.center)}, "
                                    f"{preview(b.radius)}", field="bounds")
            if b.center[0] - b.radius < -EPS or b.center[1] - b.radius < -EPS:
                raise ScenarioError("the circle must lie in x >= 0, y >= 0 (grid origin is (0, 0))",
                                    field="bounds")
        else:
            raise ScenarioError(f"must be RectBounds or CircleBounds, got {type(b).__name__}", field="bounds")
        self._validate_grid_size()
        for which in ("obstacles", "danger_zones", "moving_obstacles"):
            if len(getattr(self, which)) > limits.MAX_SHAPES:
                raise ScenarioError(f"{len(getattr(self, which)):,} entries; at most {limits.MAX_SHAPES:,}",
                                    field=which)
        corners = sum(len(o.points) for o in self.obstacles if isinstance(o, Polygon))
        if corners > limits.MAX_TOTAL_POLYGON_POINTS:
            raise ScenarioError(f"the polygons have {corners:,} points together; at most "
                                f"{limits.MAX_TOTAL_POLYGON_POINTS:,}", field="obstacles")
        for i, ob in enumerate(self.obstacles):
            self._validate_shape(ob, f"obstacles[{i}]")
        for i, dz in enumerate(self.danger_zones):
            if not _finite(*dz.center, dz.radius, dz.weight):
                raise ScenarioError("center, radius and weight must be finite numbers", field=f"danger_zones[{i}]")
            if dz.radius < 0:
                raise ScenarioError(f"must be >= 0, got {dz.radius}", field=f"danger_zones[{i}].radius")
            if dz.weight < 0:
                raise ScenarioError(f"must be >= 0, got {dz.weight}", field=f"danger_zones[{i}].weight")
        seen_ids: dict[str, int] = {}
        for i, mo in enumerate(self.moving_obstacles):
            where = f"moving_obstacles[{i}]"
            if mo.id in seen_ids:
                raise ScenarioError(f"id {mo.id!r} is used twice", field=f"{where}.id")
            seen_ids[mo.id] = i
            self._validate_shape(mo.shape, f"{where}.shape", relative=True)
            if not _finite(*mo.start):
                raise ScenarioError("must be finite numbers", field=f"{where}.start")
            if not _finite(*mo.velocity):
                raise ScenarioError("must be finite", field=f"{where}.velocity")
            if not self.obstacle_fits(mo, np.asarray([mo.start], float))[0]:
                raise ScenarioError(f"start {_fmt(mo.start)} overlaps a static obstacle or leaves the workspace",
                                    field=f"{where}.start")
            mo.motion.check(mo, self, where)
        self._validate_robots()

    def _validate_shape(self, shape: Any, where: str, relative: bool = False) -> None:
        if isinstance(shape, Circle) and not _finite(*shape.center, shape.radius):
            raise ScenarioError("center and radius must be finite numbers", field=where)
        if isinstance(shape, Rect) and not _finite(*shape.min, *shape.max):
            raise ScenarioError("min and max must be finite numbers", field=where)
        if isinstance(shape, Polygon):
            if len(shape.points) > limits.MAX_POLYGON_POINTS:
                raise ScenarioError(f"{len(shape.points):,} points; a polygon may have at most "
                                    f"{limits.MAX_POLYGON_POINTS:,}", field=f"{where}.points")
            if not np.all(np.isfinite(np.asarray(shape.points, float))):
                raise ScenarioError("must be finite numbers", field=f"{where}.points")
        if isinstance(shape, Circle):
            if not shape.radius > 0:
                raise ScenarioError(f"must be > 0, got {shape.radius}", field=f"{where}.radius")
        elif isinstance(shape, Rect):
            if not (shape.max[0] > shape.min[0] and shape.max[1] > shape.min[1]):
                raise ScenarioError(f"max {_fmt(shape.max)} must exceed min {_fmt(shape.min)} on both axes",
                                    field=where)
        elif isinstance(shape, Polygon):
            if len(shape.points) < 3:
                raise ScenarioError("a polygon needs at least 3 points", field=f"{where}.points")
            v = shape.vertices
            area = 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])
            if abs(area) < EPS:
                raise ScenarioError("the polygon has no area", field=f"{where}.points")
        else:
            raise ScenarioError(f"unknown shape {type(shape).__name__}", field=where)

    def _validate_robots(self) -> None:
        """Ids unique, radius and speed valid, starts and goals finite, inside the workspace and
        off static obstacles (checked for all robots at once; the first bad one is named)."""
        ids: dict[str, int] = {}
        for i, r in enumerate(self.robots):
            where = f"robots[{i}]"
            if not isinstance(r.id, str):
                raise ScenarioError(f"must be a string, got {preview(r.id)}", field=f"{where}.id")
            if r.id in ids:
                raise ScenarioError(f"id {preview(r.id)!r} is already used by robots[{ids[r.id]}]",
                                    field=f"{where}.id")
            ids[r.id] = i
            if not (_finite(r.radius) and r.radius >= 0):
                raise ScenarioError(f"must be a finite number >= 0, got {preview(r.radius)}", field=f"{where}.radius")
            if not (_finite(r.max_speed) and r.max_speed > 0):
                raise ScenarioError(f"must be a finite number > 0, got {preview(r.max_speed)}",
                                    field=f"{where}.max_speed")
            for which in ("start", "goal"):
                value = getattr(r, which)
                if not (isinstance(value, (tuple, list, np.ndarray)) and len(value) == 2 and _finite(*value)):
                    raise ScenarioError(f"must be two finite numbers, got {preview(value)}", field=f"{where}.{which}")
        if not self.robots:
            return
        radii = self.radii
        for which in ("start", "goal"):
            pts = np.array([getattr(r, which) for r in self.robots], float)
            bad = ~self.bounds.contains(pts, radii)
            if bad.any():
                i = int(np.argmax(bad))
                raise ScenarioError(f"{_fmt(pts[i])} lies outside the workspace", field=f"robots[{i}].{which}")
            hit = self.static_hits(pts, pts, radii)
            if hit.any():
                i = int(np.argmax(hit))
                inside = self.obstacle_at(pts[i], radii[i]) or "a static obstacle"
                raise ScenarioError(f"{_fmt(pts[i])} lies inside {inside}",
                                    field=f"robots[{i}].{which}")
        if len(self.robots) > 1:
            self._validate_distinct("start")
            self._validate_distinct("goal")

    def _validate_grid_size(self) -> None:
        """The occupancy grid at the world's resolution must stay within the cell limit."""
        ext_w, ext_h = self.bounds.extent
        cells = math.ceil(ext_w / self.resolution - 1e-9) * math.ceil(ext_h / self.resolution - 1e-9)
        if self.static_map is not None:
            sm = self.static_map
            cells = max(cells, math.ceil(sm.width * sm.cell_size / self.resolution - 1e-9)
                        * math.ceil(sm.height * sm.cell_size / self.resolution - 1e-9))
        if cells > limits.MAX_GRID_CELLS:
            raise ScenarioError(f"the workspace ({ext_w:g} x {ext_h:g}) at this resolution is a grid of {cells:,.0f} "
                                f"cells; at most {limits.MAX_GRID_CELLS:,} (use a coarser resolution)",
                                field="resolution")

    def _validate_distinct(self, which: str) -> None:
        """No two robots start (or end) on the same spot: overlapping discs, the same point, or
        for two point robots the same grid cell. A KD-tree finds the candidate pairs, so a
        hundred thousand robots validate in seconds."""
        pts = np.array([getattr(r, which) for r in self.robots], float)
        radii = np.array([r.radius for r in self.robots], float)
        reach = 2 * float(radii.max(initial=0.0)) + math.sqrt(2) * self.resolution + EPS
        pairs = cKDTree(pts).query_pairs(reach, output_type="ndarray")
        if len(pairs) == 0:
            return
        i, j = pairs[:, 0], pairs[:, 1]
        d = np.linalg.norm(pts[i] - pts[j], axis=1)
        clash = (d < radii[i] + radii[j] - EPS) | (d < EPS)
        cells = np.floor(pts / self.resolution + 1e-9).astype(np.int64)
        clash |= (radii[i] == 0) & (radii[j] == 0) & np.all(cells[i] == cells[j], axis=1)
        if clash.any():
            order = np.lexsort((np.maximum(i, j)[clash], np.minimum(i, j)[clash]))
            a, b = sorted((int(i[clash][order[0]]), int(j[clash][order[0]])))
            where = "start on the same spot" if which == "start" else "share a goal"
            raise ScenarioError(f"{_fmt(pts[b])} clashes with robots[{a}].{which} {_fmt(pts[a])}: "
                                f"two robots {where} (same point, overlapping discs, or the same grid cell)",
                                field=f"robots[{b}].{which}")

    # ------------------------------------------------------------------ queries
    def obstacle_at(self, point: ArrayLike, radius: float = 0.0) -> str | None:
        """Name of a static obstacle that a disc of ``radius`` at ``point`` enters, else None."""
        p = np.asarray(point, float)[None]
        for i, ob in enumerate(self.obstacles):
            sd = float(ob.signed_distance(p)[0])
            if (radius > 0 and sd < radius - EPS) or (radius == 0 and sd < -EPS):
                return f"obstacle {ob.id!r}" if ob.id else f"obstacles[{i}]"
        if self.static_map is not None:
            if self.static_map.segment_hits(p, p, radius)[0]:
                cell = np.floor(p[0] / self.static_map.cell_size).astype(int)
                return f"blocked map cell ({cell[0]}, {cell[1]})" if radius == 0 else "a blocked map cell"
        return None

    def static_hits(self, a: ArrayLike, b: ArrayLike, radius: ArrayLike) -> NDArray[np.bool_]:
        """For moves from ``a`` to ``b`` (shape (n, 2)) of discs ``radius`` (n,): whether each
        enters a static obstacle or leaves the workspace. Exact geometry, no grid."""
        a = np.atleast_2d(np.asarray(a, float))
        b = np.atleast_2d(np.asarray(b, float))
        r = np.broadcast_to(np.asarray(radius, float), a.shape[:1])
        hit = ~(self.bounds.contains(a, r) & self.bounds.contains(b, r))
        for ob in self.obstacles:
            lo, hi = ob.bbox
            near = np.all((np.minimum(a, b) - r[:, None] < hi) & (np.maximum(a, b) + r[:, None] > lo), axis=1)
            if not near.any():
                continue
            idx = np.flatnonzero(near)
            ra = r[idx]
            crossed = ob.segment_crosses_interior(a[idx], b[idx])
            too_close = ob.segment_clearance(a[idx], b[idx]) < ra - EPS
            hit[idx] |= np.where(ra > 0, too_close | crossed, crossed)
        if self.static_map is not None:
            hit |= self.static_map.segment_hits(a, b, r)
        return hit

    def static_clearance(self, points: ArrayLike, radius: ArrayLike = 0.0) -> FloatArray:
        """Free distance between discs at ``points`` and the nearest static obstacle or the
        boundary (negative when overlapping)."""
        p = np.atleast_2d(np.asarray(points, float))
        r = np.broadcast_to(np.asarray(radius, float), p.shape[:1])
        best = self.bounds.clearance(p)
        for ob in self.obstacles:
            best = np.minimum(best, ob.signed_distance(p))
        if self.static_map is not None:
            reach = 4 * self.static_map.cell_size
            d = self.static_map.segment_clearance(p, p, reach)
            best = np.minimum(best, d)
        return best - r

    def obstacle_fits(self, ob: MovingObstacle, positions: ArrayLike) -> NDArray[np.bool_]:
        """Whether the footprint of ``ob`` at each position avoids static obstacles and stays
        inside the workspace (shape (k,) for positions of shape (k, 2))."""
        pos = np.atleast_2d(np.asarray(positions, float))
        ok = np.ones(len(pos), dtype=bool)
        if isinstance(ob.shape, Circle):
            rho = ob.shape.radius
            ok &= self.bounds.contains(pos, rho)
            for st in self.obstacles:
                ok &= st.signed_distance(pos) >= rho - EPS
            if self.static_map is not None:
                ok &= ~self.static_map.segment_hits(pos, pos, np.full(len(pos), rho))
            return ok
        lo = pos + np.asarray(ob.shape.min, float)
        hi = pos + np.asarray(ob.shape.max, float)
        ok &= self.bounds.boxes_inside(lo, hi)
        for st in self.obstacles:
            ok &= ~st.overlaps_open_box(lo, hi)
        if self.static_map is not None:
            cs = self.static_map.cell_size
            x0 = np.floor(lo[:, 0] / cs + EPS).astype(int)
            y0 = np.floor(lo[:, 1] / cs + EPS).astype(int)
            x1 = np.ceil(hi[:, 0] / cs - EPS).astype(int)
            y1 = np.ceil(hi[:, 1] / cs - EPS).astype(int)
            ok &= self.static_map.count_blocked(x0, y0, x1, y1) == 0
        return ok

    # ------------------------------------------------------------------ grids and arrays
    def grid(self, resolution: float | None = None, radius: float = 0.0) -> OccupancyGrid:
        """The occupancy grid at ``resolution`` (default: the world's) for robots of ``radius``;
        computed once and cached."""
        res = float(resolution or self.resolution)
        key = (res, float(max(0.0, radius - res / 2)))
        if key not in self._grids:
            self._grids[key] = rasterize(self, res, radius)
        return self._grids[key]

    @property
    def n_robots(self) -> int:
        return len(self.robots)

    @property
    def starts(self) -> FloatArray:
        return np.array([r.start for r in self.robots], float).reshape(-1, 2)

    @property
    def goals(self) -> FloatArray:
        return np.array([r.goal for r in self.robots], float).reshape(-1, 2)

    @property
    def radii(self) -> FloatArray:
        return np.array([r.radius for r in self.robots], float)

    @property
    def max_speeds(self) -> FloatArray:
        return np.array([r.max_speed for r in self.robots], float)

    def replace(self, **changes: Any) -> "World":
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """The scenario-file form (schema 1) of this world; a static map is not embedded."""
        doc: dict[str, Any] = {"schema_version": 1, "name": self.name, "resolution": self.resolution,
                               "dt": self.dt, "bounds": self.bounds.to_dict()}
        if self.obstacles:
            doc["obstacles"] = [o.to_dict() for o in self.obstacles]
        if self.danger_zones:
            doc["danger_zones"] = [d.to_dict() for d in self.danger_zones]
        if self.moving_obstacles:
            doc["moving_obstacles"] = [m.to_dict() for m in self.moving_obstacles]
        doc["robots"] = [r.to_dict() for r in self.robots]
        if self.defaults:
            doc["defaults"] = dict(self.defaults)
        return doc
