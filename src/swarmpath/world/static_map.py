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

    def _window(self, a: FloatArray, b: FloatArray, reach: float) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
        """Squares of the cells near each segment: lo, hi of shape (n, k, 2) and blocked mask (n, k)."""
        cs = self.cell_size
        lo_pt = np.minimum(a, b) - reach
        hi_pt = np.maximum(a, b) + reach
        c0 = np.floor(lo_pt / cs).astype(int)
        c1 = np.floor(hi_pt / cs).astype(int)
        span = int(max(1, (c1 - c0).max(initial=0) + 1))
        off = np.arange(span)
        ox, oy = np.meshgrid(off, off, indexing="xy")
        ox, oy = ox.ravel(), oy.ravel()
        cx = c0[:, None, 0] + ox[None, :]
        cy = c0[:, None, 1] + oy[None, :]
        valid = (cx <= c1[:, None, 0]) & (cy <= c1[:, None, 1])
        inside = (cx >= 0) & (cx < self.width) & (cy >= 0) & (cy < self.height)
        blocked = np.zeros(cx.shape, dtype=bool)
        m = valid & inside
        blocked[m] = self.blocked[cy[m], cx[m]]
        lo = np.stack([cx, cy], axis=-1) * cs
        return lo, lo + cs, blocked

    def segment_clearance(self, a: ArrayLike, b: ArrayLike, reach: float = 0.0) -> FloatArray:
        """Distance from segments to the nearest blocked square, looked for within ``reach``
        (``inf`` when none is that close)."""
        a = np.atleast_2d(np.asarray(a, float))
        b = np.atleast_2d(np.asarray(b, float))
        lo, hi, blocked = self._window(a, b, reach + g.EPS)
        d = g.segment_box_distance(a[:, None, :], b[:, None, :], lo, hi)
        return np.where(blocked, d, np.inf).min(axis=-1)

    def segment_hits(self, a: ArrayLike, b: ArrayLike, radius: ArrayLike) -> NDArray[np.bool_]:
        """Whether a disc of ``radius`` moved along each segment touches a blocked square
        (for radius 0: touches at all, corner cutting included)."""
        r = np.broadcast_to(np.asarray(radius, float), np.atleast_2d(np.asarray(a)).shape[:1])
        d = self.segment_clearance(a, b, float(r.max(initial=0.0)))
        return np.where(r > 0, d < r - g.EPS, d < g.EPS)
