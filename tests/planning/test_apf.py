"""The plain ``apf`` planner: steepest descent, local-minimum detection and reporting."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.planning import PlanStatus
from swarmpath.planning.apf import APFPlanner, steepest_descent
from swarmpath.planning.potential_field import potential_field
from swarmpath.registry import PLANNERS
from swarmpath.testing import validate_paths
from swarmpath.world import Circle, CircleBounds, Rect, RectBounds, Robot, World, load_scenario

TRAPS = ["apf-trap-gap", "apf-trap-goal-near-obstacle", "apf-trap-aligned", "apf-trap-u-shape"]


def assert_grid_moves(world, robot, path):
    """Consecutive APF points are centres of 8-adjacent free cells, with no corner cutting
    (the exact start and goal aside)."""
    grid = world.grid(radius=robot.radius)
    cells = grid.cell_of(path[1:-1])
    assert np.allclose(grid.centers(cells), path[1:-1])
    steps = np.diff(cells, axis=0)
    assert np.abs(steps).max(initial=0) <= 1
    for c, s in zip(cells[:-1], steps):
        if s[0] and s[1]:
            assert grid.is_free(c + [s[0], 0]) and grid.is_free(c + [0, s[1]]), f"corner cut at {c} -> {c + s}"


def descended(r):
    """The polyline a robot plan descended: the path, or the partial path plus a placeholder
    for the (missing) exact goal."""
    return r.path if r else np.vstack([r.diagnostics["partial_path"], [np.nan, np.nan]])


def test_registered():
    assert PLANNERS.get("apf") is APFPlanner


def test_open_space_reaches_the_goal_exactly():
    robot = Robot("a", (2.2, 3.1), (17.6, 12.9))
    w = World(RectBounds(20, 16), obstacles=(Circle((10, 8), 1.5),), robots=(robot,), resolution=0.25)
    plan = APFPlanner().plan(w)
    r = plan.robots[0]
    assert r and r.status is PlanStatus.EXACT
    assert r.diagnostics["stop_reason"] == "goal" and not r.diagnostics["local_minimum"]
    assert validate_paths(w, plan.paths) == []
    assert_grid_moves(w, robot, r.path)
    assert plan.diagnostics["local_minima"] == 0


@pytest.mark.parametrize("name", TRAPS)
def test_trap_scenarios_report_a_local_minimum(name):
    w = load_scenario(name)
    plan = APFPlanner().plan(w)
    r = plan.robots[0]
    assert not r and not plan
    assert r.status is PlanStatus.LOCAL_MINIMUM and r.path is None
    d = r.diagnostics
    assert d["local_minimum"] and d["local_minima"] == 1 and d["stop_reason"] == "no_descent"
    assert d["distance_to_goal"] > w.resolution  # not at the goal
    partial = d["partial_path"]
    assert np.array_equal(partial[0], w.robots[0].start) and np.allclose(partial[-1], d["stop_point"])
    assert not w.static_hits(partial[:-1], partial[1:], np.zeros(len(partial) - 1)).any()
    # a true grid minimum: every allowed neighbour of the stop cell is at least as high
    field = potential_field(w, w.robots[0].goal)
    x, y = d["stop_cell"]
    assert np.isfinite(field.total[y, x])
    assert field.total[y, x] <= field.total[y - 1:y + 2, x - 1:x + 2].min() + 1e-12
    assert plan.diagnostics["local_minima"] == 1


def test_goal_near_obstacle_stops_in_front_of_the_goal():
    w = load_scenario("apf-trap-goal-near-obstacle")
    d = APFPlanner().plan(w).robots[0].diagnostics
    # the minimum of U along the approach lies about 0.85 from the obstacle: 0.65-0.7 short of the goal
    assert 0.4 < d["distance_to_goal"] < 1.0


def test_aligned_circle_is_a_saddle_the_grid_descent_leaves():
    # Start, circle and goal aligned on a cell column: the equilibrium in front of a circle is a
    # saddle of U (not a minimum), and the 8-neighbour descent slides off it (documented).
    robot = Robot("a", (5.125, 1.125), (5.125, 7.625))
    w = World(CircleBounds((5, 5), 5), obstacles=(Circle((5.125, 4.625), 1.5),), robots=(robot,),
              resolution=0.25)
    r = APFPlanner().plan(w).robots[0]
    assert r and validate_paths(w, [r.path]) == []


def test_no_corner_cutting_between_diagonal_obstacles():
    # Two blocks touching at a corner; start and goal on either side of the touching point.
    robot = Robot("a", (4.5, 5.5), (5.5, 4.5))
    w = World(RectBounds(10, 10), obstacles=(Rect((4, 4), (5, 5)), Rect((5, 5), (6, 6))), robots=(robot,))
    r = APFPlanner().plan(w).robots[0]
    if r:
        assert validate_paths(w, [r.path]) == []
        assert len(r.path) > 3  # went around
    assert_grid_moves(w, robot, descended(r))


def test_jaleel2016_paths_are_valid_where_they_exist():
    w = load_scenario("jaleel2016")
    plan = APFPlanner().plan(w)
    good = [r.path if r else None for r in plan.robots]
    assert validate_paths(w, good, require_all=False) == []
    for robot, r in zip(w.robots, plan.robots):
        assert_grid_moves(w, robot, descended(r))
    # the layout was designed with traps: several robots meet a local minimum
    assert 3 <= plan.diagnostics["local_minima"] <= 10


def test_step_budget():
    robot = Robot("a", (1.5, 1.5), (18.5, 1.5))
    w = World(RectBounds(20, 4), robots=(robot,))
    r = APFPlanner(max_steps=5).plan(w).robots[0]
    assert not r and r.status is PlanStatus.LOCAL_MINIMUM
    assert r.diagnostics["stop_reason"] == "step_budget" and r.diagnostics["steps"] == 5
    field = potential_field(w, robot.goal)
    assert steepest_descent(field, (1, 1), (18, 1), max_steps=100).reached


def test_start_in_a_blocked_cell_is_reported():
    # The start is free (0.41 from the circle) but its cell (3, 5) overlaps the circle.
    robot = Robot("a", (3.5, 5.0), (8.5, 5.0))
    w = World(RectBounds(10, 10), obstacles=(Circle((2, 5.2), 1.1),), robots=(robot,))
    r = APFPlanner().plan(w).robots[0]
    assert not r and r.status is PlanStatus.INVALID_START


@pytest.mark.parametrize("bad", [dict(attractive_gain=0), dict(influence_range=-1.0), dict(max_steps=0),
                                 dict(max_steps=2.5)])
def test_bad_hyperparameters(bad):
    with pytest.raises(ConfigError):
        APFPlanner(**bad)




def test_same_result_every_time():
    w = load_scenario("jaleel2016")
    a, b = APFPlanner().plan(w, rng=0), APFPlanner().plan(w, rng=1)
    for ra, rb in zip(a.robots, b.robots):
        assert ra.status == rb.status
        assert (ra.path is None and rb.path is None) or np.array_equal(ra.path, rb.path)
