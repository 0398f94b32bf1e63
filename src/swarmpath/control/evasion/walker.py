"""The walker-evasion value: how likely a robot is to be hit by a random walker within the next
steps when it dodges as well as it can.

A random walker (motion ``random-walk``) steps each step to one of the grid directions its
footprint fits in, each as likely as the others. Against one walker a robot's best play is a
finite-horizon Markov decision problem on (robot cell, walker offset), solved exactly by
dynamic programming (Bellman's backward induction):

    V_0 = 0,
    V_k(r, o) = min_a  sum_d P(r + o, d) * ( 1                          if sweep d hits r + a
                                             V_(k-1)(r + a, o + d - a)  otherwise ),

the state taken just after the walker's move (what the controller sees), a ranging over the
robot's static moves (staying included) that do not enter or cross the walker's footprint
where it stands (the checker's phase 2), d over the walker's next steps with chance
P(w, d), and "hits" deciding by the checker's own geometry (:func:`~swarmpath.world.
move_rules.footprint_hits`, phase 1) whether the walker's sweep meets the robot resting on
its cell. Offsets beyond ``radius`` cells count as escaped (value 0): the robot has kept its
distance. The risk of a robot's move a now is the same sum with V_(horizon-1): the chance of a
contact within ``horizon`` steps, this step's included, if the robot keeps playing best.

Why not the worst case: a walker that *may* reach a cell in three steps reaches nearly every
cell around a robot, so worst-case look-aheads stop telling the moves apart two or three cells
from a walker; the chances still do (a corner is caught, the open is not). Why not sampled
futures: the exact value costs less than enough samples, and has no noise.

The value depends on the static map around the two, not on the time, so it is computed once
per run, lazily: in square tiles of ``tile`` x ``tile`` cells, each layer k of a tile from
layer k - 1 of the tile and a one-cell border (a small C kernel, ``_evasion.c``), only where a
query needs it. Other robots and other obstacles are not in the state: the controller's
priority step and look-ahead tiers deal with those; several walkers near one robot are
combined as independent (1 - prod(1 - risk)), except two close to it, which are played
together for two steps (:mod:`~swarmpath.control.evasion.pair`).
"""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.evasion import _evasion
from swarmpath.world.move_rules import GRID_MOVES, footprint_hits

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]

#: Offsets (cells, Chebyshev) beyond which a walker counts as escaped from.
EVASION_RADIUS = 5
#: Side of the square tiles the value is computed and kept in.
TILE = 8
#: Memory kept for computed tiles: beyond it the least recently used tiles are dropped (and
#: computed again if a later query needs them). The whole 8-step table of a 512 x 512 map
#: (about 970 MiB) fits; with 256 MiB, 1,000 robots near 200 walkers spread over such a map
#: needed more tiles every step than the cap held and a step took 3.6 s instead of 0.05 s.
MAX_BYTES = 2 ** 30


@dataclass(frozen=True)
class WalkerModel:
    """One kind of grid walker against robots of one radius, as the dynamic program sees it.

    chances : float32 (height, width, 9)
        P(w, d): the chance that a walker on cell w steps by ``GRID_MOVES[d]`` (d = 0: it
        stays, only when no direction fits); all 0 on cells where it cannot stand.
    hit : uint8 (9, K + 2, K + 2), K = 2 radius + 1
        hit[d, cy, cx]: the walker's sweep d hits a robot resting at offset
        (cx, cy) - (radius + 1) from the walker's start.
    forbid : uint8 (9, K, K)
        forbid[a, oy, ox]: robot move a enters or crosses the walker's footprint standing at
        offset (ox, oy) - radius (or the robot is inside it already).
    """

    chances: NDArray[np.float32]
    hit: NDArray[np.uint8]
    forbid: NDArray[np.uint8]
    radius: int


