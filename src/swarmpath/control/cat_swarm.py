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
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from swarmpath.control import cat_swarm_kernels as K
from swarmpath.control.base import Controller, Decision
from swarmpath.control.cell_paths import plan_cells, remaining_lengths
from swarmpath.control.deadlock import DeadlockMonitor, priority_order
from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.reservation import reserve_moves
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Capabilities
from swarmpath.registry import register_controller
from swarmpath.search import distance_field
from swarmpath.world import geometry as geo

FloatArray = NDArray[np.float64]
CLASS_INDEX = {"short": 0, "medium": 1, "long": 2, "very long": 3}
OFFSET_INDEX = np.zeros((3, 3), np.int64)
for _k, (_dx, _dy) in enumerate(K.OFFSETS):
    OFFSET_INDEX[_dx + 1, _dy + 1] = _k
FIELD_BYTES_FLOAT64 = 256 * 2 ** 20


@register_controller("cat-swarm")
class CatSwarmController(Controller):
    """Modified cat swarm collision avoidance (Jaleel & Hassan 2016, Algorithm 4).

    Parameters (paper values where the paper gives them):
        mixture_ratio : MR of eq. 10-11 (0.4).
        seeking_range : SRD in cells (1: the 8 neighbours).
        keep_present : SPC, the present position is a candidate too (True).
        obstacle_alert : distance class up to which a moving obstacle puts a robot in conflict
            ("short", "medium" as in the paper, "long" default, "very long").
        margin : extra cells kept clear around obstacles' current and next footprints (0).
        lookahead : steps over which a robot makes sure it can keep clear of moving obstacles
            whatever they do (5; 1 = only the next step, as in the paper).
        leave_early : a robot prefers cells no obstacle can reach within this many steps and
            leaves a cell (even its goal) that an obstacle may reach that soon (2).
        hazard_horizon, hazard_weight, hazard_decay : look-ahead (steps), weight (cells of
            fitness) and decay per step of the early-warning term that makes robots leave an
            obstacle's way early (4, 2.0, 0.7).
        patience : steps without progress before a robot counts as stuck and may push (6).
        report_after : steps without progress before a deadlock event is recorded (40).
    """

    capabilities = Capabilities(grid_based=True, moving_obstacles=True, multi_robot=True, randomized=True)

    def __init__(self, mixture_ratio: float = 0.4, seeking_range: int = 1, keep_present: bool = True,
                 obstacle_alert: str = "long", margin: int = 0, lookahead: int = 5, leave_early: int = 2,
                 hazard_horizon: int = 4,
                 hazard_weight: float = 2.0, hazard_decay: float = 0.7, patience: int = 6,
                 report_after: int = 40):
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

    def reset(self, world, plan, rng: np.random.Generator) -> None:
        self._check_parameters()
        n = world.n_robots
        res = world.resolution
        self.world_ = world
        self.reach_ = world.max_speeds * world.dt
        slow = np.flatnonzero(self.reach_ < res * (1 - 1e-9))
        if len(slow):
            raise ConfigError(f"cat-swarm moves one grid cell per step: robot {world.robots[slow[0]].id!r} "
                              f"has max_speed * dt = {self.reach_[slow[0]]:g} < resolution {res:g}")
        grid = world.grid(radius=float(world.radii.max(initial=0.0)))
        self.grid_ = grid
        blocked = grid.blocked
        self.height_, self.width_ = blocked.shape
        self.moves_ = K.move_table(blocked)
        goals = world.goals
        self.goal_cells_ = grid.cell_of(goals).reshape(-1, 2)
        # one distance field per goal cell (eq. 12 and the replanned paths)
        flat_goal = self.goal_cells_[:, 1] * self.width_ + self.goal_cells_[:, 0] if n else np.zeros(0, np.int64)
        unique, self.field_index_ = np.unique(flat_goal, return_inverse=True)
        big = len(unique) * blocked.size * 8 > FIELD_BYTES_FLOAT64
        self.fields_ = np.empty((len(unique), self.height_, self.width_), np.float32 if big else np.float64)
        self.decimals_ = 3 if big else 6
        for g, flat in enumerate(unique):
            cell = (int(flat % self.width_), int(flat // self.width_))
            if grid.is_free(np.asarray(cell)):
                self.fields_[g] = distance_field(blocked, cell)
            else:
                self.fields_[g] = np.inf
        # each robot's path as grid cells (offline plan), or none: follow the distance field
        paths = plan.paths if plan is not None else [None] * n
        chunks, rems, starts, lengths = [], [], np.zeros(n, np.int64), np.zeros(n, np.int64)
        total = 0
        start_cells = grid.cell_of(world.starts).reshape(-1, 2)
        for i in range(n):
            p = paths[i] if i < len(paths) else None
            cells = plan_cells(p, res, blocked) if p is not None else None
            if cells is not None and (np.any(cells[0] != start_cells[i]) or np.any(cells[-1] != self.goal_cells_[i])):
                cells = None
            starts[i] = total
            if cells is not None:
                chunks.append(cells)
                rems.append(remaining_lengths(cells))
                lengths[i] = len(cells)
                total += len(cells)
        self.path_flat_ = np.concatenate(chunks) if chunks else np.zeros((1, 2), np.int64)
        self.path_rem_flat_ = np.concatenate(rems) if rems else np.zeros(1)
        self.path_start_ = starts
        self.path_len_ = lengths
        self.path_k_ = np.where(lengths > 0, 0, -1).astype(np.int64)
        self.tiebreak_ = rng.random(n)
        self.rng_ = rng
        self.monitor_ = DeadlockMonitor.start(n, patience=self.patience, report_after=self.report_after)
        self.forecast_ = ObstacleForecast(world, grid)

    # ------------------------------------------------------------------ helpers
    def _path_index(self, ahead: int = 0) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
        """Index into the concatenated paths of each robot's path cell ``ahead`` of its
        current one, and whether that cell exists (robots off their path: False)."""
        k = self.path_k_ + ahead
        ok = (self.path_k_ >= 0) & (k < self.path_len_)
        idx = np.clip(self.path_start_ + np.maximum(k, 0), 0, len(self.path_flat_) - 1)
        return idx, ok

    def _remaining(self, cells: NDArray[np.int64], field_here: FloatArray) -> FloatArray:
        """Remaining path length (cells): along the offline path while the robot is on it,
        else the replanned (shortest) length. A robot found off its path has replanned."""
        idx, ok = self._path_index()
        on = ok & np.all(self.path_flat_[idx] == cells, axis=1)
        self.path_k_[~on] = -1
        return np.where(on, self.path_rem_flat_[idx], field_here)

    def _path_next(self, cells: NDArray[np.int64], static_ok, tie) -> NDArray[np.int64]:
        """Offset index of the next cell of each robot's path (0 = stay): the offline path
        while the robot is on it, else the replanned shortest path (distance field)."""
        nxt = K.descent_step(self.fields_, self.field_index_, cells, static_ok, tie)
        on = self.path_k_ >= 0
        idx, has_next = self._path_index(1)
        d = self.path_flat_[idx] - cells
        step_ok = has_next & (np.max(np.abs(d), axis=1) == 1)
        k = np.where(step_ok, OFFSET_INDEX[np.clip(d[:, 0] + 1, 0, 2), np.clip(d[:, 1] + 1, 0, 2)], K.STAY)
        step_ok &= static_ok[np.arange(len(cells)), k]
        at_end = on & ~has_next
        nxt = np.where(at_end, K.STAY, np.where(on & step_ok, k, nxt))
        self.path_k_[on & has_next & ~step_ok] = -1  # the path is broken here: replan
        return nxt

    def _advance_paths(self, new_cells: NDArray[np.int64]) -> None:
        """Move each robot's place on its path; leaving the path means replanning."""
        here, on = self._path_index()
        nxt, has_next = self._path_index(1)
        advanced = has_next & np.all(self.path_flat_[nxt] == new_cells, axis=1)
        stayed = on & np.all(self.path_flat_[here] == new_cells, axis=1)
        self.path_k_ = np.where(advanced, self.path_k_ + 1, np.where(stayed, self.path_k_, -1))

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
    def act(self, obs) -> Decision:
        world = self.world_
        grid = self.grid_
        n = obs.n_robots
        if n == 0:
            return Decision(obs.positions.copy(), [])
        W, H = self.width_, self.height_
        pos = obs.positions
        goals = obs.goals
        at_goal = obs.at_goal
        active = ~at_goal
        cells = grid.cell_of(pos)
        cx, cy = cells[:, 0], cells[:, 1]
        fi = self.field_index_
        field_here = self.fields_[fi, cy, cx].astype(float)
        remaining = self._remaining(cells, field_here)
        events = self.monitor_.update(obs.step, remaining, at_goal)

        # --- candidates (step 6.1-6.3): 9 cells per robot, their targets and deletions
        copies = K.seek_copies(cells, srd=self.seeking_range, spc=self.keep_present)
        static_ok = self.moves_[cy, cx]
        targets = grid.centers(copies)
        in_goal_cell = np.all(copies == self.goal_cells_[:, None, :], axis=2)
        targets = np.where(in_goal_cell[..., None], goals[:, None, :], targets)
        targets[:, K.STAY] = np.where(in_goal_cell[:, K.STAY, None], goals, grid.centers(cells))
        reach = np.linalg.norm(targets - pos[:, None, :], axis=2) <= self.reach_[:, None] * (1 + 1e-9) + 1e-12
        valid = static_ok & reach
        valid[:, K.STAY] = True  # staying (or settling inside one's own cell) is always a move
        has_obstacles = len(world.moving_obstacles) > 0
        threatened = np.zeros(n, bool)
        options = np.full(n, 9)
        safety = None
        if has_obstacles:
            fc = self.forecast_
            covered = fc.coverage(obs.obstacle_positions, obs.obstacle_previous, self.lookahead, margin=self.margin)
            xs = np.clip(copies[..., 0], 0, W - 1)
            ys = np.clip(copies[..., 1], 0, H - 1)
            valid &= ~covered[0][ys, xs]  # never where an obstacle may be next step
            in_danger = covered[0][cy, cx]
            off_centre = np.linalg.norm(pos - grid.centers(cells), axis=1) > 1e-9
            check = np.flatnonzero(in_danger | off_centre)
            if len(check):
                valid[check] &= ~fc.crossings(pos[check], targets[check], obs.obstacle_positions)
            # look-ahead: keep to the most cautious tier that leaves the robot some choice
            undecided = np.ones(n, bool)
            base = valid
            for depth in range(self.lookahead, 1, -1):
                tier = K.safe_tier(covered, self.moves_, depth)
                strict = base & tier[ys, xs]
                usable = strict.any(axis=1) & undecided
                valid = np.where(usable[:, None], strict, valid)
                threatened |= usable & ~tier[cy, cx]
                undecided &= ~usable
                if not undecided.any():
                    break
            # and, among those, prefer cells an obstacle cannot reach soon (leave early)
            safety = np.where(valid, K.stay_depth(covered[:self.leave_early])[ys, xs], -1)
            threatened |= safety.max(axis=1) > safety[:, K.STAY]
            threatened &= ~in_danger
            options = valid.sum(axis=1)
        else:
            in_danger = np.zeros(n, bool)

        # --- fitness (eq. 12) with the early-warning term, ties by eq. 13
        tie = K.tie_break_eq13(targets, goals)
        fitness = K.fitness_eq12(self.fields_, fi, copies)
        if has_obstacles and self.hazard_horizon > 0 and self.hazard_weight > 0:
            hazard = self.forecast_.hazard(obs.obstacle_positions, obs.obstacle_previous, horizon=self.hazard_horizon,
                                           decay=self.hazard_decay)
            fitness = fitness + self.hazard_weight * hazard[np.clip(copies[..., 1], 0, H - 1),
                                                            np.clip(copies[..., 0], 0, W - 1)]
        ranked = K.rank_copies(fitness, tie, valid, decimals=self.decimals_, safety=safety)
        ranked_valid = np.take_along_axis(valid, ranked, axis=1)

        # --- collision detection and the mixture split (eq. 10-11, Algorithm 4 steps 1-5)
        edges, robot_conflict, obstacle_alert = self._conflicts(obs, active)
        conflict = robot_conflict | obstacle_alert
        seek = np.zeros(n, bool)
        members = np.flatnonzero(conflict)
        if len(members):
            local = -np.ones(n, np.int64)
            local[members] = np.arange(len(members))
            e = edges[conflict[edges[:, 0]] & conflict[edges[:, 1]]]
            graph = coo_matrix((np.ones(len(e)), (local[e[:, 0]], local[e[:, 1]])),
                               shape=(len(members), len(members)))
            _, labels = connected_components(graph, directed=False)
            seek[members] = K.mixture_split(remaining[members], labels, self.mixture_ratio,
                                            self.tiebreak_[members])
        seek |= obstacle_alert  # trace robots that see a moving obstacle switch to seek
        urgent = self.monitor_.urgent & active
        trace = conflict & ~seek

        # --- each robot's own preference list (indices into its 9 candidates)
        path_next = self._path_next(cells, static_ok, tie)
        rows = np.arange(n)
        path_ok = valid[rows, path_next] & (path_next != K.STAY)
        if safety is not None:  # do not step where an obstacle may come sooner than here
            path_ok &= safety[rows, path_next] >= safety[:, K.STAY]
        own = np.full((n, 9), -1, np.int64)
        follow_like = ~(seek | urgent | in_danger | threatened) & active
        own[follow_like & path_ok, 0] = path_next[follow_like & path_ok]
        own[follow_like & path_ok, 1] = K.STAY
        own[follow_like & ~path_ok, 0] = K.STAY
        parked = at_goal & ~in_danger & ~threatened
        own[parked, 0] = K.STAY
        searching = (seek | urgent | in_danger | threatened) & active | (at_goal & (in_danger | threatened))
        full = np.where(ranked_valid, ranked, -1)
        if not self.keep_present:  # without SPC the robot moves to the best surviving copy, else waits
            full = np.where(full == K.STAY, -1, full)
        own[searching] = full[searching]
        walled_in = ~np.isfinite(field_here) & active  # no way to the goal: stay unless pushed
        own[walled_in] = -1
        own[walled_in, 0] = K.STAY
        no_stay = np.where(ranked == K.STAY, -1, full)
        own[in_danger] = no_stay[in_danger]

        # --- joint choice: isolated robots at once, the rest in priority order with yielding
        order = priority_order(self.monitor_.urgent_since, in_danger, threatened, options, active, remaining,
                               self.tiebreak_)
        reach_pairs = cKDTree(pos).query_pairs(4.3 * world.resolution, output_type="ndarray")
        crowded = np.zeros(n, bool)
        if len(reach_pairs):
            cheb = np.max(np.abs(cells[reach_pairs[:, 0]] - cells[reach_pairs[:, 1]]), axis=1)
            near = reach_pairs[cheb <= 2]
            crowded[near[:, 0]] = True
            crowded[near[:, 1]] = True
        first = own[:, 0]
        choice = np.where(first >= 0, first, K.STAY)
        yielded = np.zeros(n, bool)
        if crowded.any():
            idx = np.flatnonzero(crowded)
            sub_order = order[crowded[order]]
            flat_cells = np.where(static_ok | (np.arange(9) == K.STAY)[None],
                                  copies[..., 1] * W + copies[..., 0], -1)
            bx = copies[..., 0] - (K.OFFSETS[:, 0] > 0)[None]
            by = copies[..., 1] - (K.OFFSETS[:, 1] > 0)[None]
            blocks = np.where(K.DIAGONAL[None], (by + 1) * (W + 2) + (bx + 1), -1)
            cur_flat = (cy * W + cx).tolist()
            cand_cell = [None] * n
            cand_block = [None] * n
            own_l = [None] * n
            push_l = [None] * n
            can_push = (urgent | in_danger | threatened).tolist()
            fc, bl, ow, ns = flat_cells[idx].tolist(), blocks[idx].tolist(), own[idx].tolist(), no_stay[idx].tolist()
            for r, i in enumerate(idx.tolist()):
                cand_cell[i] = fc[r]
                cand_block[i] = bl[r]
                own_l[i] = [k for k in ow[r] if k >= 0]
                push_l[i] = [k for k in ns[r] if k >= 0]
            sub_choice, sub_yield = reserve_moves(sub_order.tolist(), cur_flat, cand_cell, cand_block, own_l, push_l,
                                                  can_push, stay=K.STAY)
            sub_choice = np.asarray(sub_choice)
            choice[idx] = sub_choice[idx]
            yielded[idx] = np.asarray(sub_yield)[idx]
        new = targets[rows, choice]
        new, held = self._verified(pos, new, cells, grid.cell_of(new), order)
        choice[held] = K.STAY
        new_cells = cells + K.OFFSETS[choice]

        # --- bookkeeping: path progress (a robot that leaves its path replans)
        self._advance_paths(new_cells)
        modes = np.where(at_goal, "arrived", "follow").astype(object)
        modes[trace] = "trace"
        modes[trace & (choice == K.STAY)] = "wait"
        modes[seek & active] = "seek"
        modes[urgent & ~seek] = "resolve"
        modes[yielded] = "yield"
        modes[threatened & ~seek & ~yielded] = "evade"
        modes[in_danger] = "escape"
        for i in np.flatnonzero(held):
            events.append({"robot": int(i), "kind": "move_withheld", "detail": "exact check found a contact"})
        return Decision(new, modes.tolist(), events)

    def _verified(self, pos: FloatArray, new: FloatArray, cells, new_cells, order) -> tuple[FloatArray, NDArray]:
        """Exact robot-robot check of the chosen moves (same rules as the simulator's
        checker); a robot in a contact is held in place, lower priority first, until none is
        left. Catches the rare contacts cell reasoning misses (robots resting on a cell
        corner, such as an exact goal). Returns (positions, held mask)."""
        n = len(pos)
        held = np.zeros(n, bool)
        rank = np.empty(n, np.int64)
        rank[order] = np.arange(n)
        out = new.copy()
        for _ in range(n + 1):
            pairs = cKDTree(pos).query_pairs(4.3 * self.world_.resolution, output_type="ndarray")
            if len(pairs) == 0:
                break
            i, j = pairs[:, 0], pairs[:, 1]
            c1 = self.grid_.cell_of(out)
            same = np.all(c1[i] == c1[j], axis=1)
            swap = np.all(c1[i] == cells[j], axis=1) & np.all(c1[j] == cells[i], axis=1)
            touch = geo.relative_min_distance(pos[i], out[i], pos[j], out[j]) < 1e-7
            bad = np.flatnonzero(same | swap | touch)
            if len(bad) == 0:
                break
            changed = False
            for k in bad:
                a, b = int(i[k]), int(j[k])
                moved_a = np.any(out[a] != pos[a])
                moved_b = np.any(out[b] != pos[b])
                cands = [x for x, m in ((a, moved_a), (b, moved_b)) if m]
                if not cands:
                    continue
                victim = max(cands, key=lambda x: rank[x])
                out[victim] = pos[victim]
                held[victim] = True
                changed = True
            if not changed:
                break
        return out, held
