"""``swarmpath bench`` on the command line: the stable commands, a suite or a subcommand as
the first word, and bad input (a missing dask, a folder for a store) as one line, exit code 2.
The suite, the store and the report work without dask and pandas installed."""
from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

from sweep_support import TINY_SUITE, swarmpath, swarmpath_argv


def test_the_stable_commands(tmp_path: Path) -> None:
    (tmp_path / "suite.yaml").write_text(TINY_SUITE)
    r = swarmpath("bench", "suite.yaml", "--store", "r.db", "--workers", "1", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "tiny: 2 jobs, 0 already in r.db; ran 2" in " ".join(r.stdout.split())
    r = swarmpath("bench", "report", "r.db", "--out", "rep", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    with (tmp_path / "rep" / "jobs.csv").open() as fh:
        jobs = list(csv.DictReader(fh))
    assert sorted(j["seed"] for j in jobs) == ["0", "1"]
    assert {j["controller"] for j in jobs} == {"fish-swarm"} and {j["scenario"] for j in jobs} == {"karim2014"}
    for name in ("summary.md", "summary.csv", "success_rate.png", "wall_time.png"):
        assert (tmp_path / "rep" / name).is_file()
    # run again: nothing to do; 'bench run' is the same command
    r = swarmpath("bench", "run", "suite.yaml", "--store", "r.db", "--json", cwd=tmp_path)
    assert r.returncode == 0 and json.loads(r.stdout)["already"] == 2 and json.loads(r.stdout)["ran"] == 0


def test_help_list_and_suites(tmp_path: Path) -> None:
    r = swarmpath("bench", "--help")
    assert r.returncode == 0 and "SUITE --store DB" in r.stdout and "report DB" in r.stdout
    (tmp_path / "suite.yaml").write_text(TINY_SUITE)
    r = swarmpath("bench", str(tmp_path / "suite.yaml"), "--store", str(tmp_path / "r.db"), "--list", "--json")
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert len(doc["jobs"]) == 2 and not (tmp_path / "r.db").exists()
    r = swarmpath("bench", "suites")
    assert r.returncode == 0 and all(n in r.stdout for n in ("mapf-static", "dynamic", "crowd", "papers"))


def test_skipped_pairs_are_listed(tmp_path: Path) -> None:
    (tmp_path / "s.yaml").write_text("name: s\nscenarios: [karim2014]\nplanners: [none, astar]\n"
                                     "controllers: [follow]\nmax_steps: 20\n")
    r = swarmpath("bench", "s.yaml", "--store", "r.db", "--workers", "1", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    out = " ".join(r.stdout.split())
    assert "skipped 1 job" in out and "none + follow on karim2014" in out and "needs an offline plan" in out


def one_line_error(r: subprocess.CompletedProcess, *words: str) -> None:
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = [x for x in r.stderr.splitlines() if x.strip()]
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    for w in words:
        assert w in lines[0], lines[0]


def test_bad_input_is_one_line(tmp_path: Path) -> None:
    (tmp_path / "suite.yaml").write_text(TINY_SUITE)
    (tmp_path / "folder.db").mkdir()
    one_line_error(swarmpath("bench", "suite.yaml", "--store", "folder.db", cwd=tmp_path), "folder.db", "folder")
    one_line_error(swarmpath("bench", "suite.yaml", "--store", "r.db", "--retry", "ok", cwd=tmp_path), "--retry")
    one_line_error(swarmpath("bench", "suite.yaml", cwd=tmp_path), "--store")


BLOCK = '''
import importlib.abc, sys
class _Absent(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("dask", "distributed", "pandas"):
            raise ImportError(f"No module named {name!r} (blocked by the test)")
        return None
sys.meta_path.insert(0, _Absent())
'''


def without(tmp_path: Path) -> dict[str, str]:
    """An environment in which dask, distributed and pandas cannot be imported, in this
    process's children and theirs."""
    site = tmp_path / "site"
    site.mkdir()
    (site / "sitecustomize.py").write_text(BLOCK)
    env = dict(os.environ)
    env["PYTHONPATH"] = str(site) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def test_everything_but_dask_works_without_dask_and_pandas(tmp_path: Path) -> None:
    (tmp_path / "suite.yaml").write_text(TINY_SUITE)
    env = without(tmp_path)
    check = subprocess.run([sys.executable, "-c", "import pandas"], env=env, capture_output=True, text=True)
    assert check.returncode != 0 and "blocked by the test" in check.stderr
    run = [*swarmpath_argv(), "bench"]
    r = subprocess.run([*run, "suite.yaml", "--store", "r.db", "--workers", "2"], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([*run, "report", "r.db", "--out", "rep"], cwd=tmp_path, env=env, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0 and (tmp_path / "rep" / "jobs.csv").is_file(), r.stderr
    r = subprocess.run([sys.executable, "-c", "import swarmpath.bench as b; rows = b.load('r.db'); "
                        "print(type(rows).__name__, len(rows))"], cwd=tmp_path, env=env, capture_output=True,
                       text=True)
    assert r.stdout.split() == ["list", "2"], r.stderr
    r = subprocess.run([*run, "suite.yaml", "--store", "d.db", "--dask", "local"], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=300)
    one_line_error(r, "--dask needs dask and distributed", 'pip install "swarmpath[dask]"')
    assert not (tmp_path / "d.db").exists()


def test_importing_the_sweep_package_is_cheap() -> None:
    """The reproductions registry imports swarmpath.bench and its packages: no dask, no pandas,
    no simulator there."""
    code = ("import sys, swarmpath.bench, swarmpath.bench.sweep\n"
            "heavy = [m for m in ('dask', 'distributed', 'pandas', 'swarmpath.sim', 'matplotlib')\n"
            "         if m in sys.modules]\n"
            "print(heavy)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0 and r.stdout.strip() == "[]", (r.stdout, r.stderr)
