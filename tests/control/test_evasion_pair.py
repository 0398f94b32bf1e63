"""Two walkers played together (swarmpath.control.evasion.pair): the joint two-step value equals
plain expectimax over the game tree of both walkers, built only from the world's motion model
and the simulator's checker; it sees the robot between two walkers that the independent
product rates safe; and the controllers' risk uses it only where two walkers are close."""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from swarmpath.control.evasion import EVASION_RADIUS, PAIR_RADIUS, EvasionRisk, pair_move_risk
from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.pibt.core import static_moves
from swarmpath.sim.collisions import robot_moving_contacts
from swarmpath.world import Circle, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import MovingObstacle, RandomWalk

from control.test_evasion import DIRECTIONS, S2, walled_world


def reference_pair_risks(world: World, moves: np.ndarray, horizon: int, robot, walker_1, walker_2) -> np.ndarray:
    """Each of the robot's 9 moves: the chance of a contact with either walker within
    ``horizon`` steps, by plain expectimax over both walkers' steps for the first two steps
    (each walker's steps uniform over the directions its footprint fits in, from the world's
    ``obstacle_fits``; contacts from the simulator's checker), and beyond them the two
    one-walker values (as ``reference_risks`` in test_evasion.py plays them)
    combined as independent."""
    ob = world.moving_obstacles[0]
    radii = world.radii
    centre = lambda c: np.array([[c[0] + 0.5, c[1] + 0.5]])  # noqa: E731

    @lru_cache(maxsize=None)
    def contact(r0, r1, w0, w1) -> bool:
        return bool(robot_moving_contacts(world, centre(r0), centre(r1), centre(w0), centre(w1), radii))

    @lru_cache(maxsize=None)
    def steps(w):
        fits = [d for d in DIRECTIONS if world.obstacle_fits(ob, centre((w[0] + d[0], w[1] + d[1])))[0]]
        return fits or [(0, 0)]

    @lru_cache(maxsize=None)
    def alone(k, r, w) -> float:                  # one walker's value over k steps, as reference_risks
        if max(abs(w[0] - r[0]), abs(w[1] - r[1])) > EVASION_RADIUS:
            return 0.0
        best = 1.0
        for a in range(9):
            if not moves[r[1], r[0], a]:
                continue
            r1 = (r[0] + int(GRID_MOVES[a][0]), r[1] + int(GRID_MOVES[a][1]))
            if contact(r, r1, w, w):
                continue
            out = 0.0
            for d in steps(w):
                v = (w[0] + d[0], w[1] + d[1])
                if contact(r1, r1, w, v):
                    out += 1.0 / len(steps(w))
                elif k > 1:
                    out += alone(k - 1, r1, v) / len(steps(w))
            best = min(best, out)
        return best

    @lru_cache(maxsize=None)
    def q(step, r, w1, w2, a) -> float:
        if not moves[r[1], r[0], a]:
            return 1.0
        r1 = (r[0] + int(GRID_MOVES[a][0]), r[1] + int(GRID_MOVES[a][1]))
        if contact(r, r1, w1, w1) or contact(r, r1, w2, w2):
            return 1.0
        out = 0.0
        for d1 in steps(w1):
            for d2 in steps(w2):
                p = 1.0 / (len(steps(w1)) * len(steps(w2)))
                v1, v2 = (w1[0] + d1[0], w1[1] + d1[1]), (w2[0] + d2[0], w2[1] + d2[1])
                if contact(r1, r1, w1, v1) or contact(r1, r1, w2, v2):
                    out += p
                elif step == 1:
                    out += p * min(q(2, r1, v1, v2, b) for b in range(9))
                elif horizon > 2:
                    out += p * (1 - (1 - alone(horizon - 2, r1, v1)) * (1 - alone(horizon - 2, r1, v2)))
        return out

    return np.array([q(1, tuple(robot), tuple(walker_1), tuple(walker_2), a) for a in range(9)])


def _table(world: World, robot_radius: float, horizon: int):
    grid = world.grid()
    moves = static_moves(grid.blocked, 8)
    risk = EvasionRisk(world, grid, moves, ObstacleForecast(world, grid, robot_radius), robot_radius, horizon)
    return risk, risk.groups[0][0], moves, grid


@pytest.mark.parametrize("shape,robot_radius,horizon", [(Rect((-0.5, -0.5), (0.5, 0.5)), 0.0, 2),
                                                        (Rect((-0.5, -0.5), (0.5, 0.5)), 0.35, 3),
                                                        (Circle((0.0, 0.0), 0.45), 0.3, 3)])
