"""The paper-pure ``pso-predictive-paper`` and ``pso-reactive-paper`` controllers: the paper's
objective (eq. 3-7, no hard constraints) by hand, prediction vs current position in eq. 7,
conformance without a zero-contact promise, determinism."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control import pso_predictive as pp
from swarmpath.control.observation import Observation, Sensed
from swarmpath.errors import ConfigError
from swarmpath.sim.simulator import Simulator
from swarmpath.testing import check_controller
from swarmpath.world import Circle, RectBounds, Robot, World, load_scenario
from swarmpath.world.static_geometry import static_geometry


def one_robot_problem(goal=(8.0, 0.5), target=np.zeros((0, 2)), mask=None) -> pp.StepProblem:
    m = len(target)
    return pp.StepProblem(start=np.array([[0.5, 0.5]]), goal=np.array([goal]), radius=np.array([0.25]),
                          reach=np.array([1.0]), robot=np.array([0]), pair_row=np.zeros(0, np.int64),
                          pair_other=np.zeros(0, np.int64), pair_from=np.zeros((0, 2)), pair_to=np.zeros((0, 2)),
                          pair_announced=np.zeros((0, 2)), pair_separation=np.zeros(0), pair_room=np.zeros(0),
                          obstacle_now=target, obstacle_next=target, obstacle_target=target, guard=np.zeros(m),
                          path_end=target, buffer=np.zeros(m), obstacle_clear=np.zeros((1, m)),
                          obstacle_mask=np.ones((1, m), bool) if mask is None else mask,
                          static_near=np.ones(1, bool))


def test_paper_objective_adds_f_st_once_per_touching_segment():
    # a wall-like disc at (4, 0.5) r 1: the line to the goal (8, 0.5) touches it from anywhere on y = 0.5
    world = World(RectBounds(10, 10), obstacles=(Circle((4.0, 0.5), 1.0),), name="disc")
    static = static_geometry(world)
    w = pp.Weights(kin=10.0, static=2.0, moving=2.0)
    x = np.array([[[1.5, 0.5], [0.5, 0.5], [0.5, 3.0]]])           # ahead (line blocked), stay (blocked), up
    cost, violation = pp.paper_objective(one_robot_problem(), static, x, w)
    goal = np.linalg.norm(x[0] - [8.0, 0.5], axis=1)
    line_free = ~world.static_hits(x[0], np.repeat([[8.0, 0.5]], 3, axis=0), np.full(3, 0.25))
    np.testing.assert_allclose(cost[0], goal + 2.0 * ~line_free)
    assert not violation.any()
    # a step that itself enters the disc pays a second f_st
    inside = np.array([[[3.2, 0.5]]])
    problem = one_robot_problem()
    problem = pp.StepProblem(**{**problem.__dict__, "start": np.array([[2.5, 0.5]])})
    c_in, _ = pp.paper_objective(problem, static, inside, w)
    np.testing.assert_allclose(c_in[0, 0], np.linalg.norm([3.2 - 8.0, 0.0]) + 2 * 2.0)


def test_paper_objective_uses_the_target_position_of_the_obstacle():
    w = pp.Weights(kin=10.0, static=2.0, moving=2.0)
    world = World(RectBounds(10, 10), name="open")
    x = np.array([[[0.5, 2.5]]])
    near, _ = pp.paper_objective(one_robot_problem(target=np.array([[0.5, 3.5]])), static_geometry(world), x, w)
    far, _ = pp.paper_objective(one_robot_problem(target=np.array([[0.5, 6.5]])), static_geometry(world), x, w)
    assert near[0, 0] - far[0, 0] == pytest.approx(2.0 * (1 / 1.0 - 1 / 4.0))


def test_informed_particle_is_ours_and_off_in_the_paper_swarm():
    assert pp.SwarmSettings().informed and not pp.paper.PAPER_SWARM.informed
    assert pp.paper.PAPER_SWARM.n_particles == 10


def test_prediction_extrapolates_the_last_move():
    sensed = Sensed(np.zeros((0, 2), np.int64), np.zeros(0), np.zeros(0, np.int8), np.zeros((0, 2), np.int64),
                    np.zeros(0), np.zeros(0, np.int8))
    obs = Observation(step=3, dt=1.0, positions=np.zeros((0, 2)), goals=np.zeros((0, 2)), at_goal=np.zeros(0, bool),
                      obstacle_positions=np.array([[2.0, 1.0]]), obstacle_previous=np.array([[1.5, 1.0]]),
                      sensed=sensed)
    _, predicted = pp.paper.predicted_obstacles(pp.prediction.ObstacleTrack(), obs)
    np.testing.assert_allclose(predicted, [[2.5, 1.0]])


@pytest.mark.parametrize("name", ["pso-predictive-paper", "pso-reactive-paper"])
def test_paper_variants_conform_without_promising_zero_contacts(name):
    from swarmpath.registry import CONTROLLERS

    cls = CONTROLLERS.get(name)
    assert not cls.capabilities.contact_free
    assert check_controller(cls, planner=None) == []


def test_bad_hyperparameters_are_reported():
    world = load_scenario("prediction2013")
    for kw in ({"sensing_factor": 1.0}, {"eps": 0.0}):
        with pytest.raises(ConfigError, match="pso-predictive-paper"):
            pp.PaperPredictivePSOController(**kw).reset(world, None, np.random.default_rng(0))


def test_with_and_without_prediction_differ_only_in_the_obstacle_target():
    world = load_scenario("prediction2013")
    a = Simulator(world, pp.PaperPredictivePSOController(), None, seed=4, max_steps=25).run()
    b = Simulator(world, pp.PaperReactivePSOController(), None, seed=4, max_steps=25).run()
    np.testing.assert_array_equal(a.obstacle_positions, b.obstacle_positions)  # same obstacle for both
    assert not np.array_equal(a.positions, b.positions)
    robots = tuple(Robot(f"r{k}", (1.0 + 2 * k, 1.0), (1.0 + 2 * k, 9.0), 0.3, 0.5) for k in range(2))
    free = World(RectBounds(6, 10), robots=robots, name="free")  # no obstacle: both are the same method
    a = Simulator(free, pp.PaperPredictivePSOController(), None, seed=1, max_steps=40).run()
    b = Simulator(free, pp.PaperReactivePSOController(), None, seed=1, max_steps=40).run()
    np.testing.assert_array_equal(a.positions, b.positions)
