"""Evading random walkers (swarmpath.control.evasion): the dynamic program's risks equal an
exact game-tree reference built only from the world's own motion model and the simulator's
contact checker; the lazily computed tiles equal the whole map; and the controllers' settings
are checked."""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from swarmpath.control.evasion import EVASION_RADIUS, EvasionRisk, WalkerEvasion, vetoed_last, walker, walker_vetoed
from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.pibt.core import static_moves
from swarmpath.errors import ConfigError
from swarmpath.registry import CONTROLLERS
from swarmpath.sim.collisions import robot_moving_contacts
from swarmpath.world import Circle, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import Bounce8, MovingObstacle, RandomWalk

S2 = float(np.sqrt(2))
DIRECTIONS = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)]


def walled_world(shape, robot_radius: float, seed: int = 3, size: int = 12) -> World:
    """A size x size map with a wall, a pocket and random blocked cells, one robot and one
    random walker of footprint ``shape``."""
    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < 0.12
    blocked[4, 2:9] = True              # a wall
    blocked[7:10, 6] = blocked[7:10, 8] = True
    blocked[9, 6:9] = True              # a pocket open at the top
    free = np.argwhere(~blocked)[:, ::-1]
    walker_at = free[0]
    robot = Robot("r", tuple(free[-1] + 0.5), tuple(free[-1] + 0.5), robot_radius, S2)
    moving = (MovingObstacle("w", shape, tuple(walker_at + 0.5), (1.0, 0.0), RandomWalk()),)
    return World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), moving_obstacles=moving,
                 robots=(robot,), name="walled")


def reference_risks(world: World, moves: np.ndarray, horizon: int, robot, walker_cell) -> np.ndarray:
    """The chance of each of the robot's 9 moves ending in a contact within ``horizon`` steps
    when it plays best afterwards, by plain expectimax over the game tree: the walker's steps
    from the world's own ``obstacle_fits`` (uniform over the directions that fit, as the
    ``random-walk`` model draws them), contacts from the simulator's checker, walkers farther
    than EVASION_RADIUS cells counted as escaped from (as the dynamic program does)."""
    ob = world.moving_obstacles[0]
    radii = world.radii
    centre = lambda c: np.array([[c[0] + 0.5, c[1] + 0.5]])  # noqa: E731

    @lru_cache(maxsize=None)
    def contact_at(r0, r1, w1) -> bool:        # offsets from the walker's start: contacts do not depend on where
        return bool(robot_moving_contacts(world, centre(r0), centre(r1), centre((0, 0)), centre(w1), radii))

    def contact(r0, r1, w0, w1) -> bool:
        rel = lambda c: (c[0] - w0[0], c[1] - w0[1])  # noqa: E731
        return contact_at(rel(r0), rel(r1), rel(w1))

    @lru_cache(maxsize=None)
    def steps(w):
        fits = [d for d in DIRECTIONS if world.obstacle_fits(ob, centre((w[0] + d[0], w[1] + d[1])))[0]]
        return fits or [(0, 0)]

    @lru_cache(maxsize=None)
    def q(k, r, w, a):
        if not moves[r[1], r[0], a]:
            return 1.0
        r1 = (r[0] + int(GRID_MOVES[a][0]), r[1] + int(GRID_MOVES[a][1]))
        if contact(r, r1, w, w):                  # the robot moves into the walker where it stands
            return 1.0
        out = 0.0
        for d in steps(w):
            w1 = (w[0] + d[0], w[1] + d[1])
            if contact(r1, r1, w, w1):            # the walker's step sweeps over the robot
                out += 1.0 / len(steps(w))
            elif k > 1 and max(abs(w1[0] - r1[0]), abs(w1[1] - r1[1])) <= EVASION_RADIUS:
                out += min(q(k - 1, r1, w1, b) for b in range(9)) / len(steps(w))
        return out

    return np.array([q(horizon, tuple(robot), tuple(walker_cell), a) for a in range(9)])


