"""Detours around moving obstacles that linger (control/detour.py): the detour distances
against an exact reference, and robots held back by a shuttling or parked bouncer going round
it."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from swarmpath.control.detour import LINGER_DECAY, LINGER_LEVEL, Lingering
from swarmpath.sim import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import Bounce, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import MovingObstacle

S2 = float(np.sqrt(2))


def _reference(mask, goal):
    """Distances to ``goal`` by Dijkstra on an explicit graph of the free cells of ``mask``
    (h, w): the 8 grid moves, a diagonal only when both cells beside it are free too."""
    h, w = mask.shape
    rows, cols, vals = [], [], []
    for y in range(h):
        for x in range(w):
            if mask[y, x]:
                continue
            for dx, dy in GRID_MOVES[1:].tolist():
                vx, vy = x + dx, y + dy
                if not (0 <= vx < w and 0 <= vy < h) or mask[vy, vx]:
                    continue
                if dx and dy and (mask[y, vx] or mask[vy, x]):
                    continue
                rows.append(y * w + x), cols.append(vy * w + vx), vals.append(float(np.hypot(dx, dy)))
    g = coo_matrix((vals, (rows, cols)), shape=(h * w, h * w)).tocsr()
    return dijkstra(g.T, indices=goal[1] * w + goal[0]).reshape(h, w)


def test_detour_distances_are_dijkstra_on_the_map_with_the_lingering_cells_blocked() -> None:
    """Random maps and random lingering counts: d' of every cell equals Dijkstra's distance on
    the map with the cells counted LINGER_LEVEL or more blocked; inf on those cells, off the
    map, and everywhere for a goal where an obstacle lingers."""
    rng = np.random.default_rng(11)
    for trial in range(25):
        h, w = rng.integers(6, 18, size=2)
        static = rng.random((h, w)) < 0.2
        lingering = Lingering.start(static)
        lingering.level[:] = rng.random((h, w)) * 2 * LINGER_LEVEL * (rng.random((h, w)) < 0.15)
        mask = lingering.blocked()
        assert np.array_equal(mask, static | (lingering.level >= LINGER_LEVEL))
        free = np.argwhere(~static)
        goals = free[rng.choice(len(free), size=3)][:, ::-1]
        ys, xs = np.mgrid[-1:h + 1, -1:w + 1]
        cells = np.stack([xs.ravel(), ys.ravel()], axis=1)
        got = lingering.detour_distances(goals, np.repeat(cells[None], 3, axis=0))
        for r, goal in enumerate(goals):
            ref = np.full((h + 2, w + 2), np.inf)
            if not mask[goal[1], goal[0]]:
                ref[1:-1, 1:-1] = _reference(mask, goal)
            ref = ref.ravel()
            assert np.array_equal(np.isinf(got[r]), np.isinf(ref)), trial
            fin = np.isfinite(ref)
            assert np.allclose(got[r, fin], ref[fin], rtol=0, atol=1e-9), trial


def test_the_tables_follow_the_lingering_cells_and_free_the_goals_no_one_asks_for() -> None:
    """An obstacle settling on a corridor cuts the way (inf), leaving lets it through again; a
    goal not asked for on a step has its table freed."""
    static = np.ones((3, 8), bool)
    static[1, :] = False
    lingering = Lingering.start(static)
    ask = np.array([[[1, 1], [2, 1]]])
    assert np.allclose(lingering.detour_distances(np.array([[6, 1]]), ask), [[5, 4]])
    lingering.level[1, 4] = LINGER_LEVEL
    assert np.isinf(lingering.detour_distances(np.array([[6, 1]]), ask)).all()
    assert np.allclose(lingering.detour_distances(np.array([[0, 1]]), ask), [[1, 2]])
    assert lingering._tables.live == 1          # the goal (6, 1) was not asked for: freed
    lingering.level[1, 4] = LINGER_LEVEL * LINGER_DECAY
    assert np.allclose(lingering.detour_distances(np.array([[6, 1], [6, 1]]), np.repeat(ask, 2, axis=0)),
                       [[5, 4], [5, 4]])
    assert lingering._tables.live == 1          # one table for the two robots with that goal


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


def _aisle_world() -> World:
    """A 1-wide aisle (row 3, x 2-21, walls above and below) with a bouncer parked for good in
    its west mouth (x 2: walls above and below it, heading north), a robot in the aisle 12
    cells east of it with its goal just past the mouth, and ways round over and under the aisle's
    walls (about 40 cells). The parked obstacle is farther from the robot than a window around it
    would reach."""
    blocked = np.zeros((7, 26), bool)
    blocked[2, 2:22] = blocked[4, 2:22] = True
    robots = (Robot("a", (14.5, 3.5), (0.5, 3.5), 0.0, S2), Robot("b", (24.5, 0.5), (24.5, 6.5), 0.0, S2))
    parked = MovingObstacle("p", Rect((-0.5, -0.5), (0.5, 0.5)), (2.5, 3.5), (0.0, 1.0), Bounce())
    return World(RectBounds(26, 7), static_map=StaticMap(blocked, 1.0), moving_obstacles=(parked,), robots=robots,
                 name="aisle")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_goes_round_an_obstacle_parked_far_down_its_aisle(controller) -> None:
    """The robot walks to the parked bouncer, waits, then goes round the whole aisle and
    arrives (a window around the robot lost sight of the obstacle a few cells back and the robot
    stepped back and forth for good); the independent checker finds no contact. Without
    detours it never arrives."""
    from swarmpath.registry import CONTROLLERS

    world = _aisle_world()
    for seed in range(2):
        traj = Simulator(world, CONTROLLERS.get(controller)(), None, seed=seed, max_steps=300).run()
        assert validate_trajectory(world, traj) == []
        assert np.allclose(traj.obstacle_positions[:, 0], (2.5, 3.5))      # parked indeed
        assert traj.status == "all_reached", (seed, traj.status)
        assert np.any(np.abs(traj.positions[:, 0, 1] - 3.5) >= 2)            # round the aisle's walls
    held = Simulator(world, CONTROLLERS.get(controller)(detour_after=0), None, seed=0, max_steps=300).run()
    assert held.status != "all_reached"
