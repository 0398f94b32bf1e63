"""The walker-evasion risk of every move of the robots near random walkers, for a grid
controller: one :class:`~swarmpath.control.evasion.walker.WalkerEvasion` per kind of walker in
the world, queried for each robot against each walker within reach, the walkers taken as
independent (1 - prod(1 - risk)), except the two nearest of a robot with two walkers close by,
which are played together for two steps (:mod:`~swarmpath.control.evasion.pair`)."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.evasion.pair import PAIR_RADIUS, pair_move_risk
from swarmpath.control.evasion.walker import EVASION_RADIUS, WalkerEvasion, walker_model
from swarmpath.control.hazards import RANDOM_WALK, ObstacleForecast
from swarmpath.world.move_rules import GRID_MOVES

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class EvasionRisk:
    """Walker-evasion risk for the grid robots of one world.

    Walkers whose steps are one grid cell (``random-walk`` with step length = the grid's
    resolution) are modelled exactly, one :class:`WalkerEvasion` per footprint shape; other
    obstacles are not (the look-ahead tiers cover them). A walker off a cell centre (it started
    there) is skipped.

    Parameters
    ----------
    world, grid : the world and the controller's grid (robots move between its cell centres)
    moves : bool (height, width, 9), the robots' static moves
    forecast : the controller's :class:`~swarmpath.control.hazards.ObstacleForecast`
    robot_radius : the robots' (largest) radius
    horizon : steps looked ahead (>= 1)
    pair_radius : a robot with two walkers within this many cells plays the nearest two together
        (:mod:`~swarmpath.control.evasion.pair`; needs ``horizon`` >= 2); 0 takes every walker
        as independent
    """

    def __init__(self, world, grid, moves: NDArray[np.bool_], forecast: ObstacleForecast, robot_radius: float,
                 horizon: int, pair_radius: int = PAIR_RADIUS):
        self.pair_radius = int(pair_radius) if horizon >= 2 else 0
        self.resolution = grid.resolution
        self.shape = grid.blocked.shape
        self.moves = np.asarray(moves, bool)
        res = grid.resolution
        walkers = np.flatnonzero((forecast.code == RANDOM_WALK) & np.isclose(forecast.walk_step, res))
        self.groups: list[tuple[WalkerEvasion, IntArray]] = []
        if len(walkers) == 0:
            return
        h, w = self.shape
        ys, xs = np.mgrid[0:h, 0:w]
        centres = (np.stack([xs, ys], axis=-1) + 0.5) * res                   # (h, w, 2)
        for shape_id in np.unique(forecast.shape_of[walkers]):
            members = walkers[forecast.shape_of[walkers] == shape_id]
            j = int(members[0])
            where = (centres[:, :, None, :] + GRID_MOVES[None, None] * res).reshape(-1, 2)
            fits = forecast.fits(np.full(len(where), j), where).reshape(h, w, 9)
            model = walker_model(world.moving_obstacles[j].placed((0.0, 0.0)), fits, robot_radius, res)
            self.groups.append((WalkerEvasion(moves, model, horizon), members))

    def modelled(self, obstacle_positions: FloatArray) -> NDArray[np.bool_]:
        """Which obstacles (m,) :meth:`move_risk` accounts for: the walkers standing on a cell
        centre."""
        positions = np.asarray(obstacle_positions, float).reshape(-1, 2)
        out = np.zeros(len(positions), bool)
        for _, members in self.groups:
            out[members] = self._on_centre(positions[members])
        return out

    def _on_centre(self, p: FloatArray) -> NDArray[np.bool_]:
        res = self.resolution
        wc = np.floor(p / res + 1e-9)
        return np.all(np.abs(p - (wc + 0.5) * res) <= 1e-9 * max(res, 1.0), axis=1)

    def move_risk(self, cells: IntArray, obstacle_positions: FloatArray) -> FloatArray:
        """For robots on grid ``cells`` (r, 2): the chance that each of their 9 moves meets a
        walker within the horizon, shape (r, 9); 0 everywhere when no walker is within
        :data:`EVASION_RADIUS` cells; 1 for moves the static map forbids. The walkers are taken
        as independent, except that a robot with two within ``pair_radius`` cells plays the
        nearest two together (:func:`~swarmpath.control.evasion.pair.pair_move_risk`): its
        risk from them is the larger of that and their independent product."""
        cells = np.asarray(cells, np.int64).reshape(-1, 2)
        clear = np.ones((len(cells), 9))
        res = self.resolution
        positions = np.asarray(obstacle_positions, float).reshape(-1, 2)
        found = []                      # per group: robot rows, walker cells, distances, risks
        for g, (table, members) in enumerate(self.groups):
            p = positions[members]
            wc = np.floor(p / res + 1e-9).astype(np.int64)[self._on_centre(p)]
            if len(wc) == 0:
                continue
            off = np.abs(wc[None, :, :] - cells[:, None, :]).max(axis=2)               # (r, k)
            ri, wi = np.nonzero(off <= EVASION_RADIUS)
            if len(ri) == 0:
                continue
            risk = table.move_risk(cells[ri], wc[wi])
            found.append((np.full(len(ri), g), ri, wc[wi], off[ri, wi], risk))
        if found:
            group, rows, walkers, dist, risk = (np.concatenate(x) for x in zip(*found))
            paired = np.zeros(len(rows), bool)
            if self.pair_radius > 0:
                close = dist <= self.pair_radius
                for i in np.flatnonzero(np.bincount(rows[close], minlength=len(cells)) >= 2):
                    mine = np.flatnonzero((rows == i) & close)
                    x, y = mine[np.argsort(dist[mine], kind="stable")[:2]]
                    joint = pair_move_risk(self.groups[group[x]][0], self.groups[group[y]][0], self.moves,
                                           cells[i], walkers[x], walkers[y])
                    alone = 1 - (1 - risk[x]) * (1 - risk[y])
                    clear[i] *= 1 - np.maximum(joint, alone)
                    paired[[x, y]] = True
            rest = ~paired
            np.multiply.at(clear, rows[rest], 1 - risk[rest])
        h, w = self.shape
        allowed = self.moves[np.clip(cells[:, 1], 0, h - 1), np.clip(cells[:, 0], 0, w - 1)]
        return np.where(allowed, 1 - clear, 1.0)


#: A candidate the walker value rates this many times riskier than the safest allowed one ...
VETO_FACTOR = 10.0
#: ... and at least this much riskier (a chance over the horizon) is left out of the look-ahead
#: tiers (:func:`walker_vetoed`).
VETO_MARGIN = 2e-3


def walker_vetoed(allowed: NDArray[np.bool_], risk: FloatArray | None, factor: float = VETO_FACTOR,
                  margin: float = VETO_MARGIN) -> NDArray[np.bool_]:
    """The candidates (r, 9) the look-ahead tiers may not pick: among ``allowed`` (r, 9),
    those whose walker ``risk`` (r, 9, from :meth:`EvasionRisk.move_risk`) exceeds both
    ``factor`` times and ``margin`` plus the smallest risk of an allowed candidate.

    Why: the tiers take the obstacles at their worst over a few steps, and a walker at its worst
    reaches a dead-end pocket last; so the tiers sent a robot fleeing a walker into a pocket
    whose only way out was toward the walker, where the exact chance of being caught was 20
    times that of the corridor beside it (64 x 64 acceptance world, cat-swarm seed 5: caught)."""
    allowed = np.asarray(allowed, bool)
    if risk is None:
        return np.zeros(allowed.shape, bool)
    risk = np.asarray(risk, float)
    best = np.where(allowed, risk, np.inf).min(axis=1, keepdims=True)
    limit = np.maximum(factor * best, best + margin)
    return allowed & (risk > limit)


def vetoed_last(rank: NDArray[np.int64], allowed: NDArray[np.bool_], vetoed: NDArray[np.bool_]) -> NDArray[np.int64]:
    """``rank`` (r, 9) (look-ahead ranks, lower first) with each ``vetoed`` candidate that is
    still ``allowed`` (a robot that must leave may take it) ranked after every other allowed
    candidate of its robot.

    Why: the tiers and the turn game rank only the candidates they are given, and a vetoed one
    is not among them, so it kept the rank it had before and could come first. With the veto
    at twice the safest chance, on seed 8477 of the 64 x 64 acceptance world the turn game put
    the two open cells beside a robot at rank 6 and left the vetoed cell in front of a pocket
    at 4, and the robot took it and was caught there two steps later."""
    rank = np.asarray(rank, np.int64)
    vetoed = np.asarray(vetoed, bool) & np.asarray(allowed, bool)
    if not vetoed.any():
        return rank
    legit = np.asarray(allowed, bool) & ~vetoed
    top = np.where(legit, rank, -1).max(axis=1, keepdims=True)
    return np.where(vetoed, np.maximum(rank, top + 1), rank)


def check_evasion(horizon, weight, controller: str) -> None:
    """Raise :class:`~swarmpath.errors.ConfigError` naming the setting unless ``horizon`` is a
    whole number >= 0 and ``weight`` a finite number >= 0 (the controllers' evasion settings)."""
    from swarmpath.errors import ConfigError

    if isinstance(horizon, bool) or not isinstance(horizon, (int, np.integer)) or horizon < 0:
        raise ConfigError(f"{controller}: evasion_horizon must be a whole number >= 0, got {horizon!r}")
    if isinstance(weight, bool) or not isinstance(weight, (int, float, np.integer, np.floating)) \
            or not np.isfinite(weight) or weight < 0:
        raise ConfigError(f"{controller}: evasion_weight must be a finite number >= 0, got {weight!r}")