@pytest.mark.parametrize("shape,robot_radius", [(Rect((-0.5, -0.5), (0.5, 0.5)), 0.0),
                                                (Rect((-0.5, -0.5), (0.5, 0.5)), 0.35),
                                                (Circle((0.0, 0.0), 0.45), 0.3)])
def test_move_risks_equal_the_exact_game_tree(shape, robot_radius) -> None:
    """For robot-walker pairs near a wall, in a pocket and in the open, every move's risk over 3
    steps equals plain expectimax on the motion model and the checker."""
    world = walled_world(shape, robot_radius)
    grid = world.grid()
    moves = static_moves(grid.blocked, 8)
    risk = EvasionRisk(world, grid, moves, ObstacleForecast(world, grid, robot_radius), robot_radius, 3)
    assert len(risk.groups) == 1
    table = risk.groups[0][0]
    rng = np.random.default_rng(0)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    pairs = [((7, 8), (7, 6)), ((7, 8), (6, 6)), ((3, 5), (4, 6))]     # in the pocket, by the wall
    while len(pairs) < 14:
        r, w = free[rng.integers(len(free))], free[rng.integers(len(free))]
        if 1 <= np.abs(r - w).max() <= 3 and world.obstacle_fits(world.moving_obstacles[0], [w + 0.5])[0]:
            pairs.append((tuple(int(v) for v in r), tuple(int(v) for v in w)))
    tested = 0
    for r, w in pairs:
        if grid.blocked[r[1], r[0]] or not world.obstacle_fits(world.moving_obstacles[0], [np.add(w, 0.5)])[0]:
            continue
        if robot_moving_contacts(world, np.add([r], 0.5), np.add([r], 0.5), np.add([w], 0.5), np.add([w], 0.5),
                                 world.radii):
            continue                                                    # already touching
        got = table.move_risk(np.array([r]), np.array([w]))[0]
        want = reference_risks(world, moves, 3, r, w)
        np.testing.assert_allclose(got, want, atol=1e-6, err_msg=f"robot {r}, walker {w}")
        tested += 1
    assert tested >= 10


def test_the_pocket_is_riskier_than_the_open() -> None:
    """A robot in a pocket with a walker at its mouth cannot get away; in the open it can: the
    best move's risk tells them apart where the worst case cannot."""
    world = walled_world(Rect((-0.5, -0.5), (0.5, 0.5)), 0.0)
    grid = world.grid()
    moves = static_moves(grid.blocked, 8)
    risk = EvasionRisk(world, grid, moves, ObstacleForecast(world, grid), 0.0, 6)
    table = risk.groups[0][0]
    pocket = table.move_risk(np.array([[7, 8]]), np.array([[7, 6]]))[0].min()
    open_ = table.move_risk(np.array([[2, 1]]), np.array([[2, 3]]))[0].min()
    assert pocket > 0.05 and open_ < 0.01 and pocket > 10 * open_


def test_lazy_tiles_equal_the_whole_map_in_any_order(monkeypatch) -> None:
    """Values queried cell by cell in a fresh table, in another order, and with the tile memory
    dropped after every query (a tiny memory cap) are the same numbers."""
    world = walled_world(Rect((-0.5, -0.5), (0.5, 0.5)), 0.2, size=20, seed=5)
    grid = world.grid()
    moves = static_moves(grid.blocked, 8)
    forecast = ObstacleForecast(world, grid, 0.2)
    rng = np.random.default_rng(1)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    robots = free[rng.integers(len(free), size=60)]
    walkers = np.clip(robots + rng.integers(-4, 5, size=(60, 2)), 0, 19)
    whole = EvasionRisk(world, grid, moves, forecast, 0.2, 5).groups[0][0]
    whole.values(4, free)                               # every tile of every layer
    first = whole.move_risk(robots, walkers)
    fresh = EvasionRisk(world, grid, moves, forecast, 0.2, 5).groups[0][0]
    backwards = np.array([fresh.move_risk(robots[i:i + 1], walkers[i:i + 1])[0] for i in range(59, -1, -1)])[::-1]
    np.testing.assert_array_equal(first, backwards)
    monkeypatch.setattr(walker, "MAX_BYTES", 1)
    dropping = EvasionRisk(world, grid, moves, forecast, 0.2, 5).groups[0][0]
    again = np.array([dropping.move_risk(robots[i:i + 1], walkers[i:i + 1])[0] for i in range(60)])
    np.testing.assert_array_equal(first, again)
    assert dropping.bytes_ < whole.bytes_