def walker_model(shape, fits: BoolArray, robot_radius: float, resolution: float,
                 radius: int = EVASION_RADIUS) -> WalkerModel:
    """The :class:`WalkerModel` of walkers with footprint ``shape`` (placed at the origin)
    stepping one cell at a time, where ``fits`` (height, width, 9) says whether the footprint
    fits after step d from each cell (index 0: on the cell itself) as the motion model
    decides, against robots of ``robot_radius`` moving between cell centres."""
    fits = np.asarray(fits, bool)
    steps = fits[..., 1:] & fits[..., :1]
    boxed = fits[..., 0] & ~steps.any(axis=-1)
    chances = np.zeros(fits.shape, np.float32)
    chances[..., 1:] = steps / np.maximum(steps.sum(axis=-1, keepdims=True), 1)
    chances[..., 0] = boxed
    K = 2 * radius + 1
    span = np.arange(-(radius + 1), radius + 2)
    cx, cy = np.meshgrid(span, span)                                       # (K + 2, K + 2)
    rest = np.stack([cx, cy], axis=-1).reshape(-1, 2) * resolution
    r = np.full(len(rest), float(robot_radius))
    hit = np.stack([footprint_hits(shape, rest, rest - d * resolution, r) for d in GRID_MOVES])
    span = np.arange(-radius, radius + 1)
    ox, oy = np.meshgrid(span, span)
    offsets = np.stack([ox, oy], axis=-1).reshape(-1, 2) * resolution
    r = np.full(len(offsets), float(robot_radius))
    forbid = np.stack([footprint_hits(shape, -offsets, a * resolution - offsets, r) for a in GRID_MOVES])
    return WalkerModel(chances, hit.reshape(9, K + 2, K + 2).astype(np.uint8),
                       forbid.reshape(9, K, K).astype(np.uint8), radius)


