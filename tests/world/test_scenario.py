"""Scenario files: one schema for YAML and JSON, and one clear line for every kind of bad input."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from swarmpath.errors import ScenarioError
from swarmpath.world import CircleBounds, builtin_scenarios, load_scenario, scenario_json_schema, world_from_dict

BASE = {
    "schema_version": 1, "name": "t", "resolution": 1.0,
    "bounds": {"type": "rectangle", "width": 10, "height": 10},
    "obstacles": [{"type": "circle", "center": [5, 5], "radius": 1, "id": "rock"},
                  {"type": "rectangle", "min": [1, 7], "max": [3, 8]},
                  {"type": "polygon", "points": [[7, 1], [9, 1], [8, 3]]}],
    "danger_zones": [{"center": [2, 2], "radius": 0.5}],
    "moving_obstacles": [{"shape": {"type": "circle", "radius": 0.4}, "start": [5, 8.5], "velocity": [1, 0]}],
    "robots": [{"id": "a", "start": [0.5, 0.5], "goal": [9.5, 9.5]}, {"start": [9.5, 0.5], "goal": [0.5, 9.5]}],
}


def write(tmp_path: Path, doc, suffix=".yaml") -> Path:
    p = tmp_path / f"s{suffix}"
    p.write_text(json.dumps(doc) if suffix == ".json" else yaml.safe_dump(doc))
    return p


def test_yaml_and_json_give_the_same_world(tmp_path: Path) -> None:
    a = load_scenario(write(tmp_path, BASE, ".yaml"))
    b = load_scenario(write(tmp_path, BASE, ".json"))
    assert a.to_dict() == b.to_dict()
    assert [r.id for r in a.robots] == ["a", "r2"]
    assert a.robots[1].max_speed == pytest.approx(2 ** 0.5)  # default: one cell incl. diagonals
    assert len(a.obstacles) == 3 and a.moving_obstacles[0].id == "m1"


def test_round_trip_through_to_dict(tmp_path: Path) -> None:
    w = load_scenario(write(tmp_path, BASE))
    again = world_from_dict(w.to_dict())
    assert again.to_dict() == w.to_dict()


def mutate(path: str, value):
    doc = json.loads(json.dumps(BASE))
    target = doc
    keys = path.split(".")
    for k in keys[:-1]:
        target = target[int(k)] if k.isdigit() else target[k]
    last = keys[-1]
    if value is KeyError:
        del target[last]
    elif last.isdigit():
        target[int(last)] = value
    else:
        target[last] = value
    return doc


@pytest.mark.parametrize("path, value, field, words", [
    ("robots.0.speed", 3, "robots[0].speed", "unknown field"),
    ("robots", KeyError, "robots", "missing"),
    ("robots.0.start", "here", "robots[0].start", "valid"),
    ("robots.0.radius", -1, "robots[0].radius", "greater than or equal"),
    ("obstacles.0.radius", -2, "obstacles[0].radius", "greater than 0"),
    ("robots.0.start", [20, 5], "robots[0].start", "outside the workspace"),
    ("robots.0.goal", [5, 5], "robots[0].goal", "inside obstacle 'rock'"),
    ("robots.1.start", [0.5, 0.5], "robots[1].start", "same spot"),
    ("robots.1.goal", [9.5, 9.5], "robots[1].goal", "share a goal"),
    ("schema_version", 2, "schema_version", "must be 1"),
    ("bounds.type", "hexagon", "bounds", "tag"),
    ("moving_obstacles.0.start", [5, 5], "moving_obstacles[0].start", "overlaps a static obstacle"),
    ("moving_obstacles.0.motion", "teleport", "moving_obstacles[0].motion", "Input should be"),
    ("moving_obstacles.0.period", 3, "moving_obstacles[0].period", "turn-every"),
    ("obstacles.2.points", [[7, 1], [9, 1], [8, 1]], "obstacles[2].points", "no area"),
])
def test_bad_input_names_file_field_and_problem(tmp_path: Path, path, value, field, words) -> None:
    p = write(tmp_path, mutate(path, value))
    with pytest.raises(ScenarioError) as err:
        load_scenario(p)
    message = str(err.value)
    assert message.startswith(str(p) + ": " + field), message
    assert words in message, message
    assert "\n" not in message


def test_yaml_syntax_error_names_the_line(tmp_path: Path) -> None:
    p = tmp_path / "bad.yaml"
    p.write_text("schema_version: 1\nrobots: [\n  {start: [1, 2]\n")
    with pytest.raises(ScenarioError, match=r"bad.yaml: line \d+, column \d+: YAML syntax error"):
        load_scenario(p)


def test_json_syntax_error_names_the_line(tmp_path: Path) -> None:
    p = tmp_path / "bad.json"
    p.write_text('{"schema_version": 1,\n "name": }')
    with pytest.raises(ScenarioError, match=r"bad.json: line 2, column \d+: JSON syntax error"):
        load_scenario(p)


def test_not_a_mapping_and_missing_file(tmp_path: Path) -> None:
    p = tmp_path / "list.yaml"
    p.write_text("- 1\n- 2\n")
    with pytest.raises(ScenarioError, match="must be a mapping"):
        load_scenario(p)
    with pytest.raises(ScenarioError, match="no such file, and no built-in scenario"):
        load_scenario(tmp_path / "nope.yaml")


def test_map_based_scenario_reads_the_map_relative_to_the_file(tmp_path: Path, data_dir: Path) -> None:
    (tmp_path / "m.map").write_text((data_dir / "random-32-32-10.map").read_text())
    doc = {"schema_version": 1, "name": "m", "map": {"file": "m.map"},
           "robots": [{"start": [15.5, 9.5], "goal": [14.5, 11.5]}]}
    w = load_scenario(write(tmp_path, doc))
    assert w.bounds.width == 32 and w.static_map is not None
    doc["robots"][0]["start"] = [0.5, 0.5]  # (0, 0) is blocked on this map? check either way
    blocked = w.static_map.blocked[0, 0]
    if blocked:
        with pytest.raises(ScenarioError, match="blocked map cell"):
            load_scenario(write(tmp_path, doc))


def test_builtin_scenarios_all_load() -> None:
    names = builtin_scenarios()
    assert "jaleel2016" in names
    for name in names:
        world = load_scenario(name)
        assert world.name == name and world.n_robots >= 1


def test_jaleel2016_is_the_papers_setup() -> None:
    w = load_scenario("jaleel2016")
    assert isinstance(w.bounds, CircleBounds) and w.bounds.center == (15, 15) and w.bounds.radius == 15
    assert w.n_robots == 12 and w.robots[0].start == (4, 12.5) and w.robots[11].goal == (18, 27)
    assert len(w.moving_obstacles) == 3


def test_committed_json_schema_is_generated_from_the_model() -> None:
    committed = json.loads((Path(__file__).parents[2] / "docs" / "scenario.schema.json").read_text())
    assert committed == scenario_json_schema()


def test_every_builtin_scenario_round_trips_through_to_dict() -> None:
    for name in builtin_scenarios():
        world = load_scenario(name)
        if world.static_map is None:
            assert world_from_dict(world.to_dict()).to_dict() == world.to_dict(), name
