"""Fuzzing the scenario model: any document, however broken, gives a World or a
ScenarioError (never another exception), and a document that validates also runs (or is
refused with a SwarmpathError, e.g. a robot too wide for the grid controller chosen)."""
from __future__ import annotations

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from swarmpath.errors import ScenarioError, SwarmpathError
from swarmpath.runner import run_world
from swarmpath.world import world_from_dict

junk = st.one_of(st.none(), st.booleans(), st.integers(-10**20, 10**20), st.text(max_size=8),
                 st.floats(allow_nan=True, allow_infinity=True), st.lists(st.integers(-3, 3), max_size=3),
                 st.dictionaries(st.text(max_size=4), st.integers(), max_size=2))


def rarely_junk(strategy):
    """Mostly a value from ``strategy``, one time in twenty-five junk instead."""
    return st.integers(0, 24).flatmap(lambda k: junk if k == 0 else strategy)


coord = rarely_junk(st.one_of(st.floats(-0.5, 10.5), st.integers(0, 10)))
vec = rarely_junk(st.tuples(coord, coord).map(list))
positive = rarely_junk(st.one_of(st.floats(0.05, 3), st.integers(1, 3)))


shape = rarely_junk(st.one_of(
    st.fixed_dictionaries({"type": st.just("circle"), "center": vec, "radius": positive}),
    st.fixed_dictionaries({"type": st.just("rectangle"), "min": vec, "max": vec}),
    st.fixed_dictionaries({"type": st.just("polygon"), "points": st.lists(vec, min_size=0, max_size=5)})))
moving = st.fixed_dictionaries(
    {"shape": rarely_junk(st.one_of(st.fixed_dictionaries({"type": st.just("circle"), "radius": positive}),
                                    st.fixed_dictionaries({"type": st.just("rectangle"), "width": positive,
                                                           "height": positive}))),
     "start": vec, "velocity": vec},
    optional={"motion": rarely_junk(st.sampled_from(["bounce", "bounce8", "turn-every", "random-walk", "redraw",
                                                     "waypoints", "orbit"])),
              "period": rarely_junk(st.integers(-1, 5)), "points": st.lists(vec, max_size=3),
              "center": vec, "avoid_robots": rarely_junk(st.booleans())})
robot = st.fixed_dictionaries({"start": vec, "goal": vec},
                              optional={"radius": rarely_junk(st.sampled_from([0.0, 0.0, 0.2, 0.4, 0.6])),
                                        "max_speed": positive, "id": rarely_junk(st.text(max_size=5))})
document = st.fixed_dictionaries(
    {"schema_version": rarely_junk(st.just(1)), "name": rarely_junk(st.text(min_size=1, max_size=6)),
     "robots": rarely_junk(st.lists(robot, min_size=1, max_size=4)),
     "bounds": rarely_junk(st.one_of(
         st.fixed_dictionaries({"type": st.just("rectangle"), "width": st.floats(5, 12), "height": st.floats(5, 12)}),
         st.fixed_dictionaries({"type": st.just("circle"), "center": st.just([5.0, 5.0]),
                                "radius": st.floats(3, 5)})))},
    optional={"resolution": rarely_junk(st.sampled_from([0.5, 1.0, 2.0])), "dt": positive,
              "obstacles": st.lists(shape, max_size=3), "moving_obstacles": st.lists(moving, max_size=2),
              "danger_zones": st.lists(st.fixed_dictionaries({"center": vec}, optional={"radius": positive}),
                                       max_size=2),
              "defaults": st.fixed_dictionaries({}, optional={
                  "planner": st.sampled_from(["none", "astar", "lacam", "apf", "nope"]),
                  "controller": st.sampled_from(["cat-swarm", "pibt", "fish-swarm", "orca", "pso-predictive",
                                                 "follow", "nope"])})})


@settings(max_examples=600, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(doc=document)
def test_any_document_gives_a_world_or_a_scenario_error(doc) -> None:
    try:
        world = world_from_dict(doc)
    except ScenarioError as exc:
        assert str(exc) and "\n" not in str(exc)
        return
    try:
        result = run_world(world, seed=0, max_steps=3)
    except SwarmpathError as exc:   # e.g. a robot too wide for a grid controller: refused, with a line
        assert str(exc) and "\n" not in str(exc)
        return
    assert result.trajectory.n_steps <= 3
    assert all(math.isfinite(v) for v in result.trajectory.positions.ravel())
