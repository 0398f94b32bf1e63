"""Static obstacles given as an occupancy raster (a MovingAI map, or any boolean array).

Cell (x, y) = (column, row) covers the closed square [x, x+1] x [y, y+1] times ``cell_size``.
Point robots must not touch a blocked square (so a diagonal move between two blocked cells,
"corner cutting", is a collision, as in the MovingAI benchmark); discs of radius r must stay
at distance >= r from blocked squares.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world import geometry as g
from swarmpath.world.raster import Raster

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class StaticMap(Raster):
    """Blocked cells of a raster: ``blocked[y, x]`` is True for a blocked cell."""

    cell_size: float = 1.0
    source: str = ""
    _summed: NDArray[np.int64] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        super().__post_init__()
        summed = np.zeros((self.blocked.shape[0] + 1, self.blocked.shape[1] + 1), dtype=np.int64)
        summed[1:, 1:] = self.blocked.cumsum(0).cumsum(1)
        object.__setattr__(self, "_summed", summed)

    def count_blocked(self, x0: NDArray, y0: NDArray, x1: NDArray, y1: NDArray) -> NDArray[np.int64]:
        """Blocked cells in the index ranges [x0, x1) x [y0, y1) (clipped to the map)."""
        x0, x1 = np.clip(x0, 0, self.width), np.clip(x1, 0, self.width)
        y0, y1 = np.clip(y0, 0, self.height), np.clip(y1, 0, self.height)
        x1, y1 = np.maximum(x1, x0), np.maximum(y1, y0)
        s = self._summed
        return s[y1, x1] - s[y0, x1] - s[y1, x0] + s[y0, x0]

    def is_blocked_at(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether points lie in a blocked cell (points outside the map count as free)."""
        p = np.asarray(points, float) / self.cell_size
        x, y = np.floor(p[..., 0]).astype(int), np.floor(p[..., 1]).astype(int)
        inside = (x >= 0) & (x < self.width) & (y >= 0) & (y < self.height)
        out = np.zeros(x.shape, dtype=bool)
        out[inside] = self.blocked[y[inside], x[inside]]
        return out

    def _candidates(self, a: FloatArray, b: FloatArray, reach: float) -> tuple[IntArray, IntArray, IntArray]:
        """The blocked cells that may lie within ``reach`` of each segment: (segment index,
        column, row) arrays. Walks each segment along its longer axis one cell column (or row)
        at a time and takes, in that strip, the rows the segment's band of half-width
        ``reach`` can touch: about (length + 2 reach) x (1 + 2 reach) cells per segment, so a
        long segment costs what it passes, not the square of its length."""
        cs = self.cell_size
        swap = np.abs(b[:, 1] - a[:, 1]) > np.abs(b[:, 0] - a[:, 0])    # walk along y instead of x
        ua = np.where(swap, a[:, 1], a[:, 0]) / cs
        ub = np.where(swap, b[:, 1], b[:, 0]) / cs
        va = np.where(swap, a[:, 0], a[:, 1]) / cs
        vb = np.where(swap, b[:, 0], b[:, 1]) / cs
        r = reach / cs
        c0 = np.floor(np.minimum(ua, ub) - r).astype(np.int64)
        c1 = np.floor(np.maximum(ua, ub) + r).astype(np.int64)
        per_segment = c1 - c0 + 1
        seg = np.repeat(np.arange(len(a)), per_segment)
        col = c0[seg] + (np.arange(len(seg)) - np.repeat(np.cumsum(per_segment) - per_segment, per_segment))
        # the part of the segment whose walking coordinate lies in [col - r, col + 1 + r]
        du = ub[seg] - ua[seg]
        flat = np.abs(du) < 1e-12
        safe = np.where(flat, 1.0, du)
        t0 = np.clip(np.where(flat, 0.0, (col - r - ua[seg]) / safe), 0.0, 1.0)
        t1 = np.clip(np.where(flat, 1.0, (col + 1 + r - ua[seg]) / safe), 0.0, 1.0)
        v0 = va[seg] + t0 * (vb[seg] - va[seg])
        v1 = va[seg] + t1 * (vb[seg] - va[seg])
        r0 = np.floor(np.minimum(v0, v1) - r).astype(np.int64)
        r1 = np.floor(np.maximum(v0, v1) + r).astype(np.int64)
        per_column = r1 - r0 + 1
        seg = np.repeat(seg, per_column)
        col = np.repeat(col, per_column)
        row = np.repeat(r0, per_column) + (np.arange(len(seg)) - np.repeat(np.cumsum(per_column) - per_column,
                                                                             per_column))
        sw = swap[seg]
        cx, cy = np.where(sw, row, col), np.where(sw, col, row)
        inside = (cx >= 0) & (cx < self.width) & (cy >= 0) & (cy < self.height)
        keep = np.flatnonzero(inside)
        keep = keep[self.blocked[cy[keep], cx[keep]]]
        return seg[keep], cx[keep], cy[keep]

    def segment_clearance(self, a: ArrayLike, b: ArrayLike, reach: float = 0.0) -> FloatArray:
        """Distance from segments to the nearest blocked square, looked for within ``reach``
        (``inf`` when none is that close)."""
        a = np.atleast_2d(np.asarray(a, float))
        b = np.atleast_2d(np.asarray(b, float))
        out = np.full(len(a), np.inf)
        seg, cx, cy = self._candidates(a, b, reach + g.EPS)
        if len(seg):
            cs = self.cell_size
            lo = np.stack([cx, cy], axis=-1) * cs
            d = g.segment_box_distance(a[seg], b[seg], lo, lo + cs)
            np.minimum.at(out, seg, np.where(d <= reach + g.EPS, d, np.inf))
        return out

    def segment_hits(self, a: ArrayLike, b: ArrayLike, radius: ArrayLike) -> NDArray[np.bool_]:
        """Whether a disc of ``radius`` moved along each segment touches a blocked square
        (for radius 0: touches at all, corner cutting included).

        Point robots moving between centres of cells at most one cell apart (every grid
        controller's move) take a shortcut: such a move touches exactly the closed squares of
        its two cells and, for a diagonal, the two cells beside it; the tests hold the
        shortcut to the general computation."""
        a = np.atleast_2d(np.asarray(a, float))
        b = np.atleast_2d(np.asarray(b, float))
        r = np.broadcast_to(np.asarray(radius, float), a.shape[:1])
        ca, cb = a / self.cell_size - 0.5, b / self.cell_size - 0.5
        ia, ib = np.floor(ca), np.floor(cb)
        simple = (r == 0) & np.all(ca == ia, axis=1) & np.all(cb == ib, axis=1) & \
            np.all(np.abs(ib - ia) <= 1, axis=1)
        out = np.empty(len(a), dtype=bool)
        rest = ~simple
        if rest.any():
            d = self.segment_clearance(a[rest], b[rest], float(r[rest].max(initial=0.0)))
            out[rest] = np.where(r[rest] > 0, d < r[rest] - g.EPS, d < g.EPS)
        if simple.any():
            ia, ib = ia[simple].astype(np.int64), ib[simple].astype(np.int64)
            hit = self._blocked_or_outside(ia[:, 0], ia[:, 1]) | self._blocked_or_outside(ib[:, 0], ib[:, 1])
            diagonal = (ia[:, 0] != ib[:, 0]) & (ia[:, 1] != ib[:, 1])
            corner = self._blocked_or_outside(ia[:, 0], ib[:, 1]) | self._blocked_or_outside(ib[:, 0], ia[:, 1])
            out[simple] = hit | (diagonal & corner)
        return out

    def _blocked_or_outside(self, x: IntArray, y: IntArray) -> NDArray[np.bool_]:
        """Whether cells (x, y) are blocked; cells outside the map are free, as for the
        general computation (the workspace bounds are checked separately)."""
        inside = (x >= 0) & (x < self.width) & (y >= 0) & (y < self.height)
        out = np.zeros(len(x), dtype=bool)
        out[inside] = self.blocked[y[inside], x[inside]]
        return out
