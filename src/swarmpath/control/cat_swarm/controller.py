"""The ``cat-swarm`` controller: online collision avoidance of Jaleel & Hassan (2016),
section III.2, Algorithms 2-4, on the grid.

Every step, for every robot (vectorised over robots):

1. Collision detection (Algorithms 2-3): a robot is *in conflict* when another robot is in
   its short or medium distance class, or a moving obstacle is within ``obstacle_alert``
   (default: the long class, so that robots react early). Robots not in conflict follow
   their path (the offline plan turned into grid cells, or the replanned shortest path).
2. Mixture ratio (eq. 10-11): in every group of robots in conflict with each other,
   round(MR * size) robots with the longest remaining path seek, the others trace. Trace
   robots that see a moving obstacle switch to seek (step 5 of Algorithm 4).
3. Seek mode (step 6): the 8 copies (SMP = 8, SRD = 1 cell, CDC = 2) plus the present
   position (SPC); copies on static obstacles, on cells an obstacle covers now or may cover
   next step, or on another robot are deleted; fitness (eq. 12) = path length from the copy
   to the goal, read from the goal's distance field; ties by eq. 13; the robot moves to the
   best copy and its path is replanned (it then follows the distance field).
4. Trace mode (step 7): move to the next cell of the path, or wait when it is taken.
5. Conflicts between robots' choices are resolved in priority order with yielding, and
   robots that stop making progress are handled as deadlocks (:mod:`.deadlock`,
   :mod:`.reservation`).

Moves go between cell centres, one 8-neighbour cell per step; the first move of a robot that
starts off-centre goes to its cell centre (or straight to a neighbour centre within reach)
and the last one from the goal cell to the exact goal.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.cat_swarm import kernels as K
from swarmpath.control.cat_swarm.cells import PathTracker, grid_cells
from swarmpath.control.cat_swarm.deadlock import DeadlockMonitor, priority_order
from swarmpath.control.cat_swarm.reservation import reserve_moves
from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.observation import CLASS_INDEX, Observation
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.world.move_rules import move_conflicts
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]

@register_controller("cat-swarm")
class CatSwarmController(Controller):
    """Modified cat swarm collision avoidance (Jaleel & Hassan 2016, Algorithm 4).

    Parameters (paper values where the paper gives them; docs/papers/jaleel-hassan-2016.md (online phase)
    explains each choice):
        mixture_ratio : MR of eq. 10-11 (0.4).
        seeking_range : SRD in cells (1: the 8 neighbours).
        keep_present : SPC, the present position is a candidate too (True).
        obstacle_alert : distance class up to which a moving obstacle puts a robot in conflict
            ("short", "medium" as in the paper, "long" default, "very long").
        margin : extra cells kept clear around obstacles' current and next footprints (0).
        lookahead : steps over which a robot makes sure it can keep clear of moving obstacles
            whatever they do (5; 1 = only the next step, as in the paper).
        leave_early : a robot prefers cells no obstacle can reach within this many steps and
            leaves a cell (even its goal) that an obstacle may reach that soon (2; 0 = no
            such preference).
        hazard_horizon, hazard_weight, hazard_decay : look-ahead (steps), weight (cells of
            fitness) and decay per step of the early-warning term that makes robots leave an
            obstacle's way early (4, 2.0, 0.7).
        patience : steps without progress before a robot counts as stuck and may push (6).
        report_after : steps without progress before a deadlock event is recorded (40).
    """

    capabilities = Capabilities(grid_based=True, moving_obstacles=True, multi_robot=True, randomized=True)

    def __init__(self, mixture_ratio: float = 0.4, seeking_range: int = 1, keep_present: bool = True,
                 obstacle_alert: str = "long", margin: int = 0, lookahead: int = 5, leave_early: int = 2,
                 hazard_horizon: int = 4, hazard_weight: float = 2.0, hazard_decay: float = 0.7,
                 patience: int = 6, report_after: int = 40):
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
        self.patience = patience
        self.report_after = report_after

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
        if self.patience < 1 or self.report_after < 1:
            raise ConfigError("cat-swarm: patience and report_after must be >= 1")

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self._check_parameters()
        n = world.n_robots
        self.world_ = world
        cells = grid_cells(world, "cat-swarm")  # the checks, move table, distance fields
        self.cells_ = cells
        self.grid_ = cells.grid
        self.height_, self.width_ = cells.shape
        self.moves_ = cells.moves
        self.goal_cells_ = cells.goal_cells
        self.fields_, self.field_index_, self.decimals_ = cells.fields, cells.field_index, cells.decimals
        self.goal_off_centre_, self.goal_moves_ = cells.goal_off_centre, cells.goal_moves
        self.paths_ = PathTracker.from_plan(world, plan, cells)  # the offline plan as grid cells
        self.tiebreak_ = rng.random(n)
        self.rng_ = rng
        self.monitor_ = DeadlockMonitor.start(n, patience=self.patience, report_after=self.report_after)
        self.radii_ = world.radii
        self.forecast_ = ObstacleForecast(world, self.grid_, float(self.radii_.max(initial=0.0)))

    def _conflicts(self, obs, active: NDArray[np.bool_]):
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

    # ------------------------------------------------------------------ act
    def act(self, obs: Observation) -> Decision:
        n = obs.n_robots
        if n == 0:
            return Decision(obs.positions.copy(), [])
        pos, goals, at_goal = obs.positions, obs.goals, obs.at_goal
        active = ~at_goal
        cells = self.cells_.cells(pos)
        # step 6.1-6.2: the seeking memory pool, 9 candidate cells per robot, and eq. 12
        copies = K.seek_copies(cells, srd=self.seeking_range)
        path_fitness = K.fitness_eq12(self.fields_, self.field_index_, copies)
        remaining = self.paths_.remaining(cells, path_fitness[:, K.STAY])
        events = self.monitor_.update(obs.step, remaining, at_goal)
        targets, in_goal_cell, static_ok, valid = self.cells_.candidates(pos, goals, cells, copies)
        # step 6.3: delete copies near moving obstacles (now, next step, and the look-ahead)
        rules = self._obstacle_rules(obs, cells, copies, targets, in_goal_cell, static_ok, valid, active)
        valid, in_danger, threatened, options, safety, hazard = rules
        # step 6.4-6.5: rank the surviving copies (eq. 12, the warning term, eq. 13)
        tie = K.tie_break_eq13(targets, goals)
        fitness = path_fitness if hazard is None else path_fitness + self.hazard_weight * hazard
        ranked = K.rank_copies(fitness, tie, valid, decimals=self.decimals_, safety=safety)
        full = np.where(np.take_along_axis(valid, ranked, axis=1), ranked, -1)
        # steps 1-5: collision detection, mixture split, trace robots seeing obstacles seek
        seek, trace = self._behaviours(obs, active, remaining)
        urgent = self.monitor_.urgent & active
        # each robot's own preference list and where it goes when it must yield
        path_next = self.paths_.next_step(cells, path_fitness, static_ok, tie)
        own, no_stay = self._preferences(full, valid, safety, path_next, seek, urgent, in_danger, threatened,
                                         active, at_goal, np.isfinite(path_fitness[:, K.STAY]))
        # joint choice in priority order (deadlock.py, reservation.py), then the exact check
        order = priority_order(self.monitor_.urgent_since, in_danger, threatened, options, active, remaining,
                               self.tiebreak_)
        choice, yielded = self._joint_choice(cells, copies, static_ok, own, no_stay, order,
                                             urgent | in_danger | threatened)
        new, held = self._verified(pos, targets[np.arange(n), choice], cells, order)
        choice[held] = K.STAY
        self.paths_.advance(cells + K.OFFSETS[choice])  # step 6.6: leaving the path = replanning
        for i in np.flatnonzero(held):
            events.append({"robot": int(i), "kind": "move_withheld", "detail": "exact check found a contact"})
        modes = np.where(at_goal, "arrived", "follow").astype(object)
        modes[trace] = "trace"
        modes[trace & (choice == K.STAY)] = "wait"
        modes[seek & active] = "seek"
        modes[urgent & ~seek] = "resolve"
        modes[yielded] = "yield"
        modes[threatened & ~seek & ~yielded] = "evade"
        modes[in_danger] = "escape"
        return Decision(new, modes.tolist(), events)

    def _obstacle_rules(self, obs, cells, copies, targets, in_goal_cell, static_ok, valid, active):
        """Step 6.3 for moving obstacles plus our look-ahead (see the module docs). Returns
        (valid (n, 9), in danger (n,), threatened (n,), options (n,), safety (n, 9) or None,
        warning (n, 9) or None)."""
        n = len(cells)
        none = np.zeros(n, bool)
        fc = self.forecast_
        steps = max(self.lookahead, self.hazard_horizon)
        pos, obstacles = obs.positions, obs.obstacle_positions
        if fc.m == 0 or not np.any(np.max(np.abs(pos[:, None, :] - obstacles[None]), axis=2)
                                   <= fc.influence(steps) + 2 * self.world_.resolution):
            return valid, none, none, np.full(n, 9), None, None  # no obstacle can matter this step
        W, H = self.width_, self.height_
        cx, cy = cells[:, 0], cells[:, 1]
        covered = fc.coverage(obstacles, obs.obstacle_previous, steps, margin=self.margin)
        xs = np.clip(copies[..., 0], 0, W - 1)
        ys = np.clip(copies[..., 1], 0, H - 1)
        valid = valid & ~covered[0][ys, xs]  # never where an obstacle may be next step
        in_danger = covered[0][cy, cx]
        off_centre = np.linalg.norm(pos - self.grid_.centers(cells), axis=1) > 1e-9
        check = np.flatnonzero(in_danger | off_centre)
        if len(check):
            valid[check] &= ~fc.crossings(pos[check], targets[check], obstacles)
        # look-ahead: keep to the most cautious tier that leaves the robot some choice
        threatened = np.zeros(n, bool)
        undecided = np.ones(n, bool)
        base = valid
        # the tiers assume a robot at a cell centre; one that ends the step on its exact goal
        # off the centre (a cell corner, say) can reach fewer cells next step
        odd, odd_k = np.nonzero(in_goal_cell & self.goal_off_centre_[:, None])
        around = self.goal_cells_[odd][:, None, :] + K.OFFSETS[None]
        around_x = np.clip(around[..., 0], 0, W - 1)
        around_y = np.clip(around[..., 1], 0, H - 1)
        for depth in range(self.lookahead, 1, -1):
            tier, then = K.safe_tier(covered, self.moves_, depth)
            strict = base & tier[ys, xs]
            if len(odd):
                way_out = np.any(self.goal_moves_[odd] & then[around_y, around_x], axis=1)
                strict[odd, odd_k] = base[odd, odd_k] & ~covered[0][around_y[:, 0], around_x[:, 0]] & way_out
            usable = strict.any(axis=1) & undecided
            valid = np.where(usable[:, None], strict, valid)
            threatened |= usable & ~strict[:, K.STAY]
            undecided &= ~usable
            if not undecided.any():
                break
        # and, among those, prefer cells an obstacle cannot reach soon (leave early)
        safety = np.where(valid, K.stay_depth(covered[:self.leave_early], covered[0].shape)[ys, xs], -1)
        threatened |= safety.max(axis=1) > safety[:, K.STAY]
        threatened &= ~in_danger
        warning = None
        if self.hazard_horizon > 0 and self.hazard_weight > 0:
            warning = K.warning_levels(covered[:self.hazard_horizon], copies, self.hazard_decay)
        return valid, in_danger, threatened, valid.sum(axis=1), safety, warning

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

    def _preferences(self, full, valid, safety, path_next, seek, urgent, in_danger, threatened, active, at_goal,
                     reachable):
        """Each robot's own preference list (n, 9) of candidate indices, -1 padded, and the
        list it uses when it must yield (no staying). Followers and tracers: the next cell of
        their path, else wait; seekers, urgent, endangered and threatened robots: every valid
        copy from best to worst (``full``); parked robots stay."""
        n = len(full)
        rows = np.arange(n)
        path_ok = valid[rows, path_next] & (path_next != K.STAY)
        if safety is not None:  # do not step where an obstacle may come sooner than here
            path_ok &= safety[rows, path_next] >= safety[:, K.STAY]
        own = np.full((n, 9), -1, np.int64)
        follow_like = ~(seek | urgent | in_danger | threatened) & active
        own[follow_like & path_ok, 0] = path_next[follow_like & path_ok]
        own[follow_like & path_ok, 1] = K.STAY
        own[follow_like & ~path_ok, 0] = K.STAY
        own[at_goal & ~in_danger & ~threatened, 0] = K.STAY
        searching = (seek | urgent | in_danger | threatened) & active | (at_goal & (in_danger | threatened))
        if not self.keep_present:  # without SPC the robot moves to the best surviving copy, else waits
            full = np.where(full == K.STAY, -1, full)
        own[searching] = full[searching]
        walled_in = ~reachable & active  # no way to the goal: stay unless pushed
        own[walled_in] = -1
        own[walled_in, 0] = K.STAY
        no_stay = np.where(full == K.STAY, -1, full)
        own[in_danger] = no_stay[in_danger]
        return own, no_stay

    def _joint_choice(self, cells, copies, static_ok, own, no_stay, order, can_push):
        """One candidate index per robot (n,) and whether it was made to yield (n,): robots
        with no other robot within two cells take their first preference at once, the others
        go through :func:`reserve_moves` in ``order``."""
        n = len(cells)
        W = self.width_
        first = own[:, 0]
        choice = np.where(first >= 0, first, K.STAY)
        yielded = np.zeros(n, bool)
        crowded = K.crowded(cells, (self.height_, W))
        if not crowded.any():
            return choice, yielded
        idx = np.flatnonzero(crowded)  # work on the crowded robots only, renumbered 0..m-1
        local = np.full(n, -1, np.int64)
        local[idx] = np.arange(len(idx))
        c = copies[idx]
        flat_cells = np.where(static_ok[idx] | (np.arange(9) == K.STAY)[None], c[..., 1] * W + c[..., 0], -1)
        bx = c[..., 0] - (K.OFFSETS[:, 0] > 0)[None]
        by = c[..., 1] - (K.OFFSETS[:, 1] > 0)[None]
        blocks = np.where(K.DIAGONAL[None], (by + 1) * (W + 2) + (bx + 1), -1)
        fields, field_index = self.fields_, self.field_index_[idx]

        def distance(i: int, cell: int) -> float:
            return float(fields[field_index[i]].flat[cell])

        sub_choice, sub_yield = reserve_moves(local[order[crowded[order]]].tolist(),
                                              (cells[idx, 1] * W + cells[idx, 0]).tolist(), flat_cells.tolist(),
                                              blocks.tolist(), own[idx].tolist(), no_stay[idx].tolist(),
                                              can_push[idx].tolist(), stay=K.STAY, distance=distance)
        choice[idx] = sub_choice
        yielded[idx] = sub_yield
        return choice, yielded

    def _verified(self, pos: FloatArray, new: FloatArray, cells, order) -> tuple[FloatArray, NDArray]:
        """Exact robot-robot check of the chosen moves (the rules of the simulator's checker)
        where cell reasoning does not cover them: moves that start or end off a cell centre
        (an exact start or goal on a cell corner, say), and every move of disc robots (cells
        only separate points). A robot in a contact is held in place, lower priority first,
        and the robots around it are checked again. Returns (positions, held mask)."""
        n = len(pos)
        grid = self.grid_
        held = np.zeros(n, bool)
        radii = self.radii_
        discs = bool(np.any(radii > 0))
        c1 = np.floor(new / grid.resolution + 1e-9).astype(np.int64)  # the checker's cells
        special = (np.linalg.norm(pos - grid.centers(cells), axis=1) > 1e-9) | \
            (np.linalg.norm(new - grid.centers(c1), axis=1) > 1e-9)
        if discs:
            special[:] = True
        if not special.any() or n < 2:
            return new, held
        rank = np.empty(n, np.int64)
        rank[order] = np.arange(n)
        out = new.copy()
        tree = cKDTree(pos)
        reach = 4.3 * self.world_.resolution + 2 * float(radii.max(initial=0.0))
        check = special
        for _ in range(n + 1):
            idx = np.flatnonzero(check)
            if len(idx) == 0:
                break
            near = tree.query_ball_point(pos[idx], reach)
            i = np.repeat(idx, [len(v) for v in near])
            j = np.fromiter((x for v in near for x in v), np.int64, count=len(i))
            keep = i != j
            i, j = i[keep], j[keep]
            bad = np.flatnonzero(move_conflicts(pos[i], out[i], pos[j], out[j], radii[i], radii[j], grid.resolution))
            check = np.zeros(n, bool)
            for k in bad:
                a, b = int(i[k]), int(j[k])
                movers = [x for x in (a, b) if np.any(out[x] != pos[x])]
                if not movers:
                    continue
                victim = max(movers, key=lambda x: rank[x])
                out[victim] = pos[victim]
                held[victim] = True
                check[victim] = True
        return out, held
