"""Static geometry as convex features whose closest points give ORCA's obstacle half-planes.

Every static obstacle becomes convex pieces: circles stay circles, rectangles stay boxes,
polygons become their edges (segments), a raster map (MovingAI) becomes the edges between
blocked and free cells, merged into maximal straight runs (so a robot sliding along a wall
sees one segment, not a row of cell corners), and a rectangular workspace becomes its four
sides. A robot outside all pieces that keeps its swept disc off every piece never enters an
obstacle: it would have to cross the boundary first. The workspace's edge (rectangular or
circular) is handled apart, with its known normals (:meth:`StaticFeatures.bound_lines`).

For each robot :meth:`StaticFeatures.closest` returns the vector to the closest point of
every piece within reach; :func:`~swarmpath.control.orca.halfplanes.clearance_halfplanes`
turns them into lines.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.world.bounds import CircleBounds, RectBounds
from swarmpath.world.shapes import Circle, Polygon, Rect

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Up to this many segments every robot is tested against every segment; beyond, a KD-tree.
BRUTE_FORCE_SEGMENTS = 64


def raster_boundary_segments(blocked: NDArray[np.bool_], cell_size: float) -> FloatArray:
    """Edges between blocked and free cells of a raster ``blocked[y, x]``, merged into maximal
    axis-parallel runs; shape (s, 2, 2) of (start, end) points in world units. Edges on the
    raster's outer border are left out (the workspace bounds cover them)."""
    b = np.asarray(blocked, bool)
    out: list[FloatArray] = []
    # horizontal edges on the line y = k (between rows k-1 and k), k = 1..h-1
    diff_h = b[1:, :] != b[:-1, :]                       # (h-1, w)
    for k, x0, x1 in _runs(diff_h):
        y = (k + 1) * cell_size
        out.append(np.array([[x0 * cell_size, y], [x1 * cell_size, y]]))
    diff_v = (b[:, 1:] != b[:, :-1]).T                   # (w-1, h): vertical lines x = k+1
    for k, y0, y1 in _runs(diff_v):
        x = (k + 1) * cell_size
        out.append(np.array([[x, y0 * cell_size], [x, y1 * cell_size]]))
    return np.array(out, float).reshape(-1, 2, 2)


def _runs(mask: NDArray[np.bool_]) -> list[tuple[int, int, int]]:
    """Maximal runs of True along axis 1 of ``mask``: (row, first, one past last)."""
    padded = np.zeros((mask.shape[0], mask.shape[1] + 2), dtype=np.int8)
    padded[:, 1:-1] = mask
    d = np.diff(padded, axis=1)
    rows_s, starts = np.nonzero(d == 1)
    _, ends = np.nonzero(d == -1)          # same rows, same order as the starts
    return list(zip(rows_s.tolist(), starts.tolist(), ends.tolist()))


