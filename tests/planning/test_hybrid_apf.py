"""The ``hybrid-apf`` planner (Algorithm 1): APF, then A* from the local minimum, B-spline
smoothed; acceptance numbers of issue 3 on the trap scenarios and on jaleel2016."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.planning import PlanStatus
from swarmpath.planning.apf import APFPlanner
from swarmpath.planning.astar import AStarPlanner
from swarmpath.planning.hybrid_apf import HybridAPFPlanner
from swarmpath.registry import PLANNERS
from swarmpath.runner import run_world
from swarmpath.testing import unreachable_world, validate_paths, validate_trajectory
from swarmpath.world import load_scenario

TRAPS = ["apf-trap-gap", "apf-trap-goal-near-obstacle", "apf-trap-aligned", "apf-trap-u-shape"]


def max_step(path):
    return float(np.linalg.norm(np.diff(path, axis=0), axis=1).max())


def test_registered():
    assert PLANNERS.get("hybrid-apf") is HybridAPFPlanner


@pytest.mark.parametrize("name", TRAPS)
def test_trap_scenarios_are_repaired(name):
    w = load_scenario(name)
    apf = APFPlanner().plan(w).robots[0]
    plan = HybridAPFPlanner().plan(w)
    r = plan.robots[0]
    assert not apf and r and plan
    assert r.status is PlanStatus.EXACT
    assert validate_paths(w, plan.paths) == []
    d = r.diagnostics
    assert d["fallback_used"] and d["local_minima"] == 1 and d["expansions"] > 0
    assert d["stop_reason"] == "no_descent"
    # Path = APF part + smoothed A* part, joined at the stop point
    partial = apf.diagnostics["partial_path"]
    assert np.array_equal(r.path[:len(partial)], partial)
    assert np.allclose(d["stop_point"], apf.diagnostics["stop_point"])
    assert max_step(r.path) <= np.sqrt(2) * w.resolution + 1e-9  # a grid controller can follow it
    assert plan.diagnostics == {"local_minima": 1, "fallbacks": 1, "expansions": d["expansions"]}


def test_gap_is_passed_through_after_the_repair():
    # The A* part goes through the gap the field would not let the robot enter.
    w = load_scenario("apf-trap-gap")
    path = HybridAPFPlanner().plan(w).robots[0].path
    at_gap = path[np.abs(path[:, 1] - 5.0) < 0.2]
    assert len(at_gap) and np.all((at_gap[:, 0] > 4.75) & (at_gap[:, 0] < 5.5))


def test_without_smoothing_the_repair_is_the_a_star_cell_path():
    w = load_scenario("apf-trap-u-shape")
    r = HybridAPFPlanner(smooth=False).plan(w).robots[0]
    smooth = HybridAPFPlanner().plan(w).robots[0]
    assert validate_paths(w, [r.path]) == []
    grid = w.grid()
    inner = r.path[1:-1]
    assert np.allclose(grid.centers(grid.cell_of(inner)), inner)  # every vertex a cell centre
    assert smooth.length < r.length


def test_jaleel2016_acceptance(capsys):
    """All 12 robots get valid paths; per robot, hybrid length / optimal length (A* on the same
    grid, octile, world units, as a polyline with the same exact start and goal) is reported;
    the median is at most 1.15."""
    w = load_scenario("jaleel2016")
    hybrid = HybridAPFPlanner().plan(w)
    optimal = AStarPlanner().plan(w)
    assert hybrid and len(hybrid) == 12
    assert validate_paths(w, hybrid.paths) == []
    ratios = np.array([h.length / o.length for h, o in zip(hybrid.robots, optimal.robots)])
    with capsys.disabled():
        print("\nrobot  minimum  hybrid  optimal  ratio")
        for h, o, q in zip(hybrid.robots, optimal.robots, ratios):
            print(f"{h.robot_id:>5}  {str(h.diagnostics['fallback_used']):>7}  {h.length:6.2f}  {o.length:7.2f}  {q:5.3f}")
        print(f"median ratio {np.median(ratios):.3f}; local minima {hybrid.diagnostics['local_minima']}")
    assert np.median(ratios) <= 1.15
    # the smoothed parts may beat the octile optimum, never the any-angle optimum
    # (octile <= 1.0824 x Euclidean)
    assert ratios.min() > 1 / 1.0824 - 1e-9
    assert hybrid.diagnostics["local_minima"] == APFPlanner().plan(w).diagnostics["local_minima"] > 0
    for r in hybrid.robots:
        assert max_step(r.path) <= np.sqrt(2) * w.resolution + 1e-9


def test_following_a_repaired_path_in_the_simulator():
    w = load_scenario("apf-trap-u-shape")
    result = run_world(w, planner="hybrid-apf", controller="follow", seed=0)
    assert result.summary.success
    assert validate_trajectory(w, result.trajectory) == []


def test_unreachable_goal_is_infeasible():
    r = HybridAPFPlanner().plan(unreachable_world()).robots[0]
    assert not r and r.status is PlanStatus.INFEASIBLE
    assert "partial_path" in r.diagnostics


@pytest.mark.parametrize("bad", [dict(repulsive_gain=0), dict(degree=0), dict(degree=2.0), dict(max_steps=-1)])
def test_bad_hyperparameters(bad):
    with pytest.raises(ConfigError):
        HybridAPFPlanner(**bad)


