"""Artificial potential field (Jaleel & Hassan 2016, section III.1.B-C, eq. 1-8).

The paper's equations were images and are lost in the text; we use the standard forms of its
reference (Choset et al. 2005, *Principles of Robot Motion*, ch. 4), see
docs/papers/jaleel-hassan-2016.md:

- attractive potential (eq. 1), quadratic within ``d*_goal`` of the goal, conic beyond;
- repulsive potential of obstacle i (eq. 2, 3) within ``Q*`` of it;
- total potential (eq. 4) = attractive + sum over obstacles of repulsive;
- their gradients (eq. 5-8); the robot follows the negative gradient.

The kernels are small pure functions of distances and points. :func:`repulsive_field` and
:func:`potential_field` evaluate them at the centre of every cell of a world's occupancy grid
at once. Obstacle distances ``D_i`` are exact (analytic) for the workspace boundary (circle or
rectangle) and for each shape (circle, rectangle, polygon); a raster map (``world.static_map``)
counts as one obstacle whose distance comes from a Euclidean distance transform. Distances are
configuration-space distances: the robot radius is subtracted. The repulsive part does not
depend on the goal, so it is computed once per (world, grid, radius, eta, Q*) and cached; each
robot's field adds only its attractive term.
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from swarmpath.errors import ConfigError
from swarmpath.world.bounds import CircleBounds, RectBounds
from swarmpath.world.grid import OccupancyGrid, _rasterize_map
from swarmpath.world.shapes import Circle

if TYPE_CHECKING:  # pragma: no cover
    from swarmpath.world.world import World

FloatArray = NDArray[np.float64]

#: Step of the central differences used for the gradient of a shape's distance when no
#: analytic form is coded (rectangles, polygons); world units.
_FD_STEP = 1e-6


# ---------------------------------------------------------------------------------------------
# Parameters
@dataclass(frozen=True)
class FieldParameters:
    """The four constants of the field (world units), with the paper's values as defaults.

    ``attractive_gain`` = zeta, ``quadratic_range`` = d*_goal, ``repulsive_gain`` = eta,
    ``influence_range`` = Q*.
    """

    attractive_gain: float = 0.5
    quadratic_range: float = 15.0
    repulsive_gain: float = 1.0
    influence_range: float = 1.0

    def __post_init__(self) -> None:
        for name in ("attractive_gain", "quadratic_range", "repulsive_gain", "influence_range"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float, np.floating, np.integer)) and np.isfinite(value) and value > 0):
                raise ConfigError(f"{name} must be a finite number > 0, got {value!r}")


# ---------------------------------------------------------------------------------------------
# Kernels (pure functions; equations of Choset et al. 2005 as cited by the paper)
def attractive_potential(d: ArrayLike, zeta: float, d_goal: float) -> FloatArray:
    """Eq. 1: ``U_att = zeta d^2 / 2`` for ``d <= d*_goal``, else
    ``d*_goal zeta d - zeta d*_goal^2 / 2`` (continuous with a continuous slope at d*_goal).

    ``d``: distances to the goal, any shape; returns the same shape."""
    d = np.asarray(d, float)
    return np.where(d <= d_goal, 0.5 * zeta * d * d, d_goal * zeta * d - 0.5 * zeta * d_goal * d_goal)


def attractive_gradient(q: ArrayLike, goal: ArrayLike, zeta: float, d_goal: float) -> FloatArray:
    """Eq. 5: ``grad U_att = zeta (q - q_goal)`` for ``d <= d*_goal``, else
    ``d*_goal zeta (q - q_goal) / d``.

    ``q``: points of shape (..., 2); ``goal``: (2,); returns shape (..., 2)."""
    diff = np.asarray(q, float) - np.asarray(goal, float)
    d = np.linalg.norm(diff, axis=-1, keepdims=True)
    far = d > d_goal
    scale = np.where(far, d_goal * zeta / np.where(far, d, 1.0), zeta)
    return scale * diff


def repulsive_potential(D: ArrayLike, eta: float, q_star: float) -> FloatArray:
    """Eq. 2: ``U_rep,i = eta (1/D_i - 1/Q*)^2 / 2`` for ``0 < D_i <= Q*``, 0 beyond Q*,
    ``inf`` for ``D_i <= 0`` (touching or inside the obstacle).

    ``D``: distances to one obstacle, any shape; returns the same shape."""
    D = np.asarray(D, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = 0.5 * eta * (1.0 / D - 1.0 / q_star) ** 2
    return np.where(D <= 0, np.inf, np.where(D <= q_star, u, 0.0))


def repulsive_gradient(D: ArrayLike, grad_D: ArrayLike, eta: float, q_star: float) -> FloatArray:
    """Eq. 6-7: ``grad U_rep,i = eta (1/Q* - 1/D_i) (1/D_i^2) grad D_i`` for ``0 < D_i <= Q*``,
    0 beyond Q*, ``nan`` for ``D_i <= 0``.

    ``D``: distances, shape (...); ``grad_D``: unit vectors pointing away from the obstacle
    (the gradient of ``D_i``), shape (..., 2); returns shape (..., 2)."""
    D = np.asarray(D, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        mag = eta * (1.0 / q_star - 1.0 / D) / (D * D)
    mag = np.where(D <= 0, np.nan, np.where(D <= q_star, mag, 0.0))
    return mag[..., None] * np.asarray(grad_D, float)


# ---------------------------------------------------------------------------------------------
# Distances to the obstacles (the D_i of eq. 3) and their gradients
DistanceFn = Callable[[FloatArray], tuple[FloatArray, FloatArray]]


def _bounds_distance(bounds) -> DistanceFn:
    """Distance from inside points to the workspace boundary and its gradient (exact)."""
    if isinstance(bounds, CircleBounds):
        c = np.asarray(bounds.center, float)

        def circle(p: FloatArray) -> tuple[FloatArray, FloatArray]:
            diff = p - c
            r = np.linalg.norm(diff, axis=-1, keepdims=True)
            unit = diff / np.where(r > 0, r, 1.0)
            return bounds.radius - r[..., 0], -unit

        return circle
    if isinstance(bounds, RectBounds):
        w, h = bounds.width, bounds.height
        normals = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])

        def rect(p: FloatArray) -> tuple[FloatArray, FloatArray]:
            walls = np.stack([p[..., 0], p[..., 1], w - p[..., 0], h - p[..., 1]], axis=-1)
            k = np.argmin(walls, axis=-1)
            return np.take_along_axis(walls, k[..., None], -1)[..., 0], normals[k]

        return rect
    raise ConfigError(f"unsupported workspace bounds {type(bounds).__name__}")  # pragma: no cover


def _shape_distance(shape) -> DistanceFn:
    """Exact distance to one obstacle shape; gradient analytic for circles, by central
    differences of the exact signed distance otherwise."""
    if isinstance(shape, Circle):
        c = np.asarray(shape.center, float)

        def circle(p: FloatArray) -> tuple[FloatArray, FloatArray]:
            diff = p - c
            r = np.linalg.norm(diff, axis=-1, keepdims=True)
            return r[..., 0] - shape.radius, diff / np.where(r > 0, r, 1.0)

        return circle

    def general(p: FloatArray) -> tuple[FloatArray, FloatArray]:
        d = shape.signed_distance(p)
        ex, ey = np.array([_FD_STEP, 0.0]), np.array([0.0, _FD_STEP])
        gx = (shape.signed_distance(p + ex) - shape.signed_distance(p - ex)) / (2 * _FD_STEP)
        gy = (shape.signed_distance(p + ey) - shape.signed_distance(p - ey)) / (2 * _FD_STEP)
        return d, np.stack([gx, gy], axis=-1)

    return general


def obstacle_distances(world: "World", points: ArrayLike, radius: float = 0.0
                       ) -> list[tuple[FloatArray, FloatArray]]:
    """``(D_i, grad D_i)`` for each obstacle i of eq. 3 at ``points`` (shape (..., 2)): the
    workspace boundary first, then ``world.obstacles`` in order. ``D_i`` is the exact distance
    (world units) minus ``radius``, shape (...); ``grad D_i`` is a unit vector pointing away
    from the obstacle, shape (..., 2). A raster ``static_map`` is not included (see
    :func:`repulsive_field`, which handles it with a distance transform)."""
    p = np.asarray(points, float)
    out = []
    for fn in [_bounds_distance(world.bounds), *(_shape_distance(s) for s in world.obstacles)]:
        d, g = fn(p)
        out.append((d - radius, g))
    return out


def potential_at(world: "World", points: ArrayLike, goal: ArrayLike, radius: float = 0.0,
                 params: FieldParameters = FieldParameters()) -> tuple[FloatArray, FloatArray]:
    """Total potential (eq. 4) and its gradient (eq. 8) at arbitrary ``points`` (shape (..., 2)),
    from the exact obstacle distances (boundary + shapes; not a raster map). Returns
    ``(U, grad U)`` of shapes (...) and (..., 2). ``U`` is ``inf`` where a disc of ``radius``
    touches an obstacle."""
    p = np.asarray(points, float)
    if world.static_map is not None:
        raise ConfigError("potential_at needs shape obstacles; a raster map's field exists only on "
                          "the grid (use repulsive_field / potential_field)")
    goal = np.asarray(goal, float)
    u = attractive_potential(np.linalg.norm(p - goal, axis=-1), params.attractive_gain, params.quadratic_range)
    g = attractive_gradient(p, goal, params.attractive_gain, params.quadratic_range)
    for D, gD in obstacle_distances(world, p, radius):
        u = u + repulsive_potential(D, params.repulsive_gain, params.influence_range)
        g = g + repulsive_gradient(D, gD, params.repulsive_gain, params.influence_range)
    return u, g


# ---------------------------------------------------------------------------------------------
# Fields on a grid
@dataclass(frozen=True, eq=False)
class RepulsiveField:
    """The goal-independent part of the field on ``grid``: ``potential`` = sum_i U_rep,i
    (eq. 2, 4) and ``gradient`` = sum_i grad U_rep,i (eq. 6), at every cell centre.

    ``potential``: (height, width), ``inf`` on blocked cells; ``gradient``: (height, width, 2),
    0 on blocked cells; ``clearance``: (height, width) min_i D_i (world units; the distance a
    robot of ``radius`` at the cell centre keeps from the nearest obstacle)."""

    grid: OccupancyGrid
    potential: FloatArray
    gradient: FloatArray
    clearance: FloatArray
    radius: float
    repulsive_gain: float
    influence_range: float


@dataclass(frozen=True, eq=False)
class PotentialField:
    """One robot's field on a grid: the shared :class:`RepulsiveField` plus the attractive
    term of ``goal`` (eq. 1, 4). ``attractive`` and ``total`` have shape (height, width);
    ``total`` is ``inf`` on blocked cells."""

    repulsive: RepulsiveField
    goal: FloatArray
    attractive: FloatArray
    attractive_gain: float
    quadratic_range: float

    @property
    def grid(self) -> OccupancyGrid:
        return self.repulsive.grid

    @cached_property
    def total(self) -> FloatArray:
        """U = U_att + sum_i U_rep,i (eq. 4), shape (height, width)."""
        t = self.attractive + self.repulsive.potential
        t.setflags(write=False)
        return t

    @cached_property
    def gradient(self) -> FloatArray:
        """grad U (eq. 8), shape (height, width, 2); the robot follows its negative; 0 on
        blocked cells."""
        g = attractive_gradient(_cell_centres(self.grid), self.goal, self.attractive_gain, self.quadratic_range)
        g = g + self.repulsive.gradient
        g[self.grid.blocked] = 0.0
        return g


def _cell_centres(grid: OccupancyGrid) -> FloatArray:
    """World coordinates of every cell centre, shape (height, width, 2)."""
    xs = (np.arange(grid.width) + 0.5) * grid.resolution
    ys = (np.arange(grid.height) + 0.5) * grid.resolution
    return np.stack(np.meshgrid(xs, ys, indexing="xy"), axis=-1)


_CACHE: "weakref.WeakKeyDictionary[World, dict]" = weakref.WeakKeyDictionary()


def repulsive_field(world: "World", *, radius: float = 0.0, resolution: float | None = None,
                    repulsive_gain: float = 1.0, influence_range: float = 1.0) -> RepulsiveField:
    """The repulsive part of the field on ``world.grid(resolution, radius)`` (cached per world
    and arguments). Each obstacle only touches the cells within ``influence_range`` of it, so
    only those cells are evaluated."""
    FieldParameters(repulsive_gain=repulsive_gain, influence_range=influence_range)
    grid = world.grid(resolution, radius=radius)
    key = (grid.resolution, float(radius), float(repulsive_gain), float(influence_range))
    per_world = _CACHE.setdefault(world, {})
    hit = per_world.get(key)
    if hit is not None:
        return hit
    field = _compute_repulsive(world, grid, float(radius), float(repulsive_gain), float(influence_range))
    per_world[key] = field
    return field


def _compute_repulsive(world: "World", grid: OccupancyGrid, radius: float, eta: float, q_star: float
                       ) -> RepulsiveField:
    res = grid.resolution
    centres = _cell_centres(grid)
    h, w = grid.height, grid.width
    potential = np.zeros((h, w))
    gradient = np.zeros((h, w, 2))
    clearance = np.full((h, w), np.inf)

    def add(ys: slice, xs: slice, D: FloatArray, gD: FloatArray) -> None:
        potential[ys, xs] += repulsive_potential(D, eta, q_star)
        with np.errstate(invalid="ignore"):
            gradient[ys, xs] += np.nan_to_num(repulsive_gradient(D, gD, eta, q_star), nan=0.0)
        np.minimum(clearance[ys, xs], D, out=clearance[ys, xs])

    # The boundary: every cell (it is near the rim only, but the distance is cheap).
    D, gD = _bounds_distance(world.bounds)(centres)
    add(slice(None), slice(None), D - radius, gD)
    # Each shape: only the window of cells within Q* + radius of its bounding box.
    reach = q_star + radius
    for shape in world.obstacles:
        lo, hi = shape.bbox
        x0 = max(0, int(np.floor((lo[0] - reach) / res)) - 1)
        y0 = max(0, int(np.floor((lo[1] - reach) / res)) - 1)
        x1 = min(w, int(np.ceil((hi[0] + reach) / res)) + 1)
        y1 = min(h, int(np.ceil((hi[1] + reach) / res)) + 1)
        if x0 >= x1 or y0 >= y1:
            continue
        ys, xs = slice(y0, y1), slice(x0, x1)
        D, gD = _shape_distance(shape)(centres[ys, xs])
        add(ys, xs, D - radius, gD)
    # A raster map: one obstacle, distance from a Euclidean distance transform of its cells
    # rasterised at this grid's resolution: distance between cell centres minus half a cell
    # (the nearest blocked square's near side), minus the radius.
    if world.static_map is not None:
        mb = _rasterize_map(world.static_map, res, 0.0, w, h)
        if mb.any():
            dist, idx = ndimage.distance_transform_edt(~mb, sampling=res, return_indices=True)
            near = np.stack([idx[1], idx[0]], axis=-1)  # (x, y) of the nearest blocked cell
            diff = centres - (near + 0.5) * res
            unit = diff / np.where(dist > 0, dist, 1.0)[..., None]
            add(slice(None), slice(None), np.where(mb, 0.0, dist - 0.5 * res) - radius, unit)
    blocked = grid.blocked
    potential[blocked] = np.inf
    gradient[blocked] = 0.0
    for a in (potential, gradient, clearance):
        a.setflags(write=False)
    return RepulsiveField(grid, potential, gradient, clearance, radius, eta, q_star)


def potential_field(world: "World", goal: ArrayLike, *, radius: float = 0.0, resolution: float | None = None,
                    params: FieldParameters = FieldParameters()) -> PotentialField:
    """The total field (eq. 4) of a robot of ``radius`` heading to ``goal`` (world point) at
    every cell centre of ``world.grid(resolution, radius)``. The repulsive part is shared
    (cached); only the attractive term (eq. 1) is computed here."""
    rep = repulsive_field(world, radius=radius, resolution=resolution, repulsive_gain=params.repulsive_gain,
                          influence_range=params.influence_range)
    goal = np.asarray(goal, float).reshape(2)
    grid = rep.grid
    xs = (np.arange(grid.width) + 0.5) * grid.resolution - goal[0]
    ys = (np.arange(grid.height) + 0.5) * grid.resolution - goal[1]
    # eq. 1 on the squared distance: no square root inside the quadratic range
    zeta, d_goal = params.attractive_gain, params.quadratic_range
    d2 = np.add.outer(ys * ys, xs * xs)
    far = d2 > d_goal * d_goal
    att = np.multiply(d2, 0.5 * zeta, out=d2)
    if far.any():
        att[far] = attractive_potential(np.sqrt(d2[far] / (0.5 * zeta)), zeta, d_goal)
    att.setflags(write=False)
    return PotentialField(rep, goal, att, zeta, d_goal)
