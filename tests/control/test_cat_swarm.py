"""The cat-swarm controller: its kernels against hand-computed values (eq. 10-13, copies,
deletions, look-ahead), the ranking it hands to the PIBT core, the obstacle forecast, the
cell paths, and the controller itself on small worlds (conformance, determinism,
avoidance)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control import hazards as H
from swarmpath.control.cat_swarm import CatSwarmController
from swarmpath.control.cat_swarm import kernels as K
from swarmpath.control.cell_paths import (
    plan_cells,
    polyline_cells,
    remaining_lengths,
    repair_cells,
    tidy_cells,
)
from swarmpath.control.hazards import ObstacleForecast, box_cell_ranges, paint
from swarmpath.errors import ConfigError
from swarmpath.planning import plan
from swarmpath.sim import Simulator
from swarmpath.testing import check_controller, validate_trajectory
from swarmpath.world import Bounce, Bounce8, RandomWalk, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.moving import MovingObstacle

S2 = float(np.sqrt(2))


# ---------------------------------------------------------------------------- eq. 10-11
@pytest.mark.parametrize("n, expected", [(12, (5, 7)), (2, (1, 1)), (1, (0, 1)), (3, (1, 2)), (0, (0, 0))])
def test_mixture_counts_follow_eq_10_11(n, expected) -> None:
    assert K.mixture_counts(n, 0.4) == expected


def test_mixture_split_gives_seek_to_the_longest_paths_in_each_group() -> None:
    remaining = np.array([10.0, 5.0, 8.0, 1.0, 3.0, 4.0])
    groups = np.array([0, 0, 0, 0, 1, 1])
    seek = K.mixture_split(remaining, groups, 0.5, np.zeros(6))
    assert seek.tolist() == [True, False, True, False, False, True]
    # MR 0.4: group of 4 -> 2 seek (1.6 rounds to 2), group of 2 -> 1 seek
    assert K.mixture_split(remaining, groups, 0.4, np.zeros(6)).tolist() == [True, False, True, False, False, True]


def test_mixture_split_breaks_ties_with_the_random_keys() -> None:
    remaining = np.array([5.0, 5.0])
    groups = np.zeros(2, np.int64)
    assert K.mixture_split(remaining, groups, 0.4, np.array([0.9, 0.1])).tolist() == [False, True]
    assert K.mixture_split(remaining, groups, 0.4, np.array([0.1, 0.9])).tolist() == [True, False]


# ---------------------------------------------------------------------------- seek copies and deletion
def test_seek_copies_are_the_present_cell_and_its_eight_neighbours() -> None:
    copies = K.seek_copies(np.array([[4, 7]]))
    assert copies.shape == (1, 9, 2)
    assert copies[0, K.STAY].tolist() == [4, 7]
    assert sorted(map(tuple, (copies[0, 1:] - [4, 7]).tolist())) == sorted(
        (dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1) if (dx, dy) != (0, 0))


def test_move_table_deletes_copies_on_obstacles_outside_and_across_corners() -> None:
    blocked = np.zeros((3, 3), bool)
    blocked[1, 2] = True  # cell (2, 1)
    moves = K.move_table(blocked)
    k = {tuple(o): i for i, o in enumerate(K.OFFSETS.tolist())}
    at = moves[1, 1]  # from the centre cell (1, 1)
    assert not at[k[(1, 0)]]        # onto the blocked cell
    assert not at[k[(1, 1)]]        # diagonal past it (corner cutting)
    assert not at[k[(1, -1)]]
    assert at[k[(-1, 1)]] and at[k[(0, 1)]] and at[k[(0, 0)]]
    assert not moves[0, 0][k[(-1, -1)]]  # off the grid
    assert not moves[1, 2].any()         # nothing from inside a blocked cell


def test_fitness_eq12_reads_each_robots_goal_field() -> None:
    fields = np.arange(2 * 3 * 4, dtype=float).reshape(2, 3, 4)
    copies = np.array([[[0, 0], [3, 2]], [[1, 1], [2, 0]]])
    out = K.fitness_eq12(fields, np.array([0, 1]), copies)
    assert out.tolist() == [[0.0, 11.0], [17.0, 14.0]]


def test_tie_break_eq13_is_the_straight_distance_to_the_goal() -> None:
    pts = np.array([[[0.0, 0.0], [3.0, 4.0]]])
    assert K.tie_break_eq13(pts, np.array([[0.0, 0.0]])).tolist() == [[0.0, 5.0]]


def test_rank_copies_orders_by_safety_then_fitness_then_eq13_and_puts_deleted_last() -> None:
    fitness = np.array([[3.0, 2.0, 2.0, 1.0]])
    tie = np.array([[0.0, 5.0, 4.0, 0.0]])
    valid = np.array([[True, True, True, False]])
    assert K.rank_copies(fitness, tie, valid).tolist() == [[2, 1, 0, 3]]
    safety = np.array([[2, 1, 1, 2]])
    assert K.rank_copies(fitness, tie, valid, safety=safety).tolist() == [[0, 2, 1, 3]]


def test_descent_step_follows_the_distance_field() -> None:
    fit = np.full((2, 9), 10.0)
    fit[0, K.STAY] = 5.0
    fit[0, 1] = 4.0          # east: 1 + 4 = 5 = here, on a shortest path
    fit[0, 2] = 5.0 - S2     # north-east: also shortest; eq. 13 decides
    fit[1, K.STAY] = 0.0     # robot 1 is at its goal
    ok = np.ones((2, 9), bool)
    tie = np.zeros((2, 9))
    tie[0, 1] = 1.0
    assert K.descent_step(fit, ok, tie).tolist() == [2, K.STAY]
    ok[0, 2] = False
    assert K.descent_step(fit, ok, tie).tolist() == [1, K.STAY]


# ---------------------------------------------------------------------------- look-ahead kernels
def test_escape_cells_need_an_allowed_move_to_a_safe_cell() -> None:
    blocked = np.zeros((3, 5), bool)
    unsafe = np.zeros((3, 5), bool)
    unsafe[:, :3] = True  # columns 0-2 unsafe
    out = H.escape_cells(unsafe, K.move_table(blocked))
    assert out[:, 2].all() and not out[:, 1].any() and out[:, 3:].all()
    blocked[:, 3] = True  # a wall: column 2 can no longer get out
    out = H.escape_cells(unsafe, K.move_table(blocked))
    assert not out[:, 2].any()


def test_safe_tier_and_stay_depth_by_backward_induction() -> None:
    moves = K.move_table(np.zeros((1, 5), bool))
    d1 = np.array([[1, 0, 0, 0, 0]], bool)
    d2 = np.array([[1, 1, 0, 0, 0]], bool)
    d3 = np.array([[1, 1, 1, 0, 0]], bool)
    covered = [d1, d2, d3]
    assert H.safe_tier(covered, moves, 1)[0][0].tolist() == [False, True, True, True, True]
    # cell 1 is free next step and can reach cell 2 ... which is hit at step 3 unless left again
    tier, then = H.safe_tier(covered, moves, 3)
    assert tier[0].tolist() == [False, True, True, True, True]
    assert then[0].tolist() == [False, False, True, True, True]
    assert H.stay_depth(covered)[0].tolist() == [0, 1, 2, 3, 3]
    walled = K.move_table(np.array([[False, False, True, False, False]]))
    assert H.safe_tier(covered, walled, 3)[0][0].tolist() == [False, False, False, True, True]


def test_warning_levels_decay_with_time_and_reach_one_cell_around() -> None:
    d1 = np.zeros((1, 7), bool)
    d1[0, 0] = True
    d2 = np.zeros((1, 7), bool)
    d2[0, 3] = True
    cells = np.array([[x, 0] for x in range(7)])
    assert H.warning_levels([d1, d2], cells, 0.5).tolist() == [1.0, 1.0, 0.5, 0.5, 0.5, 0.0, 0.0]


# ---------------------------------------------------------------------------- obstacle forecast
def open_world(moving, size=10, blocked=None) -> World:
    sm = StaticMap(np.zeros((size, size), bool) if blocked is None else blocked, 1.0)
    return World(RectBounds(size, size), static_map=sm, moving_obstacles=tuple(moving),
                 robots=(Robot("a", (0.5, 0.5), (0.5, 1.5), 0.0, S2),), name="f")


def box(at, v, motion) -> MovingObstacle:
    return MovingObstacle("m", Rect((-0.5, -0.5), (0.5, 0.5)), at, v, motion)


def test_box_cell_ranges_cover_overlapped_cells_only() -> None:
    r = box_cell_ranges(np.array([[2.0, 3.0]]), np.array([[3.0, 4.0]]), 1.0)
    assert r.tolist() == [[2, 3, 3, 4]]  # exactly cell (2, 3); touching neighbours excluded
    r = box_cell_ranges(np.array([[2.2, 3.0]]), np.array([[3.2, 4.0]]), 1.0, margin=1)
    assert r.tolist() == [[1, 2, 5, 5]]
    grid = paint((5, 6), r)
    assert grid.sum() == 4 * 3 and grid[2:5, 1:5].all()


def test_forecast_predicts_straight_moves_and_bounces() -> None:
    world = open_world([box((4.5, 4.5), (1.0, 0.0), Bounce8())])
    fc = ObstacleForecast(world, world.grid())
    cand, possible, extra = fc.next_positions(np.array([[4.5, 4.5]]), np.array([[3.5, 4.5]]))
    assert cand[0][possible[0]].tolist() == [[5.5, 4.5]] and extra[0] == 0
    danger = fc.danger(np.array([[4.5, 4.5]]), np.array([[3.5, 4.5]]))
    assert np.argwhere(danger).tolist() == [[4, 4], [4, 5]]  # now and next cell
    # against the east wall it may turn anywhere free (and the pull-back to the west too)
    cand, possible, _ = fc.next_positions(np.array([[9.5, 4.5]]), np.array([[8.5, 4.5]]))
    options = {tuple(np.round(p, 3)) for p in cand[0][possible[0]]}
    assert (9.5, 4.5) in options and (8.5, 4.5) in options and len(options) == 6


def test_forecast_of_a_random_walker_covers_its_neighbourhood() -> None:
    world = open_world([box((4.5, 4.5), (1.0, 0.0), RandomWalk())])
    fc = ObstacleForecast(world, world.grid())
    danger = fc.danger(np.array([[4.5, 4.5]]), np.array([[3.5, 4.5]]))
    assert danger.sum() == 9 and danger[3:6, 3:6].all()
    later = fc.coverage(np.array([[4.5, 4.5]]), np.array([[3.5, 4.5]]), 3)
    assert [int(c.sum()) for c in later] == [9, 25, 49]


def test_forecast_fits_matches_the_world_exactly() -> None:
    blocked = np.zeros((10, 10), bool)
    blocked[5, 5] = True
    world = open_world([box((2.5, 2.5), (1.0, 0.0), Bounce())], blocked=blocked)
    fc = ObstacleForecast(world, world.grid())
    rng = np.random.default_rng(0)
    pts = rng.uniform(-0.5, 10.5, size=(400, 2))
    assert np.array_equal(fc.fits(np.zeros(400, np.int64), pts), world.obstacle_fits(world.moving_obstacles[0], pts))


# ---------------------------------------------------------------------------- cell paths
def test_polyline_cells_are_8_connected_without_staircases_or_loops() -> None:
    blocked = np.zeros((6, 6), bool)
    cells = polyline_cells(np.array([[0.5, 0.5], [4.5, 4.5]]), 1.0)
    assert np.max(np.abs(np.diff(cells, axis=0))) == 1
    tidy = tidy_cells(cells, blocked)
    assert tidy.tolist() == [[i, i] for i in range(5)]
    loop = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [1, 0], [1, 1]])
    assert tidy_cells(loop, blocked).tolist() == [[0, 0], [1, 1]]


def test_repair_replaces_blocked_stretches_with_a_star() -> None:
    blocked = np.zeros((5, 5), bool)
    blocked[2, 1:4] = True  # a wall across row 2, open at x = 0 and x = 4
    straight = np.array([[2, 0], [2, 1], [2, 2], [2, 3], [2, 4]])
    fixed = repair_cells(straight, blocked)
    assert fixed is not None and fixed[0].tolist() == [2, 0] and fixed[-1].tolist() == [2, 4]
    assert not blocked[fixed[:, 1], fixed[:, 0]].any()
    assert np.max(np.abs(np.diff(fixed, axis=0))) == 1
    assert plan_cells(np.array([[2.5, 0.5], [2.5, 4.5]]), 1.0, blocked) is not None
    assert remaining_lengths(np.array([[0, 0], [1, 1], [2, 1]])).tolist() == pytest.approx([1 + S2, 1.0, 0.0])


# ---------------------------------------------------------------------------- the controller
def test_cat_swarm_conforms_when_it_follows_an_offline_plan() -> None:
    """(Without a plan it is swept in tests/test_conformance.py.)"""
    assert check_controller(CatSwarmController, planner="astar") == []


@pytest.mark.parametrize("kw", [{"mixture_ratio": 1.5}, {"seeking_range": 2}, {"obstacle_alert": "near"},
                                {"lookahead": 0}, {"leave_early": 9}, {"patience": 0}, {"margin": -1}])
def test_bad_parameters_are_reported(kw) -> None:
    world = open_world([])
    with pytest.raises(ConfigError):
        CatSwarmController(**kw).reset(world, None, np.random.default_rng(0))


def test_robots_too_slow_for_one_cell_a_step_are_reported() -> None:
    world = World(RectBounds(5, 5), robots=(Robot("a", (0.5, 0.5), (4.5, 0.5), 0.0, 0.5),), name="slow")
    with pytest.raises(ConfigError, match="max_speed"):
        CatSwarmController().reset(world, None, np.random.default_rng(0))


def test_disc_robots_wider_than_a_cell_are_refused_and_small_discs_never_touch() -> None:
    big = World(RectBounds(6, 6), robots=(Robot("a", (1.0, 1.0), (4.0, 4.0), 0.6, S2),), name="disc")
    with pytest.raises(ConfigError, match="radius"):
        CatSwarmController().reset(big, None, np.random.default_rng(0))
    robots = tuple(Robot(r.id, r.start, r.goal, 0.5, S2) for r in crossing_world().robots)
    world = World(RectBounds(7, 7), robots=robots, name="discs")
    for seed in range(3):
        traj = Simulator(world, CatSwarmController(), None, seed=seed, max_steps=150).run()
        assert validate_trajectory(world, traj) == []  # half-cell discs: held back, never touching


def crossing_world() -> World:
    """Eight robots crossing a 7x7 room through its centre: everyone meets everyone."""
    robots = []
    for k, (a, b) in enumerate([((0, 3), (6, 3)), ((6, 3), (0, 3)), ((3, 0), (3, 6)), ((3, 6), (3, 0)),
                                ((0, 0), (6, 6)), ((6, 6), (0, 0)), ((0, 6), (6, 0)), ((6, 0), (0, 6))]):
        robots.append(Robot(f"r{k}", (a[0] + 0.5, a[1] + 0.5), (b[0] + 0.5, b[1] + 0.5), 0.0, S2))
    return World(RectBounds(7, 7), robots=tuple(robots), name="crossing7")


def test_a_crowded_crossing_is_collision_free_and_everyone_arrives() -> None:
    world = crossing_world()
    for seed in range(3):
        traj = Simulator(world, CatSwarmController(), plan(world, "astar"), seed=seed, max_steps=200).run()
        assert validate_trajectory(world, traj) == []
        assert traj.status == "all_reached"
        assert "seek" in traj.mode_names


def test_follow_would_collide_in_the_same_crossing() -> None:
    from swarmpath.control.follow import FollowController

    world = crossing_world()
    traj = Simulator(world, FollowController(), plan(world, "astar"), seed=0, max_steps=200).run()
    assert len(traj.contacts) > 0  # the scenario really needs avoidance


def test_a_robot_steps_out_of_an_oncoming_obstacles_way() -> None:
    # a 1-cell block runs along row 2 toward a robot parked on its goal in that row
    # (robot b keeps the run going while the block comes)
    world = World(RectBounds(12, 5), robots=(Robot("a", (9.5, 2.5), (9.5, 2.5), 0.0, S2),
                                             Robot("b", (0.5, 0.5), (11.5, 0.5), 0.0, S2)),
                  moving_obstacles=(box((1.5, 2.5), (1.0, 0.0), Bounce()),), name="oncoming")
    traj = Simulator(world, CatSwarmController(), None, seed=0, max_steps=30).run()
    assert validate_trajectory(world, traj) == []
    rows = np.floor(traj.positions[:, 0, 1]).astype(int)
    assert (rows != 2).any()  # it left the row ...
    assert traj.modes is not None and {"evade", "escape"} & set(traj.mode_names)


def test_arrival_uses_the_exact_goal_and_start_off_cell_centres() -> None:
    world = World(RectBounds(6, 6), robots=(Robot("a", (1.0, 1.0), (4.0, 4.0), 0.0, S2),
                                            Robot("b", (4.0, 1.0), (1.0, 4.0), 0.0, S2)), name="corners")
    traj = Simulator(world, CatSwarmController(), plan(world, "astar"), seed=0).run()
    assert validate_trajectory(world, traj) == []
    assert traj.status == "all_reached"
    assert np.allclose(traj.positions[-1], world.goals)


# ---------------------------------------------------------------------------- the ranking handed to the core
def test_dense_ranks_share_equal_keys_and_leave_deleted_copies_out() -> None:
    from swarmpath.control.cat_swarm.ranking import NOT_ALLOWED, dense_ranks

    k0 = np.array([[0, 1, 1, 0, 2, 1, 1, 1, 1]], float)
    k1 = np.array([[5, 1, 1, 5, 0, 2, 2, 0, 3]], float)
    valid = np.array([[True, True, True, True, True, True, True, False, True]])
    ranks = dense_ranks([k0, k1], valid)
    assert ranks.tolist() == [[0, 1, 1, 0, 4, 2, 2, NOT_ALLOWED, 3]]


def test_swarm_keys_give_each_kind_of_robot_its_ranking() -> None:
    from swarmpath.control.cat_swarm.ranking import dense_ranks, swarm_keys

    # four robots, the same fitness: copy 3 (N) is the shortest way, copy 1 (E) next
    fitness = np.tile(np.array([5.0, 4.0, 4.6, 3.6, 4.6, 6.0, 6.4, 6.0, 5.4]), (4, 1))
    score = fitness.copy()
    score[:, 3] += 2.0           # an obstacle's warning on N: the swarm prefers E
    tie = np.zeros((4, 9))
    path_next = np.array([7, 7, 7, 7])      # the path goes S
    follow = np.array([True, False, False, False])
    path_ok = np.ones(4, bool)
    stay_first = np.array([False, False, True, False])
    first = np.array([False, False, False, True])
    valid = np.ones((4, 9), bool)
    ranks = dense_ranks(swarm_keys(fitness, score, tie, None, path_next, follow, path_ok, stay_first, first), valid)
    best = np.argmin(ranks, axis=1)
    assert best.tolist() == [7, 1, 0, 3]            # follow: its path; seek: eq. 12 + warning; parked; distance first
    assert ranks[0, 0] == 1                          # a follower waits when its path cell is taken
    assert ranks[1, 3] > ranks[1, 1]                 # the warning demotes N for the seeker ...
    assert ranks[3, 3] < ranks[3, 1]                 # ... not for the robot that must progress
    safety = np.zeros((4, 9), int)
    safety[:, 8] = 2                                 # SE stays clear of obstacles longest
    ranks = dense_ranks(swarm_keys(fitness, score, tie, safety, path_next, follow, path_ok, stay_first, first), valid)
    assert np.argmin(ranks, axis=1).tolist() == [7, 8, 0, 3]


@pytest.mark.parametrize("seed", range(3))
def test_the_highest_priority_robot_progresses_whatever_the_swarm_prefers(seed) -> None:
    """Reachability (PIBT's Theorem 1) through the cat swarm's ranking: the robot of highest
    priority ranks by exact distance first, every other robot by the swarm's rules (random
    paths, modes and warnings here); without the swap emulation, on a crowded open grid, the
    top robot gets a best cell every step and walks a shortest path to its goal."""
    from swarmpath.control.cat_swarm.ranking import dense_ranks, swarm_keys
    from swarmpath.control.pibt.core import GridGraph, decision_order, pibt_step, static_moves
    from swarmpath.search.lazy_distance import LazyDistanceTables

    rng = np.random.default_rng(seed)
    blocked = np.zeros((8, 8), bool)
    graph = GridGraph.build(blocked, 8, 0.0, 1.0)
    moves_all = static_moves(blocked, 8)
    free = np.argwhere(~blocked)[:, ::-1]
    for _ in range(8):
        n = int(rng.integers(20, 50))
        cells = free[rng.choice(64, n, replace=False)]
        goals = free[rng.choice(64, n, replace=False)]
        tables = LazyDistanceTables(blocked)
        handles = tables.acquire_many(goals)
        start = tables.distance(handles[0], cells[0])
        steps = 0
        while np.any(cells[0] != goals[0]):
            fitness = np.nan_to_num(tables.neighbour_costs(handles, cells), nan=np.inf)
            valid = moves_all[cells[:, 1], cells[:, 0]]
            first = np.zeros(n, bool)
            first[0] = True
            keys = swarm_keys(fitness, fitness + 3 * rng.random((n, 9)), rng.random((n, 9)), None,
                              rng.integers(0, 9, n), rng.random(n) < 0.6, rng.random(n) < 0.8, rng.random(n) < 0.2,
                              first)
            flat = (cells[:, 1] * 8 + cells[:, 0]).astype(np.int32)
            res = pibt_step(graph, flat, dense_ranks(keys, valid), valid, rng.random((n, 9)),
                            decision_order(np.r_[1e9, rng.random(n - 1)]),
                            goals=(goals[:, 1] * 8 + goals[:, 0]).astype(np.int32), slots=handles, tables=tables._c,
                            swap=False, yield_way=True)
            assert fitness[0, res.moves[0]] == np.min(fitness[0][valid[0]])
            cells = cells + K.OFFSETS[res.moves.astype(int)]
            steps += 1
            assert steps <= 12
        assert steps <= start + 1e-9   # one step per cell of (octile) distance at most
        assert len({tuple(c) for c in cells.tolist()}) == n


# ---------------------------------------------------------------------------- scale, the corner goal, a crowd
def test_distances_come_from_lazy_tables_that_grow_with_what_the_robots_need() -> None:
    """One robot on a 1500 x 1500 open map: no distance field, no whole-grid table per step;
    the goal's table holds a small part of the map."""
    n = 1500
    world = World(RectBounds(n, n), static_map=StaticMap(np.zeros((n, n), bool), 1.0),
                  robots=(Robot("a", (0.5, 0.5), (n - 20.5, n - 30.5), 0.0, S2),), name="big")
    ctl = CatSwarmController()
    traj = Simulator(world, ctl, None, seed=0, max_steps=20).run()
    assert traj.n_steps == 20 and validate_trajectory(world, traj) == []
    assert ctl.cells_.fields is None and ctl.tables_.live == 1
    assert ctl.tables_.memory_bytes() < 0.1 * n * n * 8   # under a tenth of one distance field


