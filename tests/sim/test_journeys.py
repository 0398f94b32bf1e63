"""The step budget on maps where the way round is much longer than the straight line
(sim/journeys.py, ``default_max_steps``): the landmark bound never exceeds a robot's true
shortest path, and on a maze of 1-wide corridors the grid controllers get every robot home
within the budget wherever ``lacam`` finds a plan (the budget from twice the straight line was
shorter than the plan itself)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from swarmpath.registry import CONTROLLERS, PLANNERS
from swarmpath.search.distance_field import distance_field
from swarmpath.sim import Simulator, default_max_steps
from swarmpath.sim.journeys import journey_lower_bounds
from swarmpath.testing import validate_trajectory
from swarmpath.world import RectBounds, Robot, StaticMap, World

S2 = float(np.sqrt(2))


def perfect_maze(cells: int, rng: np.random.Generator) -> np.ndarray:
    """A depth-first maze of 1-wide corridors and 1-wide walls: blocked (2 cells + 1) squared."""
    size = 2 * cells + 1
    blocked = np.ones((size, size), bool)
    seen = np.zeros((cells, cells), bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    blocked[1, 1] = False
    while stack:
        x, y = stack[-1]
        nexts = [(x + dx, y + dy) for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
                 if 0 <= x + dx < cells and 0 <= y + dy < cells and not seen[y + dy, x + dx]]
        if not nexts:
            stack.pop()
            continue
        nx, ny = nexts[int(rng.integers(len(nexts)))]
        seen[ny, nx] = True
        blocked[2 * ny + 1, 2 * nx + 1] = False
        blocked[y + ny + 1, x + nx + 1] = False       # the wall between the two cells
        stack.append((nx, ny))
    return blocked


def world_on(blocked: np.ndarray, n: int, seed: int) -> World:
    rng = np.random.default_rng(seed)
    free = np.argwhere(~blocked)[:, ::-1]
    pick = free[rng.choice(len(free), 2 * n, replace=False)]
    robots = tuple(Robot(f"r{i}", tuple(pick[i] + 0.5), tuple(pick[n + i] + 0.5), 0.0, S2) for i in range(n))
    h, w = blocked.shape
    return World(RectBounds(w, h), static_map=StaticMap(blocked), robots=robots, name=f"maze{seed}")


def exact_lengths(world: World) -> np.ndarray:
    grid = world.grid()
    starts, goals = grid.cell_of(world.starts), grid.cell_of(world.goals)
    return np.array([distance_field(grid.blocked, tuple(g))[s[1], s[0]] for s, g in zip(starts, goals)])


@pytest.mark.parametrize("seed", range(4))
def test_the_bound_never_exceeds_the_shortest_path(seed):
    rng = np.random.default_rng(seed)
    blocked = perfect_maze(12, rng) if seed % 2 else rng.random((40, 40)) < 0.3
    world = world_on(blocked, 30, seed)
    bound = journey_lower_bounds(world)
    exact = exact_lengths(world)
    reachable = np.isfinite(exact)
    assert np.all(bound[reachable] <= exact[reachable] + 1e-9)
    assert np.all(bound[~reachable] == 0)
    if seed % 2:
        # a maze: the way round is far longer than the straight line, and the bound knows it
        straight = np.linalg.norm(world.starts - world.goals, axis=1)
        assert bound.max() > 2 * straight.max()
        assert bound.max() >= 0.9 * exact.max()


def test_open_maps_keep_the_straight_line_budget():
    world = world_on(np.zeros((30, 30), bool), 20, 1)
    longest = max(2 * math.dist(r.start, r.goal) / (r.max_speed * world.dt) for r in world.robots)
    assert default_max_steps(world) == int(200 + 4 * math.ceil(longest))
    assert not journey_lower_bounds(world).any()


@pytest.mark.parametrize("seed,robots", [(0, 20), (1, 20), (2, 20), (3, 50), (4, 50), (5, 50)])
def test_grid_controllers_finish_a_one_wide_maze_wherever_lacam_does(seed, robots):
    """20 robots: journeys longer than twice the straight line. 50: crowds stretch them
    further (the budget stretches while robots keep arriving), and LaCAM plans them only with
    its random restarts."""
    world = world_on(perfect_maze(16, np.random.default_rng(100 + seed)), robots, seed)
    budget = default_max_steps(world)
    assert budget >= 200 + 4 * math.ceil(exact_lengths(world).max() / S2 * 0.9)
    plan = PLANNERS.get("lacam")(time_limit=10.0).plan(world, rng=seed)
    if not plan:
        pytest.skip("no plan for this instance")
    for name in ("pibt", "cat-swarm"):
        traj = Simulator(world, CONTROLLERS.get(name)(), seed=seed).run()
        assert traj.status.value == "all_reached" and not traj.contacts, (name, traj.status, traj.n_steps, budget)
        assert validate_trajectory(world, traj) == []
