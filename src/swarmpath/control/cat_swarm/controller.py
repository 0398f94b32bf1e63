"""The ``cat-swarm`` controller: online collision avoidance of Jaleel & Hassan (2016),
section III.2, Algorithms 2-4, on the grid, with the PIBT core deciding for all robots at once.

The swarm chooses, the core guarantees. Every step (vectorised over robots):

1. Collision detection (Algorithms 2-3): a robot is *in conflict* when another robot is in
   its short or medium distance class, or a moving obstacle is within ``obstacle_alert``.
   Robots not in conflict follow their path (the offline plan as grid cells, or the
   replanned shortest path).
2. Mixture ratio (eq. 10-11): in every group of robots in conflict with each other,
   round(MR * size) robots with the longest remaining path seek, the others trace. Trace
   robots that see a moving obstacle switch to seek (step 5 of Algorithm 4).
3. The candidates (step 6.1-6.3): the present cell and its 8 neighbours (SMP = 8, SRD = 1,
   CDC = 2, SPC); copies on static obstacles, out of reach, where a moving obstacle may be
   next step, or outside the deepest look-ahead tier that leaves a choice are deleted
   (:mod:`swarmpath.control.hazards`, on windows around the robots an obstacle can reach).
   Other robots delete nothing: they are the core's business.
4. Each robot's ranking of its candidates (:mod:`.ranking`): follow and trace robots the
   next cell of their path, then waiting; seek robots the copies by eq. 12 (the exact path
   length to the goal, from lazy per-goal distance tables) plus an early-warning term, ties
   by eq. 13; the robot of highest priority and robots without progress for ``patience``
   steps by exact distance first (the ranking under which PIBT guarantees progress).
5. The PIBT core (:func:`swarmpath.control.pibt.core.pibt_step`, priorities of PIBT's
   section 3.2, robots in an obstacle's way first) turns the rankings into moves: no two
   robots in one cell, no swap, no crossing diagonals, the checker's own conflict table for
   the robots' radius; a robot in another's way is pushed (priority inheritance) or the other
   tries its next candidate. Moves that start or end off a cell centre are then checked
   exactly (:func:`swarmpath.control.pibt.exact.hold_conflicts`).

Moves go between cell centres, one 8-neighbour cell per step; a robot that starts off-centre
first goes to its cell centre (or straight to a neighbour centre within reach), and a robot
entering its goal cell goes to the exact goal when it is within reach, else to the cell's
centre first (a goal on the workspace's corner is reached in two steps).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.cat_swarm import kernels as K
from swarmpath.control.cat_swarm.cells import PathTracker, grid_cells
from swarmpath.control.cat_swarm.deadlock import DeadlockMonitor
from swarmpath.control.cat_swarm.ranking import dense_ranks, swarm_keys
from swarmpath.control.cornered import CHANCE_RESOLUTION, last_resort, no_escape_events, ways_clear
from swarmpath.control.detour import DETOUR_AFTER, Lingering, detour_ranking
from swarmpath.control.evasion import EvasionRisk, check_evasion, vetoed_last, walker_vetoed
from swarmpath.control.finish import finishing_step, gathering_step, held_discs, off_centre_discs, waiting_home
from swarmpath.control.hazards import (
    DEAD_END_EXTRA,
    ObstacleForecast,
    cornered_penalty,
    hazard_windows,
    next_to_dead_end,
    stay_depth,
    trap_cells,
    warning_levels,
)
from swarmpath.control.observation import CLASS_INDEX, Observation
from swarmpath.control.pibt.core import (
    PUSHED,
    GridGraph,
    decision_order,
    escape_claims,
    pibt_step_escaping,
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
from swarmpath.control.turn_game import TurnGame
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.search.lazy_distance import LazyDistanceTables, choose_landmarks
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


#: Keys of one look-ahead tier (``cornered_penalty`` is below it).
TIER_SPAN = 16

#: The joint choice of robots in danger weighs a copy by its ranking keys in ranking order,
#: with pibt's weights: a look-ahead tier, then a claimed cell, then a step within the tier
#: (the cornered penalty), then the walker risk and the rank.
JOINT_TIER, JOINT_CLAIM, JOINT_STEP = 1e8, 1e7, 1e6


@register_controller("cat-swarm")
class CatSwarmController(Controller):
    """Modified cat swarm collision avoidance (Jaleel & Hassan 2016, Algorithm 4) on the PIBT
    core.

    Parameters (paper values where the paper gives them; docs/papers/jaleel-hassan-2016.md
    (online phase) explains each choice):
        mixture_ratio : MR of eq. 10-11 (0.4).
        seeking_range : SRD in cells (1: the 8 neighbours).
        keep_present : SPC, the present position is a candidate too (True).
        obstacle_alert : distance class up to which a moving obstacle puts a robot in conflict
            ("short", "medium" as in the paper, "long" default, "very long").
        margin : extra cells kept clear around obstacles' current and next footprints (0).
        lookahead : steps over which a robot makes sure it can keep clear of moving obstacles
            whatever they do (3; 1 = only the next step, as in the paper). Every robot an
            obstacle can reach keeps every candidate, ranked by these tiers (a shallower one
            when it must leave its cell or is pushed out of it); one with no candidate
            in its deepest tier takes the cell with most ways on
            (:func:`~swarmpath.control.hazards.cornered_penalty`); one with a candidate in a
            dead end or a pocket one obstacle can close looks ``DEAD_END_EXTRA`` (2) steps
            further (as in ``pibt``).
        leave_early : a robot prefers cells no obstacle can reach within this many steps and
            leaves a cell (even its goal) that an obstacle may reach that soon (0 = no such
            preference, default). ``lookahead=5, leave_early=2`` (the defaults before) keep
            robots farther from obstacles but seldom let all of them be home at once: on the
            64 x 64 acceptance world 26 of 100 runs end with every robot home and no contact,
            against 94 of 100 with the defaults (docs/algorithms/pibt.md).
        hazard_horizon, hazard_weight, hazard_decay : look-ahead (steps), weight (cells of
            fitness) and decay per step of the early-warning term that makes robots leave an
            obstacle's way early (4, 2.0, 0.7).
        lead : the robot of highest priority ranks its candidates by exact distance first
            (True), so that it surely progresses (PIBT's reachability).
        patience : steps without progress after which a robot ranks by exact distance first
            until it reaches its goal (6; None: never).
        swap : the core's swap emulation (LaCAM3), for robots that must pass each other in a
            corridor (True).
        report_after : steps without progress before a deadlock event is recorded (40).
        landmarks : landmark cells of the lazy distance tables ("auto", see ``pibt``).
        finish_together : with moving obstacles, all robots step onto their goals at once
            when that step has no contact, which ends the run (True; see ``pibt`` and
            :mod:`swarmpath.control.finish`); also in worlds without them when disc robots'
            goals lie off their cells' centres (those wait on the centres while others are near).
        hover : within this many cells of its goal a robot keeps only the next step clear
            instead of ``leave_early`` steps (None: nowhere; 0: on its goal; see ``pibt``).
        evasion_horizon, evasion_weight : with random walkers, a robot near one ranks its
            copies, right after the look-ahead's tier, by the exact chance of being hit within
            ``evasion_horizon`` steps if it dodges as well as it can
            (:mod:`swarmpath.control.evasion`), in units of 1 / ``evasion_weight`` (8, 1e4; as
            in ``pibt``); 0: off.
        gather : with ``finish_together``, a gathering step sets up the finish when every
            robot is within two cells of its goal (True; see ``pibt`` and
            :func:`~swarmpath.control.finish.gathering_positions`).
        detour_after : with moving obstacles, a robot without progress for this many steps
            ranks its copies by the way round the cells where obstacles have lingered lately
            instead of eq. 12's static length (8; 0: off; see ``pibt`` and
            :mod:`swarmpath.control.detour`).
        turn_game : with moving obstacles, a robot a turning bounce8 obstacle can reach ranks
            its copies by how long it can keep clear watching the obstacle turn, four steps
            ahead (:mod:`swarmpath.control.turn_game`), instead of the open-loop tiers (True;
            as in ``pibt``).
        evasion_veto : with random walkers, the look-ahead tiers may not pick a copy the exact
            walker value rates ten times (and 0.002) riskier than the safest clear one
            (:func:`~swarmpath.control.evasion.walker_vetoed`; True; as in ``pibt``).
        rescue_after, rescue_work : in a static world, when progress stops for ``rescue_after``
            steps (24; 0: off), LaCAM plans the rest from where the robots stand, within
            ``rescue_work`` robot moves for the run's searches together (10^8), and they follow it
            (:mod:`swarmpath.control.pibt.rescue`; as in ``pibt``).
        joint_escape : robots in danger within two cells of one another choose their copies
            together, the combination of least total cost in ranking order that the checker
            allows (:mod:`swarmpath.control.pibt.joint_escape`; True; as in ``pibt``).
    """

    capabilities = Capabilities(grid_based=True, moving_obstacles=True, multi_robot=True, randomized=True)

    def __init__(self, mixture_ratio: float = 0.4, seeking_range: int = 1, keep_present: bool = True,
                 obstacle_alert: str = "long", margin: int = 0, lookahead: int = 3, leave_early: int = 0,
                 hazard_horizon: int = 4, hazard_weight: float = 2.0, hazard_decay: float = 0.7, lead: bool = True,
                 patience: int | None = 6, swap: bool = True, report_after: int = 40, landmarks: int | str = "auto",
                 stalled_lookahead: int = 2, relax_after: int = 20, finish_together: bool = True,
                 hover: int | None = None, evasion_horizon: int = 8, evasion_weight: float = 1e4, gather: bool = True,
                 detour_after: int = DETOUR_AFTER, turn_game: bool = True, evasion_veto: bool = True,
                 rescue_after: int = RESCUE_AFTER, rescue_work: int = RESCUE_WORK, joint_escape: bool = True):
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
        self.stalled_lookahead = stalled_lookahead
        self.relax_after = relax_after
        self.mixture_ratio = mixture_ratio
        self.seeking_range = seeking_range
        self.keep_present = keep_present
        self.obstacle_alert = obstacle_alert
        self.margin = margin
        self.lookahead = lookahead
        self.leave_early = leave_early
        self.hazard_horizon = hazard_horizon
        self.hazard_weight = hazard_weight
        self.hazard_decay = hazard_decay
        self.lead = lead
        self.patience = patience
        self.swap = swap
        self.report_after = report_after
        self.landmarks = landmarks

    # ------------------------------------------------------------------ reset
    def _check_parameters(self) -> None:
        if not 0.0 <= self.mixture_ratio <= 1.0:
            raise ConfigError(f"cat-swarm: mixture_ratio must be in [0, 1], got {self.mixture_ratio}")
        if self.seeking_range != 1:
            raise ConfigError(f"cat-swarm: seeking_range must be 1 cell on a grid, got {self.seeking_range}")
        if self.obstacle_alert not in CLASS_INDEX:
            raise ConfigError(f"cat-swarm: obstacle_alert must be one of {sorted(CLASS_INDEX)}, "
                              f"got {self.obstacle_alert!r}")
        if self.margin < 0 or self.hazard_horizon < 0 or self.hazard_weight < 0:
            raise ConfigError("cat-swarm: margin, hazard_horizon and hazard_weight must be >= 0")
        if not 0.0 <= self.hazard_decay <= 1.0:
            raise ConfigError(f"cat-swarm: hazard_decay must be in [0, 1], got {self.hazard_decay}")
        if self.lookahead < 1:
            raise ConfigError(f"cat-swarm: lookahead must be >= 1, got {self.lookahead}")
        if not 0 <= self.leave_early <= self.lookahead:
            raise ConfigError(f"cat-swarm: leave_early must be in [0, lookahead], got {self.leave_early}")
        if self.hover is not None and (isinstance(self.hover, bool) or not isinstance(self.hover, (int, np.integer))
                                       or self.hover < 0):
            raise ConfigError(f"cat-swarm: hover must be a whole number >= 0 or None, got {self.hover!r}")
        if (self.patience is not None and self.patience < 1) or self.report_after < 1:
            raise ConfigError("cat-swarm: patience (or None) and report_after must be >= 1")
        check_evasion(self.evasion_horizon, self.evasion_weight, "cat-swarm")
        check_rescue(self.rescue_after, self.rescue_work, "cat-swarm")
        if isinstance(self.detour_after, bool) or not isinstance(self.detour_after, (int, np.integer)) \
                or self.detour_after < 0:
            raise ConfigError(f"cat-swarm: detour_after must be a whole number >= 0, got {self.detour_after!r}")
        for flag in ("turn_game", "evasion_veto", "joint_escape"):
            if not isinstance(getattr(self, flag), (bool, np.bool_)):
                raise ConfigError(f"cat-swarm: {flag} must be True or False, got {getattr(self, flag)!r}")

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self._check_parameters()
        n = world.n_robots
        self.world_ = world
        cells = grid_cells(world, "cat-swarm", fields=False)  # the checks; eq. 12 from lazy tables
        self.cells_ = cells
        self.grid_ = cells.grid
        blocked = cells.grid.blocked
        self.height_, self.width_ = cells.shape
        self.goal_cells_ = cells.goal_cells
        self.goal_flat_ = (cells.goal_cells[:, 1] * self.width_ + cells.goal_cells[:, 0]).astype(np.int32)
        self.goal_ok_ = cells.grid.is_free(cells.goal_cells) if n else np.zeros(0, bool)
        # disc robots with goals off the centre wait on it while others are near (finish.py)
        self.hold_ = off_centre_discs(world, cells.grid.centers(cells.goal_cells))
        radius = float(world.radii.max(initial=0.0))
        self.graph_ = GridGraph.build(blocked, 8, radius, world.resolution)
        self.tables_ = LazyDistanceTables(blocked, connectivity=8,
                                          landmarks=choose_landmarks(self.landmarks, n, blocked))
        self.handles_ = np.full(n, -1, np.int64)  # each robot's distance table, -1: none held
        self.paths_ = PathTracker.from_plan(world, plan, cells)  # the offline plan as grid cells
        self.tiebreak_ = rng.random(n)                          # eq. 10-11 ties
        self.base_ = rng.random(n)                              # fractional parts of the priorities
        self.priority_ = self.base_.copy()
        self.rng_ = rng
        patience = self.patience if self.patience is not None else np.iinfo(np.int64).max
        self.monitor_ = DeadlockMonitor.start(n, patience=patience, report_after=self.report_after)
        self.forecast_ = ObstacleForecast(world, self.grid_, radius) if world.moving_obstacles else None
        if self.forecast_ is not None:  # the static grid padded for the look-ahead windows
            self.window_ = max(self.lookahead, 2)
            self.pad_ = self.window_ + 2 + DEAD_END_EXTRA
            self.dead_end_ = trap_cells(K.move_table(blocked))
            self.padded_ = np.pad(blocked, self.pad_, constant_values=True)
            self.lingering_ = Lingering.start(blocked, 8)
        self.moves_ = K.move_table(blocked)
        self.turn_game_ = TurnGame(self.forecast_, self.moves_) \
            if self.forecast_ is not None and self.turn_game else None
        self.evasion_ = EvasionRisk(world, self.grid_, self.moves_, self.forecast_, radius,
                                    self.evasion_horizon) if self.forecast_ is not None and self.evasion_horizon else None
        self.pushes_ = np.zeros(n, np.int64)
        self.rescue_ = StallRescue.build(world, self.grid_, self.graph_, self.tables_, 8, rng,
                                         after=self.rescue_after, work_limit=self.rescue_work, swap=self.swap)

    # ------------------------------------------------------------------ eq. 12
    def _fitness(self, cells: NDArray[np.int64], in_goal_cell: BoolArray) -> FloatArray:
        """Eq. 12 for the 9 copies (n, 9): the exact path length from each copy's cell to the
        robot's goal cell, from the goal's lazy table (inf where the move is impossible or the
        goal unreachable). In its goal cell a robot's copies are the moves' own lengths away,
        so it gives its table back (and takes it again if it is pushed farther)."""
        ok_moves = self.cells_.moves(cells)
        fit = np.where(ok_moves, K.STEP_COST[None, :], np.inf)
        fit[:, K.STAY] = 0.0
        for i in np.flatnonzero(in_goal_cell & (self.handles_ >= 0)):
            self.tables_.release(int(self.handles_[i]))
            self.handles_[i] = -1
        need = ~in_goal_cell & self.goal_ok_
        for i in np.flatnonzero(need & (self.handles_ < 0)):
            self.handles_[i] = self.tables_.acquire(self.goal_cells_[i])
        idx = np.flatnonzero(need)
        if len(idx):
            d = self.tables_.neighbour_costs(self.handles_[idx], cells[idx])
            fit[idx] = np.where(np.isnan(d), np.inf, d)
        fit[~self.goal_ok_] = np.inf  # a goal off the grid's free cells: such a robot only makes way
        return fit

    def _conflicts(self, obs, active: BoolArray):
        """Algorithms 2-3 on the simulator's sensing: (robot conflict edges among active
        robots, robot in conflict with any robot, robot alerted by a moving obstacle)."""
        n = obs.n_robots
        s = obs.sensed
        close = s.robot_class <= CLASS_INDEX["medium"]
        pairs = s.robot_pairs[close]
        robot_conflict = np.zeros(n, bool)
        robot_conflict[pairs[:, 0]] = True
        robot_conflict[pairs[:, 1]] = True
        obstacle_alert = np.zeros(n, bool)
        near = s.obstacle_class <= CLASS_INDEX[self.obstacle_alert]
        obstacle_alert[s.obstacle_pairs[near, 0]] = True
        both = active[pairs[:, 0]] & active[pairs[:, 1]]
        return pairs[both], robot_conflict & active, obstacle_alert & active

    def _behaviours(self, obs, active, remaining):
        """Algorithm 4 steps 1-5: (seek, trace) flags (n,). Robots in conflict are grouped
        (connected components of robot-robot conflicts); in each group the mixture ratio
        gives seek to the longest remaining paths; moving obstacles make a robot seek."""
        n = obs.n_robots
        edges, robot_conflict, obstacle_alert = self._conflicts(obs, active)
        conflict = robot_conflict | obstacle_alert
        seek = np.zeros(n, bool)
        members = np.flatnonzero(conflict)
        if len(members):
            labels = K.conflict_groups(edges, conflict)
            seek[members] = K.mixture_split(remaining[members], labels, self.mixture_ratio, self.tiebreak_[members])
        seek |= obstacle_alert  # trace robots that see a moving obstacle switch to seek
        return seek, conflict & ~seek

    # ------------------------------------------------------------------ act
    def act(self, obs: Observation) -> Decision:
        n = obs.n_robots
        if n == 0:
            return Decision(obs.positions.copy(), [])
        if self.forecast_ is not None:
            self.forecast_.at_step(obs.step, obs.obstacle_positions)   # turn-every, waypoints
            self.lingering_.update(self.forecast_, obs.obstacle_positions)
        if self.finish_together and (self.forecast_ is not None or self.hold_.any()):
            done = finishing_step(self.world_, obs)
            if done is None and self.gather and self.forecast_ is not None:
                done = gathering_step(self.world_, obs, self.forecast_, self.grid_, self.moves_, self.lookahead)
            if done is not None:
                return done
        if self.rescue_ is not None and self.rescue_.following:
            planned = self.rescue_.next_positions(obs.positions)
            if planned is not None:
                return planned_decision(obs.positions, planned, self.world_.goals, [])
        pos, goals = obs.positions, obs.goals
        rows = np.arange(n)
        cells = self.cells_.cells(pos)
        in_goal_cell = np.all(cells == self.goal_cells_, axis=1)
        # discs with goals off the centre wait on it while other robots are near (finish.py)
        holding = held_discs(self.hold_, cells, self.goal_cells_, (self.height_, self.width_))
        at_goal = waiting_home(obs.at_goal, holding, in_goal_cell, pos, self.grid_.centers(cells))
        active = ~at_goal
        # step 6.1-6.2: the seeking memory pool, 9 candidate cells per robot, and eq. 12
        copies = K.seek_copies(cells, srd=self.seeking_range)
        fitness = self._fitness(cells, in_goal_cell)
        rescue_events: list[dict] = []
        if self.rescue_ is not None:
            # stalled in a static world: LaCAM plans the rest from here (pibt/rescue.py)
            planned, rescue_events = self.rescue_.update(pos, cells, fitness[:, K.STAY], at_goal)
            if planned is not None:
                return planned_decision(pos, planned, self.world_.goals, rescue_events)
        remaining = self.paths_.remaining(cells, fitness[:, K.STAY])
        events = rescue_events + self.monitor_.update(obs.step, remaining, at_goal)
        if self.detour_after and self.forecast_ is not None:
            # a robot an obstacle has held back for a while goes round it (detour.py)
            slow = np.flatnonzero((self.monitor_.since >= self.detour_after) & ~in_goal_cell & self.goal_ok_)
            if len(slow):
                fitness[slow] = detour_ranking(self.lingering_, cells[slow], self.goal_cells_[slow], fitness[slow])
        targets, in_goal, static_ok, valid = self.cells_.candidates(pos, goals, cells, copies, centre_first=True,
                                                                        hold=holding)
        # step 6.3: delete copies near moving obstacles (now, next step, and the look-ahead)
        # near a random walker: each move's chance of being caught (used by the ranking and by
        # a cornered robot's last resort)
        walker_risk = None
        if self.evasion_ is not None and self.forecast_ is not None:
            walker_risk = self.evasion_.move_risk(cells, obs.obstacle_positions)
        valid, in_danger, threatened, safety, warning, tier, cornered = self._obstacle_rules(
            obs, cells, copies, targets, in_goal, valid, walker_risk, at_goal)
        # steps 1-5: collision detection, mixture split, trace robots seeing obstacles seek
        seek, trace = self._behaviours(obs, active, remaining)
        tie13 = K.tie_break_eq13(targets, goals)
        path_next = self.paths_.next_step(cells, fitness, static_ok, tie13)
        # each robot's ranking (ranking.py), then the core decides for all at once
        self.priority_ = update_priorities(self.priority_, at_goal, self.base_)
        urgent = self.monitor_.urgent & active
        first = urgent.copy()
        if self.lead and active.any():
            first[np.flatnonzero(active)[np.argmax(self.priority_[active])]] = True
        path_ok = valid[rows, path_next] & (path_next != K.STAY)
        if safety is not None:  # do not step where an obstacle may come sooner than here
            path_ok &= safety[rows, path_next] >= safety[:, K.STAY]
        searching = (seek | in_danger | threatened) & active
        follow = active & ~searching
        reachable = np.isfinite(fitness[:, K.STAY])
        stay_first = (at_goal & ~in_danger & ~threatened) | (~reachable & active)
        score = fitness if warning is None else fitness + self.hazard_weight * warning
        keys = swarm_keys(fitness, score, tie13, safety, path_next, follow, path_ok, stay_first,
                          first & reachable, self.keep_present)
        # a robot that must leave ranks the look-ahead's tiers first (all its candidates stay),
        # then, near a random walker, the chance of being caught (in units of 1 / evasion_weight)
        evade = np.zeros((n, 9)) if walker_risk is None else np.floor(self.evasion_weight * walker_risk)
        # within its look-ahead tier a robot pushed aside leaves the cells that robots which must
        # leave need to get away (pibt/core.py)
        must = in_danger & ~valid[:, K.STAY]
        claims = escape_claims(cells, valid, tier // TIER_SPAN, must, (self.height_, self.width_))
        rank = dense_ranks([tier // TIER_SPAN, claims, tier, evade] + keys, valid)
        danger = np.flatnonzero(in_danger | threatened)
        if self.joint_escape and len(danger) >= 2:
            # robots in danger beside one another choose their moves together (pibt/joint_escape.py),
            # by a cost that orders each robot's moves as its ranking does (the same weights as pibt's)
            cost = np.where(valid, (tier // TIER_SPAN) * JOINT_TIER + claims * JOINT_CLAIM
                            + (tier % TIER_SPAN) * JOINT_STEP + evade + rank, np.nan)
            rank = dense_ranks([prefer_joint_escapes(cost, cells, valid, danger, self.graph_.table,
                                                     (self.height_, self.width_), JOINT_CLAIM)], valid)
        order = decision_order(self.priority_, in_danger | threatened, valid.sum(axis=1))
        flat = (cells[:, 1] * self.width_ + cells[:, 0]).astype(np.int32)
        result = pibt_step_escaping(self.graph_, flat, rank, valid, self.rng_.random((n, 9)), order,
                                    danger=in_danger, rank=tier // TIER_SPAN, goals=self.goal_flat_,
                                    slots=self.handles_, tables=self.tables_._c, swap=self.swap, yield_way=True)
        choice = result.moves.astype(np.int64)
        new = targets[rows, choice]
        held = self._held(pos, new, cells)
        new[held] = pos[held]
        choice[held] = K.STAY
        self.paths_.advance(cells + K.OFFSETS[choice])  # step 6.6: leaving the path = replanning
        for i in held:
            events.append({"robot": int(i), "kind": "move_withheld", "detail": "exact check found a contact"})
        events += no_escape_events(in_danger & (choice == K.STAY), cornered)
        pushed = ((result.flags & PUSHED) != 0) & (choice != K.STAY)
        self.pushes_ += pushed
        modes = np.where(obs.at_goal, "arrived", np.where(at_goal, "wait", "follow")).astype(object)
        modes[trace] = "trace"
        modes[trace & (choice == K.STAY)] = "wait"
        modes[seek & active] = "seek"
        modes[urgent & ~seek] = "resolve"
        modes[pushed] = "yield"
        modes[threatened & ~seek & ~pushed] = "evade"
        modes[in_danger] = "escape"
        return Decision(new, modes.tolist(), events)

    def _obstacle_rules(self, obs, cells, copies, targets, in_goal_cell, valid, walker_risk=None, at_goal=None):
        """Step 6.3 for moving obstacles plus our look-ahead, for the robots an obstacle can
        reach (windows of :func:`~swarmpath.control.hazards.hazard_windows`); ``walker_risk``
        (n, 9): the walker-evasion risk of every move, or None without walkers. Returns (valid
        (n, 9), in danger (n,), threatened (n,), safety (n, 9) or None, warning (n, 9) or
        None, tier (n, 9): the look-ahead's rank of each candidate times TIER_SPAN plus
        :func:`~swarmpath.control.hazards.cornered_penalty`, 0 the most cautious; for a
        cornered robot the order of :func:`~swarmpath.control.cornered.last_resort`, cornered
        (n,): those robots). ``at_goal`` (n,): the robots counted as home (default: those on
        their exact goals)."""
        n = len(cells)
        in_danger = np.zeros(n, bool)
        threatened = np.zeros(n, bool)
        cornered = np.zeros(n, bool)   # robots left to cornered.last_resort this step
        fc = self.forecast_
        tier = np.zeros((n, 9), np.int64)
        if fc is None:
            return valid, in_danger, threatened, None, None, tier, cornered
        steps = max(self.lookahead, self.hazard_horizon)
        pos = obs.positions
        hz = hazard_windows(fc, obs.obstacle_positions, obs.obstacle_previous, pos, cells, self.padded_, self.pad_,
                            steps, self.window_, margin=self.margin)
        if hz is None:
            return valid, in_danger, threatened, None, None, tier, cornered  # no obstacle can matter this step
        r = hz.rows
        dest = copies[r]
        v = valid[r] & ~hz.at(hz.covered[0], dest)  # never where an obstacle may be next step
        in_danger[r] = hz.at(hz.covered[0], cells[r])
        # a cell counts as covered by its centre only: a robot resting or ending its move off
        # the centre (an exact goal) is checked where it rests, and every move on its way
        now, before = obs.obstacle_positions, obs.obstacle_previous
        cen = self.grid_.centers(dest.reshape(-1, 2)).reshape(dest.shape[0], 9, 2)
        v &= ~fc.off_centre_hits(targets[r], cen, now, before)
        in_danger[r] |= fc.off_centre_hits(pos[r], self.grid_.centers(cells[r]), now, before)
        v &= ~fc.crossings(pos[r], targets[r], now)
        # look-ahead: keep to the most cautious tier that leaves the robot some choice; a robot
        # ending the step on its exact goal off the centre (a cell corner, say) can reach fewer
        # cells from there next step
        exits = hz.at(hz.moves, dest)
        odd = in_goal_cell[r] & self.cells_.goal_off_centre[r, None] & np.all(targets[r] == obs.goals[r, None], axis=-1)
        exits = np.where(odd[..., None], self.cells_.goal_moves[r][:, None, :], exits)
        # a robot without progress for `patience` steps looks ahead less: among obstacles that
        # may head anywhere the deepest tiers can hold it in a safe pocket for good
        at_goal = obs.at_goal if at_goal is None else at_goal
        stalled = (self.monitor_.since[r] >= self.relax_after) & ~at_goal[r]
        base = v.copy()
        # the tiers may not pick a move the exact walker value rates far riskier (evasion/risk.py)
        vetoed = np.zeros_like(base)
        if self.evasion_veto and walker_risk is not None:
            vetoed = walker_vetoed(base, walker_risk[r])
        tier_base = base & ~vetoed
        looks = np.where(stalled, min(self.lookahead, self.stalled_lookahead), self.lookahead)
        # every robot keeps its shallower-tier candidates too, ranked after the deeper ones: one
        # pushed out of its cell takes a less cautious cell instead of failing its pusher (pibt)
        ranked = np.ones(len(r), bool)
        v, threat, rank, ways = hz.tiers(tier_base, dest, looks, exits, fallback=ranked)
        # next to a dead end or pocket the way out is the way in: such robots look further (see pibt)
        near = next_to_dead_end(self.dead_end_, dest, tier_base & ~stalled[:, None])
        if len(near):
            depth = self.lookahead + DEAD_END_EXTRA
            deep = hazard_windows(fc, obs.obstacle_positions, obs.obstacle_previous, pos[r[near]], cells[r[near]],
                                  self.padded_, self.pad_, depth, depth, margin=self.margin)
            if deep is not None:
                k = near[deep.rows]
                deep_exits = np.where(odd[k, :, None], exits[k], deep.at(deep.moves, dest[k]))
                v[k], threat[k], rank[k], ways[k] = deep.tiers(tier_base[k], dest[k], depth, deep_exits,
                                                               fallback=ranked[k])
        if self.turn_game_ is not None:
            # a bounce8 obstacle's turn is seen a step later: the robot can react to it (stalled
            # robots keep their shorter look-ahead)
            s = np.flatnonzero(~stalled)
            v[s], threat[s], rank[s] = self.turn_game_.ranks(obs.obstacle_positions, obs.obstacle_previous, cells[r[s]],
                                                            tier_base[s], dest[s], v[s], threat[s], rank[s],
                                                            fallback=ranked[s])
        v |= vetoed & in_danger[r][:, None]    # one that must leave may take them, ranked last
        rank = vetoed_last(rank, v, vetoed)
        # a robot with no sure move left takes the one an obstacle is least likely to hit
        stuck = np.flatnonzero(in_danger[r] & ~v.any(axis=1))
        if len(stuck):
            stuck_risk = walkers = None
            if walker_risk is not None:
                walkers = self.evasion_.modelled(obs.obstacle_positions)
                stuck_risk = walker_risk[r[stuck]]
            v[stuck], cost = last_resort(fc, obs.obstacle_positions, obs.obstacle_previous, pos[r[stuck]],
                                         targets[r[stuck]], dest[stuck], valid[r[stuck]],
                                         ways_clear(hz, stuck, dest[stuck]), stuck_risk, walkers)
            cornered[r[stuck]] = True
        # the tier first; a robot the obstacles close in on then takes the cell with most ways on
        tier[r] = rank * TIER_SPAN + cornered_penalty(v, rank, ways)
        if len(stuck):
            tier[r[stuck]] = np.round(cost / (CHANCE_RESOLUTION / 10)).astype(np.int64)
        threatened[r] = threat
        # and, among those, prefer cells an obstacle cannot reach soon (leave early)
        safety = np.where(valid, self.leave_early, -1)
        depth = hz.at(stay_depth(hz.covered[:self.leave_early], hz.covered.shape[1:]), dest)
        if self.hover is not None:
            # within `hover` cells of its goal a robot keeps one step clear only (see pibt)
            near = np.abs(cells[r] - self.goal_cells_[r]).max(axis=1) <= self.hover
            depth = np.where(near[:, None], np.minimum(depth, min(1, self.leave_early)), depth)
        safety[r] = np.where(v, depth, -1)
        valid = valid.copy()
        valid[r] = v
        threatened |= safety.max(axis=1) > safety[:, K.STAY]
        threatened &= ~in_danger
        warning = None
        if self.hazard_horizon > 0 and self.hazard_weight > 0:
            warning = np.zeros((n, 9))
            warning[r] = warning_levels(hz.covered[:self.hazard_horizon], hz.local(dest), self.hazard_decay)
        return valid, in_danger, threatened, safety, warning, tier, cornered

    def _held(self, pos: FloatArray, new: FloatArray, cells) -> list[int]:
        """Robots whose move starts or ends off a cell centre, checked exactly (the core's
        table covers centre-to-centre moves); returns the robots to hold in place."""
        c1 = self.cells_.cells(new)
        odd = np.flatnonzero((np.linalg.norm(pos - self.grid_.centers(cells), axis=1) > 1e-9)
                             | (np.linalg.norm(new - self.grid_.centers(c1), axis=1) > 1e-9))
        return hold_conflicts(pos, new, self.world_.radii, self.grid_.resolution, odd, 3 * self.grid_.resolution)
