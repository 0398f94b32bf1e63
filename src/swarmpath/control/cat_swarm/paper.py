"""The ``cat-swarm-paper`` controller: Jaleel & Hassan (2016), Algorithms 2-4, as printed.

Only the paper's rules and the interpretations the paper needs (docs/papers/
jaleel-hassan-2016.md, "The paper-pure variant"); none of the additions of ``cat-swarm``
(no obstacle forecast, look-ahead, warning term, per-group split, joint reservation,
priorities, deadlock handling or exact check). Every step, for all robots at once:

1. **Algorithm 2-3, collision detection.** Each robot's current position Rc and next
   position Rn (the next cell of its path) are compared with every object's current and
   next position: other robots (their Rc and Rn) and moving obstacles (their position and
   :func:`~.kernels.linear_next`). Positions within the medium class (``conflict_range``
   cells, eq. 9 between points) are in the robot's short/medium lists; a robot with a
   listed object is in conflict.
2. **Eq. 10-11, the flags**, over all robots of the world: the round(MR * N) robots with
   the longest remaining path get seek (flag 1), the others trace (flag 0); ties by random
   keys drawn at reset.
3. A robot not in conflict moves to the next cell of its path (no avoidance needed).
4. **Step 5.** A tracing robot in conflict with a moving obstacle in its lists seeks.
5. **Step 6, seek.** The 8 copies plus the present position (SPC); copies on static
   obstacles (or out of reach) and copies closer than ``keep_clear`` cells to a listed
   object position are deleted; none left: wait; else the smallest eq. 12 fitness, ties by
   eq. 13. The robot moves there; leaving its path, it replans (the distance field).
6. **Step 7, trace.** A listed object position closer than ``keep_clear`` cells: wait;
   else the next cell of the path.

Moves go between cell centres (one 8-neighbour cell per step). A robot that starts off its
cell centre (the starts of ``jaleel2016`` lie on cell corners) settles on the centre first;
when the next cell of its path holds its exact goal off the centre, farther than one step,
it takes the reachable copy with the best eq. 12 fitness instead. The paper's robots move
between grid points, where neither can happen.

Robots decide simultaneously from the same observation and nothing checks their choices
against each other, so contacts can happen (``capabilities.contact_free`` is False) and so
can deadlocks (nothing detects them; the simulator ends a run in which nobody moves).
"""
from __future__ import annotations

import numpy as np

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.cat_swarm import kernels as K
from swarmpath.control.cat_swarm.cells import PathTracker, grid_cells
from swarmpath.control.observation import Observation
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.world.world import World

SPLITS = ("world", "group")


