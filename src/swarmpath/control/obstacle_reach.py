"""Where an obstacle of uncertain heading can be in k steps, walls counted: the boxes of the
forecast cut to the cells it can reach.

The forecast (:class:`~swarmpath.control.hazards.ObstacleForecast`) bounds an obstacle that
may head anywhere (a random walker, a turn-every obstacle between its known steps, a bouncer
at a full stop) by a box: within k steps of travel of where it is, in every direction. In open
space that is tight. Across a wall it is not: in a maze of 2-wide passages behind 1-cell walls,
a walker in the next passage "reaches" a robot's cell through the wall in two steps, though
its way round is twenty. Robots at the mouth of a dead end then saw every cell of it covered
within their look-ahead and waited there for hundreds of steps (bench_narrow, maze worlds).

Models that only move their footprint to where it fits (``Motion.stays_clear``: bounce,
bounce8, turn-every, random-walk) go round walls. For them the box is cut to the cells the
obstacle can reach on the free cells. All lengths below are in cells:

- The footprint holds a disc of radius ``rho`` round its centre (a circle's radius, a box's
  least half-extent). Where it fits, the centre is at least ``rho`` from every blocked square,
  so it never lies in a blocked cell of the raster.
- A step moves the centre along a segment of length at most ``L``, at most ``s`` per axis. A
  blocked cell on its way can only be a corner it cuts (in through one side, out through the
  next): to pass a stretch of blocked cells one cell long, the segment would need ``1 + 2 rho``
  (a random walker's diagonal step ``sqrt(2) (1 + rho sqrt(2))``), and a step that short cannot
  clear a wall. The free cells it passes then form a chain of moves to the 8 neighbours (a
  diagonal may cut a blocked corner). The segment crosses at most ``ceil(s)`` cell borders per
  axis, and for ``s < 2`` two crossings of one axis always have one of the other between them
  (each pair is more than half the segment apart), so the chain pairs them into ``ceil(s)``
  moves; for longer steps, ``2 ceil(s)`` moves bound it. So ``R_0`` is the cell of the centre,
  and ``R_t`` adds to ``R_{t-1}`` the free cells within that many moves on free cells: a walker
  of one cell's width never reaches the passage behind a wall one cell thick. A model with a
  longer step may jump a wall: then ``R_t`` adds every free cell within ``ceil(s)`` cells
  (Chebyshev) of ``R_{t-1}``.
- The cells whose centres the footprint (half-extent ``E``, grown by the robots' radius) can
  cover during step t: within ``E`` of a point of the segment. Points in a cell of the chain
  (in ``R_t``) cover cells within ``ceil(E + 1/2) - 1`` of it. A corner cut into a blocked cell
  is a chord shorter than ``c = L - 2 rho``, and each of its points lies within ``c / (2
  sqrt(2))`` of the free cell beside it. So the footprint covers cells within ``ceil(E + c /
  (2 sqrt(2)) + 1/2) - 1`` of ``R_t``: one cell for walkers of one cell's width, the wall cells
  beside it and never the passage behind. A model that may jump: ``ceil(E + L / 2 + 1/2) - 1``
  (every point of a segment lies within ``L / 2`` of one of its ends).

The cut is the box's cells that lie in that set, listed as runs along rows. It never drops a
cell the obstacle can cover (the box and the reach set each hold every such cell), so every
guarantee of the forecast stands; it only drops cells behind walls.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Reach sets kept between calls (keyed by start cell, hop, steps and dilation) before the
#: memo is emptied: the same obstacles are asked about many times in one step.
MEMO_LIMIT = 20_000


def centre_cells(world, resolution: float, shape: tuple[int, int]) -> BoolArray | None:
    """The cells (height, width) at ``resolution`` in which the centre of a footprint that fits
    may lie: all but the static map's blocked cells. None when the static map's cells are not
    the grid's (another cell size or shape): then nothing is cut."""
    sm = world.static_map
    if sm is None:
        return np.ones(shape, bool)
    if abs(sm.cell_size - resolution) > 1e-12 or tuple(sm.blocked.shape) != tuple(shape):
        return None
    return ~np.asarray(sm.blocked, bool)


