"""Detours around moving obstacles that linger (control/detour.py): the window's values
against exact references, and robots held back by a shuttling bouncer going round it."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from swarmpath.control.detour import detour_distances, detour_exits, rim_cells, window_moves
from swarmpath.control.pibt.core import static_moves
from swarmpath.search import distance_field
from swarmpath.sim import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import Bounce, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import MovingObstacle

S2 = float(np.sqrt(2))


def _window_values(blocked, covered, goal, origin, size):
    """d' of every window cell, from the module (exits: the rim's exact goal distances)."""
    field = distance_field(blocked, goal)
    moves = static_moves(blocked)
    origins = np.array([origin])
    wm = window_moves(moves, origins, size)
    cov = covered[None] | ~wm[..., 0]
    (dy, dx), rim = rim_cells(origins, size)
    h, w = blocked.shape
    rc = rim[0]
    inside = (rc[:, 0] >= 0) & (rc[:, 0] < w) & (rc[:, 1] >= 0) & (rc[:, 1] < h)
    rim_cost = np.full(len(rc), np.inf)
    rim_cost[inside] = field[rc[inside, 1], rc[inside, 0]]
    exits = detour_exits(cov, origins, np.array([goal]), rim_cost[None])
    ys, xs = np.mgrid[0:size, 0:size]
    dest = np.stack([xs.ravel(), ys.ravel()], axis=1)[None]
    return detour_distances(cov, wm, exits, dest)[0].reshape(size, size), cov[0], field


def _reference(blocked, cov, goal, origin, size, field):
    """The same values by Dijkstra on an explicit graph: the window's free cells, their static
    moves (no corner cutting) between uncovered cells, and one sink reached from each uncovered
    rim cell at its exact goal distance (and from the goal cell, if inside and uncovered, at 0)."""
    moves = static_moves(blocked)
    n = size * size
    sink = n
    rows, cols, vals = [], [], []
    for y in range(size):
        for x in range(size):
            if cov[y, x]:
                continue
            gx, gy = origin[0] + x, origin[1] + y
            u = y * size + x
            for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
                if a == 0 or not moves[gy, gx, a]:
                    continue
                vx, vy = x + dx, y + dy
                if 0 <= vx < size and 0 <= vy < size and not cov[vy, vx]:
                    rows.append(u), cols.append(vy * size + vx), vals.append(float(np.hypot(dx, dy)))
            rim = x in (0, size - 1) or y in (0, size - 1)
            if (gx, gy) == tuple(goal):
                rows.append(u), cols.append(sink), vals.append(1e-300)  # 0 cost (csgraph drops zeros)
            elif rim and np.isfinite(field[gy, gx]):
                rows.append(u), cols.append(sink), vals.append(float(field[gy, gx]))
    g = coo_matrix((vals, (rows, cols)), shape=(n + 1, n + 1)).tocsr()
    d = dijkstra(g.T, indices=sink)
    return d[:n].reshape(size, size)


def _random_case(rng, shape, density, origins, size=9):
    """A random map, a goal on a free cell, and a window of ``size`` cells at a random corner
    drawn from ``origins`` (low, high): (blocked, goal (x, y), origin, size)."""
    blocked = rng.random(shape) < density
    free = np.argwhere(~blocked)
    gy, gx = free[rng.integers(len(free))]
    return blocked, (int(gx), int(gy)), rng.integers(*origins, size=2), size


def test_without_obstacles_the_detour_is_the_exact_distance() -> None:
    """Nothing covered: every shortest way either stays in the window or leaves it through a rim
    cell, so d' is the exact distance to the goal on every free window cell (random maps)."""
    rng = np.random.default_rng(3)
    for _ in range(30):
        blocked, (gx, gy), origin, size = _random_case(rng, (20, 24), 0.25, (-3, 14))
        values, cov, field = _window_values(blocked, np.zeros((size, size), bool), (gx, gy), origin, size)
        goal_in = np.all((np.array([gx, gy]) - origin >= 0) & (np.array([gx, gy]) - origin < size))
        sub = np.full((size, size), np.inf)
        for y in range(size):
            for x in range(size):
                cx, cy = origin[0] + x, origin[1] + y
                if 0 <= cx < 24 and 0 <= cy < 20:
                    sub[y, x] = field[cy, cx]
        assert np.allclose(values[~cov], sub[~cov], rtol=0, atol=1e-9), goal_in


