"""Golden numbers of the paper-pure variants, one seed of each paper's scenario (STYLE habit
10). They pin the paper's methods: a change to an improved variant (cat-swarm's PIBT core, an
ORCA layer for the continuous controllers) must not move them. If one of these fails, either
a shared kernel changed on purpose (update the numbers and the docs page's tables, say why in
the commit) or a paper-pure variant was changed by accident."""
from __future__ import annotations

import pytest

from swarmpath.bench.karim2014 import karim_world
from swarmpath.control.fish_swarm import FishSwarmController
from swarmpath.metrics.summary import run_summary
from swarmpath.planning.amopso_path_paper import AMOPSOPathPaperPlanner
from swarmpath.runner import run_world
from swarmpath.sim.simulator import Simulator
from swarmpath.world import load_scenario

REL = 1e-9


@pytest.mark.parametrize("scenario, planner, controller, expected", [
    # (steps, robots at goal, robot-robot, robot-moving, robot-static contacts, sum of lengths)
    ("jaleel2016", "hybrid-apf", "cat-swarm-paper", (105, 12, 37, 0, 0, 176.42150482404188)),
    ("prediction2013", "none", "pso-predictive-paper", (52, 6, 4, 0, 0, 137.23652176403542)),
    ("prediction2013", "none", "pso-reactive-paper", (52, 6, 4, 0, 0, 137.1699266665372)),
    ("abbas-case2", "amopso-path-paper", "amopso-follow-paper", (57, 5, 0, 0, 0, 85.58476676789229)),
])
def test_paper_pure_controller_golden_run(scenario, planner, controller, expected):
    s = run_world(load_scenario(scenario), planner=planner, controller=controller, seed=0, clearance=False).summary
    c = s.collisions
    assert (s.steps, s.reached, c["robot_robot"], c["robot_moving"], c["robot_static"]) == expected[:5]
    assert s.sum_of_lengths == pytest.approx(expected[5], rel=REL)


def test_amopso_path_paper_golden_plan():
    r = AMOPSOPathPaperPlanner().plan(load_scenario("abbas-case1"), rng=0).robots[0]
    assert len(r.path) == 6
    assert r.diagnostics["length"] == pytest.approx(21.227702347685444, rel=REL)
    assert r.diagnostics["danger_clearance"] == pytest.approx(0.17127960642608286, rel=REL)


@pytest.mark.parametrize("seed, expected", [(0, (10, 1)), (1, (14, 1)), (2, (9, 0))])
def test_karim_with_the_papers_uniform_redraw_golden(seed, expected):
    # the fish swarm is the paper's; the paper's redraw may put an obstacle on the robot
    world = karim_world(10, avoid_robots=False)
    traj = Simulator(world, FishSwarmController(), seed=seed).run()
    s = run_summary(world, traj, None, clearance=False)
    assert (s.steps, s.collisions["robot_moving"]) == expected and s.all_reached
