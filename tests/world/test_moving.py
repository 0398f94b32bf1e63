"""Motion models keep obstacles inside the free space, are seeded, and redraw avoids robots."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.world import (Bounce, Bounce8, Circle, MovingObstacle, RandomWalk, Rect, RectBounds, Redraw,
                             TurnEvery, Waypoints, World, advance_obstacles, initial_obstacle_state)

CELL = Rect((-0.5, -0.5), (0.5, 0.5))


def world_with(motion, velocity=(1.0, 0.0), shape=CELL) -> World:
    return World(RectBounds(10, 10), obstacles=(Rect((4, 4), (6, 6)),),
                 moving_obstacles=(MovingObstacle("m", shape, (1.5, 2.5), velocity, motion),
                                   MovingObstacle("n", shape, (8.5, 8.5), (-1.0, -1.0), motion)), name="m")


@pytest.mark.parametrize("motion", [Bounce(), Bounce8(), TurnEvery(3), RandomWalk(), Redraw(),
                                    Waypoints(((8.5, 1.5), (8.5, 8.5)), True)])
def test_obstacles_stay_in_free_space_and_are_deterministic(motion) -> None:
    world = world_with(motion)
    runs = []
    for _ in range(2):
        rng = np.random.default_rng(5)
        state = initial_obstacle_state(world)
        track = [state.positions]
        for _ in range(200):
            state = advance_obstacles(world, state, rng, keep_clear=np.array([[2.5, 2.5]]))
            for ob, p in zip(world.moving_obstacles, state.positions):
                assert world.obstacle_fits(ob, p[None])[0], (motion, p)
            track.append(state.positions)
        runs.append(np.asarray(track))
    assert np.array_equal(runs[0], runs[1])
    moved = np.linalg.norm(np.diff(runs[0], axis=0), axis=2)
    assert moved.max() > 0


def test_bounce_reflects_off_walls() -> None:
    world = World(RectBounds(5, 5), moving_obstacles=(MovingObstacle("m", Circle((0, 0), 0.5), (4.0, 2.5), (1, 0),
                                                                     Bounce()),), name="b")
    state = advance_obstacles(world, initial_obstacle_state(world), np.random.default_rng(0))
    assert state.velocities[0, 0] == -1 and state.positions[0, 0] == 3.0


def test_redraw_never_lands_on_kept_cells() -> None:
    world = World(RectBounds(3, 3), moving_obstacles=(MovingObstacle("m", CELL, (1.5, 1.5), (0, 0), Redraw()),),
                  name="r")
    keep = np.array([[0.5, 0.5], [2.5, 2.5], [1.5, 0.5]])
    rng = np.random.default_rng(0)
    state = initial_obstacle_state(world)
    for _ in range(300):
        state = advance_obstacles(world, state, rng, keep_clear=keep)
        assert not np.any(np.all(np.isclose(state.positions[0], keep), axis=1))


def test_waypoints_are_followed_at_speed() -> None:
    world = World(RectBounds(10, 10), moving_obstacles=(
        MovingObstacle("m", CELL, (1.5, 1.5), (1.0, 0.0), Waypoints(((4.5, 1.5), (4.5, 3.5)), False)),), name="w")
    state = initial_obstacle_state(world)
    rng = np.random.default_rng(0)
    seen = []
    for _ in range(7):
        state = advance_obstacles(world, state, rng)
        seen.append(tuple(state.positions[0]))
    assert seen[:3] == [(2.5, 1.5), (3.5, 1.5), (4.5, 1.5)]
    assert seen[4] == (4.5, 3.5) and seen[-1] == (4.5, 3.5)


def test_waypoint_routes_through_obstacles_are_rejected() -> None:
    from swarmpath.errors import ScenarioError

    with pytest.raises(ScenarioError, match=r"moving_obstacles\[0\].points: the route passes"):
        World(RectBounds(10, 10), obstacles=(Rect((4, 4), (6, 6)),),
              moving_obstacles=(MovingObstacle("m", CELL, (1.5, 1.5), (1, 0), Waypoints(((8.5, 8.5),), False)),))
