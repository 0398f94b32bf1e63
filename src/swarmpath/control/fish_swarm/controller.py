"""The ``fish-swarm`` controller: artificial fish swarm path planning among moving obstacles on
a grid (Karim 2014, "Path planning in dynamic environment based on artificial fish swarm";
docs/papers/karim-2014.md).

The robot and the moving obstacles (and, with several robots, the other robots) are "fish".
Every step the robot counts the fish ``nf`` in its visual range (the 8-neighbourhood by
default) and picks one behaviour (Algorithm 1, Step 3):

- ``nf == 0``: **prey** (Step 4): move to the free neighbour with the best food (nearest to
  the goal);
- ``0 < nf < w``: **follow** (Step 5): trail a visible fish that is nearer to the goal, if the
  neighbourhood is not crowded (``nf / n < delta``); otherwise prey;
- ``nf >= w``: **swarm** (Step 6): move toward the centre of the visible fish through a
  neighbour nearer to the goal, if not crowded; otherwise prey;
- **wait**: no neighbour can be entered (the robot stays; the step counts).

Food concentration Y(X) is "distance to the goal, lower is better": the Euclidean distance as in
the paper (``food="euclidean"``) or the grid distance field around the static obstacles
(``food="distance-field"``), which removes the local minima behind walls.

The paper's behaviours are the pure functions of :mod:`.behaviours` (cells are integer (x, y)
arrays, food values floats); :class:`FishSwarmController` wires them to the simulator: it finds the cells a
robot may enter this step (static grid, no corner cutting, moving-obstacle footprints at their
new positions) and, for obstacles that travel (every model except ``redraw``), avoids ending
next to one when it can, because the obstacle moves before the robot on the next step.

Several robots: each robot's behaviour ranks its candidate moves (its behaviour's choice
first, then the other cells it may enter by food, then waiting) and the PIBT core
(:func:`swarmpath.control.pibt.core.pibt_step`) decides for all robots at once: no shared cell,
no swap, no crossing, a robot in another's way pushed aside or passed by (the checker's own
rule, :func:`swarmpath.world.move_rules.grid_conflict_table`); moves off cell centres and disc
robots wider than half a cell are checked exactly
(:func:`swarmpath.control.pibt.exact.hold_conflicts`). A robot sees only the robots within its
visual range, so a step costs O(n). With one robot the core takes the behaviour's choice:
Karim's single-robot results are unchanged.
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.finish import held_discs, off_centre_discs, waiting_home
from swarmpath.control.fish_swarm.behaviours import (
    ARRIVED,
    FOOD_MODELS,
    NEIGHBOURS,
    PREY,
    WAIT,
    FloatArray,
    IntArray,
    fish_decision,
    food_euclidean,
    food_from_field,
    visible_fish,
)
from swarmpath.control.grid_robots import check_grid_robots
from swarmpath.control.observation import Observation
from swarmpath.control.pibt.core import (
    PUSHED,
    STAY,
    GridGraph,
    decision_order,
    pibt_step,
    update_priorities,
)
from swarmpath.control.pibt.exact import hold_conflicts
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.search import DistanceFieldCache
from swarmpath.world import geometry as g
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import MovingObstacle
from swarmpath.world.shapes import Rect
from swarmpath.world.world import World

#: Rank of a move the robot may not make (the core never looks at it).
NOT_ALLOWED = 99.0
#: Index into ``GRID_MOVES`` of the move (dx + 1, dy + 1).
MOVE_INDEX = np.zeros((3, 3), np.int64)
for _k, (_dx, _dy) in enumerate(GRID_MOVES.tolist()):
    MOVE_INDEX[_dx + 1, _dy + 1] = _k


class _CellIndex:
    """The robots standing in each cell, to find a robot's neighbours in O(1)."""

    def __init__(self, cells: IntArray):
        self.by_cell: dict[tuple[int, int], list[int]] = {}
        for k, (x, y) in enumerate(cells.tolist()):
            self.by_cell.setdefault((x, y), []).append(k)

    def around(self, cell, radius: int, skip: int) -> IntArray:
        """Robots (sorted) in the cells within Chebyshev ``radius`` of ``cell``, but ``skip``."""
        x0, y0 = int(cell[0]), int(cell[1])
        out = [k for dy in range(-radius, radius + 1) for dx in range(-radius, radius + 1)
               for k in self.by_cell.get((x0 + dx, y0 + dy), ()) if k != skip]
        return np.array(sorted(out), np.int64)


