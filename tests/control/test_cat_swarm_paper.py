"""The paper-pure ``cat-swarm-paper`` controller: Algorithm 2's kernels by hand (current AND
next positions of robots and objects), the paper's rules on small worlds, and what it does
not promise; plus the ``leave_early=0`` fix of the improved controller."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control import hazards as H
from swarmpath.control.cat_swarm import CatSwarmController, CatSwarmPaperController
from swarmpath.control.cat_swarm import kernels as K
from swarmpath.errors import ConfigError
from swarmpath.planning import plan
from swarmpath.sim import Simulator
from swarmpath.testing import check_controller
from swarmpath.world import Bounce, Rect, RectBounds, Robot, World, load_scenario
from swarmpath.world.moving import MovingObstacle

S2 = float(np.sqrt(2))


# ---------------------------------------------------------------------------- Algorithm 2-3 kernels
def test_linear_next_repeats_the_last_move() -> None:
    prev = np.array([[1.0, 1.0], [5.0, 5.0]])
    now = np.array([[1.5, 1.0], [5.0, 5.0]])
    assert K.linear_next(prev, now).tolist() == [[2.0, 1.0], [5.0, 5.0]]


def test_conflict_lists_compare_current_and_next_positions_of_both_sides() -> None:
    # robot 0 at x=0 moving to x=1; robot 1 at x=5 moving to x=4; limit 3:
    # current-current 5, current-next 4, next-current 4, next-next 3 -> listed (next-next only)
    robots = np.array([[[0.0, 0.0], [1.0, 0.0]], [[5.0, 0.0], [4.0, 0.0]]])
    objects = np.concatenate([robots[:, 0], robots[:, 1]])
    owner = np.array([0, 1, 0, 1])
    robot, row = K.conflict_lists(robots, objects, owner, 3.0)
    assert list(zip(robot.tolist(), row.tolist())) == [(0, 3), (1, 2)]  # each lists the other's next position
    # with current positions alone nobody would be in conflict
    robot, _ = K.conflict_lists(robots[:, :1].repeat(2, axis=1), robots[:, 0], np.array([0, 1]), 3.0)
    assert len(robot) == 0


def test_conflict_lists_include_obstacles_and_never_the_robot_itself() -> None:
    robots = np.array([[[0.0, 0.0], [0.0, 0.0]]])
    objects = np.array([[0.0, 0.0], [2.0, 0.0], [3.5, 0.0]])
    robot, row = K.conflict_lists(robots, objects, np.array([0, -1, -1]), 3.0)
    assert row.tolist() == [1]  # its own position is not an object; 3.5 is in the long class


def test_near_listed_deletes_copies_closer_than_one() -> None:
    points = np.array([[[0.0, 0.0], [1.0, 0.0], [0.5, 0.0]]])
    near = K.near_listed(points, np.array([0]), np.array([[1.2, 0.0]]), 1.0)
    assert near.tolist() == [[False, True, True]]
    assert not K.near_listed(points, np.zeros(0, np.int64), np.zeros((0, 2)), 1.0).any()


def test_conflict_groups_are_connected_components_among_members() -> None:
    edges = np.array([[0, 1], [1, 2], [3, 4], [2, 5]])
    members = np.array([True, True, True, True, True, False])
    labels = K.conflict_groups(edges, members)
    assert labels.tolist() == [0, 0, 0, 1, 1]


def test_stay_depth_with_no_steps_is_zero_everywhere() -> None:
    assert H.stay_depth([], (2, 3)).tolist() == [[0, 0, 0], [0, 0, 0]]
    with pytest.raises(ValueError):
        H.stay_depth([])


# ---------------------------------------------------------------------------- the paper's rules
def box(start, velocity, motion) -> MovingObstacle:
    return MovingObstacle("m", Rect((-0.5, -0.5), (0.5, 0.5)), start, velocity, motion)


def test_cat_swarm_paper_conforms_without_promising_zero_contacts() -> None:
    assert not CatSwarmPaperController.capabilities.contact_free
    assert check_controller(CatSwarmPaperController) == []
    assert check_controller(lambda: CatSwarmPaperController(split="group"), planner=None) == []


@pytest.mark.parametrize("kw", [{"mixture_ratio": -0.1}, {"conflict_range": 0}, {"keep_clear": -1},
                                {"split": "everyone"}])
def test_bad_parameters_are_reported(kw) -> None:
    world = World(RectBounds(5, 5), robots=(Robot("a", (0.5, 0.5), (4.5, 0.5), 0.0, S2),), name="one")
    with pytest.raises(ConfigError, match="cat-swarm-paper"):
        CatSwarmPaperController(**kw).reset(world, None, np.random.default_rng(0))


def test_two_robots_head_on_one_seeks_one_traces() -> None:
    # MR 0.4 with two robots: 1 seeks (the longer remaining path), 1 traces (eq. 10-11)
    world = World(RectBounds(11, 5), robots=(Robot("a", (0.5, 2.5), (10.5, 2.5), 0.0, S2),
                                             Robot("b", (9.5, 2.5), (1.5, 2.5), 0.0, S2)), name="head-on")
    traj = Simulator(world, CatSwarmPaperController(), plan(world, "astar"), seed=0, max_steps=60).run()
    modes = [traj.mode_names[m] for m in traj.modes[:, 0]] + [traj.mode_names[m] for m in traj.modes[:, 1]]
    assert "seek" in modes and ("trace" in modes or "wait" in modes)
    assert traj.status == "all_reached"


def test_a_robot_reacts_to_where_an_obstacle_goes_next() -> None:
    # a block moving left along row 2 toward a robot waiting on its goal in that row (robot b
    # keeps the run going): the robot lists the block's next position and leaves its cell
    # before the block gets there
    world = World(RectBounds(12, 5), robots=(Robot("a", (6.5, 2.5), (6.5, 2.5), 0.0, S2),
                                             Robot("b", (0.5, 0.5), (11.5, 0.5), 0.0, S2)),
                  moving_obstacles=(box((11.5, 2.5), (-1.0, 0.0), Bounce()),), name="oncoming")
    traj = Simulator(world, CatSwarmPaperController(), None, seed=0, max_steps=8).run()
    assert "seek" in traj.mode_names
    arrives = int(np.flatnonzero(np.isclose(traj.obstacle_positions[:, 0, 0], 6.5))[0])  # the block on its cell
    assert not np.allclose(traj.positions[arrives, 0], (6.5, 2.5))
    assert not [c for c in traj.contacts if c.kind == "robot_moving"]


def test_leave_early_zero_runs_with_obstacles_near() -> None:
    world = load_scenario("jaleel2016")
    ctrl = CatSwarmController(lookahead=1, leave_early=0, hazard_weight=0.0, obstacle_alert="medium")
    traj = Simulator(world, ctrl, plan(world, "astar"), seed=1, max_steps=60).run()
    assert traj.n_steps == 60  # obstacles came near (they cross the robots' routes) and nothing raised
    with pytest.raises(ConfigError, match="leave_early"):
        CatSwarmController(leave_early=-1).reset(world, None, np.random.default_rng(0))
