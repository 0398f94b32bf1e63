"""benchmarks/bench_narrow.py works as documented: its worlds keep the rules its docstring
states, a run reports what the simulator found, and bad input gives one clear line."""
from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.ndimage import label

SCRIPT = Path(__file__).parents[2] / "benchmarks" / "bench_narrow.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_narrow", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("family", ["warehouse", "rooms", "corridors", "maze"])
def test_the_worlds_keep_their_rules(bench, family) -> None:
    for seed in range(8):
        world = bench.narrow_world(family, seed)
        again = bench.narrow_world(family, seed)
        assert world.to_dict() == again.to_dict()                          # the seed decides all
        blocked = world.static_map.blocked
        area, _ = label(~blocked)
        starts = np.floor(world.starts).astype(int)
        goals = np.floor(world.goals).astype(int)
        cells = np.concatenate([starts, goals])
        assert len({tuple(c) for c in starts}) == len(starts) and len({tuple(c) for c in goals}) == len(goals)
        assert not blocked[cells[:, 1], cells[:, 0]].any()
        assert len(set(area[cells[:, 1], cells[:, 0]].tolist())) == 1          # one connected area
        free = int(np.sum(area == area[cells[0, 1], cells[0, 0]]))
        assert 1 <= len(world.robots) <= min(39, free // 6)
        assert len(world.moving_obstacles) <= min(40, free // 30)
        for ob in world.moving_obstacles:
            c = np.floor(ob.start).astype(int)
            assert np.abs(starts - c).max(axis=1).min() >= 3
            assert np.abs(goals - c).max(axis=1).min() >= 2
            assert not blocked[c[1], c[0]]


def test_a_run_reports_what_the_simulator_found(bench) -> None:
    out = subprocess.run([sys.executable, str(SCRIPT), "--seeds", "1:2", "--families", "corridors",
                          "--controllers", "pibt", "--workers", "1"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    row = bench.one(("corridors", "pibt", 1))
    line = next(s for s in out.stdout.splitlines() if s.startswith("corridors"))
    assert f"all arrived   {int(row['arrived'])} of 1, success   {int(row['ok'])};" in line
    assert f"robots home {row['home']} of {row['n']};" in line
    assert row["forbidden"] == 0 and row["loose"] == 0


def test_bad_input_gives_one_clear_line() -> None:
    for args, line in ((["--families", "caves"], "--families: 'caves' is not one of warehouse, rooms, corridors, maze"),
                       (["--seeds", "3:3"], "--seeds '3:3' names no seed (in 'a:b', b must be above a)"),
                       (["--workers", "0"], "--workers must be >= 1, got 0")):
        out = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=60)
        assert out.returncode == 2
        assert out.stderr.strip().splitlines() == [f"bench_narrow.py: {line}"]
