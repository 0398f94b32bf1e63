"""The ``amopso-path`` planner (issue 8): conformance, statuses, the Pareto front and the
weighted sum, and the acceptance numbers on abbas-case1 and abbas-case2 (the latter executed
in the simulator with the ``amopso-follow`` controller)."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.optim.pareto import non_dominated
from swarmpath.planning import PlanStatus
from swarmpath.planning.amopso_path import AMOPSOPathPlanner, choose_from_front
from swarmpath.planning.path_objectives import danger_distances, path_lengths
from swarmpath.planning.reference_paths import visibility_shortest_path
from swarmpath.registry import PLANNERS
from swarmpath.runner import run_world
from swarmpath.testing import check_planner, validate_paths, validate_trajectory
from swarmpath.world import Circle, Rect, RectBounds, Robot, World, load_scenario

#: The stated minimum clearance of abbas-case1 plans: outside both danger zones, i.e. at least
#: the zones' radius (3 m in the scenario) from both centres.
CASE1_ZONE_RADIUS = 3.0
CASE1_SEEDS = range(20)


@pytest.fixture(scope="module")
def case1():
    return load_scenario("abbas-case1")


@pytest.fixture(scope="module")
def case1_plans(case1):
    return [AMOPSOPathPlanner().plan(case1, rng=s) for s in CASE1_SEEDS]


def test_registered_and_capabilities():
    cls = PLANNERS.get("amopso-path")
    assert cls is AMOPSOPathPlanner
    assert cls.capabilities.multi_objective and cls.capabilities.randomized and cls.capabilities.continuous


@pytest.mark.parametrize("kwargs", [
    {"update": "amopso5"}, {"mode": "lexicographic"}, {"init": "rrt"}, {"danger_objective": "max"},
    {"weights": (0.7, 0.7)}, {"weights": (1.0,)}, {"waypoints": 0}, {"particles": 1}, {"iterations": 0},
    {"waypoints": 2.5}, {"danger_margin": float("nan")}, {"archive_size": True},
])
def test_bad_hyperparameters(kwargs):
    with pytest.raises(ConfigError):
        AMOPSOPathPlanner(**kwargs)


def test_choice_rule():
    lengths = np.array([14.5, 14.6, 14.9, 16.0])
    clearance = np.array([-0.2, 0.05, 0.4, 1.0])
    assert choose_from_front(lengths, clearance, 0.0) == 1
    assert choose_from_front(lengths, clearance, 0.3) == 2
    assert choose_from_front(lengths, clearance, 5.0) == 3                           # none: the safest
    assert choose_from_front(lengths, np.full(4, np.inf), 0.0) == 0                  # no danger zones


@pytest.mark.slow
def test_conformance_of_a_non_default_configuration():
    """(The default configuration is swept in tests/test_conformance.py.)"""
    assert check_planner(lambda: AMOPSOPathPlanner(update="pso", mode="weighted-sum", init="random",
                                                   iterations=40)) == []


def test_seeds_matter_and_repeat(case1):
    a = AMOPSOPathPlanner(iterations=30).plan(case1, rng=3).robots[0].path
    b = AMOPSOPathPlanner(iterations=30).plan(case1, rng=3).robots[0].path
    c = AMOPSOPathPlanner(iterations=30).plan(case1, rng=4).robots[0].path
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def test_invalid_start_and_goal_and_unreachable():
    w = World(RectBounds(10, 10), obstacles=(Rect((6, 6), (11, 6.8)), Rect((6, 6), (6.8, 11))),
              robots=(Robot("a", (1.5, 1.5), (8.5, 8.5), 0.0, 1.0),))
    planner = AMOPSOPathPlanner(particles=10, iterations=20)
    r = planner.plan(w, rng=0).robots[0]
    assert not r and r.status is PlanStatus.INFEASIBLE and r.path is None
    assert "A*" in r.diagnostics["reason"]
    rng = np.random.default_rng(0)
    r = planner.plan_robot(w, Robot("b", (6.4, 8), (1, 1), 0.0, 1.0), rng=rng)
    assert r.status is PlanStatus.INVALID_START and not r
    r = planner.plan_robot(w, Robot("b", (1, 1), (8, 6.5), 0.0, 1.0), rng=rng)
    assert r.status is PlanStatus.INVALID_GOAL and not r
    r = planner.plan_robot(w, Robot("b", (1, 1), (10.5, 1), 0.0, 1.0), rng=rng)
    assert r.status is PlanStatus.INVALID_GOAL


def test_budget_too_small_is_a_timeout():
    # A wall with a narrow gap: two random particles and one iteration never find the gap,
    # but A* on the grid does, so the planner says it ran out of budget.
    w = World(RectBounds(10, 10), obstacles=(Rect((4.5, 0), (5.5, 4.6)), Rect((4.5, 5.4), (5.5, 10))),
              robots=(Robot("a", (1, 1), (9, 9), 0.0, 1.0),), resolution=0.2)
    r = AMOPSOPathPlanner(particles=2, iterations=1, init="random").plan(w, rng=0).robots[0]
    assert r.status is PlanStatus.TIMEOUT and not r and r.path is None
    assert validate_paths(w, [r.diagnostics["best_infeasible_path"]]) != []
    ok = AMOPSOPathPlanner().plan(w, rng=0)
    assert ok and validate_paths(w, ok.paths) == []


# ----------------------------------------------------------------------------- case 1
@pytest.mark.slow
def test_case1_acceptance(case1, case1_plans):
    lengths = []
    for plan in case1_plans:
        assert plan, plan.robots[0].diagnostics.get("reason")
        assert validate_paths(case1, plan.paths) == []
        path = plan.robots[0].path
        d = danger_distances(path[None], [z.center for z in case1.danger_zones])[0]
        assert np.all(d >= CASE1_ZONE_RADIUS), d                  # outside both zones
        lengths.append(path_lengths(path[None])[0])
    lengths = np.array(lengths)
    zones = tuple(Circle(z.center, z.radius) for z in case1.danger_zones)
    shortest_safe = visibility_shortest_path(case1.replace(obstacles=case1.obstacles + zones), case1.robots[0])[1]
    assert shortest_safe == pytest.approx(14.48, abs=0.01)
    assert np.median(lengths) <= 14.8                              # paper 14.4-14.7
    assert np.all(lengths >= shortest_safe - 1e-9)                 # nothing beats the yardstick
    assert np.median(lengths) <= 1.01 * shortest_safe


def test_pareto_front(case1, case1_plans):
    for plan in case1_plans[:5]:
        d = plan.robots[0].diagnostics
        F = d["front_objectives"]
        assert len(F) >= 5 and d["front_size"] == len(F)
        assert non_dominated(F).all()                              # eq. 14: nobody dominates
        assert np.all(np.diff(d["front_lengths"]) >= 0)            # sorted by length
        np.testing.assert_allclose(F[:, 0], d["front_lengths"])
        np.testing.assert_allclose(F[:, 1], 1 / d["front_danger_distances"].sum(axis=1))
        for p in d["front_paths"]:
            assert validate_paths(case1, [p]) == []
        # the rule: the returned path is the shortest front member outside the zones
        safe = d["front_clearance"] >= 0
        assert d["length"] == pytest.approx(d["front_lengths"][safe].min())


def test_weighted_sum_moves_along_the_front(case1):
    def medians(w_danger):
        plans = [AMOPSOPathPlanner(mode="weighted-sum", weights=(1 - w_danger, w_danger)).plan(case1, rng=s)
                 for s in range(3)]
        for p in plans:
            assert validate_paths(case1, p.paths) == []
        L = np.median([p.robots[0].length for p in plans])
        dsum = np.median([p.robots[0].diagnostics["danger_distances"].sum() for p in plans])
        return L, dsum

    l1, d1 = medians(0.5)
    l2, d2 = medians(0.97)
    l3, d3 = medians(0.99)
    assert l1 < l2 < l3                                            # more weight on danger: longer
    assert d1 < d2 < d3                                            # ... and farther from the zones


def test_choice_margin_and_clearance_objective(case1):
    base = AMOPSOPathPlanner().plan(case1, rng=0).robots[0]
    safer = AMOPSOPathPlanner(danger_margin=0.5).plan(case1, rng=0).robots[0]
    assert safer.diagnostics["danger_clearance"] >= 0.5 > base.diagnostics["danger_clearance"]
    assert safer.length > base.length
    clr = AMOPSOPathPlanner(danger_objective="clearance").plan(case1, rng=0).robots[0]
    assert clr and clr.diagnostics["danger_clearance"] >= 0 and clr.diagnostics["front_size"] >= 5
    assert validate_paths(case1, [clr.path]) == []


@pytest.mark.parametrize("update", ["spso", "pso", "amopso1", "amopso2", "amopso3"])
@pytest.mark.parametrize("init", ["astar", "random"])
def test_every_rule_and_initialisation_gives_collision_free_paths(case1, update, init):
    plan = AMOPSOPathPlanner(update=update, init=init, iterations=60).plan(case1, rng=1)
    assert plan and validate_paths(case1, plan.paths) == []
    assert plan.robots[0].diagnostics["init"] == init and plan.robots[0].diagnostics["update"] == update


# ----------------------------------------------------------------------------- case 2
@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2])     # seed 0 runs through the command line below
def test_case2_acceptance(seed):
    w = load_scenario("abbas-case2")
    result = run_world(w, seed=seed)
    assert result.planner == "amopso-path" and result.controller == "amopso-follow"
    assert validate_paths(w, result.plan.paths) == []
    s = result.summary
    assert s.success and s.collisions == {"robot_robot": 0, "robot_static": 0, "robot_moving": 0}
    assert validate_trajectory(w, result.trajectory) == []
    for robot, rs in zip(w.robots, s.robots):
        shortest = visibility_shortest_path(w, robot)[1]
        assert rs.planned_length / shortest <= 1.1, (robot.id, rs.planned_length, shortest)
        assert rs.path_length / shortest <= 1.1, (robot.id, rs.path_length, shortest)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["abbas-case1", "abbas-case2"])
def test_cli_contract(name):
    p = subprocess.run([sys.executable, "-m", "swarmpath.cli", "run", name, "--json"], capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert doc["planner"] == "amopso-path" and doc["controller"] == "amopso-follow"
    assert doc["success"] and sum(doc["collisions"].values()) == 0
    w = load_scenario(name)
    for robot, rs in zip(w.robots, doc["robots"]):
        shortest = visibility_shortest_path(w, robot)[1]
        assert rs["path_length"] / shortest <= 1.1 and rs["planned_length"] / shortest <= 1.1


@pytest.mark.slow
def test_reproduction_writes_the_report(tmp_path):
    from swarmpath.bench.amopso_paths import reproduce
    from swarmpath.registry import REPRODUCTIONS

    assert REPRODUCTIONS.get("amopso-paths") is reproduce
    calls = []
    report = reproduce(tmp_path, runs=1, updates=("spso", "amopso4"), inits=("astar",),
                       case2_configs=(("amopso4", "pareto", "astar"),), sweep=(0.5, 0.99),
                       progress=lambda done, total: calls.append((done, total)))
    text = report.read_text()
    for needle in ("Table 5 in kind", "Table 6 in kind", "The paper's Table 5", "AMOPSO4", "SPSO",
                   "paper's budget", "| R5 |", "case1-front.png"):
        assert needle in text, needle
    for png in ("case1-paths.png", "case1-front.png", "case2-paths.png"):
        assert (tmp_path / png).stat().st_size > 1000
    assert calls[-1][0] == calls[-1][1] and calls[0] == (0, calls[-1][1])
    with pytest.raises(ConfigError):
        reproduce(tmp_path, runs=0)
