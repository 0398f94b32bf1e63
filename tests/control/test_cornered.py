"""The last resort of a cornered robot (swarmpath.control.cornered): the chances of being hit
against the motion models themselves, and both grid controllers taking the least likely move
instead of standing where a walker is more likely to come."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.base import Controller, Decision
from swarmpath.control.cornered import hit_chances, move_weights
from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.observation import Observation, SensingConfig
from swarmpath.registry import CONTROLLERS
from swarmpath.sim.sensing import sense
from swarmpath.sim.simulator import Simulator
from swarmpath.world import Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.moving import Bounce8, MovingObstacle, RandomWalk

S2 = float(np.sqrt(2))
BOX = Rect((-0.5, -0.5), (0.5, 0.5))


def open_world(size: tuple[int, int], walkers, robots=(), blocked=None) -> World:
    w, h = size
    grid = np.zeros((h, w), bool) if blocked is None else blocked
    moving = tuple(MovingObstacle(f"m{k}", BOX, (x + 0.5, y + 0.5), (1.0, 0.0), motion)
                   for k, (x, y, motion) in enumerate(walkers))
    return World(RectBounds(w, h), static_map=StaticMap(grid, 1.0), moving_obstacles=moving, robots=tuple(robots))


def all_cells(w: int, h: int) -> np.ndarray:
    ys, xs = np.mgrid[0:h, 0:w]
    return np.stack([xs.ravel(), ys.ravel()], axis=1)[None]


def test_move_weights_follow_the_motion_models():
    possible = np.zeros((3, 10), bool)
    possible[:, 0] = True
    possible[0, [2, 5, 7]] = True          # a walker with three free directions
    possible[1, 1] = True                  # a bouncer going straight on
    weights = move_weights(possible, np.zeros(3))
    assert np.allclose(weights[0, [2, 5, 7]], 1 / 3) and weights[0, 0] == 0 and weights[0].sum() == pytest.approx(1)
    assert weights[1, 1] == 1 and weights[1].sum() == 1
    assert weights[2, 0] == 1              # boxed in: it stays
    # a model that may head anywhere keeps its one (grown) position
    assert move_weights(possible[2:], np.array([1.0]))[0, 0] == 1


def test_hit_chances_of_a_walker_in_the_open_and_a_bouncer():
    """A walker in the open takes each of 8 directions with chance 1/8; its sweep holds the
    centres of its own cell and of the cell it steps to, a diagonal step too (the corner it
    passes touches the centres beside it, no more): its own cell with chance 1, each
    neighbour 1/8, 2 cells in all. A bouncer going east covers the cell ahead for sure and
    nothing beside it."""
    world = open_world((9, 9), [(4, 4, RandomWalk())])
    fc = ObstacleForecast(world, world.grid())
    here = np.array([[4.5, 4.5]])
    chance, now = hit_chances(fc, here, here, all_cells(9, 9))
    chance, now = chance.reshape(9, 9), now.reshape(9, 9)
    assert chance[4, 4] == pytest.approx(1) and now[4, 4] and now.sum() == 1
    assert chance[4, 5] == pytest.approx(1 / 8) and chance[3, 4] == pytest.approx(1 / 8)
    assert chance[5, 5] == pytest.approx(1 / 8) and chance[3, 3] == pytest.approx(1 / 8)
    assert chance[4, 6] == 0 and chance.sum() == pytest.approx(2)

    world = open_world((9, 9), [(4, 4, Bounce8())])
    fc = ObstacleForecast(world, world.grid())
    chance, _ = hit_chances(fc, here, np.array([[3.5, 4.5]]), all_cells(9, 9))
    chance = chance.reshape(9, 9)
    assert chance[4, 5] == 1 and chance[4, 4] == 1 and chance.sum() == 2


def test_hit_chances_match_the_walkers_own_moves_by_a_wall():
    """Against the motion model itself: a walker in a 4 x 4 room with a pillar (most of its
    positions touch a wall, so fewer directions are free) is run for 4,000 steps; per cell
    of the room, the chances summed over the steps equal the number of steps on which its sweep
    held the cell's centre (sampled densely along the step), within 4 standard errors."""
    blocked = np.zeros((4, 4), bool)
    blocked[1, 2] = True

    class Still(Controller):
        def reset(self, world, plan, rng):
            pass

        def act(self, obs):
            return Decision(obs.positions.copy())

    # a robot that never moves keeps the run going (the walker passes through it: contacts do not matter here)
    world = open_world((4, 4), [(0, 0, RandomWalk())], robots=[Robot("a", (3.5, 3.5), (0.5, 3.5), 0.0, S2)],
                       blocked=blocked)
    steps = 4000
    traj = Simulator(world, Still(), seed=3, max_steps=steps, deadlock_window=10 ** 6, progress_window=10 ** 6).run()
    fc = ObstacleForecast(world, world.grid())
    cells = all_cells(4, 4)
    expected = np.zeros(16)
    seen = np.zeros(16)
    obstacle = traj.obstacle_positions[:, 0]
    for t in range(1, len(obstacle) - 1):
        chance, _ = hit_chances(fc, obstacle[t][None], obstacle[t - 1][None], cells)
        expected += chance[0]
        p, q = obstacle[t], obstacle[t + 1]
        swept = p + np.linspace(0.0, 1.0, 201)[:, None] * (q - p)                 # the box's centre
        gap = np.abs(cells[0][:, None, :] + 0.5 - swept[None]).max(axis=-1).min(axis=1)
        seen += gap < 0.5 - 1e-6
    assert len(obstacle) > steps // 2
    assert np.all(np.abs(seen - expected) <= 4 * np.sqrt(expected) + 1)
    assert seen.sum() > 1.5 * len(obstacle)    # it moves on most steps (two centres a step)


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_cornered_robot_takes_the_move_a_walker_is_least_likely_to_hit(controller):
    """A robot on the bottom edge (cell (1, 0)) with a walker right above it (cell (1, 1)):
    every move ends where the walker may be next, and each is hit with chance 1/8 (the sweep
    holds a cell's centre only when the walker steps onto it; a diagonal step passes the
    centres beside it). Without the walker-evasion value the robot steps to (2, 0), towards
    its goal, and reports ``no_escape``. Before, it stood."""
    world = open_world((9, 4), [(1, 1, RandomWalk())], robots=[Robot("a", (1.5, 0.5), (8.5, 0.5), 0.0, S2)])
    ctrl = CONTROLLERS.get(controller)(evasion_horizon=0)
    ctrl.reset(world, None, np.random.default_rng(0))
    pos = np.array([[1.5, 0.5]])
    walker = np.array([[1.5, 1.5]])
    obs = Observation(1, 1.0, pos, world.goals, np.array([False]), walker, walker,
                      sense(pos, walker, SensingConfig(), world.resolution))
    fc = ObstacleForecast(world, world.grid())
    chance, _ = hit_chances(fc, walker, walker, np.array([[[1, 0], [2, 0], [0, 0], [2, 1], [0, 1]]]))
    assert np.allclose(chance, 1 / 8)
    decision = ctrl.act(obs)
    assert tuple(decision.positions[0]) == (2.5, 0.5)
    assert any(e["kind"] == "no_escape" and e["robot"] == 0 for e in decision.events)


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_cornered_robot_weighs_a_walker_by_its_exact_chance_over_the_horizon(controller):
    """The same corner with the walker-evasion value (the default): by the checker's geometry a
    walker's diagonal step only touches the corner of a point robot's cell, so every move
    beside it is hit with chance 1/8 this step; over 8 steps the edge is worse than the open
    row, where the robot can keep dodging. The robot takes the move of least exact risk,
    (2, 1), and still reports ``no_escape`` (every move ends where the walker may be next)."""
    from swarmpath.control.evasion import EvasionRisk
    from swarmpath.control.pibt.core import static_moves

    world = open_world((9, 4), [(1, 1, RandomWalk())], robots=[Robot("a", (1.5, 0.5), (8.5, 0.5), 0.0, S2)])
    ctrl = CONTROLLERS.get(controller)()
    ctrl.reset(world, None, np.random.default_rng(0))
    pos = np.array([[1.5, 0.5]])
    walker = np.array([[1.5, 1.5]])
    obs = Observation(1, 1.0, pos, world.goals, np.array([False]), walker, walker,
                      sense(pos, walker, SensingConfig(), world.resolution))
    grid = world.grid()
    risk = EvasionRisk(world, grid, static_moves(grid.blocked, 8), ObstacleForecast(world, grid), 0.0, 8)
    one_step = EvasionRisk(world, grid, static_moves(grid.blocked, 8), ObstacleForecast(world, grid), 0.0, 1)
    np.testing.assert_allclose(one_step.move_risk(np.array([[1, 0]]), walker)[0, [0, 1, 2, 4, 5]], 1 / 8)
    exact = risk.move_risk(np.array([[1, 0]]), walker)[0]
    assert int(np.argmin(exact)) == 2 and exact[2] < exact[[0, 1, 4, 5]].min() - 0.005
    decision = ctrl.act(obs)
    assert tuple(decision.positions[0]) == (2.5, 1.5)
    assert any(e["kind"] == "no_escape" and e["robot"] == 0 for e in decision.events)