class WalkerEvasion:
    """The walker-evasion value of one map (module docstring), computed lazily.

    Parameters
    ----------
    moves : bool array (height, width, 9)
        The robots' static moves from each cell in ``GRID_MOVES`` order (index 0: the cell is
        free), as the controller allows them (4- or 8-connected, no corner cutting).
    model : WalkerModel
        The walkers' step chances and contact geometry.
    horizon : int
        Steps looked ahead (>= 1): the risk of a move is the chance of a contact within this
        many steps.
    """

    def __init__(self, moves: BoolArray, model: WalkerModel, horizon: int):
        self.model = model
        self.horizon = int(horizon)
        self.R = model.radius
        self.K = 2 * self.R + 1
        moves = np.asarray(moves, bool)
        self.shape = moves.shape[:2]
        h, w = self.shape
        T, R = TILE, self.R
        self.ny, self.nx = -(-h // T), -(-w // T)
        self.moves_ = np.zeros((self.ny * T, self.nx * T, 9), np.uint8)
        self.moves_[:h, :w] = moves
        self.chances_ = np.zeros((self.ny * T + 2 * R, self.nx * T + 2 * R, 9), np.float32)
        self.chances_[R:R + h, R:R + w] = model.chances
        #: computed tiles by (layer, tx, ty), least recently used first
        self.tiles_: OrderedDict[tuple[int, int, int], NDArray[np.float32]] = OrderedDict()
        self.bytes_ = 0

    # ------------------------------------------------------------------ tiles
    def _tile(self, k: int, tx: int, ty: int) -> NDArray[np.float32]:
        """Layer k (0 <= k < horizon) on tile (tx, ty): float32 (TILE, TILE, K, K)."""
        out = self.tiles_.get((k, tx, ty))
        if out is not None:
            self.tiles_.move_to_end((k, tx, ty))
            return out
        T, K, R = TILE, self.K, self.R
        out = np.zeros((T, T, K, K), np.float32)
        if k > 0:
            prev = np.zeros((T + 2, T + 2, K, K), np.float32)
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    x, y = tx + dx, ty + dy
                    if not (0 <= x < self.nx and 0 <= y < self.ny):
                        continue
                    src = self._tile(k - 1, x, y)
                    ys = slice(0, T) if dy == 0 else (slice(T - 1, T) if dy < 0 else slice(0, 1))
                    xs = slice(0, T) if dx == 0 else (slice(T - 1, T) if dx < 0 else slice(0, 1))
                    yd = slice(1, T + 1) if dy == 0 else (slice(0, 1) if dy < 0 else slice(T + 1, T + 2))
                    xd = slice(1, T + 1) if dx == 0 else (slice(0, 1) if dx < 0 else slice(T + 1, T + 2))
                    prev[yd, xd] = src[ys, xs]
            moves = np.ascontiguousarray(self.moves_[ty * T:(ty + 1) * T, tx * T:(tx + 1) * T])
            chances = np.ascontiguousarray(self.chances_[ty * T:ty * T + T + 2 * R, tx * T:tx * T + T + 2 * R])
            _evasion.layer(T, R, prev, moves, chances, self.model.hit, self.model.forbid, out)
        self.tiles_[(k, tx, ty)] = out
        self.bytes_ += out.nbytes
        return out

    def _evict(self) -> None:
        """Drop the least recently used tiles until the memory kept is within MAX_BYTES (called
        before each query: the tiles the robots near walkers use step after step stay)."""
        while self.bytes_ > MAX_BYTES and self.tiles_:
            _, tile = self.tiles_.popitem(last=False)
            self.bytes_ -= tile.nbytes

    def values(self, k: int, cells: IntArray) -> NDArray[np.float32]:
        """V_k (module docstring) at grid ``cells`` (n, 2), shape (n, K, K) indexed [oy + R,
        ox + R]; 0 for k = 0 and off the grid."""
        cells = np.asarray(cells, np.int64).reshape(-1, 2)
        out = np.zeros((len(cells), self.K, self.K), np.float32)
        if k == 0 or len(cells) == 0:
            return out
        h, w = self.shape
        inside = (cells[:, 0] >= 0) & (cells[:, 0] < w) & (cells[:, 1] >= 0) & (cells[:, 1] < h)
        for i in np.flatnonzero(inside):
            x, y = int(cells[i, 0]), int(cells[i, 1])
            out[i] = self._tile(k, x // TILE, y // TILE)[y % TILE, x % TILE]
        return out

    # ------------------------------------------------------------------ queries
    def move_risk(self, robots: IntArray, walkers: IntArray) -> FloatArray:
        """For pairs of a robot on grid cell ``robots[p]`` and a walker on cell ``walkers[p]``
        (shapes (p, 2), the walker just moved): the chance that each of the robot's 9 moves
        (``GRID_MOVES`` order) ends in a contact with that walker within ``horizon`` steps,
        this step's included, when the robot plays best afterwards; shape (p, 9). A move the
        static map forbids, or into or through the walker where it stands, scores 1; a walker
        farther than ``radius`` cells scores 0 for every allowed move."""
        self._evict()
        robots = np.asarray(robots, np.int64).reshape(-1, 2)
        walkers = np.asarray(walkers, np.int64).reshape(-1, 2)
        R, K = self.R, self.K
        h, w = self.shape
        allowed = self.moves_[np.clip(robots[:, 1], 0, h - 1), np.clip(robots[:, 0], 0, w - 1)].astype(bool)
        out = np.where(allowed, 0.0, 1.0)
        o = walkers - robots
        near = np.flatnonzero(np.abs(o).max(axis=1) <= R)
        if len(near) == 0:
            return out
        r, o, allowed = robots[near], o[near], allowed[near]
        q = len(near)
        after = r[:, None, :] + GRID_MOVES[None]                                    # (q, 9, 2)
        V = self.values(self.horizon - 1, after.reshape(-1, 2)).reshape(q, 9, K, K)
        wc = r + o
        P = self.model.chances[wc[:, 1], wc[:, 0]].astype(float)                    # (q, 9)
        a, d = GRID_MOVES[None, :, None, :], GRID_MOVES[None, None, :, :]           # (1, 9, 1, 2), (1, 1, 9, 2)
        n = o[:, None, None, :] + d - a                                             # (q, 9, 9, 2)
        inside = np.abs(n).max(axis=-1) <= R
        ni = np.clip(n + R, 0, K - 1)
        qi = np.arange(q)[:, None, None]
        ai = np.arange(9)[None, :, None]
        later = np.where(inside, V[qi, ai, ni[..., 1], ni[..., 0]], 0.0)
        c = a - o[:, None, None, :] + R + 1                                         # (q, 9, 1, 2)
        c = np.broadcast_to(c, n.shape)
        hits = self.model.hit[np.arange(9)[None, None, :], c[..., 1], c[..., 0]].astype(bool)
        risk = np.sum(P[:, None, :] * np.where(hits, 1.0, later), axis=-1)          # (q, 9)
        forbid = self.model.forbid[np.arange(9)[None, :], (o[:, 1] + R)[:, None], (o[:, 0] + R)[:, None]].astype(bool)
        out[near] = np.where(allowed & ~forbid, np.minimum(risk, 1.0), 1.0)
        return out
