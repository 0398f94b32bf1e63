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
new positions, cells and moves already taken by other robots) and, for obstacles that travel
(every model except ``redraw``), avoids ending next to one when it can, because the obstacle
moves before the robot on the next step.
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
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
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.search import DistanceFieldCache
from swarmpath.world import geometry as g
from swarmpath.world.move_rules import NO_CONFLICT, move_conflicts
from swarmpath.world.moving import MovingObstacle
from swarmpath.world.shapes import Rect
from swarmpath.world.world import World


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

    def _food(self, i: int, cells: IntArray) -> FloatArray:
        grid = self.grids_[i]
        if self.food == "distance-field":
            return food_from_field(cells, self.fields_[i])
        return food_euclidean(grid.centers(cells), self.world_.robots[i].goal)

    # ------------------------------------------------------------------ one step
    def act(self, obs: Observation) -> Decision:
        n = obs.positions.shape[0]
        pos = obs.positions
        new = pos.copy()
        modes = [WAIT] * n
        events: list[dict] = []
        decided = np.zeros(n, dtype=bool)
        obstacles = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        n_fish = len(obstacles) + n - 1
        for i in range(n):
            target, mode = self._decide(i, obs, new, decided, obstacles, n_fish, events)
            new[i] = target
            modes[i] = mode
            decided[i] = True
        return Decision(new, modes, tuple(events))

    def _decide(self, i: int, obs, new: FloatArray, decided: NDArray[np.bool_], obstacles: FloatArray,
                n_fish: int, events: list) -> tuple[FloatArray, str]:
        world = self.world_
        robot = world.robots[i]
        grid = self.grids_[i]
        p = obs.positions[i]
        goal = np.asarray(robot.goal, float)
        if np.linalg.norm(p - goal) <= 1e-9:
            return p.copy(), ARRIVED
        cell = grid.cell_of(p)
        centre = grid.centers(cell)
        if np.array_equal(cell, self.goal_cells_[i]):
            moves = [goal]          # in the goal cell: step onto the exact goal point
        elif np.linalg.norm(p - centre) > 1e-9:
            moves = [centre]        # off a cell centre (start of the run): align first
        else:
            moves = None
        if moves is not None:
            ok, exposure = self._feasible(i, p, np.concatenate([np.asarray(moves, float), p[None]]), obs, new,
                                          decided, obstacles)
            if ok[0] and exposure[0] <= exposure[1]:
                return np.asarray(moves[0], float), PREY
            return p.copy(), WAIT

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
        ok, exposure = self._feasible(i, p, np.concatenate([points, p[None]]), obs, new, decided, obstacles)
        ok, exposure, stay_exposure = ok[:-1], exposure[:-1], int(exposure[-1])
        # The least exposed of the allowed moves and staying: with redraw obstacles only, every
        # exposure is 0 and the pool is every allowed move (the paper); with travelling obstacles
        # the robot keeps out of their reach when it can, else takes the cells fewest can reach.
        least = min([stay_exposure, *exposure[ok].tolist()])
        pool = ok & (exposure == least)
        if not pool.any():
            return p.copy(), WAIT
        cand, points = cand[pool], points[pool]

        # The fish: the moving obstacles and the other robots (at their current cells).
        others = np.delete(np.arange(len(obs.positions)), i)
        fish_pts = np.concatenate([obstacles, obs.positions[others]]).reshape(-1, 2)
        fish_cells = grid.cell_of(fish_pts)
        seen = visible_fish(cell, fish_cells, self.visual)
        k, mode = fish_decision(cell, float(self._food(i, cell[None])[0]), cand, points, self._food(i, cand),
                                fish_cells[seen], grid.centers(fish_cells[seen]), self._food(i, fish_cells[seen]),
                                n_fish=n_fish, w=self.w, delta=self.delta)
        if k is None:
            return p.copy(), WAIT
        return points[k].copy(), mode

    def _feasible(self, i: int, p: FloatArray, targets: FloatArray, obs, new: FloatArray,
                  decided: NDArray[np.bool_], obstacles: FloatArray) -> tuple[NDArray[np.bool_], IntArray]:
        """For moves of robot ``i`` from ``p`` to each of ``targets`` (k, 2): whether the move is
        allowed now (enters no obstacle footprint at its new position and meets no other
        robot's decided move or current position) and its exposure, the number of travelling
        (non-``redraw``) obstacles whose next move can reach the end point (0 = safe)."""
        world = self.world_
        r = world.robots[i].radius
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
        # Other robots: no shared end cell, no swap, no crossing (decided robots by their chosen
        # move; undecided ones stand still and keep their cell).
        if len(new) > 1:
            ok &= self._robot_moves_ok(i, p, targets, obs.positions, new, decided)
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

    def _robot_moves_ok(self, i: int, p: FloatArray, targets: FloatArray, current: FloatArray, new: FloatArray,
                        decided: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """Moves of robot ``i`` (``p`` -> each target, (k, 2)) that no other robot's move
        meets, by the checker's move rules; robots still to decide stand still."""
        world = self.world_
        others = np.flatnonzero(np.arange(len(new)) != i)
        q0 = current[others]
        q1 = np.where(decided[others, None], new[others], q0)
        kinds = move_conflicts(p[None, None, :], targets[:, None, :], q0[None], q1[None], world.robots[i].radius,
                               self.radii_[others][None], world.resolution)
        return ~np.any(kinds != NO_CONFLICT, axis=1)

    def __repr__(self) -> str:
        return (f"FishSwarmController(visual={self.visual}, w={self.w}, delta={self.delta}, food={self.food!r}, "
                f"avoid_next={self.avoid_next})")