def test_a_goal_on_the_workspace_corner_is_reached_through_its_cell_centre() -> None:
    world = World(RectBounds(10, 10), robots=(Robot("a", (0.5, 0.5), (10.0, 10.0), 0.0, S2),
                                              Robot("b", (9.5, 0.5), (0.0, 10.0), 0.0, S2)), name="corner")
    traj = Simulator(world, CatSwarmController(), None, seed=0, max_steps=60).run()
    assert validate_trajectory(world, traj) == []
    assert traj.status == "all_reached"
    first = int(np.flatnonzero(np.all(traj.positions[:, 0] == (10.0, 10.0), axis=1))[0])
    assert np.allclose(traj.positions[first - 1, 0], (9.5, 9.5))   # the cell's centre, then the corner


def test_the_crossing_example_gets_every_robot_home() -> None:
    """examples/crossing.yaml: six robots swap sides of a room through two doors while two carts
    patrol (the old cat swarm got 1 of 6 home)."""
    from pathlib import Path

    from swarmpath.world import load_scenario

    world = load_scenario(Path(__file__).parents[2] / "examples" / "crossing.yaml")
    for seed in range(3):
        traj = Simulator(world, CatSwarmController(), None, seed=seed).run()
        assert validate_trajectory(world, traj) == []
        assert traj.status == "all_reached" and not traj.contacts, seed