@register_controller("cat-swarm-paper")
class CatSwarmPaperController(Controller):
    """Modified cat swarm collision avoidance exactly as Jaleel & Hassan (2016) print it.

    Parameters (the paper's values as defaults):
        mixture_ratio : MR of eq. 10-11 (0.4).
        keep_present : SPC, the present position is one of the copies (True).
        conflict_range : upper bound of the medium distance class, cells (3: short (0, 2],
            medium (2, 3]); an object position this close to Rc or Rn puts a robot in conflict.
        keep_clear : the paper's "distance less than one", cells (1): copies this close to a
            listed object position are deleted, and a tracing robot this close to one waits.
        split : over whom eq. 10-11 split the robots: ``"world"`` (every robot, the paper's
            example: 12 robots, 5 seek) or ``"group"`` (each group of robots in conflict with
            each other, the reading ``cat-swarm`` uses; see the docs page).
    """

    capabilities = Capabilities(grid_based=True, moving_obstacles=True, multi_robot=True, randomized=True,
                                contact_free=False)

    def __init__(self, mixture_ratio: float = 0.4, keep_present: bool = True, conflict_range: float = 3.0,
                 keep_clear: float = 1.0, split: str = "world"):
        self.mixture_ratio = mixture_ratio
        self.keep_present = keep_present
        self.conflict_range = conflict_range
        self.keep_clear = keep_clear
        self.split = split

    def _check_parameters(self) -> None:
        if not 0.0 <= self.mixture_ratio <= 1.0:
            raise ConfigError(f"cat-swarm-paper: mixture_ratio must be in [0, 1], got {self.mixture_ratio}")
        if not self.conflict_range > 0:
            raise ConfigError(f"cat-swarm-paper: conflict_range must be > 0 cells, got {self.conflict_range}")
        if not self.keep_clear > 0:
            raise ConfigError(f"cat-swarm-paper: keep_clear must be > 0 cells, got {self.keep_clear}")
        if self.split not in SPLITS:
            raise ConfigError(f"cat-swarm-paper: split must be one of {', '.join(SPLITS)}, got {self.split!r}")

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self._check_parameters()
        self.cells_ = grid_cells(world, "cat-swarm-paper")
        self.paths_ = PathTracker.from_plan(world, plan, self.cells_)
        self.tiebreak_ = rng.random(world.n_robots)
        self.resolution_ = world.resolution

    def act(self, obs: Observation) -> Decision:
        n = obs.n_robots
        if n == 0:
            return Decision(obs.positions.copy(), [])
        pos, goals = obs.positions, obs.goals
        rows = np.arange(n)
        cells = self.cells_.cells(pos)
        copies = K.seek_copies(cells)
        fitness = K.fitness_eq12(self.cells_.fields, self.cells_.field_index, copies)
        remaining = self.paths_.remaining(cells, fitness[:, K.STAY])
        targets, _, static_ok, valid = self.cells_.candidates(pos, goals, cells, copies)
        tie = K.tie_break_eq13(targets, goals)
        path_next = self.paths_.next_step(cells, fitness, static_ok, tie)
        # Algorithm 2-3: current and next positions of robots and objects
        robot_next = targets[rows, path_next]
        now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        nxt = K.linear_next(obs.obstacle_previous, now)
        objects = np.concatenate([pos, robot_next, now, nxt])
        owner = np.concatenate([rows, rows, np.full(2 * len(now), -1)])
        robot, row = K.conflict_lists(np.stack([pos, robot_next], axis=1), objects, owner,
                                      self.conflict_range * self.resolution_)
        listed = objects[row]
        in_conflict = np.zeros(n, bool)
        in_conflict[robot] = True
        sees_obstacle = np.zeros(n, bool)
        sees_obstacle[robot[owner[row] < 0]] = True
        # eq. 10-11 (over all robots, or per conflict group), then step 5
        if self.split == "world":
            seek = K.mixture_split(remaining, np.zeros(n, np.int64), self.mixture_ratio, self.tiebreak_)
        else:
            seek = np.zeros(n, bool)
            members = np.flatnonzero(in_conflict)
            is_robot = owner[row] >= 0
            edges = np.stack([robot[is_robot], owner[row[is_robot]]], axis=1)
            seek[members] = K.mixture_split(remaining[members], K.conflict_groups(edges, in_conflict),
                                            self.mixture_ratio, self.tiebreak_[members])
        seek = in_conflict & (seek | sees_obstacle)
        trace = in_conflict & ~seek
        # step 6: delete copies, rank the rest (eq. 12, eq. 13), wait when none is left
        clear = self.keep_clear * self.resolution_
        copy_ok = valid & ~K.near_listed(targets, robot, listed, clear)
        if not self.keep_present:
            copy_ok[:, K.STAY] = False
        best = K.rank_copies(fitness, tie, copy_ok, decimals=self.cells_.decimals)[:, 0]
        seek_choice = np.where(copy_ok[rows, best], best, K.STAY)
        # steps 3 and 7: the next cell of the path (a tracing robot with a listed object too close
        # waits). A next cell out of reach: a robot off its cell centre (its exact start) settles
        # on the centre first; at a centre, next to an exact goal farther than a step, it takes
        # the reachable copy with the best eq. 12 fitness
        reachable = K.rank_copies(fitness, tie, valid, decimals=self.cells_.decimals)[:, 0]
        off_centre = np.linalg.norm(pos - self.cells_.grid.centers(cells), axis=1) > 1e-9
        step = np.where(valid[rows, path_next], path_next, np.where(off_centre, K.STAY, reachable))
        blocked = trace & K.near_listed(pos[:, None, :], robot, listed, clear)[:, 0]
        follow_choice = np.where(blocked, K.STAY, step)
        choice = np.where(seek, seek_choice, follow_choice)
        self.paths_.advance(cells + K.OFFSETS[choice])  # step 6.6: leaving the path = replanning
        modes = np.where(obs.at_goal, "arrived", "follow").astype(object)
        modes[trace] = "trace"
        modes[seek] = "seek"
        modes[in_conflict & (choice == K.STAY) & ~obs.at_goal] = "wait"
        return Decision(targets[rows, choice], modes.tolist())
