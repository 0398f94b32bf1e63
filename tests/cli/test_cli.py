"""The command line: the stable commands work, --json prints one object, bad input prints one
line on stderr and exits with code 2 (never a traceback)."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from swarmpath.data.movingai import MOVINGAI

DATA = MOVINGAI


def swarmpath(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "swarmpath.cli", *args], capture_output=True, text=True, timeout=300)


def assert_bad_input(p: subprocess.CompletedProcess, *words: str) -> None:
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "Traceback" not in p.stderr
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, p.stderr
    for w in words:
        assert w in lines[0], lines[0]


def test_scenarios_lists_the_default() -> None:
    p = swarmpath("scenarios")
    assert p.returncode == 0 and "jaleel2016" in p.stdout


def test_validate_ok_and_bad(tmp_path: Path) -> None:
    p = swarmpath("validate", str(DATA / "random-32-32-10.map"))
    assert p.returncode == 0 and "ok" in p.stdout
    bad = tmp_path / "bad.yaml"
    bad.write_text("robots: [\n")
    assert_bad_input(swarmpath("validate", str(bad)), "bad.yaml", "YAML syntax error")
    bad.write_text("schema_version: 1\nname: x\nbounds: {type: rectangle, width: 5, height: 5}\n"
                   "robots: [{start: [1, 1], goal: [9, 9], colour: red}]\n")
    p = swarmpath("validate", str(bad))
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "robots[0].colour: unknown field" in p.stderr and "robots[0].goal" not in p.stderr


@pytest.mark.parametrize("args, words", [
    (["path", "--map", str(DATA / "random-32-32-10.map"), "--start", "99", "0", "--goal", "1", "1"],
     ["start (99, 0) is outside the map"]),
    (["path", "--map", "nonexistent.map", "--start", "0", "0", "--goal", "1", "1"], ["no such map file"]),
    (["path", "--map", str(DATA / "random-32-32-10.map"), "--start", "a", "0", "--goal", "1", "1"], ["--start"]),
    (["run", "no-such-scenario"], ["no-such-scenario", "no built-in scenario"]),
    (["run", "jaleel2016", "--planner", "nope", "--controller", "follow"], ["unknown planner 'nope'"]),
    (["run", "--map", str(DATA / "random-32-32-10.map"), "--scen", str(DATA / "random-32-32-10-random-1.scen"),
      "--agents", "5000"], ["asks for 5000 agents"]),
    (["run", "--agents", "3"], ["--agents needs --map"]),
    (["optimize", "--algorithm", "nope", "--function", "sphere", "--runs", "1", "--iterations", "2"],
     ["unknown optimizer 'nope'"]),
    (["reproduce", "no-such-paper"], ["unknown reproduction"]),
    (["replay", "missing.npz", "--html", "x.html"], ["no such trajectory file"]),
    (["frobnicate"], ["No such command"]),
])
def test_bad_input_exits_2_with_one_line(args, words) -> None:
    assert_bad_input(swarmpath(*args), *words)


def test_bad_map_file_exits_2(tmp_path: Path) -> None:
    m = tmp_path / "broken.map"
    m.write_text("type octile\nheight 2\nwidth 3\nmap\n...\n..\n")
    assert_bad_input(swarmpath("path", "--map", str(m), "--start", "0", "0", "--goal", "1", "0"),
                     "broken.map", "line 6", "width 3")


def test_path_unreachable_prints_null_and_exits_0(tmp_path: Path) -> None:
    m = tmp_path / "split.map"
    m.write_text("type octile\nheight 3\nwidth 3\nmap\n.@.\n.@.\n.@.\n")
    p = swarmpath("path", "--map", str(m), "--start", "0", "0", "--goal", "2", "2", "--json")
    assert p.returncode == 0
    doc = json.loads(p.stdout)
    assert doc["cost"] is None and doc["path"] is None


def test_run_movingai_json_reports_what_happened(tmp_path: Path) -> None:
    """Every field of ``run --json`` holds the right value: lengths, arrivals and contacts are
    recomputed here from the saved trajectory, and the planned lengths are the .scen file's
    optimal lengths (A* is optimal)."""
    import numpy as np

    from swarmpath.sim import Trajectory
    from swarmpath.world import read_scen

    scen = DATA / "random-32-32-10-random-1.scen"
    p = swarmpath("run", "--map", str(DATA / "random-32-32-10.map"), "--scen", str(scen), "--agents", "10",
                  "--planner", "astar", "--controller", "follow", "--seed", "1", "--json", "--out", str(tmp_path))
    assert p.returncode == 0, p.stderr
    doc = json.loads(p.stdout)
    assert (doc["scenario"], doc["planner"], doc["controller"], doc["seed"]) == (
        "random-32-32-10", "astar", "follow", 1)
    traj = Trajectory.load(tmp_path / "trajectory.npz")
    assert doc["steps"] == traj.n_steps and doc["status"] == traj.status.value
    kinds = {"robot_robot": 0, "robot_static": 0, "robot_moving": 0}
    for c in traj.contacts:
        kinds[c.kind] += 1
    assert doc["collisions"] == kinds
    assert doc["safe"] == (sum(kinds.values()) == 0)
    at_goal = np.linalg.norm(traj.positions - traj.goals[None], axis=2) <= 1e-9
    reached = at_goal[-1]
    assert doc["reached"] == int(reached.sum()) and doc["n_robots"] == 10
    assert doc["success"] == (bool(reached.all()) and doc["safe"])
    steps = np.linalg.norm(np.diff(traj.positions, axis=0), axis=2)
    rows = read_scen(scen)[:10]
    arrivals = []
    for i, robot in enumerate(doc["robots"]):
        assert robot["id"] == traj.robot_ids[i]
        assert robot["path_length"] == pytest.approx(steps[:, i].sum())
        assert robot["planned_length"] == pytest.approx(rows[i].optimal_length, abs=1e-6)
        away = np.flatnonzero(~at_goal[:, i])
        arrival = (int(away[-1]) + 1 if len(away) else 0) if reached[i] else None
        assert robot["arrival_step"] == arrival and robot["reached"] == bool(reached[i])
        moved = np.any(traj.positions[1:, i] != traj.positions[:-1, i], axis=1)
        assert robot["waits"] == int(np.count_nonzero(~moved & ~at_goal[:-1, i]))
        arrivals.append(arrival)
    assert doc["sum_of_lengths"] == pytest.approx(steps.sum())
    if reached.all():
        assert doc["makespan"] == max(arrivals) and doc["sum_of_arrival_steps"] == sum(arrivals)
    else:
        assert doc["makespan"] is None and doc["sum_of_arrival_steps"] is None
    assert doc["planning_time_s"] >= 0 and doc["sim_time_s"] > 0
    assert doc["min_clearance"] <= 0.5 + 1e-9


def test_import_is_lazy() -> None:
    code = ("import sys, swarmpath; "
            "heavy = [m for m in ('scipy', 'matplotlib', 'pydantic', 'yaml') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