def test_memory_cap_drops_the_least_recently_used_tiles(monkeypatch) -> None:
    """Over the cap, the tiles no query has used for longest go first: a robot queried step
    after step keeps its tiles (the same arrays, not computed again) while tiles used once
    elsewhere are dropped, and the numbers stay the same."""
    world = walled_world(Rect((-0.5, -0.5), (0.5, 0.5)), 0.2, size=40, seed=2)
    grid = world.grid()
    moves = static_moves(grid.blocked, 8)
    forecast = ObstacleForecast(world, grid, 0.2)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    near = free[np.argmin(np.abs(free - [4, 4]).sum(axis=1))][None]
    far = free[np.argmin(np.abs(free - [35, 35]).sum(axis=1))][None]
    table = EvasionRisk(world, grid, moves, forecast, 0.2, 3).groups[0][0]
    expect_near = table.move_risk(near, near + 1)
    near_tiles = dict(table.tiles_)
    expect_far = table.move_risk(far, far - 1)
    assert not set(near_tiles) & (set(table.tiles_) - set(near_tiles)), "the two queries share no tile"
    one = sum(t.nbytes for t in near_tiles.values())
    monkeypatch.setattr(walker, "MAX_BYTES", int(one * 1.5))
    fresh = EvasionRisk(world, grid, moves, forecast, 0.2, 3).groups[0][0]
    np.testing.assert_array_equal(fresh.move_risk(far, far - 1), expect_far)
    np.testing.assert_array_equal(fresh.move_risk(near, near + 1), expect_near)
    kept = dict(fresh.tiles_)
    for _ in range(3):
        np.testing.assert_array_equal(fresh.move_risk(near, near + 1), expect_near)
        assert fresh.bytes_ <= walker.MAX_BYTES
        assert all(fresh.tiles_[key] is kept[key] for key in near_tiles)      # never recomputed
    assert len(fresh.tiles_) > len(near_tiles)          # some of the far tiles still fit
    np.testing.assert_array_equal(fresh.move_risk(far, far - 1), expect_far)


def test_only_walkers_count_and_far_ones_do_not() -> None:
    """Bouncers are not walkers (no table); a walker more than EVASION_RADIUS cells away adds no
    risk; moves the static map forbids score 1."""
    blocked = np.zeros((16, 16), bool)
    blocked[0, 1] = True
    box = Rect((-0.5, -0.5), (0.5, 0.5))
    bounce = (MovingObstacle("b", box, (8.5, 8.5), (1.0, 0.0), Bounce8()),)
    robot = (Robot("r", (0.5, 0.5), (0.5, 0.5), 0.0, S2),)
    world = World(RectBounds(16, 16), static_map=StaticMap(blocked, 1.0), moving_obstacles=bounce, robots=robot)
    grid = world.grid()
    moves = static_moves(blocked, 8)
    assert EvasionRisk(world, grid, moves, ObstacleForecast(world, grid), 0.0, 8).groups == []
    far = world.replace(moving_obstacles=(MovingObstacle("w", box, (0.5 + EVASION_RADIUS + 1, 0.5), (1.0, 0.0),
                                                         RandomWalk()),))
    risk = EvasionRisk(far, grid, moves, ObstacleForecast(far, grid), 0.0, 8)
    got = risk.move_risk(np.array([[0, 0]]), far.moving_obstacles[0].start)[0]
    np.testing.assert_array_equal(got, np.where(moves[0, 0], 0.0, 1.0))
    near = risk.move_risk(np.array([[3, 3]]), np.array([[5.5, 3.5]]))[0]
    assert np.all(near[moves[3, 3]] > 0) and np.all(near < 1)


