"""Occupancy grids: a world rasterised at a resolution, inflated for a robot radius.

Cell (x, y) = (column, row) covers [x, x+1) x [y, y+1) times ``resolution``; its centre is
(x + 0.5, y + 0.5) times ``resolution``. ``blocked[y, x]`` is True where a robot may not be.

Rasterising is conservative: a cell is blocked when an obstacle grown by
``max(0, radius - resolution / 2)`` overlaps the open cell square, or the grown square leaves
the workspace. Then a disc robot moving between centres of 8-adjacent free cells (with both
orthogonal neighbours of a diagonal move free) never touches an obstacle: every point of such
a move is at least ``resolution / 2`` inside the union of the free squares it passes.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world.raster import Raster

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class OccupancyGrid(Raster):
    """A boolean raster ``blocked`` of shape (height, width) with its cell size."""

    resolution: float = 1.0

    @property
    def free(self) -> NDArray[np.bool_]:
        return ~self.blocked

    def cell_of(self, points: ArrayLike) -> IntArray:
        """Cells containing points: int array (..., 2) of (x, y). A point on the grid's far
        edge (x = width or y = height in cells) belongs to the last cell, as a point on any
        other cell border belongs to the cell above/right of it."""
        scaled = np.asarray(points, float) / self.resolution
        cells = np.floor(scaled + 1e-9).astype(np.int64)
        extent = np.array([self.width, self.height])
        on_far_edge = (cells == extent) & (np.abs(scaled - extent) < 1e-9)
        return np.where(on_far_edge, extent - 1, cells)

    def centers(self, cells: ArrayLike) -> FloatArray:
        """World coordinates of cell centres, shape (..., 2)."""
        return (np.asarray(cells, float) + 0.5) * self.resolution

    def contains_cells(self, cells: ArrayLike) -> NDArray[np.bool_]:
        c = np.asarray(cells)
        return (c[..., 0] >= 0) & (c[..., 0] < self.width) & (c[..., 1] >= 0) & (c[..., 1] < self.height)

    def is_free(self, cells: ArrayLike) -> NDArray[np.bool_]:
        """Whether cells are inside the grid and not blocked."""
        c = np.asarray(cells, dtype=np.int64)
        ok = self.contains_cells(c)
        out = np.zeros(c.shape[:-1], dtype=bool)
        out[ok] = ~self.blocked[c[ok][..., 1], c[ok][..., 0]]
        return out

    def index(self, cells: ArrayLike) -> IntArray:
        """Flat indices ``y * width + x`` of cells."""
        c = np.asarray(cells, dtype=np.int64)
        return c[..., 1] * self.width + c[..., 0]


class StaticScene(Protocol):
    """What rasterising reads of a world (:class:`swarmpath.world.World` is one)."""

    bounds: Any
    obstacles: Sequence[Any]
    static_map: Any


def rasterize(world: StaticScene, resolution: float, radius: float = 0.0) -> OccupancyGrid:
    """The occupancy grid of ``world`` at ``resolution`` for robots of ``radius``."""
    ext_w, ext_h = world.bounds.extent
    width = int(np.ceil(ext_w / resolution - 1e-9))
    height = int(np.ceil(ext_h / resolution - 1e-9))
    if world.static_map is not None:
        sm = world.static_map
        width = max(width, int(np.ceil(sm.width * sm.cell_size / resolution - 1e-9)))
        height = max(height, int(np.ceil(sm.height * sm.cell_size / resolution - 1e-9)))
    grow = max(0.0, radius - resolution / 2)
    xs = np.arange(width) * resolution
    ys = np.arange(height) * resolution
    lo = np.stack(np.meshgrid(xs, ys, indexing="xy"), axis=-1)
    hi = lo + resolution
    blocked = ~world.bounds.boxes_inside(lo, hi, grow)
    for shape in world.obstacles:
        s_lo, s_hi = shape.bbox
        x0 = max(0, int(np.floor((s_lo[0] - grow) / resolution)) - 1)
        y0 = max(0, int(np.floor((s_lo[1] - grow) / resolution)) - 1)
        x1 = min(width, int(np.ceil((s_hi[0] + grow) / resolution)) + 1)
        y1 = min(height, int(np.ceil((s_hi[1] + grow) / resolution)) + 1)
        if x0 >= x1 or y0 >= y1:
            continue
        wlo, whi = lo[y0:y1, x0:x1], hi[y0:y1, x0:x1]
        hit = shape.box_clearance(wlo, whi) < grow if grow > 0 else shape.overlaps_open_box(wlo, whi)
        blocked[y0:y1, x0:x1] |= hit
    if world.static_map is not None:
        blocked |= _rasterize_map(world.static_map, resolution, grow, width, height)
    return OccupancyGrid(blocked, resolution)


def _rasterize_map(sm, resolution: float, grow: float, width: int, height: int) -> NDArray[np.bool_]:
    """Cells of the target grid whose grown open square overlaps a blocked map cell."""
    if grow == 0 and np.isclose(resolution, sm.cell_size) and (width, height) == (sm.width, sm.height):
        return sm.blocked.copy()
    cs = sm.cell_size
    xs = np.arange(width) * resolution
    ys = np.arange(height) * resolution
    # Map cell indices overlapping the open interval (lo - grow, hi + grow); the grown square
    # is approximated by a box (conservative: it contains the Euclidean growth).
    x0 = np.floor((xs - grow) / cs + 1e-9).astype(int)
    x1 = np.ceil((xs + resolution + grow) / cs - 1e-9).astype(int)
    y0 = np.floor((ys - grow) / cs + 1e-9).astype(int)
    y1 = np.ceil((ys + resolution + grow) / cs - 1e-9).astype(int)
    X0, Y0 = np.meshgrid(x0, y0, indexing="xy")
    X1, Y1 = np.meshgrid(x1, y1, indexing="xy")
    return sm.count_blocked(X0, Y0, X1, Y1) > 0
