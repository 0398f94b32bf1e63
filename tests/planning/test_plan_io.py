"""Plan.save / Plan.load: every registered planner's plan reads back exactly (statuses, paths,
times, diagnostics with their types), and a malformed file is refused with one line."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan, PlanStatus, RobotPlan
from swarmpath.registry import PLANNERS
from swarmpath.world import load_scenario, world_from_movingai


def assert_same(a, b) -> None:
    """Deep equality that compares arrays by value, dtype and shape, and keeps tuple/list apart."""
    assert type(a) is type(b), (type(a), type(b))
    if isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    elif isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            assert_same(a[k], b[k])
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            assert_same(x, y)
    elif isinstance(a, float) and np.isnan(a):
        assert np.isnan(b)
    else:
        assert a == b


def assert_same_plan(a: Plan, b: Plan) -> None:
    assert (a.planner, a.wall_time_s, len(a.robots)) == (b.planner, b.wall_time_s, len(b.robots))
    assert_same(dict(a.diagnostics), dict(b.diagnostics))
    for ra, rb in zip(a.robots, b.robots):
        assert (ra.robot_id, ra.status) == (rb.robot_id, rb.status)
        assert_same(ra.path, rb.path)
        assert_same(ra.times, rb.times)
        assert_same(dict(ra.diagnostics), dict(rb.diagnostics))


WORLDS = {"grid": lambda: world_from_movingai("empty-8-8.map", "empty-8-8-even-10.scen", 4),
          "trap": lambda: load_scenario("apf-trap-u-shape")}


@pytest.mark.parametrize("world_name", sorted(WORLDS))
@pytest.mark.parametrize("planner", PLANNERS.names())
def test_every_planner_round_trips(tmp_path: Path, planner: str, world_name: str) -> None:
    world = WORLDS[world_name]()
    cls = PLANNERS.get(planner)
    kwargs = {"iterations": 20, "particles": 10} if planner == "amopso-path" else {}
    plan = cls(**kwargs).plan(world, rng=3)
    path = plan.save(tmp_path / "plan.json")
    back = Plan.load(path)
    assert_same_plan(plan, back)
    assert bool(back) == bool(plan)
    # the file is plain JSON that other tools read
    doc = json.loads(path.read_text())
    assert doc["format"] == "swarmpath-plan" and len(doc["robots"]) == len(plan.robots)


def test_tagged_values_round_trip(tmp_path: Path) -> None:
    diag = {"front": np.arange(6, dtype=np.int32).reshape(2, 3), "point": (1.5, -2.0), "nan": float("nan"),
            "inf": float("-inf"), "flags": [True, None, "x"], "np": np.float32(0.25), "nested": {"t": (1, (2, 3))}}
    plan = Plan("astar", (RobotPlan("r1", PlanStatus.LOCAL_MINIMUM, np.array([[0.5, 0.5], [1.5, 2.5]]), diag,
                                    np.array([0, 3])),
                          RobotPlan("r2", PlanStatus.INFEASIBLE, None, {"reason": "walled in"})),
                0.125, {"expansions": 7})
    back = Plan.load(plan.save(tmp_path / "p.json"))
    assert back.robots[0].diagnostics["np"] == 0.25 and type(back.robots[0].diagnostics["np"]) is float
    del diag["np"], back.robots[0].diagnostics["np"]      # numpy scalars come back as Python numbers
    assert_same_plan(plan, back)
    assert back.robots[1].reason == "walled in"


def test_unsavable_diagnostics_name_the_key(tmp_path: Path) -> None:
    plan = Plan("x", (RobotPlan("r1", PlanStatus.EXACT, np.zeros((2, 2)), {"bad": object()}),), 0.0)
    with pytest.raises(ConfigError, match=r"robots\[0\]\.bad"):
        plan.save(tmp_path / "p.json")


@pytest.mark.parametrize("text, words", [
    ("{", "JSON syntax error"),
    ('{"format": "other"}', "format marker"),
    ('{"format": "swarmpath-plan", "version": 1, "planner": "a", "wall_time_s": 0, "diagnostics": {}, '
     '"robots": [{"robot_id": "r", "status": "lost", "path": null, "times": null, "diagnostics": {}}]}', "status"),
    ('{"format": "swarmpath-plan", "version": 1, "planner": "a", "wall_time_s": 0, "diagnostics": {}, '
     '"robots": [{"robot_id": "r", "status": "exact", "path": [[0, 0], [1, 1]], "times": [2, 1], '
     '"diagnostics": {}}]}', "non-decreasing"),
    ('{"format": "swarmpath-plan", "format": "swarmpath-plan"}', "appears twice"),
])
def test_malformed_files_are_refused(tmp_path: Path, text: str, words: str) -> None:
    p = tmp_path / "bad.json"
    p.write_text(text)
    with pytest.raises(ConfigError, match=words) as info:
        Plan.load(p)
    assert "bad.json" in str(info.value) and "\n" not in str(info.value)


def test_a_missing_file_is_one_line(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="no such plan file"):
        Plan.load(tmp_path / "nope.json")
