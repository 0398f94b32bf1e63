"""The ``amopso-follow`` controller (case 2): kernels by hand, conformance, the follower's own
rules (slowing down, waiting and side stepping) with no contact, and the default behind the
safety layer with guidance along the plan: rooms, mazes, MovingAI maps and moving obstacles
(the simulator's checker and validate_trajectory decide)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.amopso_follow import AMOPSOFollowController, moves_conflict, turned
from swarmpath.control.amopso_follow_paper import AMOPSOFollowPaperController
from swarmpath.errors import ConfigError
from swarmpath.planning import Plan, PlanStatus, RobotPlan
from swarmpath.planning.amopso_path import AMOPSOPathPlanner
from swarmpath.registry import CONTROLLERS, PLANNERS
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import ALL_REACHED
from swarmpath.testing import check_controller, validate_trajectory
from swarmpath.testing.conformance import conformance_worlds
from swarmpath.world import Rect, RectBounds, Robot, World


def rules_only(**kw) -> AMOPSOFollowController:
    """The follower with its own rules alone (principle 2 with shorter moves and waiting; no
    layer, guidance or deadlock breaking): the former default."""
    return AMOPSOFollowController(give_way=True, safety=False, guidance=False, side_bias=0.0, yield_after=0, **kw)


def straight_plan(world) -> Plan:
    return Plan("straight", tuple(RobotPlan(r.id, PlanStatus.EXACT, np.array([r.start, r.goal], float))
                                  for r in world.robots), 0.0)


def test_turned_by_hand():
    out = turned([1.0, 0.0], [90, -90, 45, 180])
    np.testing.assert_allclose(out, [[0, 1], [0, -1], [np.sqrt(0.5), np.sqrt(0.5)], [-1, 0]], atol=1e-12)


def test_moves_conflict_by_hand():
    a, b = np.array([1.0, 1.0]), np.array([2.0, 1.0])
    q0 = np.array([[3.0, 1.0], [2.1, 3.0], [2.1, 1.0], [1.6, 0.0], [5.0, 5.0]])
    q1 = np.array([[2.0, 1.0],            # head-on into the same point
                   [2.1, 2.05],           # ends 1.05 above b: far enough, another cell
                   [1.1, 1.0],            # swaps cells with the robot (res 1)
                   [1.6, 2.0],            # crosses the robot's segment at the same time
                   [5.0, 5.0]])           # far away, standing
    bad = moves_conflict(a, b, q0, q1, 0.0, np.zeros(5), 0.25, 1.0)
    np.testing.assert_array_equal(bad, [True, False, True, True, False])
    # same grid cell at the end although 0.6 apart: a conflict for point robots only
    q0, q1 = np.array([[2.6, 1.9]]), np.array([[2.6, 1.9]])
    assert moves_conflict(a, np.array([2.0, 1.5]), q0, q1, 0.0, np.zeros(1), 0.25, 1.0)[0]
    assert not moves_conflict(a, np.array([2.0, 1.5]), q0, q1, 0.1, np.full(1, 0.1), 0.25, 1.0)[0]
    # discs of radius 0.2: the closest approach is 0.7 (at b); conflict below 0.4 + separation
    q = np.array([[2.0, 1.7]])
    assert not moves_conflict(a, b, q, q, 0.2, np.full(1, 0.2), 0.25, 1.0)[0]      # 0.7 >= 0.65
    assert moves_conflict(a, b, q, q, 0.2, np.full(1, 0.2), 0.35, 1.0)[0]          # 0.7 < 0.75
    # already closer than the separation: only getting closer is a conflict
    q = np.array([[1.0, 1.2]])
    assert not moves_conflict(a, np.array([1.0, 0.8]), q, q, 0.0, np.zeros(1), 0.25, 0.1)[0]
    assert moves_conflict(a, np.array([1.0, 1.1]), q, q, 0.0, np.zeros(1), 0.25, 0.1)[0]


def test_registered_and_bad_configuration():
    assert CONTROLLERS.get("amopso-follow") is AMOPSOFollowController
    assert AMOPSOFollowController.capabilities.needs_plan
    for kw in ({"sidestep": 0}, {"sidestep": float("inf")}, {"separation": -1}, {"max_waits": -1}, {"max_waits": 1.5},
               {"safety": False}, {"safety_horizon": 0}, {"side_bias": 2.0}, {"patience": 0}):
        with pytest.raises(ConfigError):
            AMOPSOFollowController(**kw)
    w = conformance_worlds()[0]
    with pytest.raises(ConfigError, match="needs an offline plan"):
        Simulator(w, AMOPSOFollowController(), None).run()


@pytest.mark.parametrize("planner", ["astar", "amopso-path"])
def test_conformance(planner):
    # behind the layer it avoids moving obstacles too (capabilities); its own rules alone
    # ignore them, so those are checked on the static worlds only
    assert AMOPSOFollowController.capabilities.moving_obstacles
    assert check_controller(AMOPSOFollowController, planner=planner) == []
    worlds = [w for w in conformance_worlds() if not w.moving_obstacles]
    assert check_controller(rules_only, planner=planner, worlds=worlds) == []
    assert check_controller(lambda: rules_only(max_waits=0), planner=planner, worlds=worlds) == []


def _head_on(radius: float = 0.0) -> World:
    return World(RectBounds(10, 10), robots=(Robot("a", (1, 5), (9, 5), radius, 0.5),
                                             Robot("b", (9, 5), (1, 5), radius, 0.5)), resolution=0.25)


@pytest.mark.parametrize("factory, waits", [(lambda: rules_only(max_waits=0), False),
                                             (rules_only, True),
                                             (AMOPSOFollowPaperController, False)])
@pytest.mark.parametrize("radius", [0.0, 0.3])
def test_head_on_robots_side_step(factory, waits, radius):
    w = _head_on(radius)
    traj = Simulator(w, factory(), straight_plan(w), seed=0, max_steps=200).run()
    assert traj.status == ALL_REACHED
    assert validate_trajectory(w, traj) == [] and traj.contacts == []
    steps = [e for e in traj.events if e.get("kind") == "sidestep"]
    assert steps and not [e for e in traj.events if e.get("kind") == "invalid_move"]
    modes = set(traj.mode_names)
    assert "sidestep" in modes and ("wait" in modes) == waits


def test_the_paper_rule_turns_at_once_and_never_slows_down():
    w = _head_on()
    paper = Simulator(w, AMOPSOFollowPaperController(), straight_plan(w), seed=0, max_steps=200).run()
    ours = Simulator(w, rules_only(max_waits=0), straight_plan(w), seed=0, max_steps=200).run()
    assert "slow" not in paper.mode_names and "slow" in ours.mode_names  # max_waits=0 still slows down first
    turn = paper.modes == paper.mode_names.index("sidestep")
    step, robot = (int(v[0]) for v in np.nonzero(turn))
    assert paper.mode_names[paper.modes[step - 1, robot]] == "follow"  # straight from following to turning
    assert CONTROLLERS.get("amopso-follow-paper") is AMOPSOFollowPaperController
    with pytest.raises(ConfigError, match="amopso-follow-paper"):
        AMOPSOFollowPaperController(sidestep=-1)


def test_corridor_and_crossing():
    corridor = World(RectBounds(10, 4), obstacles=(Rect((3, 0), (7, 1.3)), Rect((3, 2.7), (7, 4))),
                     robots=(Robot("a", (1, 2), (9, 2), 0.0, 0.5), Robot("b", (9, 2), (1, 2), 0.0, 0.5)),
                     resolution=0.25)
    cross = World(RectBounds(10, 10), robots=(
        Robot("a", (1, 5), (9, 5), 0.2, 0.5), Robot("b", (9, 5), (1, 5), 0.2, 0.5),
        Robot("c", (5, 1), (5, 9), 0.2, 0.5), Robot("d", (5, 9), (5, 1), 0.2, 0.5)), resolution=0.25)
    for w in (corridor, cross):
        plan = AMOPSOPathPlanner().plan(w, rng=0)
        for factory in (AMOPSOFollowController, rules_only):
            traj = Simulator(w, factory(), plan, seed=0, max_steps=300).run()
            assert traj.status == ALL_REACHED, w
            assert validate_trajectory(w, traj) == [] and traj.contacts == []


def test_a_robot_without_a_plan_stays_put_and_is_avoided():
    # b has no plan and stands on a's goal: a comes as close as allowed, never collides, and
    # the run ends without success (deadlock or the step budget), not with an error
    w = _head_on()
    plan = Plan("x", (straight_plan(w).robots[0], RobotPlan("b", PlanStatus.INFEASIBLE, None)), 0.0)
    traj = Simulator(w, AMOPSOFollowController(), plan, seed=0, max_steps=100).run()
    assert np.allclose(traj.positions[:, 1], [9, 5])
    assert traj.status != ALL_REACHED
    assert validate_trajectory(w, traj) == []
    assert np.linalg.norm(traj.positions[:, 0] - [9, 5], axis=1).min() >= 0.25 - 1e-9


# ------------------------------------------------------------------------------ the default: layer, guidance
def test_the_former_default_is_the_rules_only_variant_bit_for_bit():
    """With the layer, guidance and deadlock breaking off, the follower is what it was: the
    case-2 runs of the former default (makespan 31-32) come back unchanged."""
    from swarmpath.world import load_scenario

    w = load_scenario("abbas-case2")
    plan = AMOPSOPathPlanner().plan(w, rng=0)
    traj = Simulator(w, rules_only(), plan, seed=0).run()
    assert traj.status == ALL_REACHED and traj.n_steps == 31
    assert float(np.abs(np.diff(traj.positions, axis=0)).sum()) == pytest.approx(76.01085562204419, rel=1e-12)
    # the default reaches the goals on the workspace's edge as fast, without contact
    ours = Simulator(w, AMOPSOFollowController(), plan, seed=0).run()
    assert ours.status == ALL_REACHED and ours.n_steps <= 33 and ours.contacts == []
    assert validate_trajectory(w, ours) == []


@pytest.mark.slow
@pytest.mark.parametrize("name, n", [("room-32-32-4", 20), ("maze-32-32-2", 20)])
def test_maps_with_doors_and_corridors_all_arrive(name, n):
    """20 disc robots of radius 0.4 cells on A* plans: the follower's own rules left 3-6 of
    them waiting for each other in doors; behind the layer, steering along the plan by the
    guidance and with the deterministic yielding, everyone arrives without contact."""
    from swarmpath.world.generators import movingai

    w = movingai(name, n, radius=0.4)
    plan = PLANNERS.get("astar")().plan(w, rng=0)
    traj = Simulator(w, AMOPSOFollowController(), plan, seed=0).run()
    assert traj.status == ALL_REACHED and traj.contacts == []
    assert validate_trajectory(w, traj) == []


@pytest.mark.parametrize("kind", ["redraw", "turn-every", "random-walk", "waypoints"])
def test_moving_obstacles_of_every_kind_never_push_robots_into_walls(kind):
    from swarmpath.world.generators import rooms_with_doors, with_obstacles

    for seed in range(3):
        w = with_obstacles(rooms_with_doors(), kind, 3, seed)
        plan = PLANNERS.get("astar")().plan(w, rng=seed)
        traj = Simulator(w, AMOPSOFollowController(), plan, seed=seed, max_steps=150).run()
        assert not [c for c in traj.contacts if c.kind in ("robot_static", "robot_robot")], f"seed {seed}"
        assert not [e for e in traj.events if e["kind"] == "invalid_move"]
