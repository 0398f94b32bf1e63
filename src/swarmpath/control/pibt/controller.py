"""The ``pibt`` controller: PIBT (Okumura et al., AIJ 2022) as an online controller.

Every step: the robots' cells, the exact distance to goal of every candidate cell (lazy
per-goal tables, :mod:`swarmpath.search.lazy_distance`), the cells a moving obstacle may
reach in the next steps around the robots it can reach
(:func:`~swarmpath.control.hazards.hazard_windows`), the priorities of section 3.2, then one
PIBT step in C (:func:`swarmpath.control.pibt.core.pibt_step`). Robot-robot moves obey the
checker's own rule (``move_rules.grid_conflict_table``), so without moving obstacles the
checker finds no contact.

Cells and positions: robots move between cell centres of ``world.grid(radius=max radius)``;
a robot that starts off a centre first settles on its cell's centre (or moves straight to a
neighbour centre within reach), and a robot entering its goal cell goes to its exact goal
when it is within reach (else to the cell centre, then the goal). In its goal cell a robot's
distances are the move costs themselves, so its table is released on arrival (and taken
again, lazily, if it is pushed farther away).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.cornered import last_resort, no_escape_events, ways_clear
from swarmpath.control.detour import DETOUR_AFTER, Lingering, detour_ranking
from swarmpath.control.evasion import EvasionRisk, check_evasion, vetoed_last, walker_vetoed
from swarmpath.control.finish import finishing_step, gathering_step, held_discs, off_centre_discs, waiting_home
from swarmpath.control.grid_robots import check_grid_robots
from swarmpath.control.hazards import (
    DEAD_END_EXTRA,
    ObstacleForecast,
    cornered_penalty,
    hazard_windows,
    next_to_dead_end,
    stay_depth,
    trap_cells,
)
from swarmpath.control.observation import Observation
from swarmpath.control.pibt.core import (
    DIAGONAL_MOVE,
    PUSHED,
    STAY,
    GridGraph,
    check_connectivity,
    decision_order,
    escape_claims,
    pibt_step_escaping,
    static_moves,
    update_priorities,
)
from swarmpath.control.pibt.exact import hold_conflicts
from swarmpath.control.pibt.joint_escape import prefer_joint_escapes
from swarmpath.control.pibt.rescue import (
    RESCUE_AFTER,
    RESCUE_WORK,
    StallRescue,
    check_rescue,
    planned_decision,
)
from swarmpath.control.progress import progress_update
from swarmpath.control.turn_game import TurnGame
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.search.lazy_distance import LazyDistanceTables, choose_landmarks
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
MOVE_COST = np.linalg.norm(GRID_MOVES, axis=1)
#: Added to a candidate's distance per step it is less clear of obstacles than the clearest.
CLEAR_WEIGHT = 1e6
#: Added per rank of the look-ahead (``HazardWindows.tiers``): a robot that must leave takes a
#: less cautious cell only when the more cautious ones are taken.
TIER_WEIGHT = 1e8
#: Times the cost of :func:`~swarmpath.control.cornered.last_resort` for a cornered robot:
#: the least likely hit first, the distance to the goal last.
LAST_RESORT_WEIGHT = 1e12
#: Added per robot that must leave its cell and needs a candidate's cell to get away
#: (:func:`~swarmpath.control.pibt.core.escape_claims`): after the look-ahead tier, before
#: everything else.
CLAIM_WEIGHT = 1e7


@register_controller("pibt")
class PIBTController(Controller):
    """Priority Inheritance with Backtracking, one grid step per simulator step.

    Parameters
    ----------
    connectivity : int
        8 (octile moves without corner cutting) or 4.
    swap : bool
        LaCAM3's swap emulation (True): two robots that must pass each other in a corridor
        (each one's goal lies behind the other) swap where the corridor branches, instead of
        pushing each other back and forth. False is the paper's PIBT, whose reachability
        guarantee (the highest-priority robot reaches its goal) holds.
    yield_way : bool
        A robot pushed off its goal steps out of the pusher's way rather than ahead of it
        (True; see :func:`~swarmpath.control.pibt.core.pibt_step`).
    lookahead : int
        With moving obstacles: how many steps beyond the next a robot makes sure it can keep
        clear of every obstacle whatever the obstacles do: it keeps to the deepest tier of
        :meth:`~swarmpath.control.hazards.HazardWindows.tiers` that leaves it a candidate (a
        dead end an obstacle is heading into is left while it still can be). 2 (default):
        two steps beyond the next; 0: the next step only. Every robot an obstacle can reach
        keeps every candidate, ranked by these tiers (a shallower one only when the deeper ones
        are taken: a robot that must leave its cell, or one pushed out of it), and one with no
        candidate in its deepest tier takes the cell with most ways
        on (:func:`~swarmpath.control.hazards.cornered_penalty`). A robot with a candidate in
        a dead end (:func:`~swarmpath.control.hazards.dead_end_cells`) or a pocket one
        obstacle can close (:func:`~swarmpath.control.hazards.pocket_cells`) looks
        ``DEAD_END_EXTRA`` (2) steps further: the way out is the way in, so it must leave
        before an obstacle can reach the mouth.
    leave_early : int
        With moving obstacles: robots an obstacle can reach rank first the candidates that
        stay clear of every obstacle longest over this many steps, and leave a cell an
        obstacle may reach that soon when a clearer one is free; 0 (default) ranks by
        distance alone. Larger values keep robots farther from obstacles, so they are
        seldom all home at once among obstacles that never stop (docs/algorithms/pibt.md).
    landmarks : int or "auto"
        Landmark cells of the distance tables' differential heuristic ("auto": 8 when there is
        a robot per 4,096 free cells or more, else 0; 0: octile only): about half the cells
        expanded on cluttered maps for a fixed cost of 8 distance fields at reset.
    release_at_goal : bool
        Free a robot's distance table when it reaches its goal cell (True).
    finish_together : bool
        With moving obstacles: on a step on which every robot can step onto its goal at once
        without any contact, all do, and the run ends (True; see
        :mod:`swarmpath.control.finish`). Robots wait beside goals an obstacle may enter next
        step, so otherwise they are seldom all home at one moment. Also in worlds without
        them when disc robots' goals lie off their cells' centres: such robots wait on the
        centres while others are near (:func:`~swarmpath.control.finish.held_discs`).
    hover : int or None
        With ``leave_early`` >= 2: within this many cells (Chebyshev) of its goal a robot
        keeps only the next step clear (as with ``leave_early=1``): 0 keeps robots on their
        goals until an obstacle may come next step, larger values keep them waiting beside
        threatened goals. With ``finish_together`` more runs then end with every robot home
        at once; waiting closer to obstacles costs some contacts from 1 cell on. None
        (default): ``leave_early`` applies everywhere. Measured in docs/algorithms/pibt.md.
    evasion_horizon : int
        With random walkers (``random-walk`` obstacles stepping one cell): a robot near one
        ranks its candidates, within their look-ahead tier, by the exact chance of being hit
        within this many steps if it dodges as well as it can afterwards
        (:mod:`swarmpath.control.evasion`), before the distance to its goal. 8 (default); 0:
        off.
    evasion_weight : float
        Cells of distance to its goal a robot gives up to lower that chance by 1 (1e4: a
        one-in-ten-thousand chance weighs as much as one cell).
    evasion_veto : bool
        With random walkers: the look-ahead tiers may not pick a move whose exact chance of
        being caught is both ten times and 0.002 above the safest clear move's
        (:func:`~swarmpath.control.evasion.walker_vetoed`); a robot that must leave still may,
        ranked last. The worst case reaches a dead end last, so without it robots fleeing a
        walker stepped into pockets whose only way out led back to it. True (default).
    gather : bool
        With ``finish_together``: when every robot is within two cells of its goal, all step
        to cells one move from their goals in one step, if that is safe and makes the
        finishing step likely next step (:func:`~swarmpath.control.finish.gathering_positions`).
        True (default).
    detour_after : int
        With moving obstacles: a robot that has not come closer to its goal for this many
        steps ranks its moves by the way round the cells where obstacles have lingered lately
        (:mod:`swarmpath.control.detour`) instead of the static distance: an obstacle
        shuttling on its shortest way no longer holds it for good.
        8 (default); 0: off.
    turn_game : bool
        With moving obstacles: a robot a turning bounce8 obstacle can reach (one whose
        straight run meets something within four steps) ranks its candidates by how many of
        the next four steps it can keep clear when it watches the obstacle turn and reacts
        (:mod:`swarmpath.control.turn_game`: a small game tree), instead of the open-loop tiers
        that take every turn at once. True (default).
    rescue_after : int
        In a static world: when for this many steps no robot away from its goal has come
        closer to it than before, one robot has been pushed to and fro this many times
        without coming closer, or for twice as many steps the robots' summed distance has not
        fallen, LaCAM plans the rest of the run from where the robots stand and they follow
        that plan (:mod:`swarmpath.control.pibt.rescue`); PIBT alone can shuttle for ever
        where a goal lies at the bottom of a dead end behind a robot already home. 24
        (default); 0: off.
    rescue_work : int
        Budget of the run's LaCAM searches together in robot moves (PIBT calls times robots;
        10^8, about 5 to 50 s), the same on any machine so that a seed decides the run; at
        most three searches a run.
    joint_escape : bool
        With moving obstacles: robots that must or should leave their cells and stand within
        two cells of one another choose their moves together, the combination of least total
        ranking key that the checker allows (:mod:`swarmpath.control.pibt.joint_escape`),
        instead of whoever decides first taking the cell the next one needed. True (default).
    """

    capabilities = Capabilities(grid_based=True, moving_obstacles=True, multi_robot=True, randomized=True)

    def __init__(self, connectivity: int = 8, swap: bool = True, yield_way: bool = True, lookahead: int = 2,
                 landmarks: int | str = "auto", release_at_goal: bool = True, leave_early: int = 0,
                 finish_together: bool = True, hover: int | None = None, evasion_horizon: int = 8,
                 evasion_weight: float = 1e4, gather: bool = True, detour_after: int = DETOUR_AFTER,
                 turn_game: bool = True, evasion_veto: bool = True, rescue_after: int = RESCUE_AFTER,
                 rescue_work: int = RESCUE_WORK, joint_escape: bool = True):
        self.joint_escape = joint_escape
        self.rescue_after = rescue_after
        self.rescue_work = rescue_work
        self.evasion_veto = evasion_veto
        self.turn_game = turn_game
        self.detour_after = detour_after
        self.evasion_horizon = evasion_horizon
        self.evasion_weight = evasion_weight
        self.gather = gather
        self.hover = hover
        self.finish_together = finish_together
        self.leave_early = leave_early
        self.connectivity = connectivity
        self.landmarks = landmarks
        self.lookahead = lookahead
        self.swap = swap
        self.yield_way = yield_way
        self.release_at_goal = release_at_goal

    # ------------------------------------------------------------------ reset
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        check_connectivity(self.connectivity, "pibt")
        if isinstance(self.lookahead, bool) or not isinstance(self.lookahead, (int, np.integer)) or self.lookahead < 0:
            raise ConfigError(f"pibt: lookahead must be a whole number >= 0, got {self.lookahead!r}")
        if isinstance(self.leave_early, bool) or not isinstance(self.leave_early, (int, np.integer)) \
                or self.leave_early < 0:
            raise ConfigError(f"pibt: leave_early must be a whole number >= 0, got {self.leave_early!r}")
        if self.hover is not None and (isinstance(self.hover, bool) or not isinstance(self.hover, (int, np.integer))
                                       or self.hover < 0):
            raise ConfigError(f"pibt: hover must be a whole number >= 0 or None, got {self.hover!r}")
        check_evasion(self.evasion_horizon, self.evasion_weight, "pibt")
        check_rescue(self.rescue_after, self.rescue_work, "pibt")
        if isinstance(self.detour_after, bool) or not isinstance(self.detour_after, (int, np.integer)) \
                or self.detour_after < 0:
            raise ConfigError(f"pibt: detour_after must be a whole number >= 0, got {self.detour_after!r}")
        for flag in ("turn_game", "evasion_veto", "joint_escape"):
            if not isinstance(getattr(self, flag), (bool, np.bool_)):
                raise ConfigError(f"pibt: {flag} must be True or False, got {getattr(self, flag)!r}")
        n = world.n_robots
        res = world.resolution
        radius = float(world.radii.max(initial=0.0))
        self.reach_ = world.max_speeds * world.dt
        self.diag_ok_ = self.reach_ >= res * np.sqrt(2) * (1 - 1e-9)
        check_grid_robots(world, "pibt")
        grid = world.grid(radius=radius)
        self.world_ = world
        self.grid_ = grid
        self.height_, self.width_ = grid.blocked.shape
        self.moves_ = static_moves(grid.blocked, self.connectivity)
        self.graph_ = GridGraph.build(grid.blocked, self.connectivity, radius, res)
        self.tables_ = LazyDistanceTables(grid.blocked, connectivity=self.connectivity,
                                          landmarks=choose_landmarks(self.landmarks, world.n_robots, grid.blocked))
        self.goals_ = world.goals
        self.goal_cells_ = self._cells(self.goals_)
        self.goal_ok_ = grid.is_free(self.goal_cells_) if n else np.zeros(0, bool)
        # disc robots with goals off the centre wait on it while others are near (finish.py)
        self.hold_ = off_centre_discs(world, grid.centers(self.goal_cells_))
        self.holding_ = self.hold_
        self.handles_ = np.full(n, -1, np.int64)          # table of each robot, -1: none held
        self.base_ = rng.random(n)                        # fractional parts of the priorities
        self.priority_ = self.base_.copy()
        self.pushes_ = np.zeros(n, np.int64)              # times each robot was pushed and moved
        self.best_ = np.full(n, np.inf)                   # each robot's least distance to its goal so far
        self.since_ = np.zeros(n, np.int64)               # steps since it last came closer
        self.rng_ = rng
        self.forecast_ = ObstacleForecast(world, grid, radius) if world.moving_obstacles else None
        if self.forecast_ is not None:   # the static grid padded for the look-ahead windows
            self.pad_ = self.lookahead + 2 + DEAD_END_EXTRA
            self.dead_end_ = trap_cells(self.moves_)
            self.padded_ = np.pad(grid.blocked, self.pad_, constant_values=True)
            self.lingering_ = Lingering.start(grid.blocked, self.connectivity)
        self.turn_game_ = TurnGame(self.forecast_, self.moves_) \
            if self.forecast_ is not None and self.turn_game else None
        self.evasion_ = EvasionRisk(world, grid, self.moves_, self.forecast_, radius, self.evasion_horizon) \
            if self.forecast_ is not None and self.evasion_horizon else None
        self.rescue_ = StallRescue.build(world, grid, self.graph_, self.tables_, self.connectivity, rng,
                                         after=self.rescue_after, work_limit=self.rescue_work, swap=self.swap)

    def _cells(self, points: FloatArray) -> NDArray[np.int64]:
        cells = self.grid_.cell_of(np.asarray(points, float).reshape(-1, 2))
        return np.clip(cells, 0, [self.width_ - 1, self.height_ - 1])

    # ------------------------------------------------------------------ act
    def _distances(self, cells: NDArray[np.int64], in_goal_cell: NDArray[np.bool_]) -> FloatArray:
        """Cost to goal (n, 9) of each move's cell; NaN for impossible moves. In its goal cell
        a robot's costs are the moves' own costs (a move's cell is that far from the goal)."""
        n = len(cells)
        ok_moves = self.moves_[cells[:, 1], cells[:, 0]]
        dist = np.where(ok_moves, MOVE_COST[None, :], np.nan)
        dist[:, STAY] = 0.0
        need = ~in_goal_cell & self.goal_ok_
        if self.release_at_goal and n:
            for i in np.flatnonzero(in_goal_cell & (self.handles_ >= 0)):
                self.tables_.release(int(self.handles_[i]))
                self.handles_[i] = -1
        for i in np.flatnonzero(need & (self.handles_ < 0)):
            self.handles_[i] = self.tables_.acquire(self.goal_cells_[i])
        idx = np.flatnonzero(need)
        if len(idx):
            d = self.tables_.neighbour_costs(self.handles_[idx], cells[idx])
            dist[idx] = np.where(ok_moves[idx], d, np.nan)
            dist[idx, STAY] = d[:, STAY]
        lost = ~self.goal_ok_   # a goal off the grid's free cells: such a robot only makes way
        dist[lost] = np.where(np.isnan(dist[lost]), np.nan, 0.0)
        return dist

    def _targets(self, pos: FloatArray, cells: NDArray[np.int64], rows: NDArray[np.int64]
                 ) -> tuple[FloatArray, NDArray[np.bool_]]:
        """Where each move takes robots ``rows`` (k, 9, 2) and whether it is within reach: cell
        centres; the exact goal on entering or staying in the goal cell when in reach."""
        pos, cells = pos[rows], cells[rows]
        reach = self.reach_[rows, None] * (1 + 1e-9) + 1e-12
        dest = cells[:, None, :] + GRID_MOVES[None]
        targets = self.grid_.centers(dest)
        to_goal = np.all(dest == self.goal_cells_[rows, None, :], axis=2) & ~self.holding_[rows, None]
        goal_t = np.broadcast_to(self.goals_[rows, None, :], targets.shape)
        goal_reach = np.linalg.norm(goal_t - pos[:, None, :], axis=2) <= reach
        targets = np.where((to_goal & goal_reach)[..., None], goal_t, targets)
        in_reach = np.linalg.norm(targets - pos[:, None, :], axis=2) <= reach
        in_reach[:, STAY] = True
        return targets, in_reach

    def act(self, obs: Observation) -> Decision:
        pos = obs.positions
        n = len(pos)
        if self.forecast_ is not None:
            self.forecast_.at_step(obs.step, obs.obstacle_positions)   # turn-every, waypoints
            self.lingering_.update(self.forecast_, obs.obstacle_positions)
        if self.finish_together and (self.forecast_ is not None or self.hold_.any()):
            done = finishing_step(self.world_, obs)
            if done is None and self.gather and self.forecast_ is not None:
                done = gathering_step(self.world_, obs, self.forecast_, self.grid_, self.moves_, 1 + self.lookahead)
            if done is not None:
                return done
        if self.rescue_ is not None and self.rescue_.following:
            planned = self.rescue_.next_positions(pos)
            if planned is not None:
                return planned_decision(pos, planned, self.goals_, [])
        cells = self._cells(pos)
        in_goal_cell = np.all(cells == self.goal_cells_, axis=1)
        # discs with goals off the centre wait on it while other robots are near (finish.py)
        self.holding_ = held_discs(self.hold_, cells, self.goal_cells_, (self.height_, self.width_))
        centre = self.grid_.centers(cells)
        at_goal = waiting_home(obs.at_goal, self.holding_, in_goal_cell, pos, centre)
        dist = self._distances(cells, in_goal_cell)
        self.best_, self.since_ = progress_update(self.best_, self.since_, dist[:, STAY], at_goal)
        rescue_events: list[dict] = []
        if self.rescue_ is not None:
            # stalled in a static world: LaCAM plans the rest from here (rescue.py)
            planned, rescue_events = self.rescue_.update(pos, cells, dist[:, STAY], at_goal)
            if planned is not None:
                return planned_decision(pos, planned, self.goals_, rescue_events)
        # most robots stand on a cell centre away from their goal: every move ends on a centre
        # within reach (diagonals need reach sqrt 2); the others are worked out exactly
        special = np.flatnonzero((np.abs(pos - centre).max(axis=1) > 1e-9)
                                 | (np.abs(cells - self.goal_cells_).max(axis=1) <= 1))
        allowed = ~np.isnan(dist) & (self.diag_ok_[:, None] | ~DIAGONAL_MOVE[None, :])
        special_targets, special_reach = self._targets(pos, cells, special)
        allowed[special] = ~np.isnan(dist[special]) & special_reach
        allowed[:, STAY] = True
        feasible = allowed.copy()       # what the static map and the robots' reach allow
        goal_dist = dist.copy()
        urgent = np.zeros(n, bool)
        cornered = np.zeros(n, bool)
        threatened = np.zeros(n, bool)
        ranks = np.zeros((n, 9), np.int64)
        hz = None
        if self.forecast_ is not None and self.detour_after:
            # a robot an obstacle has held back for a while goes round it (detour.py), however
            # far it has gone since: near the obstacle only, it turned back once out of reach
            slow = np.flatnonzero((self.since_ >= self.detour_after) & ~in_goal_cell & self.goal_ok_)
            if len(slow):
                dist[slow] = detour_ranking(self.lingering_, cells[slow], self.goal_cells_[slow], dist[slow])
        if self.forecast_ is not None:
            hz = hazard_windows(self.forecast_, obs.obstacle_positions, obs.obstacle_previous, pos, cells,
                                self.padded_, self.pad_, max(1 + self.lookahead, self.leave_early), 1 + self.lookahead,
                                connectivity=self.connectivity)
        if hz is not None:
            rows = hz.rows
            dest = cells[rows, None, :] + GRID_MOVES[None]
            allowed[rows] &= ~hz.at(hz.covered[0], dest)
            urgent[rows] = hz.at(hz.covered[0], cells[rows])
            # cells count as covered by their centres only: a robot off a cell centre (an exact
            # goal) is checked where it rests, and every move near an obstacle on its way (a
            # diagonal past an obstacle off the grid, or one already reaching the robot)
            fc, now, before = self.forecast_, obs.obstacle_positions, obs.obstacle_previous
            ends = self.grid_.centers(self._cells(special_targets.reshape(-1, 2))).reshape(special_targets.shape)
            allowed[special] &= ~fc.off_centre_hits(special_targets, ends, now, before)
            urgent |= fc.off_centre_hits(pos, centre, now, before)
            reach_targets, _ = self._targets(pos, cells, rows)
            allowed[rows] &= ~fc.crossings(pos[rows], reach_targets, now)
            walker_risk = None
            if self.evasion_ is not None:
                # near a random walker: each move's exact chance of being caught
                walker_risk = self.evasion_.move_risk(cells[rows], obs.obstacle_positions)
            if self.lookahead:
                # keep out of cells that leave no way out later, unless nothing else is left; a
                # robot that must leave may fall back to less cautious cells, in rank order; the
                # tiers may not pick a move the walker value rates far riskier (evasion/risk.py)
                full = allowed[rows]
                vetoed = walker_vetoed(full, walker_risk) if self.evasion_veto else np.zeros_like(full)
                # every robot keeps its candidates of the shallower tiers too, ranked after the
                # deeper ones: one pushed out of its cell then takes a less cautious cell instead
                # of failing the robot that pushed it, often one an obstacle closes in on
                ranked = np.ones(len(rows), bool)
                base = full & ~vetoed
                allowed[rows], threatened[rows], rank, ways = hz.tiers(base, dest, 1 + self.lookahead,
                                                                       fallback=ranked)
                # next to a dead end or pocket the way out is the way in: an obstacle heading for the
                # mouth corners the robot unless it leaves early, so such robots look further
                near = next_to_dead_end(self.dead_end_, dest, base)
                if len(near):
                    depth = 1 + self.lookahead + DEAD_END_EXTRA
                    deep = hazard_windows(self.forecast_, obs.obstacle_positions, obs.obstacle_previous,
                                          pos[rows[near]], cells[rows[near]], self.padded_, self.pad_, depth, depth,
                                          connectivity=self.connectivity)
                    if deep is not None:
                        k = near[deep.rows]
                        allowed[rows[k]], threatened[rows[k]], rank[k], ways[k] = deep.tiers(
                            base[k], dest[k], depth, fallback=ranked[k])
                if self.turn_game_ is not None:
                    # a bounce8 obstacle's turn is seen a step later: the robot can react to it
                    allowed[rows], threatened[rows], rank = self.turn_game_.ranks(
                        obs.obstacle_positions, obs.obstacle_previous, cells[rows], base, dest, allowed[rows],
                        threatened[rows], rank, fallback=ranked)
                # one that must leave may still take them, ranked last
                allowed[rows] |= vetoed & urgent[rows][:, None]
                rank = vetoed_last(rank, allowed[rows], vetoed)
                dist[rows] += TIER_WEIGHT * rank + CLEAR_WEIGHT * cornered_penalty(allowed[rows], rank, ways)
                ranks[rows] = rank
            if walker_risk is not None:
                # within a tier: the move least likely to be caught by a random walker
                dist[rows] += self.evasion_weight * walker_risk
            if self.leave_early:
                # prefer the candidates that stay clear of every obstacle longest (up to leave_early steps;
                # one step for robots within `hover` cells of their goals, which wait beside it)
                early = np.full(len(rows), self.leave_early, np.int64)
                if self.hover is not None:
                    near = np.abs(cells[rows] - self.goal_cells_[rows]).max(axis=1) <= self.hover
                    early[near] = min(1, self.leave_early)
                depth = np.minimum(hz.at(stay_depth(hz.covered[:self.leave_early]), dest), early[:, None])
                depth = np.where(allowed[rows], depth, -1)
                threatened[rows] |= depth.max(axis=1) > depth[:, STAY]
                dist[rows] = np.where(np.isnan(dist[rows]), np.nan,
                                      dist[rows] + CLEAR_WEIGHT * (early[:, None] - depth))
            # a robot with no sure move left takes the one an obstacle is least likely to hit
            stuck = np.flatnonzero(urgent & ~allowed.any(axis=1))
            if len(stuck):
                cornered[stuck] = True
                targets, _ = self._targets(pos, cells, stuck)
                dest = cells[stuck, None, :] + GRID_MOVES[None]
                at = np.searchsorted(hz.rows, stuck)
                ways = ways_clear(hz, at, dest)
                stuck_risk = walkers = None
                if walker_risk is not None:
                    walkers = self.evasion_.modelled(obs.obstacle_positions)
                    stuck_risk = walker_risk[at]
                ok, cost = last_resort(self.forecast_, obs.obstacle_positions, obs.obstacle_previous, pos[stuck],
                                       targets, dest, feasible[stuck], ways, stuck_risk, walkers)
                allowed[stuck] = ok
                dist[stuck] = np.where(ok, np.nan_to_num(goal_dist[stuck]) + LAST_RESORT_WEIGHT * cost, np.nan)
                ranks[stuck] = 0
            # robots pushed aside leave the cells that robots which must leave need to get away
            must = urgent & ~allowed[:, STAY]
            if must.any():
                dist += CLAIM_WEIGHT * escape_claims(cells, allowed, ranks, must, (self.height_, self.width_))
            if self.joint_escape:
                # robots in danger beside one another choose their moves together (joint_escape.py)
                dist = prefer_joint_escapes(dist, cells, allowed, np.flatnonzero(urgent | threatened),
                                            self.graph_.table, (self.height_, self.width_), CLAIM_WEIGHT)
        self.priority_ = update_priorities(self.priority_, at_goal, self.base_)
        # robots that must or should leave their cell first, the most constrained first
        order = decision_order(self.priority_, urgent | threatened, allowed.sum(axis=1))
        tie = self.rng_.random((n, 9))
        flat = (cells[:, 1] * self.width_ + cells[:, 0]).astype(np.int32)
        goal_flat = (self.goal_cells_[:, 1] * self.width_ + self.goal_cells_[:, 0]).astype(np.int32)
        result = pibt_step_escaping(self.graph_, flat, np.nan_to_num(dist, nan=np.inf), allowed, tie, order,
                                    danger=urgent, rank=ranks, goals=goal_flat, slots=self.handles_,
                                    tables=self.tables_._c, swap=self.swap, yield_way=self.yield_way)
        moves = result.moves.astype(np.int64)
        new = centre + GRID_MOVES[moves] * self.grid_.resolution
        new[special] = special_targets[np.arange(len(special)), moves[special]]
        events: list[dict] = list(rescue_events)
        held = self._exact_check(pos, new, cells)
        for i in held:
            new[i] = pos[i]
            moves[i] = STAY
            events.append({"robot": int(i), "kind": "move_withheld", "detail": "off-centre move conflicts"})
        events += no_escape_events(urgent & (moves == STAY), cornered)
        if result.conflicts:
            events.append({"robot": -1, "kind": "pibt_conflict", "detail": f"{result.conflicts} pairs"})
        pushed = ((result.flags & PUSHED) != 0) & (moves != STAY)
        self.pushes_ += pushed
        arrived = np.linalg.norm(new - self.goals_, axis=1) <= 1e-9
        modes = np.where(arrived, "arrived", np.where(moves == STAY, "wait", "move")).astype(object)
        modes[pushed] = "pushed"
        return Decision(new, modes.tolist(), events)

    def _exact_check(self, pos: FloatArray, new: FloatArray, cells: NDArray[np.int64]) -> list[int]:
        """Robots whose move starts or ends off a cell centre are checked exactly
        (:func:`~swarmpath.control.pibt.exact.hold_conflicts`); the conflict table covers
        centre-to-centre moves only. Returns the robots to hold."""
        centres = self.grid_.centers(self._cells(new))
        odd = np.flatnonzero((np.linalg.norm(pos - self.grid_.centers(cells), axis=1) > 1e-9)
                             | (np.linalg.norm(new - centres, axis=1) > 1e-9))
        return hold_conflicts(pos, new, self.world_.radii, self.grid_.resolution, odd, 3 * self.grid_.resolution)
