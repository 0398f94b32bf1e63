"""Controllers pso-predictive and pso-reactive (PSO-prediction paper 2013): kernels by hand,
conformance, determinism, the point of prediction, and the acceptance runs on prediction2013."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from swarmpath.control import pso_predictive as pp
from swarmpath.errors import ConfigError
from swarmpath.registry import CONTROLLERS
from swarmpath.runner import choose_pair
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import ALL_REACHED
from swarmpath.testing import check_controller, validate_trajectory
from swarmpath.testing.conformance import conformance_worlds
from swarmpath.world import Circle, Rect, RectBounds, Robot, World, load_scenario
from swarmpath.world.moving import Bounce, MovingObstacle
from swarmpath.world.static_geometry import StaticGeometry, static_geometry


# ------------------------------------------------------------------------------ kernels by hand
def test_next_position_eq_1_2():
    x = pp.next_position(np.array([[1.0, 2.0]]), np.array([[0.0, np.pi / 2]]), np.array([[1.0, 0.5]]),
                         np.array([2.0]))
    np.testing.assert_allclose(x, [[[3.0, 2.0], [1.0, 3.0]]], atol=1e-12)


def test_goal_kin_obstacle_and_static_terms():
    x = np.array([[[3.0, 4.0], [0.0, 0.0]]])                                   # (k=1, p=2, 2)
    np.testing.assert_allclose(pp.goal_distance(x, np.array([[0.0, 0.0]])), [[5.0, 0.0]])
    # one sensed robot announced at (0, 0.5), required separation 1.05: only particle 2 is too close
    kin = pp.kin_penalty(x, np.array([0]), np.array([[0.0, 0.5]]), np.array([1.05]))
    np.testing.assert_allclose(kin, [[0.0, 0.55 ** 2]])
    inv = pp.inverse_obstacle_distance(x, np.array([[0.0, 2.0]]), np.array([[True]]))
    np.testing.assert_allclose(inv, [[1 / np.hypot(3, 2), 0.5]])
    assert pp.inverse_obstacle_distance(x, np.array([[0.0, 2.0]]), np.array([[False]])).sum() == 0
    np.testing.assert_allclose(pp.static_clearance_penalty(np.array([0.5, 0.25, 0.0, -0.25]), 0.25),
                               [0.0, 0.0, 1.0, 2.0])
    # a smaller margin for one robot (its way is narrower), on the same scale
    np.testing.assert_allclose(pp.static_clearance_penalty(np.array([0.2, 0.1, 0.0]), 0.1, 0.25),
                               [0.0, 0.0, 0.4])


def test_path_buffer_penalty_by_hand():
    x = np.array([[[0.0, 2.0], [0.0, 1.0], [5.0, 5.0]]])
    # path from (-1, 0) to (1, 0); contact distance 1.5, buffer 0.5 -> zero beyond 2.0
    got = pp.path_buffer_penalty(x, np.array([-1.0, 0.0]), np.array([1.0, 0.0]), np.array([1.5]), 0.5)
    np.testing.assert_allclose(got, [[0.0, 1.0 ** 2 * 4, 0.0]])


def test_wrapped_velocity_update_eq_8():
    x = np.array([[[3.0, 0.5]]])
    best = np.array([[[-3.0, 0.5]]])            # 0.28 rad away across the +-pi seam, not 6 rad
    v = pp.pso_velocity_update_wrapped(np.zeros((1, 1, 2)), x, best, best, 0.7, 1.0, 1.0,
                                       np.ones((1, 1, 2)), np.ones((1, 1, 2)))
    np.testing.assert_allclose(v[0, 0], [2 * (2 * np.pi - 6.0), 0.0], atol=1e-12)
    np.testing.assert_allclose(pp.wrap_angle(np.array([np.pi, -np.pi, 3 * np.pi / 2])),
                               [-np.pi, -np.pi, -np.pi / 2])


def test_fast_static_geometry_agrees_with_the_world():
    world = World(RectBounds(10, 8), obstacles=(Circle((3, 3), 1.0), Rect((6, 2), (8, 5))),
                  robots=(Robot("a", (1, 7), (9, 7), 0.4, 1.0),))
    fast = static_geometry(world)
    assert isinstance(fast, StaticGeometry)
    rng = np.random.default_rng(0)
    a = rng.uniform(0, 10, (2000, 2)) * [1, 0.8]
    b = a + rng.normal(0, 0.7, a.shape)
    r = rng.uniform(0, 0.5, len(a))
    exact = world.static_hits(a, b, r)
    quick = fast.static_hits(a, b, r)
    assert np.all(quick[exact])                        # never misses a hit
    assert np.mean(quick != exact) < 0.01              # only touching moves differ
    np.testing.assert_allclose(fast.static_clearance(a, r), world.static_clearance(a, r), atol=1e-12)


def test_predicted_sweep_is_a_hard_constraint_only_with_prediction():
    """A robot that would end where the obstacle is predicted to be next is rejected by the
    predictive problem and accepted by the reactive one."""
    world = World(RectBounds(20, 20), robots=(Robot("a", (10, 5), (10, 15), 0.5, 0.5),),
                  moving_obstacles=(MovingObstacle("m", Circle((0, 0), 1.0), (7.0, 7.0), (0.5, 0.0), Bounce()),))
    from swarmpath.control.observation import Observation, SensingConfig
    from swarmpath.sim.sensing import sense

    pos = np.array([[10.0, 5.6]])
    now, prev = np.array([[8.4, 7.0]]), np.array([[7.9, 7.0]])
    obs = Observation(4, 1.0, pos, world.goals, np.array([False]), now, prev,
                      sense(pos, now, SensingConfig(), world.resolution))
    candidate = np.array([[[10.0, 6.0]]])          # 1.6 from `now`, 1.28 from the predicted (8.9, 7)
    for cls, rejected in ((pp.PredictivePSOController, True), (pp.ReactivePSOController, False)):
        ctrl = cls(turn_guard="never")
        ctrl.reset(world, None, np.random.default_rng(0))
        problem = ctrl._problem(obs, world.goals)
        viol = pp.hard_violation(problem, ctrl.static_, candidate)
        assert (viol[0, 0] > 0) == rejected, cls.__name__


def test_bad_hyperparameters_raise():
    with pytest.raises(ConfigError):
        pp.PredictivePSOController(sensing_factor=1.0)
    with pytest.raises(ConfigError):
        pp.PredictivePSOController(turn_guard="sometimes")
    with pytest.raises(ConfigError):
        pp.PredictivePSOController(swarm=pp.SwarmSettings(n_particles=0))


# ------------------------------------------------------------------------------ interface
@pytest.mark.parametrize("name", ["pso-predictive", "pso-reactive"])
def test_registered_with_honest_capabilities(name):
    cls = CONTROLLERS.get(name)
    assert cls.capabilities.continuous and not cls.capabilities.needs_plan
    # the non-predictive baseline does not promise to avoid moving obstacles (the paper's point)
    assert cls.capabilities.moving_obstacles == (name == "pso-predictive")


def test_reactive_baseline_can_be_run_over_in_the_conformance_world():
    """What the capability says: with a moving obstacle the reactive swarm collides in the
    conformance world, the predictive controller does not (check_controller forced strict).
    Its safety layer sees the obstacle standing, so it does not promise more (the parked
    robot below is run over with the layer on)."""
    moving = [w for w in conformance_worlds() if w.moving_obstacles]
    assert check_controller(lambda: pp.ReactivePSOController(safety=False), planner="none", worlds=moving,
                            require_collision_free=True)
    for factory in (pp.PredictivePSOController, lambda: pp.PredictivePSOController(safety=False)):
        assert check_controller(factory, planner="none", worlds=moving, require_collision_free=True) == []


def test_scenario_defaults():
    world = load_scenario("prediction2013")
    assert choose_pair(world, None, None) == ("none", "pso-predictive")
    assert len(world.obstacles) == 5 and len(world.moving_obstacles) == 1
    assert all(r.radius > 0 for r in world.robots)
    full = load_scenario("prediction2013-14")
    assert full.n_robots == 14
    assert [r.id for r in world.robots] == [r.id for r in full.robots[:6]]
    fig16 = load_scenario("prediction2013-fig16")
    assert fig16.moving_obstacles[0].start == (2.5, 15.0)          # pixel (50, 300) at 20 px/unit
    assert world.moving_obstacles[0].start == (10.0, 15.0)         # pixel (200, 300)


@pytest.mark.parametrize("name", ["pso-predictive", "pso-reactive"])
def test_same_seed_same_trajectory(name):
    world = load_scenario("prediction2013")
    runs = [Simulator(world, CONTROLLERS.get(name)(), seed=s, max_steps=40).run() for s in (5, 5, 6)]
    np.testing.assert_array_equal(runs[0].positions, runs[1].positions)
    assert not np.array_equal(runs[0].positions, runs[2].positions)


# ------------------------------------------------------------------------------ behaviour
def _parked_robot_world() -> World:
    """A robot waits at its goal while a disc obstacle drives straight at it (no turns); a slow
    second robot far away keeps the run going."""
    return World(RectBounds(20, 12), robots=(Robot("a", (14.0, 6.0), (14.0, 6.0), 0.5, 0.5),
                                             Robot("b", (1.0, 1.0), (19.0, 1.0), 0.5, 0.1)),
                 moving_obstacles=(MovingObstacle("m", Circle((0, 0), 1.0), (4.0, 6.0), (0.25, 0.0), Bounce()),),
                 name="parked")


def test_prediction_keeps_a_parked_robot_out_of_the_obstacles_way():
    world = _parked_robot_world()
    for seed in range(4):
        predictive = Simulator(world, pp.PredictivePSOController(), seed=seed, max_steps=70).run()
        reactive = Simulator(world, pp.ReactivePSOController(), seed=seed, max_steps=70).run()
        assert predictive.contacts == [] and validate_trajectory(world, predictive) == []
        # the reactive robot stays just clear of where the obstacle is and gets run over
        assert any(c.kind == "robot_moving" for c in reactive.contacts)


def test_guidance_or_a_detour_gets_a_robot_out_of_the_local_minimum_of_a_flat_wall():
    """Eq. 3 alone (no guidance, no detours) leaves a robot in front of a wall whose goal lies
    straight behind it; a detour gets it round, and so does the guidance (the steering point
    is a cell in sight along the goal's distance field), without any detour."""
    world = World(RectBounds(10, 10), obstacles=(Rect((4, 3), (6, 7)),),
                  robots=(Robot("a", (2.0, 5.0), (8.0, 5.0), 0.5, 0.5),), name="wall")
    for seed in range(3):
        stuck = Simulator(world, pp.PredictivePSOController(stuck_steps=0, guidance=False), seed=seed,
                          max_steps=150).run()
        assert stuck.status != ALL_REACHED
        freed = Simulator(world, pp.PredictivePSOController(stuck_steps=10, guidance=False), seed=seed,
                          max_steps=150).run()
        assert freed.status == ALL_REACHED and validate_trajectory(world, freed) == []
        assert any(e["kind"] == "detour" for e in freed.events)
        guided = Simulator(world, pp.PredictivePSOController(), seed=seed, max_steps=150).run()
        assert guided.status == ALL_REACHED and validate_trajectory(world, guided) == []
        assert not any(e["kind"] == "detour" for e in guided.events)
        assert guided.n_steps < freed.n_steps


def test_discs_of_radius_0_4_get_through_the_corridors_of_a_movingai_maze():
    """In maze-32-32-2 every corridor is two cells wide, so a disc of radius 0.4 has 0.1 of
    clearance in the cells by a wall, goals included. With the full static margin (0.25) each
    goal cost more than the point 0.15 off it and no robot ever arrived (0 of 10, all 440 steps);
    the margin now never asks for more than the robot's way to its target has."""
    from swarmpath.world.generators import movingai

    world = movingai("maze-32-32-2", 6, radius=0.4)
    for seed in range(2):
        traj = Simulator(world, pp.PredictivePSOController(), seed=seed, max_steps=400).run()
        assert traj.status == ALL_REACHED, seed
        assert validate_trajectory(world, traj) == [], seed
        ends = traj.positions[-1]
        np.testing.assert_array_equal(ends, world.goals)
    # the margin shrinks only where hard constraints keep robots out of walls: in the purely
    # soft objective (rung 1 of the ladder) it is all that keeps them out, so it stays whole
    near = np.ones(world.n_robots, bool)
    for weights, shrinks in ((pp.Weights(), True), (pp.Weights(hard=0.0), False)):
        ctrl = pp.PredictivePSOController(weights=weights)
        ctrl.reset(world, None, np.random.default_rng(0))
        margin = ctrl._route_margin(world.starts, world.goals, near)
        assert (margin < weights.static_margin).any() == shrinks
        assert np.all((margin >= 0) & (margin <= weights.static_margin))


# ------------------------------------------------------------------------------ acceptance
def _robots(world: World, n: int) -> World:
    return world.replace(robots=world.robots[:n])


@pytest.mark.slow
def test_acceptance_every_robot_reaches_its_goal_without_collisions():
    """prediction2013 with pso-predictive, 2..14 robots (a subset of the counts; the
    reproduction runs them all), 10 seeds each: all goals reached, zero contacts."""
    full = load_scenario("prediction2013-14")
    fig16 = dataclasses.replace(full.moving_obstacles[0], start=(2.5, 15.0))
    cases = [(full, n) for n in (2, 6, 10, 14)] + [(full.replace(moving_obstacles=(fig16,)), 6)]
    for world, n in cases:
        w = _robots(world, n)
        for seed in range(10):
            traj = Simulator(w, pp.PredictivePSOController(), seed=seed).run()
            where = f"{n} robots, obstacle at {w.moving_obstacles[0].start}, seed {seed}"
            assert traj.status == ALL_REACHED, where
            assert traj.contacts == [], where
            assert validate_trajectory(w, traj) == [], where


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["redraw", "turn-every", "random-walk", "waypoints"])
@pytest.mark.parametrize("name", ["pso-predictive", "pso-reactive"])
def test_moving_obstacles_of_every_kind_never_push_robots_into_walls(name, kind):
    """Rooms with doors and three obstacles of each motion kind, teleporting ones included:
    no robot ever touches a wall, leaves the workspace or touches another robot."""
    from swarmpath.world.generators import rooms_with_doors, with_obstacles

    for seed in range(3):
        w = with_obstacles(rooms_with_doors(), kind, 3, seed)
        traj = Simulator(w, CONTROLLERS.get(name)(), seed=seed, max_steps=150).run()
        assert not [c for c in traj.contacts if c.kind in ("robot_static", "robot_robot")], f"seed {seed}"
        assert not [e for e in traj.events if e["kind"] == "invalid_move"]
        assert all("robot_moving" in v.problem for v in validate_trajectory(w, traj)), f"seed {seed}"
