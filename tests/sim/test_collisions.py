"""The independent collision checker on hand-made steps: every kind of contact is found, and
near misses are not contacts. Each case has a twin that must stay clean, so the tests fail
if the checker reports too much as well as too little."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.sim.collisions import (
    ROBOT_MOVING,
    ROBOT_ROBOT,
    ROBOT_STATIC,
    robot_robot_contacts,
    step_contacts,
)
from swarmpath.sim.trajectory import Trajectory
from swarmpath.testing import validate_trajectory
from swarmpath.world import Bounce, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.moving import MovingObstacle

BIG = 10.0  # robots may move far in one step here: the checker judges geometry, not speed


def world_of(starts, radius=0.0, obstacles=(), moving=(), static_map=None) -> World:
    robots = tuple(Robot(f"r{i}", tuple(map(float, p)), tuple(map(float, p)), radius, BIG)
                   for i, p in enumerate(starts))
    return World(RectBounds(10, 10), obstacles=tuple(obstacles), moving_obstacles=tuple(moving), robots=robots,
                 static_map=static_map, name="hand-made")


def contacts(world, p0, p1, o0=None, o1=None):
    o0 = np.zeros((0, 2)) if o0 is None else np.asarray(o0, float)
    o1 = o0 if o1 is None else np.asarray(o1, float)
    return step_contacts(world, 1, np.asarray(p0, float), np.asarray(p1, float), o0, o1)


def kinds(found) -> list[tuple[str, int, int, str]]:
    return [(c.kind, c.robot, c.other, c.detail) for c in found]


# ---------------------------------------------------------------------------- robot-robot
def test_two_point_robots_ending_in_the_same_cell_collide() -> None:
    p0 = [[0.5, 0.5], [2.5, 0.5]]
    p1 = [[1.2, 0.5], [1.8, 0.6]]  # different points, one cell
    world = world_of(p0)
    assert kinds(contacts(world, p0, p1)) == [(ROBOT_ROBOT, 0, 1, "vertex")]


def test_point_robots_in_neighbouring_cells_do_not_collide() -> None:
    p0 = [[0.5, 0.5], [2.5, 0.5]]
    p1 = [[1.5, 0.5], [2.5, 0.5]]  # one moves next to the other
    assert contacts(world_of(p0), p0, p1) == []


def test_swapping_cells_collides() -> None:
    p0 = [[0.5, 0.5], [1.5, 0.5]]
    p1 = [[1.5, 0.5], [0.5, 0.5]]
    found = kinds(contacts(world_of(p0), p0, p1))
    assert found == [(ROBOT_ROBOT, 0, 1, "swap")]


def test_following_into_a_cell_being_left_is_not_a_collision() -> None:
    p0 = [[0.5, 0.5], [1.5, 0.5]]
    p1 = [[1.5, 0.5], [2.5, 0.5]]  # a train: the follower enters the leader's old cell
    assert contacts(world_of(p0), p0, p1) == []


def test_crossing_diagonals_collide() -> None:
    p0 = [[0.5, 0.5], [1.5, 0.5]]
    p1 = [[1.5, 1.5], [0.5, 1.5]]  # both pass (1, 1) at mid-step
    found = kinds(contacts(world_of(p0), p0, p1))
    assert found == [(ROBOT_ROBOT, 0, 1, "crossing")]


def test_paths_that_cross_at_different_times_do_not_collide() -> None:
    p0 = [[0.5, 0.5], [1.25, 1.0]]
    p1 = [[1.5, 1.5], [0.25, 1.0]]  # both pass (1, 1): robot 1 at t = 0.25, robot 0 at t = 0.5
    assert contacts(world_of(p0), p0, p1) == []
    late = [[1.5, 1.5], [0.5, 1.0]]  # robot 1 now passes (1, 1) at t = 0.5 as well
    assert kinds(contacts(world_of(p0), [[0.5, 0.5], [1.5, 1.0]], late)) == [(ROBOT_ROBOT, 0, 1, "crossing")]


def test_discs_that_overlap_only_mid_step_collide() -> None:
    p0 = [[1.0, 1.0], [5.0, 1.6]]
    p1 = [[5.0, 1.0], [1.0, 1.6]]  # they pass each other 0.6 apart; radii 0.4 + 0.4
    world = world_of(p0, radius=0.4)
    found = kinds(contacts(world, p0, p1))
    assert found == [(ROBOT_ROBOT, 0, 1, "crossing")]
    # the same moves 1.0 apart are clear, and the ends are far apart in both cases
    q0 = [[1.0, 1.0], [5.0, 2.0]]
    q1 = [[5.0, 1.0], [1.0, 2.0]]
    assert contacts(world_of(q0, radius=0.4), q0, q1) == []


def test_touching_discs_are_not_a_collision() -> None:
    p = [[1.0, 1.0], [1.8, 1.0]]  # exactly 2 * 0.4 apart, standing still
    assert robot_robot_contacts(np.asarray(p), np.asarray(p), np.array([0.4, 0.4]), 1.0) == []
    q = [[1.0, 1.0], [1.79, 1.0]]
    assert robot_robot_contacts(np.asarray(q), np.asarray(q), np.array([0.4, 0.4]), 1.0) == [(0, 1, "vertex")]


# ---------------------------------------------------------------------------- robot-static
def test_corner_cutting_past_a_blocked_map_cell_collides() -> None:
    blocked = np.zeros((10, 10), bool)
    blocked[0, 1] = True  # cell (1, 0)
    world = world_of([[0.5, 0.5]], static_map=StaticMap(blocked, 1.0))
    assert kinds(contacts(world, [[0.5, 0.5]], [[1.5, 1.5]])) == [(ROBOT_STATIC, 0, -1, "obstacle")]
    assert contacts(world, [[0.5, 0.5]], [[0.5, 1.5]]) == []  # straight up is clear


def test_leaving_the_workspace_is_a_boundary_contact() -> None:
    world = world_of([[0.5, 0.5]])
    assert kinds(contacts(world, [[0.5, 0.5]], [[-0.5, 0.5]])) == [(ROBOT_STATIC, 0, -1, "boundary")]


# ---------------------------------------------------------------------------- robot-moving obstacle
def block(at) -> MovingObstacle:
    return MovingObstacle("m", Rect((-0.5, -0.5), (0.5, 0.5)), tuple(at), (1.0, 0.0), Bounce())


def test_obstacle_moving_into_a_standing_robot_collides() -> None:
    robot = [[3.5, 3.5]]
    world = world_of(robot, moving=[block((2.5, 3.5))])
    found = kinds(contacts(world, robot, robot, [[2.5, 3.5]], [[3.5, 3.5]]))
    assert found == [(ROBOT_MOVING, 0, 0, "obstacle moved into robot")]


def test_obstacle_stopping_next_to_a_robot_does_not_collide() -> None:
    robot = [[3.5, 3.5]]
    world = world_of(robot, moving=[block((1.5, 3.5))])
    assert contacts(world, robot, robot, [[1.5, 3.5]], [[2.5, 3.5]]) == []  # its box touches the cell


def test_obstacle_sweeping_over_a_robot_collides_even_if_it_ends_beyond() -> None:
    robot = [[3.5, 3.5]]
    world = world_of(robot, moving=[block((2.5, 3.5))])
    found = kinds(contacts(world, robot, robot, [[2.5, 3.5]], [[4.5, 3.5]]))
    assert found == [(ROBOT_MOVING, 0, 0, "obstacle moved into robot")]
    # the same sweep one cell higher misses the robot
    assert contacts(world, robot, robot, [[2.5, 4.5]], [[4.5, 4.5]]) == []


def test_robot_moving_into_an_obstacle_collides() -> None:
    world = world_of([[1.5, 3.5]], moving=[block((3.5, 3.5))])
    found = kinds(contacts(world, [[1.5, 3.5]], [[2.5, 3.5]], [[3.5, 3.5]], [[3.5, 3.5]]))
    assert found == []  # ends touching the box
    found = kinds(contacts(world, [[1.5, 3.5]], [[3.5, 3.5]], [[3.5, 3.5]], [[3.5, 3.5]]))
    assert found == [(ROBOT_MOVING, 0, 0, "robot moved into obstacle")]


def test_robot_passing_through_an_obstacle_collides() -> None:
    world = world_of([[2.5, 3.5]], moving=[block((3.5, 3.5))])
    found = kinds(contacts(world, [[2.5, 3.0]], [[4.5, 4.0]], [[3.5, 3.5]], [[3.5, 3.5]]))
    assert found == [(ROBOT_MOVING, 0, 0, "robot moved into obstacle")]


# ---------------------------------------------------------------------------- whole trajectories
def trajectory(world, positions, obstacles=None) -> Trajectory:
    pos = np.asarray(positions, float)
    obs = np.zeros((len(pos), 0, 2)) if obstacles is None else np.asarray(obstacles, float)
    return Trajectory(scenario=world.name, seed=0, dt=1.0, resolution=1.0, robot_ids=[r.id for r in world.robots],
                      radii=world.radii, goals=world.goals, positions=pos,
                      obstacle_ids=[o.id for o in world.moving_obstacles], obstacle_positions=obs)


@pytest.mark.parametrize("second, expected", [
    ([[1.5, 0.5], [0.5, 0.5]], ["swap"]),     # swap
    ([[1.5, 1.5], [0.5, 1.5]], ["crossing"]),  # crossing diagonals (robot 1 starts at (1.5, 0.5))
    ([[0.5, 1.5], [1.5, 1.5]], []),            # parallel moves
])
def test_validate_trajectory_reports_robot_contacts(second, expected) -> None:
    world = world_of([[0.5, 0.5], [1.5, 0.5]])
    found = validate_trajectory(world, trajectory(world, [[[0.5, 0.5], [1.5, 0.5]], second]))
    assert [v.problem.split("(")[-1].rstrip(")") for v in found] == expected
    assert all(v.where == "step 1" for v in found)


def test_validate_trajectory_reports_an_obstacle_entering_a_robot_cell() -> None:
    world = world_of([[3.5, 3.5]], moving=[block((1.5, 3.5))])
    positions = [[[3.5, 3.5]]] * 3
    clean = validate_trajectory(world, trajectory(world, positions, [[[1.5, 3.5]], [[2.5, 3.5]], [[2.5, 4.5]]]))
    assert clean == []
    hit = validate_trajectory(world, trajectory(world, positions, [[[1.5, 3.5]], [[2.5, 3.5]], [[3.5, 3.5]]]))
    assert len(hit) == 1 and hit[0].where == "step 2" and "robot_moving" in hit[0].problem
