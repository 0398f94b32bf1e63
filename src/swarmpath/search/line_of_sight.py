"""Line of sight on an occupancy grid, in the strict sense point robots need: the segment
between two points may not touch any blocked cell's closed square (so passing exactly
through the corner between two blocked cells is blocked, as corner cutting is)."""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.search.grid_input import blocked_array
from swarmpath.world.geometry import EPS, segment_box_distance


def line_of_sight(grid: Any, a: ArrayLike, b: ArrayLike, resolution: float | None = None) -> NDArray[np.bool_]:
    """Whether each segment ``a``-``b`` (world points, shape (..., 2)) touches no blocked cell
    and stays inside the grid. ``resolution`` defaults to the grid's own."""
    blocked = blocked_array(grid)
    res = float(resolution if resolution is not None else getattr(grid, "resolution", 1.0))
    a = np.atleast_2d(np.asarray(a, float)) / res
    b = np.atleast_2d(np.asarray(b, float)) / res
    h, w = blocked.shape
    out = np.ones(len(a), dtype=bool)
    for i in range(len(a)):
        p, q = a[i], b[i]
        length = float(np.linalg.norm(q - p))
        n_pieces = max(1, int(np.ceil(length / 4.0)))
        ts = np.linspace(0.0, 1.0, n_pieces + 1)
        pa = p + ts[:-1, None] * (q - p)
        pb = p + ts[1:, None] * (q - p)
        lo = np.floor(np.minimum(pa, pb) - EPS).astype(int) - 1
        off = np.arange(7)
        ox, oy = np.meshgrid(off, off, indexing="xy")
        cx = lo[:, None, 0] + ox.ravel()[None]
        cy = lo[:, None, 1] + oy.ravel()[None]
        touch = segment_box_distance(pa[:, None], pb[:, None], np.stack([cx, cy], -1),
                                     np.stack([cx + 1, cy + 1], -1)) < EPS
        outside = (cx < 0) | (cx >= w) | (cy < 0) | (cy >= h)
        if np.any(touch & outside):
            # touching the grid's outer boundary is allowed; leaving it is not
            inside_pts = np.all((np.concatenate([pa, pb]) >= 0) & (np.concatenate([pa, pb]) <= [w, h]), axis=1)
            if not inside_pts.all():
                out[i] = False
                continue
        cxi, cyi = np.clip(cx, 0, w - 1), np.clip(cy, 0, h - 1)
        out[i] = not np.any(touch & ~outside & blocked[cyi, cxi])
    return out
