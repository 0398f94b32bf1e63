"""The motion-model registry: every model conforms, the docs list is generated from it, the
scenario form round-trips, bad parameters are refused, and no model hangs on huge numbers."""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from swarmpath.errors import ScenarioError
from swarmpath.testing import check_motion
from swarmpath.world import world_from_dict
from swarmpath.world.motions import Bounce, motions_markdown
from swarmpath.world.moving import advance_obstacles, initial_obstacle_state

DOCS = Path(__file__).parents[2] / "docs" / "scenarios.md"


def test_the_scenario_docs_list_every_registered_motion() -> None:
    text = DOCS.read_text(encoding="utf-8")
    begin, end = text.index("<!-- motions:begin"), text.index("<!-- motions:end -->")
    listed = text[text.index("\n", begin) + 1:end].strip()
    assert listed == motions_markdown()


@dataclass(frozen=True)
class Overshoot(Bounce):
    """A broken model: moves twice as far as its declared max_step."""

    def advance(self, ob, position, velocity, counter, ctx):
        p, v, c = super().advance(ob, position, velocity, counter, ctx)
        return position + 2 * (p - position), v, c


def test_the_check_finds_a_model_that_outruns_its_declared_reach() -> None:
    problems = check_motion(Overshoot())
    assert any("more than its max_step" in p for p in problems)


def doc_with(**motion) -> dict:
    return {"schema_version": 1, "name": "m", "bounds": {"type": "rectangle", "width": 10, "height": 10},
            "moving_obstacles": [{"shape": {"type": "circle", "radius": 0.4}, "start": [2.5, 2.5],
                                  "velocity": [1, 0], **motion}],
            "robots": [{"start": [0.5, 0.5], "goal": [9.5, 9.5]}]}


@pytest.mark.parametrize("field, value, motion, users", [
    ("period", 3, "bounce", "turn-every"),
    ("points", [[5, 5]], "redraw", "waypoints"),
    ("avoid_robots", False, "waypoints", "redraw"),
])
def test_a_parameter_of_another_motion_is_refused(field, value, motion, users) -> None:
    extra = {"points": [[8.5, 2.5]]} if motion == "waypoints" else {}
    with pytest.raises(ScenarioError, match=rf"moving_obstacles\[0\]\.{field}: only used with motion: {users}"):
        world_from_dict(doc_with(motion=motion, **{field: value}, **extra))


def test_an_unknown_motion_names_the_choices() -> None:
    with pytest.raises(ScenarioError, match=r"moving_obstacles\[0\]\.motion: .*bounce8"):
        world_from_dict(doc_with(motion="teleport"))


def test_redraw_round_trips_the_papers_uniform_variant() -> None:
    world = world_from_dict(doc_with(motion="redraw", avoid_robots=False))
    assert world.moving_obstacles[0].to_dict()["avoid_robots"] is False
    assert world_from_dict(world.to_dict()).moving_obstacles[0].motion == world.moving_obstacles[0].motion
    default = world_from_dict(doc_with(motion="redraw"))
    assert "avoid_robots" not in default.moving_obstacles[0].to_dict()


def test_the_papers_redraw_may_land_on_robots() -> None:
    """avoid_robots: false draws over every free cell, robots' cells included."""
    doc = doc_with(motion="redraw", avoid_robots=False)
    doc["bounds"] = {"type": "rectangle", "width": 3, "height": 3}
    doc["moving_obstacles"][0]["start"] = [1.5, 1.5]
    doc["robots"] = [{"start": [0.5, 0.5], "goal": [2.5, 2.5]}]
    world = world_from_dict(doc)
    keep = np.array([[0.5, 0.5], [2.5, 2.5]])
    state, rng, landed = initial_obstacle_state(world), np.random.default_rng(0), 0
    for _ in range(200):
        state = advance_obstacles(world, state, rng, keep_clear=keep)
        landed += bool(np.any(np.all(np.isclose(state.positions[0], keep), axis=1)))
    assert 0 < landed < 200


def test_a_waypoint_obstacle_with_a_huge_speed_takes_bounded_time() -> None:
    """A scenario file may not ask for such a speed (coordinates and velocities are limited);
    through the Python API the motion still takes bounded time per step."""
    doc = doc_with(motion="waypoints", points=[[8.5, 2.5], [8.5, 7.5]])
    doc["moving_obstacles"][0]["velocity"] = [1e17, 0]
    with pytest.raises(ScenarioError, match=r"moving_obstacles\[0\]\.velocity\[0\]: .*less than or equal"):
        world_from_dict(doc)
    doc["moving_obstacles"][0]["velocity"] = [1, 0]
    slow = world_from_dict(doc)
    fast = slow.replace(moving_obstacles=(dataclasses.replace(slow.moving_obstacles[0], velocity=(1e17, 0.0)),))
    state, rng = initial_obstacle_state(fast), np.random.default_rng(0)
    t0 = time.process_time()
    for _ in range(50):
        state = advance_obstacles(fast, state, rng)
    assert time.process_time() - t0 < 5.0        # a budget, not a benchmark: it used to never return
    assert np.all(np.isfinite(state.positions))
    assert fast.obstacle_fits(fast.moving_obstacles[0], state.positions)[0]
