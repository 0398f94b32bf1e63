"""The pibt controller and its core: the checker's rule holds by construction, PIBT's
priority inheritance and reachability, determinism, MovingAI instances, moving obstacles in
narrow passages."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.pibt import PIBTController
from swarmpath.control.pibt.core import (
    PUSHED,
    STAY,
    GridGraph,
    decision_order,
    pibt_step,
    static_moves,
    update_priorities,
)
from swarmpath.data.movingai import MOVINGAI
from swarmpath.errors import ConfigError
from swarmpath.search.lazy_distance import LazyDistanceTables
from swarmpath.sim.simulator import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import Circle, Rect, RectBounds, Robot, World, world_from_movingai
from swarmpath.world.move_rules import GRID_MOVES, grid_conflict_table, move_conflicts
from swarmpath.world.moving import (
    Bounce,
    Bounce8,
    MovingObstacle,
    RandomWalk,
    Redraw,
    TurnEvery,
    Waypoints,
)
from swarmpath.world.static_map import StaticMap

DATA = MOVINGAI
S2 = float(np.sqrt(2))


def run(world, seed=0, max_steps=None, controller="pibt", **kw):
    from swarmpath.registry import CONTROLLERS

    return Simulator(world, CONTROLLERS.get(controller)(**kw), seed=seed, max_steps=max_steps).run()


def arrived(world, traj) -> np.ndarray:
    return np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9


# ---------------------------------------------------------------------------- the core
def random_step_case(rng, radius, connectivity, n_max=30, size=9):
    """A random grid, robots on distinct free cells, goals, and everything pibt_step needs."""
    blocked = rng.random((size, size)) < 0.15
    free = np.argwhere(~blocked)[:, ::-1]
    n = int(min(len(free) - 1, rng.integers(2, n_max)))
    pick = rng.choice(len(free), size=n, replace=False)
    cells = free[pick]
    goals = free[rng.choice(len(free), size=n, replace=False)]
    tables = LazyDistanceTables(blocked, connectivity=connectivity)
    handles = tables.acquire_many(goals)
    dist = tables.neighbour_costs(handles, cells)
    moves = static_moves(blocked, connectivity)[cells[:, 1], cells[:, 0]]
    graph = GridGraph.build(blocked, connectivity, radius, 1.0)
    w = blocked.shape[1]
    flat = (cells[:, 1] * w + cells[:, 0]).astype(np.int32)
    gflat = (goals[:, 1] * w + goals[:, 0]).astype(np.int32)
    order = decision_order(rng.random(n))
    return blocked, cells, goals, tables, handles, dist, moves, graph, flat, gflat, order


@pytest.mark.parametrize("radius", [0.0, 0.3, 0.5])
@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("swap", [False, True])
def test_one_step_never_breaks_the_checkers_rule(radius, connectivity, swap):
    """Random crowded configurations: the moves PIBT returns have no conflict by the
    checker's predicate (move_conflicts on the actual segments), no corner cutting and no
    blocked cell."""
    rng = np.random.default_rng(int(radius * 10) + connectivity + 100 * swap)
    for _ in range(60):
        blocked, cells, goals, tables, handles, dist, moves, graph, flat, gflat, order = \
            random_step_case(rng, radius, connectivity)
        res = pibt_step(graph, flat, np.nan_to_num(dist, nan=np.inf), moves, rng.random(dist.shape), order,
                        goals=gflat, slots=handles, tables=tables._c, swap=swap, yield_way=True)
        assert res.ok and res.conflicts == 0
        m = res.moves.astype(int)
        assert np.all(moves[np.arange(len(m)), m])
        p0 = cells + 0.5
        p1 = p0 + GRID_MOVES[m]
        i, j = np.triu_indices(len(m), 1)
        kinds = move_conflicts(p0[i], p1[i], p0[j], p1[j], radius, radius, 1.0)
        assert not kinds.any(), list(zip(i[kinds > 0], j[kinds > 0]))


def test_priority_inheritance_pushes_a_lower_robot_out_of_the_way():
    """A 1-wide corridor with a side pocket: the higher robot wants the cell of the lower one,
    which must step into the pocket (inheritance), not block it."""
    blocked = np.ones((3, 6), bool)
    blocked[1, :] = False       # corridor y = 1, x = 0..5
    blocked[0, 3] = False       # pocket above x = 3
    graph = GridGraph.build(blocked, 4, 0.0, 1.0)
    cells = np.array([[2, 1], [3, 1]])
    goals = np.array([[5, 1], [3, 1]])       # robot 1 sits on its goal
    tables = LazyDistanceTables(blocked, connectivity=4)
    handles = tables.acquire_many(goals)
    dist = tables.neighbour_costs(handles, cells)
    moves = static_moves(blocked, 4)[cells[:, 1], cells[:, 0]]
    flat = (cells[:, 1] * 6 + cells[:, 0]).astype(np.int32)
    res = pibt_step(graph, flat, np.nan_to_num(dist, nan=np.inf), moves, np.zeros((2, 9)),
                    np.array([0, 1], np.int32), goals=(goals[:, 1] * 6 + goals[:, 0]).astype(np.int32),
                    slots=handles, tables=tables._c)
    assert tuple(GRID_MOVES[res.moves[0]]) == (1, 0)       # the high robot advances
    assert tuple(GRID_MOVES[res.moves[1]]) in ((1, 0), (0, -1))   # the low one makes way
    assert res.flags[1] & PUSHED
    # without a way out the low robot stays and the high one backtracks to waiting
    blocked[0, 3] = True
    blocked[1, 4:] = True
    graph = GridGraph.build(blocked, 4, 0.0, 1.0)
    moves = static_moves(blocked, 4)[cells[:, 1], cells[:, 0]]
    dist[:, 1] = np.where(moves[:, 1], dist[:, 1], np.nan)
    res = pibt_step(graph, flat, np.nan_to_num(dist, nan=np.inf), moves, np.zeros((2, 9)),
                    np.array([0, 1], np.int32), goals=np.array([1 * 6 + 3, 1 * 6 + 3], np.int32))
    assert res.moves[1] == STAY and res.ok and res.conflicts == 0
    assert res.moves[0] in (STAY, 5)   # waits or backs off, never into the occupied cell


@pytest.mark.parametrize("connectivity", [4, 8])
def test_the_highest_priority_robot_always_gets_its_best_cell(connectivity):
    """Theorem 1 of the paper: on a graph where every two adjacent vertices lie on a cycle (an
    open grid), the robot of highest priority moves to a best cell every step, however
    crowded; so it reaches its goal in as many steps as its distance (without swaps)."""
    rng = np.random.default_rng(connectivity)
    blocked = np.zeros((8, 8), bool)
    graph = GridGraph.build(blocked, connectivity, 0.0, 1.0)
    free = np.argwhere(~blocked)[:, ::-1]
    moves_all = static_moves(blocked, connectivity)
    for _ in range(20):
        n = int(rng.integers(10, 50))
        cells = free[rng.choice(64, n, replace=False)]
        goals = free[rng.choice(64, n, replace=False)]
        tables = LazyDistanceTables(blocked, connectivity=connectivity)
        handles = tables.acquire_many(goals)
        steps = 0
        while np.any(cells[0] != goals[0]):
            dist = tables.neighbour_costs(handles, cells)
            moves = moves_all[cells[:, 1], cells[:, 0]]
            prio = np.r_[1e9, rng.random(n - 1)]
            flat = (cells[:, 1] * 8 + cells[:, 0]).astype(np.int32)
            res = pibt_step(graph, flat, np.nan_to_num(dist, nan=np.inf), moves, rng.random((n, 9)),
                            decision_order(prio), goals=(goals[:, 1] * 8 + goals[:, 0]).astype(np.int32),
                            slots=handles, tables=tables._c, swap=False, yield_way=True)
            best = np.nanmin(dist[0])
            assert dist[0, res.moves[0]] == best
            cells = cells + GRID_MOVES[res.moves.astype(int)]
            steps += 1
            assert steps <= 20
        assert len({tuple(c) for c in cells.tolist()}) == n


def test_robots_that_must_leave_decide_first_the_most_constrained_first():
    prio = np.array([5.0, 4.0, 3.0, 2.0])
    urgent = np.array([False, True, True, False])
    assert decision_order(prio, urgent).tolist() == [1, 2, 0, 3]
    assert decision_order(prio, urgent, np.array([9, 3, 1, 9])).tolist() == [2, 1, 0, 3]


def test_a_robot_left_without_a_way_out_chooses_first_on_the_retry():
    """Two robots must leave their cells (a moving obstacle may reach both). The first to
    decide takes the cell the other needed, or crosses its diagonal; pibt_step_escaping lets
    the robot left behind choose first and both get out."""
    from swarmpath.control.pibt.core import pibt_step_escaping

    blocked = np.zeros((4, 4), bool)
    graph = GridGraph.build(blocked, 8, 0.0, 1.0)
    cells = np.array([[2, 2], [2, 1]])                  # A above B
    flat = (cells[:, 1] * 4 + cells[:, 0]).astype(np.int32)
    allowed = np.zeros((2, 9), bool)
    west, south_west, north_west = 5, 6, 4
    allowed[0, [west, south_west]] = True               # A: to (1, 2) or (1, 1)
    allowed[1, [north_west, west]] = True               # B: to (1, 2) or (1, 1)
    dist = np.full((2, 9), 9.0)
    dist[0, west], dist[0, south_west] = 0.0, 1.0
    dist[1, north_west], dist[1, west] = 0.0, 1.0
    order = np.array([1, 0], np.int32)                  # B first
    kw = {"goals": flat.copy()}
    plain = pibt_step(graph, flat, dist, allowed, np.zeros((2, 9)), order, **kw)
    assert plain.moves.tolist() == [STAY, north_west]   # A is left in the obstacle's way
    both = pibt_step_escaping(graph, flat, dist, allowed, np.zeros((2, 9)), order, danger=np.ones(2, bool), **kw)
    assert both.moves.tolist() == [west, west]
    assert both.conflicts == 0


def test_three_robots_fleeing_side_by_side_all_get_out_on_a_later_try():
    """Three robots in a column must leave (an obstacle may reach them all); each may step east
    or diagonally east. The greedy order lets the outer two take both cells the middle one
    could reach, or cross its diagonal; with the middle one first the top one is left
    behind. The retries are built from the last try (the robots that failed there first),
    so the third try moves all three east. A robot that moved to a worse tier than its best
    counts as failed, but a robot left standing in danger weighs more: a try that only
    degrades one beats a try that leaves one standing."""
    from swarmpath.control.pibt.core import pibt_step_escaping

    east, north_east, south_east, north, south = 1, 2, 8, 3, 7
    blocked = np.zeros((3, 4), bool)
    graph = GridGraph.build(blocked, 8, 0.0, 1.0)
    cells = np.array([[0, 0], [0, 1], [0, 2]])           # bottom, middle, top
    flat = (cells[:, 1] * 4 + cells[:, 0]).astype(np.int32)
    allowed = np.zeros((3, 9), bool)
    allowed[0, [east, north_east]] = True
    allowed[1, [east, north_east, south_east]] = True
    allowed[2, [east, south_east]] = True
    dist = np.full((3, 9), 9.0)
    dist[0, north_east], dist[0, east] = 1.0, 2.0
    dist[1, north_east], dist[1, east], dist[1, south_east] = 1.0, 2.0, 3.0
    dist[2, east], dist[2, south_east] = 1.0, 2.0
    order = np.array([0, 2, 1], np.int32)                # the middle one decides last
    kw = {"goals": flat.copy()}
    danger = np.ones(3, bool)
    plain = pibt_step(graph, flat, dist, allowed, np.zeros((3, 9)), order, **kw)
    assert plain.moves[1] == STAY                        # the middle one is left in the way
    out = pibt_step_escaping(graph, flat, dist, allowed, np.zeros((3, 9)), order, danger=danger, **kw)
    assert out.moves.tolist() == [east, east, east] and out.conflicts == 0
    # ranks: the middle robot may also go north or south (tier 1 there, rank 4); the greedy
    # order degrades it, a retry gets it a cell of its best tier
    allowed[1, [north, south]] = True
    dist[1, [north, south]] = 0.5 + 4e8
    rank = np.zeros((3, 9), np.int64)
    rank[1, [north, south]] = 4
    first = pibt_step(graph, flat, dist, allowed, np.zeros((3, 9)), order, **kw)
    assert first.moves[1] in (north, south)
    out = pibt_step_escaping(graph, flat, dist, allowed, np.zeros((3, 9)), order, danger=danger, rank=rank, **kw)
    assert out.moves.tolist() == [east, east, east]


def test_two_robots_whose_best_ways_out_cross_both_get_out():
    """Two robots side by side must leave (an obstacle may reach both); each may step straight
    down or diagonally down across the other's column, and each prefers its diagonal. Whoever
    decides first takes its diagonal, which crosses the other's diagonal and takes the other's
    straight cell: reordering alone leaves one standing in either order. Trying the left-behind
    robot's ways out one at a time finds both straight down."""
    from swarmpath.control.pibt.core import pibt_step_escaping

    south, south_east, south_west = 7, 8, 6
    blocked = np.zeros((3, 4), bool)
    graph = GridGraph.build(blocked, 8, 0.0, 1.0)
    cells = np.array([[1, 1], [2, 1]])                   # A left of B
    flat = (cells[:, 1] * 4 + cells[:, 0]).astype(np.int32)
    allowed = np.zeros((2, 9), bool)
    allowed[0, [south, south_east]] = True               # A: to (1, 0) or (2, 0)
    allowed[1, [south, south_west]] = True               # B: to (2, 0) or (1, 0)
    dist = np.full((2, 9), 9.0)
    dist[0, south_east], dist[0, south] = 1.0, 2.0
    dist[1, south_west], dist[1, south] = 1.0, 2.0
    kw = {"goals": flat.copy()}
    danger = np.ones(2, bool)
    for order in ([1, 0], [0, 1]):
        order = np.array(order, np.int32)
        plain = pibt_step(graph, flat, dist, allowed, np.zeros((2, 9)), order, **kw)
        assert sorted(plain.moves.tolist()) in ([STAY, south_east], [STAY, south_west])
        both = pibt_step_escaping(graph, flat, dist, allowed, np.zeros((2, 9)), order, danger=danger, **kw)
        assert both.moves.tolist() == [south, south] and both.conflicts == 0
        # without the danger (the robots may stay) nothing changes
        calm = pibt_step_escaping(graph, flat, dist, allowed | (np.arange(9) == STAY), np.zeros((2, 9)), order,
                                  danger=np.zeros(2, bool), **kw)
        assert calm.moves.tolist() == pibt_step(graph, flat, dist, allowed | (np.arange(9) == STAY),
                                                np.zeros((2, 9)), order, **kw).moves.tolist()