def test_detour_values_match_dijkstra_with_covered_cells() -> None:
    """With random covered cells the window's values equal Dijkstra's on an explicit graph."""
    rng = np.random.default_rng(11)
    for trial in range(30):
        blocked, (gx, gy), origin, size = _random_case(rng, (16, 16), 0.2, (-2, 8))
        covered = rng.random((size, size)) < 0.2
        values, cov, field = _window_values(blocked, covered, (gx, gy), origin, size)
        ref = _reference(blocked, cov, (gx, gy), origin, size, field)
        ref[cov] = np.inf
        goal = np.array([gx, gy]) - origin
        if np.all((goal >= 0) & (goal < size)) and cov[goal[1], goal[0]]:
            ref[:] = np.where(cov, np.inf, ref)   # a covered goal leaves only the rim's exits
            assert not np.isfinite(values).any()  # ... and the module gives none at all
            continue
        assert np.allclose(np.where(np.isfinite(ref), ref, -1), np.where(np.isfinite(values), values, -1),
                           rtol=0, atol=1e-9), trial


def _slot_world() -> World:
    """A wall across the map (row 4) with a 2-cell gap (x 3-4) a bouncer shuttles in for ever and
    a 1-cell door at x 8; a robot above the gap with its goal below it: the short way is the
    gap, the way round the door."""
    blocked = np.zeros((9, 10), bool)
    blocked[4, :] = True
    blocked[4, 3] = blocked[4, 4] = False
    blocked[4, 8] = False
    robots = (Robot("a", (3.5, 7.5), (3.5, 1.5), 0.0, S2), Robot("b", (0.5, 8.5), (0.5, 6.5), 0.0, S2))
    shuttle = MovingObstacle("s", Rect((-0.5, -0.5), (0.5, 0.5)), (3.5, 4.5), (1.0, 0.0), Bounce())
    return World(RectBounds(10, 9), static_map=StaticMap(blocked, 1.0), moving_obstacles=(shuttle,), robots=robots,
                 name="slot")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_goes_round_a_bouncer_shuttling_on_its_way(controller) -> None:
    """The bouncer never leaves the gap, so the robot above it waits for ever without detours
    (the run ends in a deadlock); with them it goes round through the door and arrives, and the
    independent checker finds no contact."""
    from swarmpath.registry import CONTROLLERS

    world = _slot_world()
    for seed in range(3):
        traj = Simulator(world, CONTROLLERS.get(controller)(), None, seed=seed, max_steps=200).run()
        assert validate_trajectory(world, traj) == []
        assert traj.status == "all_reached", (seed, traj.status)
        # it went through the door (x 8), not the gap
        crossed = traj.positions[:, 0]
        assert np.any(np.all(np.floor(crossed) == (8, 4), axis=1))
    held = Simulator(world, CONTROLLERS.get(controller)(detour_after=0), None, seed=0, max_steps=200).run()
    assert held.status != "all_reached"
    assert np.linalg.norm(held.positions[-1, 0] - world.goals[0]) > 1


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_detour_after_is_checked(controller) -> None:
    from swarmpath.errors import ConfigError
    from swarmpath.registry import CONTROLLERS

    for bad in (-1, 2.5, True):
        with pytest.raises(ConfigError, match="detour_after"):
            Simulator(_slot_world(), CONTROLLERS.get(controller)(detour_after=bad), None, seed=0, max_steps=2).run()