def closest_on_segments(p: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Closest points on segments a-b to points p (all (e, 2))."""
    ab = b - a
    denom = np.einsum("ij,ij->i", ab, ab)
    t = np.einsum("ij,ij->i", p - a, ab) / np.where(denom > 0, denom, 1.0)
    t = np.clip(np.where(denom > 0, t, 0.0), 0.0, 1.0)
    return a + t[:, None] * ab


class StaticFeatures:
    """The static geometry of a world as circles, boxes and segments (built once per run).

    Parameters
    ----------
    world : the :class:`~swarmpath.world.World`; its ``obstacles``, ``static_map`` and
        ``bounds`` are read.
    """

    def __init__(self, world):
        self.bounds = world.bounds
        circles = [o for o in world.obstacles if isinstance(o, Circle)]
        rects = [o for o in world.obstacles if isinstance(o, Rect)]
        segs: list[FloatArray] = []
        for o in world.obstacles:
            if isinstance(o, Polygon):
                a, b = o.edges
                segs.append(np.stack([a, b], axis=1))
        if world.static_map is not None:
            segs.append(raster_boundary_segments(world.static_map.blocked, world.static_map.cell_size))
        self.centers = np.array([c.center for c in circles], float).reshape(-1, 2)
        self.rho = np.array([c.radius for c in circles], float)
        self.lo = np.array([r.min for r in rects], float).reshape(-1, 2)
        self.hi = np.array([r.max for r in rects], float).reshape(-1, 2)
        self.segments = np.concatenate(segs).reshape(-1, 2, 2) if segs else np.zeros((0, 2, 2))
        self._tree = None
        if len(self.segments) > BRUTE_FORCE_SEGMENTS:
            # index pieces of at most `piece` length; a hit names the whole segment
            piece = max(float(world.resolution), 1e-9) * 2.0
            lengths = np.linalg.norm(self.segments[:, 1] - self.segments[:, 0], axis=1)
            count = np.maximum(1, np.ceil(lengths / piece)).astype(np.int64)
            parent = np.repeat(np.arange(len(self.segments)), count)
            k = np.arange(len(parent)) - np.repeat(np.cumsum(count) - count, count)
            frac = (k + 0.5) / count[parent]
            a, b = self.segments[parent, 0], self.segments[parent, 1]
            self._tree = cKDTree(a + frac[:, None] * (b - a))
            self._parent = parent
            self._half_piece = float(np.max(lengths / count)) / 2 + 1e-9

    def closest(self, positions: FloatArray, reach: FloatArray) -> tuple[IntArray, FloatArray]:
        """For robots at ``positions`` (n, 2): every feature whose closest point lies within
        ``reach`` (n,) of the robot, as (owner (e,), offset (e, 2) = closest point - position),
        ordered by robot and then by feature (deterministic)."""
        pos = np.asarray(positions, float).reshape(-1, 2)
        reach = np.broadcast_to(np.asarray(reach, float), (len(pos),))
        owners: list[IntArray] = []
        offsets: list[FloatArray] = []
        if len(self.rho):
            rel = self.centers[None] - pos[:, None]                         # (n, c, 2)
            d = np.linalg.norm(rel, axis=-1)
            i, j = np.nonzero(d - self.rho[None] <= reach[:, None])
            dd = np.maximum(d[i, j], 1e-12)
            offsets.append(rel[i, j] * ((dd - self.rho[j]) / dd)[:, None])
            owners.append(i)
        if len(self.lo):
            q = np.clip(pos[:, None], self.lo[None], self.hi[None])          # (n, b, 2)
            rel = q - pos[:, None]
            i, j = np.nonzero(np.linalg.norm(rel, axis=-1) <= reach[:, None])
            offsets.append(rel[i, j])
            owners.append(i)
        if len(self.segments):
            if self._tree is None:
                i, j = np.nonzero(np.ones((len(pos), len(self.segments)), bool))
            else:
                i, j = self._pairs(pos, reach)
            if len(i):
                q = closest_on_segments(pos[i], self.segments[j, 0], self.segments[j, 1])
                rel = q - pos[i]
                keep = np.linalg.norm(rel, axis=1) <= reach[i]
                offsets.append(rel[keep])
                owners.append(i[keep])
        if not owners:
            return np.zeros(0, np.int64), np.zeros((0, 2))
        owner = np.concatenate(owners).astype(np.int64)
        offset = np.concatenate(offsets)
        order = np.argsort(owner, kind="stable")
        return owner[order], offset[order]

    def _pairs(self, pos: FloatArray, reach: FloatArray) -> tuple[IntArray, IntArray]:
        """(robot, segment) pairs whose indexed pieces lie near enough, each pair once."""
        tree = cKDTree(pos)
        r = float(reach.max(initial=0.0)) + self._half_piece
        sp = tree.sparse_distance_matrix(self._tree, r, output_type="ndarray")
        i = sp["i"].astype(np.int64)
        j = self._parent[sp["j"]]
        # sparse_distance_matrix drops exact zero distances: add robots standing on a piece centre
        key = np.unique(i * len(self.segments) + j)
        extra_i, extra_j = self._coincident(pos)
        if len(extra_i):
            key = np.unique(np.concatenate([key, extra_i * len(self.segments) + extra_j]))
        return key // len(self.segments), key % len(self.segments)

    def _coincident(self, pos: FloatArray) -> tuple[IntArray, IntArray]:
        d, k = self._tree.query(pos, k=1)
        hit = np.flatnonzero(d == 0)
        return hit.astype(np.int64), self._parent[k[hit]].astype(np.int64)

    def bound_lines(self, positions: FloatArray, clearance: FloatArray, step: FloatArray,
                    reach: FloatArray | None = None) -> tuple[IntArray, FloatArray, FloatArray]:
        """The workspace's edge as half-planes ``v . u <= room / tau`` with ``u`` an outward
        normal: returns (owner, normal u (e, 2), room (e,)) for robots near the edge.

        A rectangular workspace gives its sides (bottom, right, top, left), each with its
        own normal, for robots within ``clearance + reach`` of it (default ``reach``: two
        steps; room: the distance to the
        side less the clearance); a robot standing on a side (a point robot may) keeps the
        side's normal, which a closest-point offset of length 0 could not give. A circular
        workspace gives the inner half-plane ``(x - c) . u <= h``, ``u`` the outward direction
        at the robot and ``h = sqrt(R'^2 - s^2)``, R' = R - clearance, s the robot's step:
        every point of the half-plane within ``s`` of the robot lies in the disc of radius R'
        (room: ``h - (p - c) . u``), for robots within ``2 s`` of the rim."""
        pos = np.asarray(positions, float).reshape(-1, 2)
        clearance = np.broadcast_to(np.asarray(clearance, float), (len(pos),))
        s = np.broadcast_to(np.asarray(step, float), (len(pos),))
        if isinstance(self.bounds, RectBounds):
            w, h = self.bounds.width, self.bounds.height
            gaps = np.stack([pos[:, 1], w - pos[:, 0], h - pos[:, 1], pos[:, 0]], axis=1)       # (n, 4)
            normals = np.array([[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])
            near = 2 * s if reach is None else np.broadcast_to(np.asarray(reach, float), (len(pos),))
            i, k = np.nonzero(gaps <= (clearance + near)[:, None] + 1e-9)
            return i.astype(np.int64), normals[k], gaps[i, k] - clearance[i]
        if not isinstance(self.bounds, CircleBounds):
            return np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0)
        c = np.asarray(self.bounds.center, float)
        rel = pos - c
        d = np.linalg.norm(rel, axis=1)
        r_in = self.bounds.radius - clearance
        h = np.sqrt(np.maximum(r_in * r_in - s * s, 0.0))
        near = np.flatnonzero(d > r_in - 2 * s - 1e-12)
        u = rel[near] / np.maximum(d[near], 1e-12)[:, None]
        u[d[near] <= 1e-12] = [1.0, 0.0]
        return near.astype(np.int64), u, h[near] - d[near]