def test_robots_pushed_aside_leave_the_cells_that_robots_in_danger_need():
    """Two robots in a pocket must leave (an obstacle may reach both) down into the row where
    two calm robots stand; the right one prefers straight down, the left one its diagonal,
    and the left one decides first. The calm robot below the right one, pushed, prefers the
    cell to its west, which is a way out of both: in every retry one robot in danger is left
    standing. With escape_claims added to its ranking (after the tier) the pushed robot
    steps elsewhere and both robots in danger get out, in either order."""
    from swarmpath.control.pibt.core import escape_claims, pibt_step_escaping

    south, south_east, south_west, west = 7, 8, 6, 5
    blocked = np.zeros((3, 3), bool)
    graph = GridGraph.build(blocked, 8, 0.0, 1.0)
    cells = np.array([[0, 2], [1, 2], [1, 1], [0, 1]])  # B, A (in the pocket), C, D (below)
    flat = (cells[:, 1] * 3 + cells[:, 0]).astype(np.int32)
    allowed = np.zeros((4, 9), bool)
    allowed[0, [south, south_east]] = True               # B: to (0, 1) or (1, 1)
    allowed[1, [south, south_west]] = True               # A: to (1, 1) or (0, 1)
    allowed[2:] = static_moves(blocked, 8)[cells[2:, 1], cells[2:, 0]]
    dist = np.full((4, 9), 9.0)
    dist[0, south_east], dist[0, south] = 1.0, 2.0
    dist[1, south], dist[1, south_west] = 1.0, 2.0
    dist[2, STAY], dist[2, west] = 0.0, 1.0              # C: stay, else west (D's cell)
    dist[3, STAY], dist[3, south] = 0.0, 1.0
    danger = np.array([True, True, False, False])
    rank = np.zeros((4, 9), np.int64)
    kw = {"goals": np.full(4, 2, np.int32)}                 # no robot on its goal
    plain = pibt_step_escaping(graph, flat, dist, allowed, np.zeros((4, 9)), np.arange(4, dtype=np.int32),
                               danger=danger, rank=rank, **kw)
    assert plain.moves[1] == STAY and plain.moves[2] == west
    for order in ([0, 1, 2, 3], [1, 0, 2, 3]):
        order = np.array(order, np.int32)
        claims = escape_claims(cells, allowed, rank, danger & ~allowed[:, STAY], (3, 3))
        assert claims[2, west] == 2 and claims[2, STAY] == 0 and (claims[:2] == 0).all()
        out = pibt_step_escaping(graph, flat, dist + 10.0 * claims, allowed, np.zeros((4, 9)), order, danger=danger,
                                 rank=rank, **kw)
        assert out.moves[0] != STAY and out.moves[1] != STAY and out.conflicts == 0
        assert out.moves[2] != west


