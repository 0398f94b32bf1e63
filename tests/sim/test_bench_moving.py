"""benchmarks/bench_moving.py works as documented: on one of the acceptance seeds it runs the
simulator, finds the success the acceptance test asserts, and says so in its report; bad
seeds give one clear line."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).parents[2] / "benchmarks" / "bench_moving.py"


def test_the_benchmark_reports_a_success_on_an_acceptance_seed() -> None:
    out = subprocess.run([sys.executable, str(SCRIPT), "--seeds", "0:1", "--controllers", "pibt", "--workers", "1"],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "pibt: 1 of 1 runs succeed" in out.stdout
    assert "robot-moving 0" in out.stdout and "failed seeds: none" in out.stdout


def test_bad_seeds_give_one_clear_line() -> None:
    out = subprocess.run([sys.executable, str(SCRIPT), "--seeds", "a:b"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == ["bench_moving.py: --seeds must be 'a:b' or a comma list of whole "
                                               "numbers, got 'a:b'"]


def test_a_seed_range_too_long_gives_one_clear_line_before_any_work() -> None:
    out = subprocess.run([sys.executable, str(SCRIPT), "--seeds", "0:1000000000"], capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == ["bench_moving.py: --seeds names 1000000000 seeds (at most 100000)"]


def test_an_empty_seed_range_and_no_workers_each_get_their_own_line() -> None:
    for args, line in ((["--seeds", "5:3"], "--seeds '5:3' names no seed (in 'a:b', b must be above a)"),
                       (["--seeds", "0,-4"], "--seeds must be whole numbers >= 0, got -4"),
                       (["--workers", "0"], "--workers must be >= 1, got 0")):
        out = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=60)
        assert out.returncode == 2
        assert out.stderr.strip().splitlines() == [f"bench_moving.py: {line}"]