def test_pair_risks_equal_the_exact_game_tree_of_both_walkers(shape, robot_radius, horizon) -> None:
    """By a wall, in a pocket, in the open and between two walkers: every move's value equals
    the reference (exact for both walkers over 2 steps; one-walker values beyond)."""
    world = walled_world(shape, robot_radius)
    _, table, moves, grid = _table(world, robot_radius, horizon)
    ob = world.moving_obstacles[0]
    fits = lambda c: bool(world.obstacle_fits(ob, [np.add(c, 0.5)])[0])  # noqa: E731
    centre = lambda c: np.add([c], 0.5)  # noqa: E731
    rng = np.random.default_rng(1)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    fixed = [((7, 8), (7, 6), (5, 7)), ((1, 1), (3, 1), (1, 3))]       # at the pocket's mouth; in the open
    tested = 0
    for trial in range(400):
        if trial < len(fixed):
            r, w1, w2 = fixed[trial]
        else:
            c = free[rng.integers(len(free))]
            r, w1, w2 = (tuple(int(v) for v in x) for x in (c, c + rng.integers(-3, 4, 2), c + rng.integers(-3, 4, 2)))
        if grid.blocked[r[1], r[0]] or not (fits(w1) and fits(w2)):
            continue
        if any(robot_moving_contacts(world, centre(r), centre(r), centre(w), centre(w), world.radii) for w in (w1, w2)):
            continue                                                    # already touching
        got = pair_move_risk(table, table, moves, r, w1, w2)
        want = reference_pair_risks(world, moves, horizon, r, w1, w2)
        np.testing.assert_allclose(got, want, atol=1e-6, err_msg=f"robot {r}, walkers {w1} {w2}")
        tested += 1
        if tested == 10:
            break
    assert tested == 10


def open_world(walkers: int = 1) -> World:
    """An open 15 x 15 map, one robot and ``walkers`` 1 x 1 random walkers."""
    blocked = np.zeros((15, 15), bool)
    robot = Robot("r", (7.5, 7.5), (7.5, 7.5), 0.0, S2)
    moving = tuple(MovingObstacle(f"w{k}", Rect((-0.5, -0.5), (0.5, 0.5)), (0.5 + 2 * k, 0.5), (1.0, 0.0), RandomWalk())
                   for k in range(walkers))
    return World(RectBounds(15, 15), static_map=StaticMap(blocked, 1.0), moving_obstacles=moving,
                 robots=(robot,), name="open")


def test_a_robot_between_two_walkers_is_at_risk_though_each_alone_is_escapable() -> None:
    """Two walkers two cells either side of a robot in the open: each alone can always be
    escaped (value 0 for staying), but together they close in from both sides: staying, and
    the moves up and down (two cells from both still), are rated above the independent product,
    and no move below it."""
    world = open_world()
    _, table, moves, _ = _table(world, 0.0, 8)
    r, w1, w2 = np.array([7, 7]), np.array([5, 7]), np.array([9, 7])
    alone = table.move_risk(np.array([r, r]), np.array([w1, w2]))
    assert alone[0, 0] == 0 and alone[1, 0] == 0
    joint = pair_move_risk(table, table, moves, r, w1, w2)
    assert joint[0] > 1e-3                                              # staying between them
    independent = 1 - (1 - alone[0]) * (1 - alone[1])
    assert np.all(joint >= independent - 1e-12)
    assert np.sum(joint > independent + 1e-3) >= 3                      # staying, up and down


def test_the_controllers_risk_plays_two_close_walkers_together_and_only_them() -> None:
    """EvasionRisk.move_risk: with both walkers within PAIR_RADIUS the nearest two are played
    together (the larger of that and the independent product); with one farther, or with the
    pairing off, the walkers are independent as before."""
    world = open_world(walkers=2)
    grid = world.grid()
    moves = static_moves(grid.blocked, 8)
    forecast = ObstacleForecast(world, grid, 0.0)
    paired = EvasionRisk(world, grid, moves, forecast, 0.0, 8)
    single = EvasionRisk(world, grid, moves, forecast, 0.0, 8, pair_radius=0)
    assert len(paired.groups) == 1
    table = paired.groups[0][0]
    r = np.array([7, 7])
    for w1, w2, close in (((5, 7), (9, 7), True), ((5, 7), (7, 7 + PAIR_RADIUS + 1), False)):
        cells = np.array([w1, w2])
        a = table.move_risk(np.array([r, r]), cells)
        alone = 1 - (1 - a[0]) * (1 - a[1])
        want = np.maximum(pair_move_risk(table, table, moves, r, w1, w2), alone) if close else alone
        positions = cells + 0.5
        np.testing.assert_allclose(paired.move_risk(r[None], positions)[0], want, atol=1e-12)
        np.testing.assert_allclose(single.move_risk(r[None], positions)[0], alone, atol=1e-12)
    assert paired.move_risk(r[None], np.array([[5.5, 7.5], [9.5, 7.5]]))[0, 0] > 1e-3