def test_controllers_run_the_same_with_evasion_off_when_no_walker_exists() -> None:
    """Without random walkers the evasion settings change nothing (same seed, same run)."""
    from swarmpath.sim import Simulator

    blocked = np.zeros((10, 10), bool)
    blocked[5, 1:8] = True
    robots = tuple(Robot(f"r{i}", (i + 0.5, 0.5), (9 - i + 0.5, 9.5), 0.0, S2) for i in range(4))
    moving = (MovingObstacle("b", Rect((-0.5, -0.5), (0.5, 0.5)), (8.5, 3.5), (1.0, 0.0), Bounce8()),)
    world = World(RectBounds(10, 10), static_map=StaticMap(blocked, 1.0), moving_obstacles=moving, robots=robots)
    for name in ("pibt", "cat-swarm"):
        on = Simulator(world, CONTROLLERS.get(name)(), None, seed=4).run()
        off = Simulator(world, CONTROLLERS.get(name)(evasion_horizon=0), None, seed=4).run()
        np.testing.assert_array_equal(on.positions, off.positions)


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
@pytest.mark.parametrize("setting,value", [("evasion_horizon", -1), ("evasion_horizon", 2.5),
                                           ("evasion_horizon", True), ("evasion_weight", -1.0),
                                           ("evasion_weight", float("nan")), ("evasion_weight", "high"),
                                           ("evasion_veto", "yes"), ("evasion_veto", 1)])
def test_bad_evasion_settings_are_one_clear_error(controller, setting, value) -> None:
    world = walled_world(Rect((-0.5, -0.5), (0.5, 0.5)), 0.0)
    with pytest.raises(ConfigError, match=setting):
        CONTROLLERS.get(controller)(**{setting: value}).reset(world, None, np.random.default_rng(0))


def test_the_tiers_may_not_pick_a_move_the_walker_value_rates_far_riskier() -> None:
    """walker_vetoed leaves out exactly the allowed candidates whose risk exceeds both ten times
    and 0.002 more than the safest allowed one; forbidden candidates and robots without a
    walker (risk None) are never vetoed."""
    risk = np.array([[0.0004, 1.0, 1.0, 0.0003, 1.0, 0.0068, 1.0, 0.0060, 1.0],      # the caught robot's numbers
                     [0.0, 0.001, 0.0025, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],           # margin decides
                     [0.2, 0.25, 0.5, 0.9, 1.0, 0.2, 0.2, 0.2, 0.2]])              # ratio decides
    allowed = np.array([[1, 0, 0, 1, 0, 1, 0, 1, 0],
                        [1, 1, 1, 0, 0, 0, 0, 0, 0],
                        [0, 1, 1, 1, 1, 0, 0, 0, 0]], bool)
    got = walker_vetoed(allowed, risk)
    want = np.zeros_like(allowed)
    want[0, [5, 7]] = True          # 0.0068 and 0.0060 > max(10 x 0.0003, 0.0003 + 0.002)
    want[1, 2] = True               # 0.0025 > max(0, 0.002); 0.001 is not
    want[2, 4] = False              # best allowed 0.25: 2.5 is the limit, nothing exceeds it
    np.testing.assert_array_equal(got, want)
    assert not walker_vetoed(allowed, None).any()
    # the safest allowed candidate itself is never vetoed, whatever the numbers
    rng = np.random.default_rng(1)
    r = rng.random((500, 9)) ** 4
    a = rng.random((500, 9)) < 0.6
    a[:, 0] = True
    v = walker_vetoed(a, r)
    best = np.argmin(np.where(a, r, np.inf), axis=1)
    assert not v[np.arange(500), best].any() and not (v & ~a).any()


