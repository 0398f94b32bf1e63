"""The robot-robot move rules, written once: when do two robots' moves of one step collide?

Two robots move in straight lines from ``p0`` to ``p1`` during a step, at constant speed,
both at once. Their moves conflict when

- discs (either radius > 0): they come closer than the sum of their radii at some time of
  the step (touching without overlap is allowed);
- point robots (both radius 0, which occupy the grid cell containing them): they end in
  the same cell (a *vertex* conflict), exchange cells (a *swap*), or pass through the same
  point at the same time (a *crossing*, e.g. two diagonal moves across one 2x2 block).

The simulator's checker (:mod:`swarmpath.sim.collisions`) decides contacts with these
predicates, and every controller that checks its own moves calls them too, so a controller
can never disagree with the checker about what a contact is. The tests hold them against a
brute-force reference that samples the motion (no shared code).

Cells follow the grid convention of :mod:`swarmpath.world.grid`: a point belongs to the cell
``floor(p / resolution)``, points on a border to the cell above/right of it.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world import geometry as g
from swarmpath.world.geometry import EPS, origin_segment_distance
from swarmpath.world.shapes import Circle

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Conflict kinds returned by :func:`move_conflicts` (0 = none).
NO_CONFLICT, VERTEX, SWAP, CROSSING = 0, 1, 2, 3
KIND_NAMES = ("none", "vertex", "swap", "crossing")

#: The 9 grid moves: stay, then E, NE, N, NW, W, SW, S, SE (cells (dx, dy)).
GRID_MOVES = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], np.int64)
#: Start offsets (dx, dy) of a second robot that a one-cell move can reach: Chebyshev <= 2.
NEAR_OFFSETS = np.array([[dx, dy] for dy in range(-2, 3) for dx in range(-2, 3)], np.int64)


def point_cells(points: ArrayLike, resolution: float) -> IntArray:
    """The grid cell (x, y) that holds each point, shape (..., 2)."""
    return np.floor(np.asarray(points, float) / resolution + 1e-9).astype(np.int64)


def swept_gap(p0_i: ArrayLike, p1_i: ArrayLike, p0_j: ArrayLike, p1_j: ArrayLike) -> FloatArray:
    """The smallest distance between the centres of two robots moving ``p0 -> p1`` in
    straight lines during the same step (shape (..., 2) each -> (...)): the relative motion
    is a segment, and its distance to the origin is the answer."""
    p0_i, p1_i, p0_j, p1_j = (np.asarray(v, float) for v in (p0_i, p1_i, p0_j, p1_j))
    return origin_segment_distance(p0_i - p0_j, p1_i - p1_j)


def contact_distance(radius_i: ArrayLike, radius_j: ArrayLike) -> FloatArray:
    """The distance two robots must keep (exclusive): the sum of their radii, or EPS for two
    point robots (which then only meet by passing through the same point)."""
    rsum = np.asarray(radius_i, float) + np.asarray(radius_j, float)
    return np.where(rsum > 0, rsum - EPS, EPS)


def move_conflicts(p0_i: ArrayLike, p1_i: ArrayLike, p0_j: ArrayLike, p1_j: ArrayLike, radius_i: ArrayLike,
                   radius_j: ArrayLike, resolution: float) -> NDArray[np.int8]:
    """The conflict kind of each pair of moves ``p0_i -> p1_i`` and ``p0_j -> p1_j`` (arrays
    of shape (..., 2), radii (...)): :data:`NO_CONFLICT`, :data:`VERTEX` (same end cell, or
    discs overlapping at the end), :data:`SWAP` (point robots exchanging cells) or
    :data:`CROSSING` (too close during the step). Broadcasts over leading axes."""
    p0_i, p1_i, p0_j, p1_j = (np.asarray(v, float) for v in (p0_i, p1_i, p0_j, p1_j))
    r_i = np.asarray(radius_i, float)
    r_j = np.asarray(radius_j, float)
    need = contact_distance(r_i, r_j)
    gap = swept_gap(p0_i, p1_i, p0_j, p1_j)
    both_points = (r_i == 0) & (r_j == 0)
    c0_i, c1_i = point_cells(p0_i, resolution), point_cells(p1_i, resolution)
    c0_j, c1_j = point_cells(p0_j, resolution), point_cells(p1_j, resolution)
    same_cell = both_points & np.all(c1_i == c1_j, axis=-1)
    swap = both_points & np.all(c1_i == c0_j, axis=-1) & np.all(c1_j == c0_i, axis=-1) & \
        np.any(c0_i != c0_j, axis=-1)
    end_overlap = np.linalg.norm(p1_i - p1_j, axis=-1) < need
    crossing = gap < need
    kind = np.where(swap, SWAP, np.where(same_cell | end_overlap, VERTEX, np.where(crossing, CROSSING, NO_CONFLICT)))
    return kind.astype(np.int8)


def grid_conflict_table(radius_i: float, radius_j: float, resolution: float = 1.0) -> BoolArray:
    """Which one-cell moves of two robots standing on cell centres conflict, as a lookup
    table ``table[k, a, b]`` (shape (25, 9, 9)): robot j starts at offset ``NEAR_OFFSETS[k]``
    from robot i, robot i makes ``GRID_MOVES[a]`` and robot j ``GRID_MOVES[b]``. Robots
    farther apart than two cells (Chebyshev) cannot conflict with radii up to half a cell.

    Grid planners and controllers (PIBT, LaCAM, the swarms on the grid) consult this table,
    so their cell reasoning is exactly the checker's rule for the radii given."""
    k, a, b = np.meshgrid(np.arange(len(NEAR_OFFSETS)), np.arange(9), np.arange(9), indexing="ij")
    centre = np.full(2, 0.5 * resolution)
    p0_i = np.broadcast_to(centre, k.shape + (2,))
    p1_i = p0_i + GRID_MOVES[a] * resolution
    p0_j = centre + NEAR_OFFSETS[k] * resolution
    p1_j = p0_j + GRID_MOVES[b] * resolution
    table = move_conflicts(p0_i, p1_i, p0_j, p1_j, radius_i, radius_j, resolution) != NO_CONFLICT
    table[np.all(NEAR_OFFSETS == 0, axis=1)] = True   # two robots never share a start cell
    return table


def footprint_hits(shape, a: FloatArray, b: FloatArray, r: FloatArray) -> BoolArray:
    """Whether discs of radius ``r`` (k,) moving ``a -> b`` (k, 2) enter the footprint
    ``shape`` of a moving obstacle standing still (coordinates relative to the obstacle,
    ``shape`` placed at the origin). Touching is allowed; a point robot (r = 0) hits a box
    only by crossing its open interior. The checker's phase-2 rule (robots move among the
    obstacles' new positions), shared with controllers that check their own moves."""
    if isinstance(shape, Circle):
        d = g.point_segment_distance(np.asarray(shape.center, float), a, b)
        return d < shape.radius + r - g.EPS
    lo, hi = np.asarray(shape.min, float), np.asarray(shape.max, float)
    crossed = g.segment_crosses_open_box(a, b, lo, hi)
    close = g.segment_box_distance(a, b, lo, hi) < r - g.EPS
    return np.where(r > 0, close | crossed, crossed)
