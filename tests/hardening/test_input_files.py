"""Malformed, hostile and oversized input files: one line on stderr naming the file and the
field, exit code 2, no traceback, in bounded time and memory."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_helpers import one_error_line, swarmpath

ROBOTS = "robots:\n  - {start: [0.5, 0.5], goal: [4.5, 4.5]}\n"
HEAD = "schema_version: 1\nname: t\nbounds: {type: rectangle, width: 5, height: 5}\n"


def write(tmp_path: Path, text: str, name: str = "s.yaml") -> str:
    f = tmp_path / name
    f.write_text(text, encoding="utf-8")
    return str(f)


def alias_bomb(levels: int = 9, width: int = 9) -> str:
    lines = ["a0: &a0 [" + ", ".join(["x"] * width) + "]"]
    for k in range(1, levels + 1):
        lines.append(f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * width) + "]")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("command", ["validate", "run"])
@pytest.mark.parametrize("text, words", [
    (alias_bomb(), ["values once its aliases are expanded"]),
    (HEAD + "obstacles: &o [" + ", ".join(["*o"] * 3) + "]\n" + ROBOTS, ["recursive"]),
    ("[" * 500 + "]" * 500, ["nested"]),
    (HEAD + ROBOTS + "robots: []\n", ["appears twice"]),
    (HEAD + "resolution: true\n" + ROBOTS, ["resolution"]),
    (HEAD + "dt: '10'\n" + ROBOTS, ["dt"]),
])
def test_hostile_yaml(tmp_path, command, text, words) -> None:
    one_error_line(swarmpath(command, write(tmp_path, text)), "s.yaml", *words)


def test_deep_json_and_duplicate_json_keys(tmp_path) -> None:
    one_error_line(swarmpath("validate", write(tmp_path, "[" * 100_000 + "]" * 100_000, "s.json")), "nested")
    doc = '{"schema_version": 1, "name": "a", "name": "b"}'
    one_error_line(swarmpath("validate", write(tmp_path, doc, "s.json")), "appears twice")


@pytest.mark.parametrize("field, value, where", [
    ("obstacles", "[{type: circle, center: [.nan, 2], radius: 1}]", "obstacles[0].center"),
    ("obstacles", "[{type: rectangle, min: [1, 1], max: [.inf, 3]}]", "obstacles[0].max"),
    ("danger_zones", "[{center: [1, .nan], radius: 1}]", "danger_zones[0].center"),
    ("moving_obstacles", "[{shape: {type: circle, radius: 0.4}, start: [2, 2], velocity: [1e17, 0]}]",
     "moving_obstacles[0].velocity"),
])
def test_non_finite_or_huge_numbers_name_their_field(tmp_path, field, value, where) -> None:
    for command in ("validate", "run"):
        one_error_line(swarmpath(command, write(tmp_path, HEAD + f"{field}: {value}\n" + ROBOTS)), where)


@pytest.mark.parametrize("bounds, resolution", [("width: 1e6, height: 1e6", 1.0), ("width: 1e308, height: 5", 1.0),
                                                ("width: 100, height: 100", 0.0001)])
def test_grids_too_large_are_refused_before_anything_is_allocated(tmp_path, bounds, resolution) -> None:
    text = f"schema_version: 1\nname: t\nresolution: {resolution}\nbounds: {{type: rectangle, {bounds}}}\n" + ROBOTS
    for command in ("validate", "run"):
        one_error_line(swarmpath(command, write(tmp_path, text)), "s.yaml", "bounds" if "308" in bounds else "cells")


def test_nan_circle_bounds_blame_the_bounds(tmp_path) -> None:
    text = "schema_version: 1\nname: t\nbounds: {type: circle, center: [.nan, 5], radius: 5}\n" + ROBOTS
    one_error_line(swarmpath("validate", write(tmp_path, text)), "bounds.center")


def test_a_huge_polygon_is_refused_in_bounded_memory(tmp_path) -> None:
    points = ", ".join(f"[{5 + 4 * __import__('math').cos(k / 1e4):.5f}, {5 + 4 * __import__('math').sin(k / 1e4):.5f}]"
                       for k in range(200_000))
    text = "schema_version: 1\nname: t\nbounds: {type: rectangle, width: 10, height: 10}\n" \
           f"obstacles: [{{type: polygon, points: [{points}]}}]\n" + ROBOTS
    one_error_line(swarmpath("validate", write(tmp_path, text)), "obstacles[0].points")


def test_dev_zero_and_folders_are_not_read_whole(tmp_path) -> None:
    one_error_line(swarmpath("validate", "/dev/zero"), "/dev/zero")
    one_error_line(swarmpath("path", "--map", "/dev/zero", "--start", "0", "0", "--goal", "1", "1"), "/dev/zero")
    one_error_line(swarmpath("run", str(tmp_path)), str(tmp_path))


def test_user_text_with_newlines_stays_on_one_line_with_its_problem(tmp_path) -> None:
    text = "schema_version: 1\nname: \"line one\\nline two\\u001b[31m\"\nbounds: {type: rectangle, width: 5, " \
           "height: 5}\nrobots:\n  - {id: \"a\\nb\", start: [0.5, 0.5], goal: [9.5, 0.5]}\n"
    line = one_error_line(swarmpath("validate", write(tmp_path, text)), "robots[0].goal", "outside the workspace")
    assert "\x1b" not in line


def test_a_scen_without_rows_is_refused(tmp_path) -> None:
    scen = write(tmp_path, "version 1\n", "empty.scen")
    one_error_line(swarmpath("run", "--map", "empty-8-8.map", "--scen", scen, "--json"), "empty.scen", "no rows")


def test_markup_in_names_prints_as_itself(tmp_path) -> None:
    text = "schema_version: 1\nname: '[/bold]weird'\nbounds: {type: rectangle, width: 5, height: 5}\n" \
           "robots:\n  - {id: '[/red]', start: [0.5, 0.5], goal: [4.5, 0.5]}\n"
    p = swarmpath("run", write(tmp_path, text), "--planner", "astar", "--controller", "follow")
    assert p.returncode == 0, p.stderr
    assert "[/red]" in p.stdout and "[/bold]weird" in p.stdout


@pytest.mark.parametrize("out", ["/dev/null", "/proc/version"])
def test_an_unwritable_out_fails_before_the_run(out) -> None:
    one_error_line(swarmpath("run", "karim2014", "--out", out), "--out")


@pytest.mark.parametrize("doc, words", [
    ("[1, 2, 3]", ["JSON list"]),
    (None, ["contact"]),
    ("ids", ["robot_ids"]),
])
def test_replay_of_malformed_trajectories(tmp_path, doc, words) -> None:
    from swarmpath.runner import run_world
    from swarmpath.world import load_scenario

    good = run_world(load_scenario("karim2014"), seed=0).trajectory.to_json_dict()
    if doc is None:
        good["contacts"] = [{"step": "x"}]
        text = json.dumps(good)
    elif doc == "ids":
        good["robot_ids"] = [1]
        text = json.dumps(good)
    else:
        text = doc
    f = write(tmp_path, text, "t.json")
    one_error_line(swarmpath("replay", f, "--html", str(tmp_path / "r.html")), "t.json", *words)


def test_replay_of_garbage_npz_does_not_talk_about_pickles(tmp_path) -> None:
    f = tmp_path / "t.npz"
    f.write_bytes(b"\x93NUMPY garbage" * 100)
    line = one_error_line(swarmpath("replay", str(f), "--html", str(tmp_path / "r.html")), "t.npz")
    assert "pickle" not in line
    import zipfile

    z = tmp_path / "z.npz"
    with zipfile.ZipFile(z, "w") as archive:
        archive.writestr("header.npy", b"not an array")
    one_error_line(swarmpath("replay", str(z), "--html", str(tmp_path / "r.html")), "z.npz")


@pytest.mark.parametrize("args", [["--dim", "100000", "--particles", "100000"], ["--dim", "0"],
                                  ["--particles", "10000000"]])
def test_optimize_refuses_swarms_it_cannot_hold(args) -> None:
    one_error_line(swarmpath("optimize", "--algorithm", "pso", "--function", "sphere", "--iterations", "2", *args))
