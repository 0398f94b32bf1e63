"""The crowded random grid among moving obstacles (the grid controllers' acceptance world):
what it promises about starts, goals and obstacles, its determinism, and one clear error for
numbers that cannot make a world."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.errors import ScenarioError
from swarmpath.search import distance_field
from swarmpath.world import Bounce, Bounce8, RandomWalk, Redraw, TurnEvery
from swarmpath.world.generators import random_grid_with_movers


@pytest.mark.parametrize("seed", range(12))
def test_robots_share_one_connected_area_and_obstacles_start_clear_of_them(seed: int) -> None:
    world = random_grid_with_movers(seed, n_robots=60, n_moving=12, size=40, density=0.2)
    blocked = world.static_map.blocked
    starts = np.floor(world.starts).astype(int)
    goals = np.floor(world.goals).astype(int)
    assert len({tuple(c) for c in starts.tolist()}) == 60 and len({tuple(c) for c in goals.tolist()}) == 60
    assert not blocked[starts[:, 1], starts[:, 0]].any() and not blocked[goals[:, 1], goals[:, 0]].any()
    # every start reaches every goal: one area (8-neighbour moves without cutting corners)
    field = distance_field(blocked, tuple(int(v) for v in starts[0]))
    assert np.isfinite(field[starts[:, 1], starts[:, 0]]).all() and np.isfinite(field[goals[:, 1], goals[:, 0]]).all()
    obstacles = np.floor([ob.start for ob in world.moving_obstacles]).astype(int)
    assert len(obstacles) == 12
    assert np.abs(obstacles[:, None, :] - starts[None]).max(axis=2).min() >= 3
    assert [ob.motion.kind for ob in world.moving_obstacles] == ["bounce8", "random-walk"] * 6


def test_same_seed_same_world_and_goal_offsets_leave_the_rest_alone() -> None:
    a, b = random_grid_with_movers(7), random_grid_with_movers(7)
    assert repr(a.robots) == repr(b.robots) and repr(a.moving_obstacles) == repr(b.moving_obstacles)
    assert (a.static_map.blocked == b.static_map.blocked).all()
    assert repr(random_grid_with_movers(8).robots) != repr(a.robots)
    shifted = random_grid_with_movers(7, goal_offset=0.3)
    assert np.allclose(shifted.starts, a.starts) and repr(shifted.moving_obstacles) == repr(a.moving_obstacles)
    moved = np.abs(shifted.goals - a.goals)
    assert moved.max() <= 0.3 and moved.max() > 0
    assert (np.floor(shifted.goals) == np.floor(a.goals)).all()


def test_motions_are_used_in_turn() -> None:
    motions = (Bounce(), Bounce8(), RandomWalk(), TurnEvery(), Redraw())
    world = random_grid_with_movers(3, n_robots=20, n_moving=10, size=32, motions=motions)
    assert [ob.motion.kind for ob in world.moving_obstacles] == [m.kind for m in motions] * 2


@pytest.mark.parametrize("args, field", [
    (dict(n_robots=3000), "n_robots"),
    (dict(n_robots=0), "n_robots"),
    (dict(n_moving=-1), "n_moving"),
    (dict(size=True), "size"),
    (dict(density=1.5), "density"),
    (dict(radius=0.7), "radius"),
    (dict(goal_offset=float("nan")), "goal_offset"),
])
def test_numbers_that_cannot_make_a_world_raise_one_clear_error(args: dict, field: str) -> None:
    with pytest.raises(ScenarioError, match=field):
        random_grid_with_movers(0, **args)


def test_a_random_cell_in_a_small_pocket_falls_back_to_the_largest_area() -> None:
    # on seed 4136 the random free cell has no free neighbour: the robots go to the largest area
    world = random_grid_with_movers(4136)
    starts = np.floor(world.starts).astype(int)
    goals = np.floor(world.goals).astype(int)
    field = distance_field(world.static_map.blocked, tuple(int(v) for v in starts[0]))
    assert np.isfinite(field[starts[:, 1], starts[:, 0]]).all() and np.isfinite(field[goals[:, 1], goals[:, 0]]).all()
    assert world.n_robots == 100 and len(world.moving_obstacles) == 20


@pytest.mark.parametrize("seed", range(6))
def test_a_crowded_map_still_gets_every_obstacle_clear_of_the_starts(seed: int) -> None:
    # 100 robots on 32 x 32: most of the cells drawn for obstacles lie within 2 cells of a start
    # (before, the world silently had about half the obstacles asked for)
    world = random_grid_with_movers(seed, n_robots=100, n_moving=40, size=32)
    starts = np.floor(world.starts).astype(int)
    goals = np.floor(world.goals).astype(int)
    obstacles = np.floor([ob.start for ob in world.moving_obstacles]).astype(int)
    assert len(obstacles) == 40 and len({tuple(c) for c in obstacles.tolist()}) == 40
    assert np.abs(obstacles[:, None, :] - starts[None]).max(axis=2).min() >= 3
    assert not (obstacles[:, None, :] == goals[None]).all(axis=2).any()
    assert not world.static_map.blocked[obstacles[:, 1], obstacles[:, 0]].any()
    field = distance_field(world.static_map.blocked, tuple(int(v) for v in starts[0]))
    assert np.isfinite(field[obstacles[:, 1], obstacles[:, 0]]).all()


def test_obstacles_that_cannot_start_clear_of_the_robots_raise_one_clear_error() -> None:
    with pytest.raises(ScenarioError, match="n_moving 60 obstacles do not fit"):
        random_grid_with_movers(1, n_robots=300, n_moving=60, size=32)