def test_priorities_follow_section_3_2():
    base = np.array([0.1, 0.7, 0.3])
    p = update_priorities(base.copy(), np.array([False, True, False]), base)
    assert np.allclose(p, [1.1, 0.7, 1.3])
    p = update_priorities(p, np.array([True, False, False]), base)
    assert np.allclose(p, [0.1, 1.7, 2.3])
    assert decision_order(p).tolist() == [2, 1, 0]
    assert decision_order(p, np.array([True, False, False])).tolist() == [0, 2, 1]


# ---------------------------------------------------------------------------- the controller
@pytest.mark.parametrize("name,scen,n", [("random-32-32-10", "random-32-32-10-random-1", 100),
                                         ("room-32-32-4", "room-32-32-4-even-10", 60),
                                         ("maze-32-32-2", "maze-32-32-2-even-10", 40),
                                         ("empty-8-8", "empty-8-8-even-10", 32)])
@pytest.mark.parametrize("connectivity", [4, 8])
def test_movingai_instances_all_arrive_without_contacts(name, scen, n, connectivity):
    world = world_from_movingai(DATA / f"{name}.map", DATA / f"{scen}.scen", n)
    traj = run(world, connectivity=connectivity)
    assert traj.status.value == "all_reached"
    assert validate_trajectory(world, traj) == []
    steps = np.abs(np.diff(np.floor(traj.positions), axis=0)).sum(axis=2)
    assert steps.max() <= (1 if connectivity == 4 else 2)