def test_a_vetoed_move_a_robot_may_still_take_ranks_after_all_its_other_candidates() -> None:
    """vetoed_last: the numbers of seed 8477 (the turn game ranked the two open cells 6 and left
    the vetoed cell at 4) and random rows. A vetoed allowed candidate ranks above every other
    allowed one of its robot and never better than before; nothing else changes."""
    rank = np.array([[4, 4, 4, 4, 6, 6, 4, 4, 4]])
    allowed = np.array([[0, 0, 0, 0, 1, 1, 1, 0, 0]], bool)
    vetoed = np.array([[0, 0, 0, 0, 0, 0, 1, 0, 0]], bool)
    np.testing.assert_array_equal(vetoed_last(rank, allowed, vetoed), [[4, 4, 4, 4, 6, 6, 7, 4, 4]])
    rng = np.random.default_rng(2)
    rank = rng.integers(0, 10, (400, 9))
    allowed = rng.random((400, 9)) < 0.6
    vetoed = rng.random((400, 9)) < 0.3
    got = vetoed_last(rank, allowed, vetoed)
    v, legit = vetoed & allowed, allowed & ~vetoed
    np.testing.assert_array_equal(got[~v], rank[~v])
    assert (got >= rank).all()
    for i in np.flatnonzero(v.any(axis=1) & legit.any(axis=1)):
        assert got[i, v[i]].min() > got[i, legit[i]].max()


# A 1-wide corridor (x = 6) with a dead end beside it, (6, 5), (6, 6), (7, 6), whose only way out
# is the corridor: the layout that caught a cat-swarm robot on the 64 x 64 acceptance world.
POCKET_ROWS = [                       # top row first: y = 12 ... 0
    ".....#.#.....",
    "#............",
    ".....#.#..#..",
    ".......#..##.",
    "#....#.#.#..#",
    ".......#....#",
    ".....#..#....",
    ".....#.#.....",
    "....#.#......",
    ".....##....#.",
    "..##.........",
    "..#......#...",
    ".......#.....",
]
POCKET = {(6, 5), (6, 6), (7, 6)}


def pocket_world() -> World:
    """The corridor and dead end above, a point robot at the pocket's mouth (6, 7) with its goal
    at (3, 6), and a random walker at (3, 8), three cells away."""
    blocked = np.array([[c == "#" for c in row] for row in POCKET_ROWS[::-1]])
    robot = Robot("r", (6.5, 7.5), (3.5, 6.5), 0.0, S2)
    walker_ = MovingObstacle("w", Rect((-0.5, -0.5), (0.5, 0.5)), (3.5, 8.5), (1.0, 0.0), RandomWalk())
    return World(RectBounds(13, 13), static_map=StaticMap(blocked, 1.0), moving_obstacles=(walker_,),
                 robots=(robot,), name="pocket")


@pytest.mark.parametrize("controller", ["cat-swarm", "pibt"])
def test_a_robot_fleeing_a_walker_does_not_take_the_dead_end_the_walker_value_rejects(controller) -> None:
    """The look-ahead tiers take the walker at its worst, and at its worst a walker reaches a
    dead end last: without the veto the robot steps into the pocket whatever the walker did. With
    it, it never does where the exact value rates the pocket ten times riskier than its safest
    move (and 0.002 more), and does where the walker has turned away."""
    from swarmpath.sim import Simulator

    world = pocket_world()
    grid = world.grid()
    table = EvasionRisk(world, grid, static_moves(grid.blocked, 8), ObstacleForecast(world, grid), 0.0, 8)
    rejected = {True: [], False: []}
    entered = {True: [], False: []}
    for veto in (True, False):
        for seed in range(16):
            ctrl = CONTROLLERS.get(controller)(evasion_veto=veto)
            traj = Simulator(world, ctrl, None, seed=seed, max_steps=1).run()
            assert not traj.contacts
            seen = traj.obstacle_positions[1]                   # what the robot decided on
            risk = table.move_risk(np.array([[6, 7]]), seen)[0]
            pocket = risk[7] > max(10 * risk.min(), risk.min() + 2e-3)
            cell = tuple(int(v) for v in np.floor(traj.positions[1, 0]))
            rejected[veto].append(bool(pocket))
            entered[veto].append(cell in POCKET)
    assert rejected[True] == rejected[False] and 4 <= sum(rejected[True]) <= 12   # the walker's step decides
    assert all(entered[False])
    assert not any(e and r for e, r in zip(entered[True], rejected[True]))
    assert any(entered[True])
