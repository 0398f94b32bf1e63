"""The lacam planner and the timed-plan validator: every plan checked independently
(validate_timed_plan) and executed by the follow controller through the simulator."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.data.movingai import MOVINGAI
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan, PlanStatus, RobotPlan
from swarmpath.planning.lacam import LaCAMPlanner
from swarmpath.planning.lacam.planner import arrival_step
from swarmpath.registry import CONTROLLERS
from swarmpath.sim.simulator import Simulator
from swarmpath.testing import conformance_worlds, unreachable_world, validate_trajectory
from swarmpath.testing.timed_plans import validate_timed_plan
from swarmpath.world import Circle, RectBounds, Robot, World, world_from_movingai
from swarmpath.world.static_map import StaticMap

DATA = MOVINGAI
S2 = float(np.sqrt(2))


def movingai(name: str, scen: str, n: int) -> World:
    return world_from_movingai(DATA / f"{name}.map", DATA / f"{scen}.scen", n)


def follow(world: World, plan: Plan, seed: int = 0):
    return Simulator(world, CONTROLLERS.get("follow")(), plan, seed=seed).run()


def check_plan(world: World, plan: Plan) -> None:
    assert bool(plan), [r.diagnostics for r in plan.robots[:1]]
    assert validate_timed_plan(world, plan) == []
    lengths = {len(r.path) for r in plan.robots}
    assert len(lengths) == 1
    for r, robot in zip(plan.robots, world.robots):
        assert r.status is PlanStatus.EXACT
        assert np.array_equal(r.times, np.arange(len(r.path)))
        assert np.allclose(r.path[0], robot.start) and np.allclose(r.path[-1], robot.goal)


@pytest.mark.parametrize("name,scen,n", [("random-32-32-10", "random-32-32-10-random-1", 150),
                                         ("room-32-32-4", "room-32-32-4-even-10", 100),
                                         ("maze-32-32-2", "maze-32-32-2-even-10", 100),
                                         ("den312d", "den312d-even-10", 120),
                                         ("empty-8-8", "empty-8-8-even-10", 32)])
@pytest.mark.parametrize("connectivity", [4, 8])
def test_plans_are_valid_and_follow_executes_them_without_contacts(name, scen, n, connectivity):
    world = movingai(name, scen, n)
    plan = LaCAMPlanner(connectivity=connectivity).plan(world, rng=0)
    check_plan(world, plan)
    traj = follow(world, plan)
    assert traj.status.value == "all_reached"
    assert validate_trajectory(world, traj) == []
    assert len(traj.positions) == len(plan.robots[0].path)


def swap_corridor() -> World:
    """A 1-wide corridor with one side pocket: two robots must exchange ends (PIBT alone
    pushes them back and forth; the search finds the pocket manoeuvre)."""
    blocked = np.ones((3, 9), bool)
    blocked[1, :] = False
    blocked[0, 4] = False
    robots = (Robot("a", (0.5, 1.5), (8.5, 1.5), 0.0, S2), Robot("b", (8.5, 1.5), (0.5, 1.5), 0.0, S2),
              Robot("c", (2.5, 1.5), (6.5, 1.5), 0.0, S2))
    return World(RectBounds(9, 3), static_map=StaticMap(blocked), robots=robots, name="swap-corridor")


@pytest.mark.parametrize("swap", [True, False])
def test_robots_pass_each_other_through_a_pocket(swap):
    world = swap_corridor()
    plan = LaCAMPlanner(swap=swap).plan(world, rng=1)
    check_plan(world, plan)
    assert validate_trajectory(world, follow(world, plan)) == []


def test_same_seed_same_plan():
    world = movingai("maze-32-32-2", "maze-32-32-2-even-10", 80)
    a, b = (LaCAMPlanner().plan(world, rng=5) for _ in range(2))
    assert all(np.array_equal(p, q) for p, q in zip(a.paths, b.paths))
    hard = swap_corridor()
    c, d = LaCAMPlanner().plan(hard, rng=2), LaCAMPlanner().plan(hard, rng=2)
    assert all(np.array_equal(p, q) for p, q in zip(c.paths, d.paths))


def test_budget_exhausted_means_timeout_for_everyone():
    world = swap_corridor()
    plan = LaCAMPlanner(node_limit=2).plan(world, rng=0)
    assert not plan
    assert all(r.status is PlanStatus.TIMEOUT and r.path is None for r in plan.robots)
    assert "node limit" in plan.diagnostics["reason"]
    assert plan.diagnostics["nodes"] <= 2


def test_unreachable_and_invalid_robots_are_reported_not_planned():
    plan = LaCAMPlanner().plan(unreachable_world(), rng=0)
    assert plan.robots[0].status is PlanStatus.INFEASIBLE and plan.robots[0].path is None
    blocked = np.zeros((6, 6), bool)
    blocked[:, 3] = True
    robots = (Robot("a", (0.5, 0.5), (5.5, 5.5), 0.0, S2), Robot("b", (1.5, 0.5), (2.5, 4.5), 0.0, S2))
    world = World(RectBounds(6, 6), static_map=StaticMap(blocked), robots=robots)
    plan = LaCAMPlanner().plan(world, rng=0)
    assert [r.status for r in plan.robots] == [PlanStatus.INFEASIBLE, PlanStatus.INFEASIBLE]
    assert "cut off" in plan.robots[0].diagnostics["reason"]
    assert "no joint plan" in plan.robots[1].diagnostics["reason"]
    # a goal on a cell the grid blocks for the robot's radius (the circle covers the cell)
    world = World(RectBounds(8, 8), obstacles=(Circle((4.0, 4.0), 0.9),),
                  robots=(Robot("a", (0.5, 0.5), (4.5, 4.5 + 0.95), 0.0, S2),
                          Robot("b", (3.0, 3.0), (7.5, 7.5), 0.0, S2)))
    plan = LaCAMPlanner().plan(world, rng=0)
    assert plan.robots[0].status in (PlanStatus.INVALID_GOAL, PlanStatus.INFEASIBLE)
    assert plan.robots[1].status in (PlanStatus.INVALID_START, PlanStatus.INFEASIBLE)


def test_continuous_worlds_plan_on_the_occupancy_grid():
    for world in conformance_worlds()[:2]:
        plan = LaCAMPlanner().plan(world, rng=0)
        check_plan(world, plan)
        assert validate_trajectory(world, follow(world, plan)) == []


def test_off_centre_starts_and_goals_get_a_first_and_a_last_step():
    robots = (Robot("a", (0.2, 0.3), (5.9, 0.1), 0.0, S2), Robot("b", (5.5, 0.5), (1.0, 1.0), 0.0, S2),
              Robot("c", (3.5, 2.5), (3.5, 0.5), 0.0, S2))
    world = World(RectBounds(6, 3), robots=robots)
    plan = LaCAMPlanner().plan(world, rng=0)
    check_plan(world, plan)
    assert np.allclose(plan.robots[0].path[1], (0.5, 0.5))
    assert validate_trajectory(world, follow(world, plan)) == []


def test_disc_robots_plan_with_the_checkers_rule():
    from scipy import ndimage

    rng = np.random.default_rng(2)
    blocked = rng.random((12, 12)) < 0.1
    labels, _ = ndimage.label(~blocked)
    comp = np.argwhere(labels == np.bincount(labels.ravel())[1:].argmax() + 1)[:, ::-1]
    pick = rng.choice(len(comp), 24, replace=False)
    robots = tuple(Robot(f"r{i}", tuple(comp[pick[i]] + 0.5), tuple(comp[pick[12 + i]] + 0.5), 0.5, S2)
                   for i in range(12))
    world = World(RectBounds(12, 12), static_map=StaticMap(blocked), robots=robots)
    plan = LaCAMPlanner(connectivity=4).plan(world, rng=0)
    check_plan(world, plan)
    assert validate_trajectory(world, follow(world, plan)) == []


def test_bad_parameters_raise_config_errors():
    world = swap_corridor()
    for kwargs, word in (({"connectivity": 3}, "connectivity"), ({"time_limit": 0}, "time_limit"),
                         ({"node_limit": 0}, "node_limit"), ({"restart": -0.1}, "restart"),
                         ({"restart": float("nan")}, "restart"), ({"restart": True}, "restart")):
        with pytest.raises(ConfigError, match=word):
            LaCAMPlanner(**kwargs).plan(world, rng=0)


def test_arrival_step_counts_until_the_goal_is_held():
    path = np.array([[0, 0], [1, 0], [2, 0], [1, 0], [2, 0], [2, 0]], float)
    assert arrival_step(path, (2, 0)) == 4
    assert arrival_step(path[:1], (0, 0)) == 0


@pytest.mark.slow
def test_statistics_over_seeds_on_crowded_maps():
    """Every seed solves; sum of costs stays within 3x the sum of individual shortest paths
    (LaCAM's first solution is not optimised; the 2-wide maze is the worst, about 2.5x)."""
    from swarmpath.search.lazy_distance import LazyDistanceTables

    for name, scen, n in [("random-32-32-10", "random-32-32-10-random-1", 300), ("room-32-32-4", "room-32-32-4-even-10", 130),
                          ("maze-32-32-2", "maze-32-32-2-even-10", 200)]:
        world = movingai(name, scen, n)
        grid = world.grid()
        tables = LazyDistanceTables(grid.blocked, connectivity=4)
        lb = 0.0
        for r in world.robots:
            lb += tables.distance(tables.acquire(grid.cell_of(r.goal)), grid.cell_of(r.start))
        for seed in range(4):
            plan = LaCAMPlanner(connectivity=4).plan(world, rng=seed)
            check_plan(world, plan)
            assert plan.diagnostics["sum_of_costs"] <= 3 * lb, (name, seed)


def crowded_room(n: int, seed: int = 0) -> World:
    """room-32-32-4 with ``n`` robots on distinct random cells of its free component (the
    shipped scen has 130 rows)."""
    from scipy import ndimage

    base = movingai("room-32-32-4", "room-32-32-4-even-10", 1)
    blocked = base.static_map.blocked
    labels, _ = ndimage.label(~blocked)
    free = np.argwhere(labels == np.bincount(labels.ravel())[1:].argmax() + 1)[:, ::-1] + 0.5
    rng = np.random.default_rng(seed)
    s, g = (free[rng.choice(len(free), n, replace=False)] for _ in range(2))
    robots = tuple(Robot(f"r{i}", tuple(a), tuple(b), 0.0, S2) for i, (a, b) in enumerate(zip(s, g)))
    return World(base.bounds, static_map=base.static_map, robots=robots, name="crowded-room")


@pytest.mark.slow
def test_random_restarts_get_a_crowded_room_planned():
    """400 robots in room-32-32-4 (8-connected): with restarts every seed plans within 20,000
    configurations and the plan checks; without them the depth-first search gets lost on some
    seeds (the contrast shows the test tells the two apart)."""
    world = crowded_room(400)
    lost = 0
    for seed in range(6):
        plan = LaCAMPlanner(node_limit=20_000, time_limit=120.0).plan(world, rng=seed)
        check_plan(world, plan)
        lost += not LaCAMPlanner(node_limit=20_000, time_limit=120.0, restart=0).plan(world, rng=seed)
    assert lost >= 1


# ---------------------------------------------------------------------------- the validator
def timed(world: World, paths) -> Plan:
    robots = tuple(RobotPlan(r.id, PlanStatus.EXACT, np.asarray(p, float), {}, np.arange(len(p)))
                   for r, p in zip(world.robots, paths))
    return Plan("hand", robots, 0.0)


def test_validator_finds_each_kind_of_violation():
    blocked = np.zeros((4, 4), bool)
    blocked[1, 1] = True
    robots = (Robot("a", (0.5, 0.5), (2.5, 0.5), 0.0, S2), Robot("b", (2.5, 0.5), (0.5, 0.5), 0.0, S2))
    world = World(RectBounds(4, 4), static_map=StaticMap(blocked), robots=robots)
    good = timed(world, [[(0.5, 0.5), (1.5, 0.5), (2.5, 0.5)], [(2.5, 0.5), (3.5, 0.5), (3.5, 1.5)]])
    bad_goal = validate_timed_plan(world, good)
    assert [v.robot for v in bad_goal] == [1]      # b ends on (3.5, 1.5), not its goal
    assert "not the goal" in bad_goal[0].problem
    swap = timed(world, [[(0.5, 0.5), (1.5, 0.5), (2.5, 0.5)], [(2.5, 0.5), (1.5, 0.5), (0.5, 0.5)]])
    found = " ".join(v.problem for v in validate_timed_plan(world, swap))
    assert "vertex" in found
    corner = timed(world, [[(0.5, 0.5), (0.5, 0.5), (1.5, 0.5), (2.5, 0.5)],
                           [(2.5, 0.5), (2.5, 1.5), (2.5, 2.5), (1.5, 2.5), (0.5, 1.5), (0.5, 0.5)]])
    msgs = validate_timed_plan(world, corner)
    assert any("static" in v.problem for v in msgs)   # (1.5, 2.5) -> (0.5, 1.5) cuts (1, 1)'s corner
    jump = timed(world, [[(0.5, 0.5), (2.5, 0.5)], [(2.5, 0.5), (2.5, 2.5), (0.5, 2.5), (0.5, 0.5)]])
    assert any("moves" in v.problem for v in validate_timed_plan(world, jump))
    untimed = Plan("hand", tuple(RobotPlan(r.id, PlanStatus.EXACT, np.asarray([r.start, r.goal]))
                                 for r in world.robots), 0.0)
    assert all("not timed" in v.problem for v in validate_timed_plan(world, untimed))
    none = Plan("hand", tuple(RobotPlan(r.id, PlanStatus.TIMEOUT) for r in world.robots), 0.0)
    assert len(validate_timed_plan(world, none)) == 2 and validate_timed_plan(world, none, require_all=False) == []


def test_validator_accepts_a_crossing_free_plan_and_rejects_a_diagonal_crossing():
    world = World(RectBounds(2, 2), robots=(Robot("a", (0.5, 0.5), (1.5, 1.5), 0.0, S2),
                                            Robot("b", (1.5, 0.5), (0.5, 1.5), 0.0, S2)))
    cross = timed(world, [[(0.5, 0.5), (1.5, 1.5)], [(1.5, 0.5), (0.5, 1.5)]])
    assert any("crossing" in v.problem for v in validate_timed_plan(world, cross))
    wait = timed(world, [[(0.5, 0.5), (1.5, 1.5), (1.5, 1.5)], [(1.5, 0.5), (1.5, 0.5), (0.5, 1.5)]])
    assert validate_timed_plan(world, wait) == []