def dilate(cells: BoolArray, radius: int) -> BoolArray:
    """The cells within ``radius`` (Chebyshev) of a True cell of ``cells`` (h, w), same shape."""
    if radius <= 0:
        return cells.copy()
    h, w = cells.shape
    padded = np.pad(cells, radius)
    out = np.zeros((h, w), bool)
    # separable: along x, then along y
    along_x = np.zeros((h + 2 * radius, w), bool)
    for dx in range(2 * radius + 1):
        along_x |= padded[:, dx:dx + w]
    for dy in range(2 * radius + 1):
        out |= along_x[dy:dy + h, :]
    return out


def row_runs(mask: BoolArray, x0: int, y0: int) -> IntArray:
    """The True cells of ``mask`` (h, w), whose cell [0, 0] is (``x0``, ``y0``), as cell ranges
    (k, 4) (x0, y0, x1, y1), one per run along a row."""
    h, w = mask.shape
    edges = np.diff(np.pad(mask.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    ys, starts = np.nonzero(edges == 1)
    _, ends = np.nonzero(edges == -1)
    # nonzero lists row by row, left to right: the k-th start and the k-th end pair up
    return np.stack([starts + x0, ys + y0, ends + x0, ys + y0 + 1], axis=1).astype(np.int64)


class WallAwareReach:
    """Cuts forecast boxes to the cells an obstacle can reach on ``free`` (height, width): the
    cells a fitting footprint's centre may lie in (:func:`centre_cells`)."""

    def __init__(self, free: BoolArray):
        self.free = np.asarray(free, bool)
        self.shape = self.free.shape
        # (start x, start y, hop, jump): (x0, y0, radius of the window, [R_0, R_1, ...])
        self._reach: dict[tuple[int, int, int, bool], tuple[int, int, int, list[BoolArray]]] = {}
        self._memo: dict[tuple[int, int, int, int, int, bool], tuple[int, int, BoolArray] | None] = {}

    def covered(self, start: tuple[int, int], hop: int, steps: int, dil: int, jump: bool = False
                ) -> tuple[int, int, BoolArray] | None:
        """Cells within ``dil`` of ``R_steps`` from ``start`` (module docstring; ``hop`` moves
        on free cells a step, or with ``jump`` one hop of ``hop`` cells over anything), on a
        window: (x0, y0, mask) with mask[dy, dx] for cell (x0 + dx, y0 + dy), clipped to the
        grid. None for a centre off the grid (nothing is cut then)."""
        key = (int(start[0]), int(start[1]), int(hop), int(steps), int(dil), bool(jump))
        if key in self._memo:
            return self._memo[key]
        h, w = self.shape
        sx, sy = key[0], key[1]
        if not (0 <= sx < w and 0 <= sy < h):
            return None
        x0, y0, sets = self._reach_sets((sx, sy), int(hop), int(steps), int(dil), bool(jump))
        out = (x0, y0, dilate(sets[min(steps, len(sets) - 1)], int(dil)))
        if len(self._memo) >= MEMO_LIMIT:
            self._memo.clear()
        self._memo[key] = out
        return out

    def _reach_sets(self, start: tuple[int, int], hop: int, steps: int, dil: int, jump: bool
                    ) -> tuple[int, int, list[BoolArray]]:
        """R_0 ... R_steps (or fewer, once they stop growing) from ``start`` on a window wide
        enough for ``steps`` and ``dil``: the sets of one obstacle are grown once a step and
        reused for every look-ahead depth asked of it."""
        key = (start[0], start[1], hop, jump)
        need = steps * hop + dil
        entry = self._reach.get(key)
        if entry is None or entry[2] < need:
            h, w = self.shape
            rad = max(need, 8 * hop + 2)
            sx, sy = start
            x0, y0 = max(sx - rad, 0), max(sy - rad, 0)
            first = np.zeros((min(sy + rad + 1, h) - y0, min(sx + rad + 1, w) - x0), bool)
            first[sy - y0, sx - x0] = True
            entry = (x0, y0, rad, [first])
            if len(self._reach) >= MEMO_LIMIT:
                self._reach.clear()
            self._reach[key] = entry
        x0, y0, rad, sets = entry
        if len(sets) <= steps and (len(sets) < 2 or (sets[-1] != sets[-2]).any()):
            free = self.free[y0:y0 + sets[0].shape[0], x0:x0 + sets[0].shape[1]]
            size, times = (hop, 1) if jump else (1, hop)
            while len(sets) <= steps:
                reach = sets[-1]
                for _ in range(times):
                    reach = reach | (dilate(reach, size) & free)
                sets.append(reach)
                if (reach == sets[-2]).all():
                    break
        return x0, y0, sets

    def cut(self, boxes: IntArray, owners: IntArray, starts: IntArray, hops: IntArray, steps: IntArray,
            dils: IntArray, jumps: BoolArray) -> tuple[IntArray, IntArray]:
        """Boxes (q, 4) of obstacles ``owners`` (q,), each cut to the cells the obstacle can
        cover: from the cell ``starts`` (q, 2) of its centre, ``steps`` (q,) steps of ``hops``
        (q,) moves (or jumps, ``jumps`` (q,)), covering ``dils`` (q,) cells around
        (:meth:`covered`). Returns the ranges and their owners; a box inside its reach set
        comes back whole."""
        if len(boxes) == 0:
            return boxes, owners
        h, w = self.shape
        out_boxes: list[IntArray] = []
        out_owners: list[IntArray] = []
        for q in range(len(boxes)):
            bx0, by0, bx1, by1 = (int(v) for v in boxes[q])
            cx0, cy0, cx1, cy1 = max(bx0, 0), max(by0, 0), min(bx1, w), min(by1, h)
            if cx0 >= cx1 or cy0 >= cy1:
                continue                  # off the grid: covers no cell
            window = self.covered(tuple(starts[q]), int(hops[q]), int(steps[q]), int(dils[q]), bool(jumps[q]))
            if window is None:
                out_boxes.append(boxes[q:q + 1].astype(np.int64))
                out_owners.append(owners[q:q + 1].astype(np.int64))
                continue
            x0, y0, mask = window
            mh, mw = mask.shape
            # the box's cells on the mask's window; cells of the box outside it are out of reach
            sub = np.zeros((cy1 - cy0, cx1 - cx0), bool)
            ix0, iy0 = max(cx0, x0), max(cy0, y0)
            ix1, iy1 = min(cx1, x0 + mw), min(cy1, y0 + mh)
            if ix0 < ix1 and iy0 < iy1:
                sub[iy0 - cy0:iy1 - cy0, ix0 - cx0:ix1 - cx0] = mask[iy0 - y0:iy1 - y0, ix0 - x0:ix1 - x0]
            if sub.all():
                out_boxes.append(np.array([[cx0, cy0, cx1, cy1]], np.int64))
            elif sub.any():
                out_boxes.append(row_runs(sub, cx0, cy0))
            else:
                continue
            out_owners.append(np.full(len(out_boxes[-1]), owners[q], np.int64))
        if not out_boxes:
            return np.zeros((0, 4), np.int64), np.zeros(0, np.int64)
        return np.concatenate(out_boxes), np.concatenate(out_owners)


def reach_rule(step: float, length: float, rho: float, extent: float, walker: bool, margin: int = 0
               ) -> tuple[int, bool, int]:
    """How to bound a model's reach (module docstring): (moves a step, jumps, cells covered
    round the reach set). ``step``: its most travel a step per axis, ``length``: along its
    path, ``rho``: the radius of the disc its footprint holds, ``extent``: the half-extent of
    its footprint grown by the robots' radius, all in cells; ``walker``: it steps along the 8
    grid directions only (a random walker), whose diagonal crosses a wall's corner at length
    sqrt(2) at least."""
    clear = step < 1 + rho * math.sqrt(2) if walker else length < 1 + 2 * rho
    if clear:
        chord = max(0.0, length - 2 * rho)
        dil = math.ceil(extent + chord / (2 * math.sqrt(2)) + 0.5 - 1e-9) - 1
        moves = math.ceil(step - 1e-9)
        return (moves if step < 2 else 2 * moves), False, max(0, dil) + int(margin)
    dil = math.ceil(extent + length / 2 + 0.5 - 1e-9) - 1
    return math.ceil(step - 1e-9), True, max(0, dil) + int(margin)


__all__ = ["WallAwareReach", "centre_cells", "dilate", "reach_rule", "row_runs"]