def test_same_seed_same_trajectory_bit_for_bit_and_seeds_differ():
    world = world_from_movingai(DATA / "room-32-32-4.map", DATA / "room-32-32-4-even-10.scen", 80)
    a, b, c = run(world, seed=3), run(world, seed=3), run(world, seed=4)
    assert np.array_equal(a.positions, b.positions)
    assert a.modes is not None and np.array_equal(a.modes, b.modes)
    assert not (a.positions.shape == c.positions.shape and np.array_equal(a.positions, c.positions))


def test_pushes_are_reported_in_the_modes():
    world = world_from_movingai(DATA / "maze-32-32-2.map", DATA / "maze-32-32-2-even-10.scen", 100)
    ctl = PIBTController()
    traj = Simulator(world, ctl, seed=0).run()
    names = traj.mode_names
    pushed = (traj.modes == names.index("pushed")).sum(axis=0)
    assert pushed.sum() > 0
    assert np.array_equal(pushed, ctl.pushes_)
    assert set(names) <= {"move", "wait", "pushed", "arrived"}


def disc_world(radius: float, n: int, seed: int = 0) -> World:
    from scipy import ndimage

    rng = np.random.default_rng(seed)
    blocked = rng.random((16, 16)) < 0.1
    labels, _ = ndimage.label(~blocked)
    comp = np.argwhere(labels == np.bincount(labels.ravel())[1:].argmax() + 1)[:, ::-1]
    pick = rng.choice(len(comp), 2 * n, replace=False)
    starts, goals = comp[pick[:n]] + 0.5, comp[pick[n:]] + 0.5
    robots = tuple(Robot(f"r{i}", tuple(s), tuple(g), radius, S2) for i, (s, g) in enumerate(zip(starts, goals)))
    return World(RectBounds(16, 16), static_map=StaticMap(blocked), robots=robots)