def _max_obstacle_step(world: World, ob: MovingObstacle) -> float:
    """Longest move an obstacle can make in one step (world units, its motion model's worst
    case); 0 for a model that teleports (``redraw``), whose next position is unknown."""
    return 0.0 if ob.motion.teleports else ob.max_step(world.dt, world.resolution)


@register_controller("fish-swarm")
class FishSwarmController(Controller):
    """Artificial fish swarm controller (Karim 2014) for point or disc robots on the world's
    grid (8-connected moves between cell centres).

    Parameters
    ----------
    visual : visual range in cells (Chebyshev radius; 1 = the 8-neighbourhood, the paper's)
    w : fish count from which the robot swarms instead of following (paper: 3)
    delta : crowd factor, follow/swarm need ``nf / n < delta`` (paper: 0.5; 0 disables them:
        the robot always preys)
    food : ``"euclidean"`` (the paper) or ``"distance-field"`` (grid distance to the goal
        around static obstacles; complete on static maps)
    avoid_next : keep out of the one-step reach of travelling (non-``redraw``) obstacles when
        another move, or waiting, is possible
    """

    capabilities: ClassVar[Capabilities] = Capabilities(needs_plan=False, grid_based=True, moving_obstacles=True,
                                                        multi_robot=True)

    def __init__(self, visual: int = 1, w: int = 3, delta: float = 0.5, food: str = "euclidean",
                 avoid_next: bool = True):
        if int(visual) != visual or visual < 1:
            raise ConfigError(f"fish-swarm: visual must be an integer >= 1 (cells), got {visual!r}")
        if int(w) != w or w < 1:
            raise ConfigError(f"fish-swarm: w must be an integer >= 1, got {w!r}")
        if not (0.0 <= float(delta) <= 1.0):
            raise ConfigError(f"fish-swarm: delta must be in [0, 1], got {delta!r}")
        if food not in FOOD_MODELS:
            raise ConfigError(f"fish-swarm: food must be one of {', '.join(FOOD_MODELS)}, got {food!r}")
        self.visual = int(visual)
        self.w = int(w)
        self.delta = float(delta)
        self.food = food
        self.avoid_next = bool(avoid_next)

    # ------------------------------------------------------------------ run state
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        check_grid_robots(world, "fish-swarm", max_radius_cells=float("inf"))  # it checks discs exactly
        self.world_ = world
        self.rng_ = rng
        self.grids_ = [world.grid(radius=r.radius) for r in world.robots]
        self.goal_cells_ = [grid.cell_of(np.asarray(r.goal, float)) for grid, r in zip(self.grids_, world.robots)]
        self.fields_: list[FloatArray | None] = [None] * world.n_robots
        if self.food == "distance-field":
            caches: dict[int, DistanceFieldCache] = {}
            for i, (grid, cell) in enumerate(zip(self.grids_, self.goal_cells_)):
                if grid.is_free(cell):
                    cache = caches.setdefault(id(grid), DistanceFieldCache(grid))
                    self.fields_[i] = cache.field(cell)
                else:
                    self.fields_[i] = np.full(grid.blocked.shape, np.inf)
        self.obstacle_reach_ = np.array([_max_obstacle_step(world, ob) for ob in world.moving_obstacles], float)
        self.obstacle_extent_ = np.array([ob.extent for ob in world.moving_obstacles], float)
        self.obstacle_is_box_ = np.array([isinstance(ob.shape, Rect) for ob in world.moving_obstacles], dtype=bool)
        self.obstacle_lo_ = np.array([ob.shape.min if isinstance(ob.shape, Rect) else (0.0, 0.0)
                                      for ob in world.moving_obstacles], float).reshape(-1, 2)
        self.obstacle_hi_ = np.array([ob.shape.max if isinstance(ob.shape, Rect) else (0.0, 0.0)
                                      for ob in world.moving_obstacles], float).reshape(-1, 2)
        self.warned_ = set()
        self.radii_ = world.radii
        # the PIBT core, for several robots: priorities from a child stream, so that the draws
        # of the behaviours (one shuffle per robot and step) are those of a single robot's run
        n = world.n_robots
        grid = self.grids_[int(np.argmax(world.radii))] if n else world.grid()
        self.graph_ = GridGraph.build(grid.blocked, 8, float(min(world.radii.max(initial=0.0), 0.5 * world.resolution)),
                                      world.resolution)
        cells = np.clip(grid.cell_of(world.goals), 0, [grid.width - 1, grid.height - 1]) if n else np.zeros((0, 2))
        self.goal_flat_ = (cells[:, 1] * grid.width + cells[:, 0]).astype(np.int32)
        self.base_ = rng.spawn(1)[0].random(n)
        self.priority_ = self.base_.copy()
        # disc robots with goals off the centre wait on it while other robots are near
        # (control/finish.py): resting on the goal they would graze their neighbours' moves
        goal_centres = np.array([g.centers(c) for g, c in zip(self.grids_, self.goal_cells_)], float).reshape(-1, 2)
        self.hold_ = off_centre_discs(world, goal_centres) if n > 1 else np.zeros(n, bool)
        self.holding_ = self.hold_

    def _food(self, i: int, cells: IntArray) -> FloatArray:
        grid = self.grids_[i]
        if self.food == "distance-field":
            return food_from_field(cells, self.fields_[i])
        return food_euclidean(grid.centers(cells), self.world_.robots[i].goal)

    # ------------------------------------------------------------------ one step
    def act(self, obs: Observation) -> Decision:
        n = obs.positions.shape[0]
        pos = obs.positions
        obstacles = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        n_fish = len(obstacles) + n - 1
        rank = np.full((n, 9), NOT_ALLOWED)
        allowed = np.zeros((n, 9), bool)
        targets = np.repeat(pos[:, None, :], 9, axis=1)
        food = np.full((n, 9), np.inf)
        modes = [WAIT] * n
        events: list[dict] = []
        near = _CellIndex(self.grids_[0].cell_of(pos)) if n > 1 else None
        at_goal = obs.at_goal
        if self.hold_.any():
            cells = np.array([g.cell_of(q) for g, q in zip(self.grids_, pos)], np.int64).reshape(-1, 2)
            goal_cells = np.asarray(self.goal_cells_, np.int64).reshape(-1, 2)
            in_goal_cell = np.all(cells == goal_cells, axis=1)
            self.holding_ = held_discs(self.hold_, cells, goal_cells, self.grids_[0].blocked.shape)
            centres = np.array([g.centers(c) for g, c in zip(self.grids_, cells)], float).reshape(-1, 2)
            at_goal = waiting_home(at_goal, self.holding_, in_goal_cell, pos, centres)
        for i in range(n):
            modes[i] = self._rank(i, obs, obstacles, n_fish, near, rank[i], allowed[i], targets[i], food[i], events)
        allowed[:, STAY] = True   # waiting is always possible
        if n == 1:
            choice = np.array([int(np.argmin(rank[0]))])
            pushed = np.zeros(1, bool)
        else:
            self.priority_ = update_priorities(self.priority_, at_goal, self.base_)
            active = np.flatnonzero(~at_goal)
            if len(active):
                # the robot of highest priority ranks by food first (its own cell included), the
                # behaviour's order among equal food: PIBT's ranking, under which it surely
                # progresses (with distance-field food), and the swap emulation can reverse it
                lead = active[np.argmax(self.priority_[active])]
                key = np.where(allowed[lead], np.round(food[lead], 9), np.inf)
                order = np.lexsort((rank[lead], key))
                rank[lead, order] = np.where(allowed[lead, order], np.arange(9, dtype=float), NOT_ALLOWED)
            cells = self.grids_[0].cell_of(pos)
            flat = (cells[:, 1] * self.graph_.width + cells[:, 0]).astype(np.int32)
            res = pibt_step(self.graph_, flat, rank, allowed, np.zeros((n, 9)), decision_order(self.priority_),
                            goals=self.goal_flat_, swap=True, yield_way=True)
            choice = res.moves.astype(np.int64)
            pushed = ((res.flags & PUSHED) != 0) & (choice != STAY)
        new = targets[np.arange(n), choice]
        if n > 1:
            held = self._held(pos, new)
            new[held] = pos[held]
            choice[held] = STAY
            for i in held:
                events.append({"robot": int(i), "kind": "move_withheld", "detail": "exact check found a contact"})
            first = np.argmin(rank, axis=1)
            for i in np.flatnonzero(choice != first):
                modes[i] = "yield" if pushed[i] else (WAIT if choice[i] == STAY else PREY)
        return Decision(new, modes, tuple(events))

    def _rank(self, i: int, obs, obstacles: FloatArray, n_fish: int, near, rank: FloatArray, allowed,
              targets: FloatArray, food9: FloatArray, events: list) -> str:
        """Robot ``i``'s ranking of its 9 moves (``GRID_MOVES`` order, written into ``rank``,
        ``allowed``, ``targets`` and their food into ``food9``; staying is index 0): the move
        its behaviour picks first, then, for when the core needs it elsewhere, the other cells
        it may enter (best food first) and waiting. Returns the behaviour (Algorithm 1)."""
        world = self.world_
        robot = world.robots[i]
        grid = self.grids_[i]
        p = obs.positions[i]
        goal = np.asarray(robot.goal, float)
        cell = grid.cell_of(p)
        # only a robot with another robot within two cells can be asked to make way this step
        several = near is not None and len(near.around(cell, 2, i)) > 0
        centre = grid.centers(cell)
        if several:
            food9[STAY] = self._food(i, cell[None])[0]
        parked = self.holding_[i] and np.array_equal(cell, self.goal_cells_[i]) and np.linalg.norm(p - centre) <= 1e-9
        if (np.linalg.norm(p - goal) <= 1e-9 and not self.holding_[i]) or parked:
            rank[STAY] = 0.0
            if several:   # parked: where it goes if another robot must pass
                self._fallback(i, p, cell, obs, obstacles, rank, allowed, targets, food9, start=1.0)
            return WAIT if parked else ARRIVED
        if np.array_equal(cell, self.goal_cells_[i]) or np.linalg.norm(p - centre) > 1e-9:
            # in the goal cell: step onto the exact goal point (a held disc: onto the centre);
            # off a cell centre (start of the run): align first
            to = goal if np.array_equal(cell, self.goal_cells_[i]) and not self.holding_[i] else centre
            ok, exposure = self._feasible(i, p, np.stack([to, p]), obstacles)
            rank[STAY] = 0.0
            go = bool(ok[0] and exposure[0] <= exposure[1])
            if go:
                targets[STAY] = to
            if several:
                self._fallback(i, p, cell, obs, obstacles, rank, allowed, targets, food9, start=1.0)
            return PREY if go else WAIT

        if self.food == "distance-field" and not np.isfinite(self._food(i, cell[None])[0]) and i not in self.warned_:
            self.warned_.add(i)
            events.append({"robot": i, "kind": "goal_unreachable", "detail": "no static path to the goal"})

        # Candidate neighbour cells (Step 4's "near positions"), in a seeded random order so that
        # ties between equally good cells are broken without bias.
        cand = cell[None] + NEIGHBOURS[self.rng_.permutation(len(NEIGHBOURS))]
        inside = grid.is_free(cand)
        diag = np.all(cand != cell[None], axis=1)
        corner_a = grid.is_free(np.stack([cand[:, 0], np.full(len(cand), cell[1])], axis=1))
        corner_b = grid.is_free(np.stack([np.full(len(cand), cell[0]), cand[:, 1]], axis=1))
        cand = cand[inside & (~diag | (corner_a & corner_b))]
        points = grid.centers(cand)
        ok, exposure = self._feasible(i, p, np.concatenate([points, p[None]]), obstacles)
        ok, exposure, stay_exposure = ok[:-1], exposure[:-1], int(exposure[-1])
        # The least exposed of the allowed moves and staying: with redraw obstacles only, every
        # exposure is 0 and the pool is every allowed move (the paper); with travelling obstacles
        # the robot keeps out of their reach when it can, else takes the cells fewest can reach.
        least = min([stay_exposure, *exposure[ok].tolist()])
        pool = ok & (exposure == least)
        slot = MOVE_INDEX[cand[:, 0] - cell[0] + 1, cand[:, 1] - cell[1] + 1]
        targets[slot] = points
        allowed[slot] = ok
        food = self._food(i, cand)
        food9[slot] = food
        food9[STAY] = self._food(i, cell[None])[0]
        # after the behaviour's choice: the other least exposed cells by food, waiting, the rest
        order = np.lexsort((np.arange(len(cand)), food, exposure, ~pool))
        rank[slot[order]] = 2.0 + np.arange(len(cand))
        rank[STAY] = 1.5 + np.count_nonzero(pool)
        if not pool.any():
            rank[STAY] = 0.0
            return WAIT
        cand, points = cand[pool], points[pool]

        # The fish: the moving obstacles and the other robots (at their current cells).
        others = near.around(cell, self.visual, i) if near is not None else np.zeros(0, np.int64)
        fish_pts = np.concatenate([obstacles, obs.positions[others]]).reshape(-1, 2)
        fish_cells = grid.cell_of(fish_pts)
        seen = visible_fish(cell, fish_cells, self.visual)
        k, mode = fish_decision(cell, float(self._food(i, cell[None])[0]), cand, points, food[pool],
                                fish_cells[seen], grid.centers(fish_cells[seen]), self._food(i, fish_cells[seen]),
                                n_fish=n_fish, w=self.w, delta=self.delta)
        if k is None:
            rank[STAY] = 0.0
            return WAIT
        rank[slot[np.flatnonzero(pool)[k]]] = 0.0
        return mode

    def _fallback(self, i: int, p: FloatArray, cell, obs, obstacles: FloatArray, rank: FloatArray, allowed,
                  targets: FloatArray, food9: FloatArray, start: float) -> None:
        """Where robot ``i`` goes when another robot needs its cell: the neighbour centres it
        may enter and reach this step, least exposed first, then by food (fixed order; no
        random draw, so a robot that is never pushed draws nothing)."""
        grid = self.grids_[i]
        moves = GRID_MOVES[1:]
        cand = cell[None] + moves
        inside = grid.is_free(cand)
        diag = np.all(moves != 0, axis=1)
        corner_a = grid.is_free(np.stack([cand[:, 0], np.full(len(cand), cell[1])], axis=1))
        corner_b = grid.is_free(np.stack([np.full(len(cand), cell[0]), cand[:, 1]], axis=1))
        points = grid.centers(cand)
        reach = float(self.world_.robots[i].max_speed * self.world_.dt) * (1 + 1e-9) + 1e-12
        ok = inside & (~diag | (corner_a & corner_b)) & (np.linalg.norm(points - p, axis=1) <= reach)
        idx = np.flatnonzero(ok)
        if len(idx) == 0:
            return
        feasible, exposure = self._feasible(i, p, points[idx], obstacles)
        idx, exposure = idx[feasible], exposure[feasible]
        food = self._food(i, cand[idx])
        order = np.lexsort((food, exposure))
        slots = 1 + idx[order]
        food9[slots] = food[order]
        targets[slots] = points[idx[order]]
        allowed[slots] = True
        rank[slots] = start + 1.0 + np.arange(len(slots))

    def _held(self, pos: FloatArray, new: FloatArray) -> list[int]:
        """Robots to hold in place after the exact check: robots resting or moving off a cell
        centre, and every move when a robot is wider than half a cell (the core's table
        covers centre-to-centre moves of discs up to half a cell)."""
        grid = self.grids_[0]
        res = grid.resolution
        wide = bool(np.any(self.radii_ > 0.5 * res + 1e-12))
        moving = np.any(new != pos, axis=1)
        odd = (np.linalg.norm(pos - grid.centers(grid.cell_of(pos)), axis=1) > 1e-9) | \
            (np.linalg.norm(new - grid.centers(grid.cell_of(new)), axis=1) > 1e-9)
        # a robot resting off a centre is checked too: a neighbour's move between centres may graze it
        check = np.flatnonzero(odd | (moving & wide))
        reach = 3 * res + 2 * float(self.radii_.max(initial=0.0))
        return hold_conflicts(pos, new, self.radii_, res, check, reach)

    def _feasible(self, i: int, p: FloatArray, targets: FloatArray, obstacles: FloatArray
                  ) -> tuple[NDArray[np.bool_], IntArray]:
        """For moves of robot ``i`` from ``p`` to each of ``targets`` (k, 2): whether the move is
        allowed now (enters no obstacle footprint at its new position) and its exposure, the
        number of travelling (non-``redraw``) obstacles whose next move can reach the end point
        (0 = safe). Other robots are the core's business."""
        r = self.world_.robots[i].radius
        k = len(targets)
        a = np.broadcast_to(p, (k, 2))
        ok = np.ones(k, dtype=bool)
        exposure = np.zeros(k, dtype=np.int64)
        if len(obstacles):
            step = float(np.max(np.linalg.norm(targets - p, axis=1), initial=0.0))
            gap = np.linalg.norm(obstacles - p, axis=1)
            near = np.flatnonzero(gap < self.obstacle_extent_ + r + step + self.obstacle_reach_ + 1e-6)
            if len(near):
                hit, dist = self._footprint_tests(near, obstacles, a, targets, r)
                ok &= ~hit.any(axis=1)
                if self.avoid_next:
                    exposure += np.count_nonzero(dist < self.obstacle_reach_[near][None, :] + r - g.EPS, axis=1)
        return ok, exposure

    def _footprint_tests(self, near: IntArray, obstacles: FloatArray, a: FloatArray, b: FloatArray,
                         r: float) -> tuple[NDArray[np.bool_], FloatArray]:
        """For moves a -> b (k, 2) of a disc of radius ``r`` and the obstacles ``near`` (L,) at
        their new positions: whether each move enters each footprint (k, L) and the signed
        distance from each end point to each footprint (k, L) (inf for ``redraw`` obstacles,
        which cannot come to the robot)."""
        k, n_near = len(b), len(near)
        hit = np.zeros((k, n_near), dtype=bool)
        dist = np.full((k, n_near), np.inf)
        world = self.world_
        boxes = self.obstacle_is_box_[near]
        if r == 0 and boxes.all():
            lo = obstacles[near] + self.obstacle_lo_[near]
            hi = obstacles[near] + self.obstacle_hi_[near]
            hit = g.segment_crosses_open_box(a[:, None, :], b[:, None, :], lo[None], hi[None])
            dist = g.point_box_signed_distance(b[:, None, :], lo[None], hi[None])
        else:
            for col, j in enumerate(near):
                shape = world.moving_obstacles[j].placed(obstacles[j])
                if r > 0:
                    hit[:, col] = shape.segment_clearance(a, b) < r - g.EPS
                else:
                    hit[:, col] = shape.segment_crosses_interior(a, b)
                dist[:, col] = shape.signed_distance(b)
        dist[:, self.obstacle_reach_[near] <= 0] = np.inf
        return hit, dist

    def __repr__(self) -> str:
        return (f"FishSwarmController(visual={self.visual}, w={self.w}, delta={self.delta}, food={self.food!r}, "
                f"avoid_next={self.avoid_next})")
