"""The ``orbit`` motion: circles its centre at its speed, checks its circle, round-trips."""
from __future__ import annotations

import math

import numpy as np
import pytest

from swarmpath.errors import ScenarioError
from swarmpath.world import world_from_dict
from swarmpath.world.moving import advance_obstacles, initial_obstacle_state


def doc(**motion) -> dict:
    return {"schema_version": 1, "name": "o", "bounds": {"type": "rectangle", "width": 20, "height": 20},
            "moving_obstacles": [{"shape": {"type": "circle", "radius": 0.5}, "start": [14, 10],
                                  "velocity": [0, 1], "motion": "orbit", **motion}],
            "robots": [{"start": [0.5, 0.5], "goal": [19.5, 19.5]}]}


@pytest.mark.parametrize("clockwise, sign", [(False, 1), (True, -1)])
def test_it_circles_the_centre_at_its_speed(clockwise, sign) -> None:
    world = world_from_dict(doc(center=[10, 10], clockwise=clockwise))
    state = initial_obstacle_state(world)
    angles = []
    for _ in range(40):
        state = advance_obstacles(world, state, np.random.default_rng(0))
        p = state.positions[0]
        assert math.dist(p, (10, 10)) == pytest.approx(4.0)
        angles.append(math.atan2(p[1] - 10, p[0] - 10))
    steps = np.diff(np.unwrap(angles))
    assert np.allclose(steps, sign * 1.0 / 4.0)        # speed 1, radius 4: a quarter radian a step


def test_a_circle_through_a_wall_is_refused() -> None:
    bad = doc(center=[10, 10])
    bad["obstacles"] = [{"type": "rectangle", "min": [5, 9], "max": [7, 11]}]
    with pytest.raises(ScenarioError, match=r"moving_obstacles\[0\]\.center: the orbit passes"):
        world_from_dict(bad)


def test_it_needs_a_centre_and_round_trips() -> None:
    with pytest.raises(ScenarioError, match=r"moving_obstacles\[0\]\.center: orbit motion needs a center"):
        world_from_dict(doc())
    world = world_from_dict(doc(center=[10, 10], clockwise=True))
    again = world_from_dict(world.to_dict())
    assert again.moving_obstacles[0].motion == world.moving_obstacles[0].motion