@pytest.mark.parametrize("radius", [0.3, 0.4, 0.5])
def test_disc_robots_up_to_half_a_cell_never_touch(radius):
    """Discs above ~0.354 cell: following diagonally or passing a robot that stays are
    contacts for the checker; the conflict table keeps the controller out of them, even in a
    crowd where some robots then cannot pass each other (PIBT is not complete)."""
    world = disc_world(radius, 30)
    for connectivity in (8, 4):
        traj = run(world, max_steps=150, connectivity=connectivity)
        assert validate_trajectory(world, traj) == []
    # next to another robot a big disc cannot move diagonally, so octile distances mislead
    # it; with 4-connectivity sparse robots all arrive
    for seed in range(1, 4):
        sparse = disc_world(radius, 8, seed=seed)
        traj = run(sparse, connectivity=4)
        assert validate_trajectory(sparse, traj) == []
        assert arrived(sparse, traj).all()


def test_off_centre_starts_and_goals_settle_on_centres_then_the_exact_goal():
    robots = (Robot("a", (0.2, 0.3), (5.9, 0.1), 0.0, S2), Robot("b", (5.5, 0.5), (1.0, 1.0), 0.0, S2),
              Robot("c", (3.5, 2.5), (3.5, 0.5), 0.0, S2))
    world = World(RectBounds(6, 3), robots=robots)
    traj = run(world)
    assert validate_trajectory(world, traj) == []
    assert arrived(world, traj).all()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_many_off_centre_points_never_collide(seed):
    """Starts and goals anywhere inside distinct cells of a crowded open grid: the exact check
    (and the holds it cascades) keeps every off-centre move contact-free."""
    rng = np.random.default_rng(seed)
    cells = rng.choice(100, 80, replace=False)
    starts = np.stack([cells[:40] % 10, cells[:40] // 10], axis=1) + rng.uniform(0.05, 0.95, (40, 2))
    goals = np.stack([cells[40:] % 10, cells[40:] // 10], axis=1) + rng.uniform(0.05, 0.95, (40, 2))
    robots = tuple(Robot(f"r{i}", tuple(s), tuple(g), 0.0, S2) for i, (s, g) in enumerate(zip(starts, goals)))
    world = World(RectBounds(10, 10), robots=robots)
    traj = run(world, seed=seed)
    assert validate_trajectory(world, traj) == []
    assert arrived(world, traj).all()


def test_bad_parameters_raise_config_errors():
    world = world_from_movingai(DATA / "empty-8-8.map", DATA / "empty-8-8-even-10.scen", 4)
    with pytest.raises(ConfigError, match="connectivity"):
        PIBTController(connectivity=6).reset(world, None, np.random.default_rng(0))
    for kw in ({"lookahead": -1}, {"leave_early": -2}, {"lookahead": 1.5}):
        with pytest.raises(ConfigError, match=next(iter(kw))):
            PIBTController(**kw).reset(world, None, np.random.default_rng(0))
    slow = world.replace(robots=tuple(Robot(r.id, r.start, r.goal, 0.0, 0.5) for r in world.robots))
    with pytest.raises(ConfigError, match="max_speed"):
        PIBTController().reset(slow, None, np.random.default_rng(0))
    big = World(RectBounds(8, 8), robots=(Robot("a", (3.5, 3.5), (5.5, 5.5), 0.6, S2),))
    with pytest.raises(ConfigError, match="radius"):
        PIBTController().reset(big, None, np.random.default_rng(0))


@pytest.mark.slow
def test_success_over_seeds_on_crowded_maps():
    """Statistics: every robot arrives without a contact on every seed."""
    for name, scen, n in [("random-32-32-10", "random-32-32-10-random-1", 300),
                          ("maze-32-32-2", "maze-32-32-2-even-10", 150), ("den312d", "den312d-even-10", 200)]:
        world = world_from_movingai(DATA / f"{name}.map", DATA / f"{scen}.scen", n)
        for seed in range(3):
            traj = run(world, seed=seed)
            assert traj.status.value == "all_reached" and not traj.contacts, (name, seed)


# ---------------------------------------------------------------------------- moving obstacles
def corridor_world(kind: str, n_obstacles: int, n_robots: int = 6, room: int = 12, height: int = 14) -> World:
    """Narrow passages: two rooms (``room`` cells wide) joined by 2-wide corridors, one with a
    1-cell door, and a dead-end niche; robots cross from one room to the other while
    obstacles of ``kind`` move in the rooms."""
    w, h = 2 * room + 6, height
    blocked = np.zeros((h, w), bool)
    blocked[:, room:room + 6] = True
    blocked[3:5, room:room + 6] = False          # a 2-wide corridor
    blocked[h - 5:h - 3, room:room + 6] = False  # another one
    blocked[h - 4, room + 3] = True              # a door: 1 cell wide in the second corridor
    blocked[h // 2 - 1:h // 2 + 1, room + 6:room + 10] = True   # a dead-end niche on the right
    blocked[h // 2, room + 6:room + 9] = False
    robots = []
    for i in range(n_robots):
        y = 1 + (2 * i) % (h - 2)
        x = 1.5 + i // ((h - 1) // 2)
        robots.append(Robot(f"r{i}", (x, y + 0.5), (w - 1.5 - i // ((h - 1) // 2), h - 1.5 - y + 1), 0.0, S2))
    motion = {"bounce": Bounce(), "bounce8": Bounce8(), "turn-every": TurnEvery(5), "random-walk": RandomWalk(),
              "redraw": Redraw(), "waypoints": None}[kind]
    obstacles = []
    rng = np.random.default_rng(n_obstacles)
    columns = [c + 0.5 for c in range(3, room - 2, 2)] + [c + 0.5 for c in range(room + 11, w - 4, 2)]
    for j in range(n_obstacles):
        x = float(columns[j % len(columns)])
        y = float(2.5 + (3 * j + j // len(columns)) % (h - 4))
        if kind == "waypoints":
            mo = MovingObstacle(f"o{j}", Circle((0, 0), 0.4), (x, y), (0.5, 0.0),
                                Waypoints(((x, h - 1.5), (x, 1.5)), True))
        else:
            shape = Rect((-0.4, -0.4), (0.4, 0.4)) if j % 2 else Circle((0, 0), 0.4)
            mo = MovingObstacle(f"o{j}", shape, (x, y), (0.0, 0.7) if j % 2 else (0.7, 0.0), motion)
        obstacles.append(mo)
    return World(RectBounds(w, h), static_map=StaticMap(blocked), robots=tuple(robots),
                 moving_obstacles=tuple(obstacles), name=f"corridor-{kind}")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
@pytest.mark.parametrize("kind,count", [("bounce", 5), ("bounce8", 10), ("turn-every", 8), ("random-walk", 12),
                                        ("redraw", 20), ("waypoints", 6)])
def test_narrow_passages_with_moving_obstacles(kind, count, controller):
    """Both controllers on the core (cat-swarm ranks with the swarm's rules)."""
    world = corridor_world(kind, count)
    traj = run(world, max_steps=400, controller=controller)
    problems = validate_trajectory(world, traj)   # the independent check finds the recorded contacts only
    assert len(problems) == len(traj.contacts) and all("robot_moving" in v.problem for v in problems)
    kinds = [c.kind for c in traj.contacts]
    assert "robot_robot" not in kinds and "robot_static" not in kinds
    assert arrived(world, traj).all(), traj.status
    # a contact with a moving obstacle only where the robot was cornered (no move led out)
    cornered = {(e["step"], e["robot"]) for e in traj.events if e.get("kind") == "no_escape"}
    for c in traj.contacts:
        assert (c.step, c.robot) in cornered or (c.step - 1, c.robot) in cornered, c


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_many_obstacles_and_robots_in_the_passages_over_seeds(controller):
    for kind in ("bounce8", "random-walk", "waypoints"):
        world = corridor_world(kind, 40, n_robots=10, room=22, height=24)
        for seed in range(2):
            traj = run(world, seed=seed, max_steps=600, controller=controller)
            kinds = [c.kind for c in traj.contacts]
            assert "robot_robot" not in kinds and "robot_static" not in kinds, (kind, seed)
            assert arrived(world, traj).all(), (kind, seed)
            cornered = {(e["step"], e["robot"]) for e in traj.events if e.get("kind") == "no_escape"}
            assert all((c.step, c.robot) in cornered or (c.step - 1, c.robot) in cornered for c in traj.contacts)


def test_conflict_table_is_the_move_rules_table():
    from swarmpath.control.pibt.core import conflict_table
    for r in (0.0, 0.2, 0.5):
        assert np.array_equal(conflict_table(r, 1.0).astype(bool), grid_conflict_table(r, r, 1.0))


def _nook_world(walker_y: int) -> World:
    """A robot on its goal in a 1-cell nook at the east edge (cell (9, 6), way out (9, 5)), a
    random walker (9, walker_y) below the nook's mouth, a second robot far off."""
    blocked = np.zeros((8, 10), bool)
    blocked[6, 8] = blocked[7, 9] = True
    robots = (Robot("a", (9.5, 6.5), (9.5, 6.5), 0.0, S2), Robot("b", (0.5, 0.5), (3.5, 7.5), 0.0, S2))
    walker = MovingObstacle("w", Rect((-0.5, -0.5), (0.5, 0.5)), (9.5, walker_y + 0.5), (0.0, 1.0), RandomWalk())
    return World(RectBounds(10, 8), static_map=StaticMap(blocked, 1.0), moving_obstacles=(walker,), robots=robots,
                 name="nook")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_in_a_nook_leaves_before_a_walker_can_close_its_mouth(controller):
    """Next to a dead end robots look DEAD_END_EXTRA steps further: with the walker 4 cells
    below the nook's mouth the robot on its goal in the nook steps out now (waiting longer,
    the walker could reach the mouth before the robot got clear of it); 5 cells below, it
    stays. With the plain look-ahead it stays in both, and is cornered a few steps later."""
    from swarmpath.registry import CONTROLLERS

    moved = {}
    for walker_y in (0, 1):
        world = _nook_world(walker_y)
        traj = Simulator(world, CONTROLLERS.get(controller)(), None, seed=0, max_steps=1).run()
        moved[walker_y] = tuple(traj.positions[1][0])
    assert moved[0] == (9.5, 6.5)
    assert moved[1] == (9.5, 5.5)


def _pocket_world(walker: tuple[int, int]) -> World:
    """A robot on its goal in the far corner (cell (9, 7)) of a 2 x 2 pocket at the map's
    north-east corner (cells x 8-9, y 6-7, walled off on the west), whose mouth (8, 5)-(9, 5)
    is two cells wide; a random walker at cell ``walker`` below it; a second robot far off."""
    blocked = np.zeros((8, 10), bool)
    blocked[6, 7] = blocked[7, 7] = True
    robots = (Robot("a", (9.5, 7.5), (9.5, 7.5), 0.0, S2), Robot("b", (0.5, 0.5), (3.5, 7.5), 0.0, S2))
    walker = MovingObstacle("w", Rect((-0.5, -0.5), (0.5, 0.5)), (walker[0] + 0.5, walker[1] + 0.5), (0.0, 1.0),
                            RandomWalk())
    return World(RectBounds(10, 8), static_map=StaticMap(blocked, 1.0), moving_obstacles=(walker,), robots=robots,
                 name="pocket")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_in_a_pocket_leaves_before_a_walker_can_close_its_mouth(controller, monkeypatch):
    """A pocket two cells wide is shut by one walker as surely as a 1-cell nook (the robot may
    not end a step next to it), so robots next to one look DEAD_END_EXTRA steps further too:
    with the walker 2 cells below the mouth the robot heads out now, 3 cells below it stays.
    Without pockets (only 1-wide dead ends) and without the walker-evasion value (which sees
    the pocket's risk by itself: the robot then leaves too) it stays in both."""
    from swarmpath.control import hazards
    from swarmpath.registry import CONTROLLERS

    def first_move(walker, **params):
        traj = Simulator(_pocket_world(walker), CONTROLLERS.get(controller)(**params), None, seed=0,
                         max_steps=1).run()
        return tuple(traj.positions[1][0])

    assert hazards.pocket_cells(static_moves(_pocket_world((0, 0)).static_map.blocked, 8))[6:8, 8:10].all()
    assert first_move((9, 2)) == (9.5, 6.5)
    assert first_move((9, 1)) == (9.5, 7.5)
    monkeypatch.setattr(hazards, "pocket_cells", lambda moves: np.zeros(np.shape(moves)[:2], bool))
    assert first_move((9, 2), evasion_horizon=0) == (9.5, 7.5)
    assert first_move((9, 2)) == (9.5, 6.5)
