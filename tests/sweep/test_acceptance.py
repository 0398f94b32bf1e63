"""Acceptance: a 200-job suite (grid and continuous worlds, some jobs failing on purpose)
stores identical results with 1 worker, 2 workers and ``--dask local``; killed after about
half and resumed, every job is stored exactly once and nothing it finished is lost; a job over
its time limit is stored as a timeout and the sweep goes on."""
from __future__ import annotations

import json
import signal
import sqlite3
import subprocess
import time
from pathlib import Path

import pytest
from sweep_support import ACCEPTANCE_SUITE, swarmpath, swarmpath_argv

from swarmpath.bench.sweep.jobs import expand
from swarmpath.bench.sweep.store import Store
from swarmpath.bench.sweep.suite import load_suite

pytestmark = pytest.mark.slow
N_JOBS = 200


@pytest.fixture(scope="module")
def suite_file(tmp_path_factory) -> Path:
    p = tmp_path_factory.mktemp("acceptance") / "acceptance.yaml"
    p.write_text(ACCEPTANCE_SUITE)
    return p


@pytest.fixture(scope="module")
def reference(suite_file: Path) -> list[tuple]:
    """The suite run with one worker: the stored results every other run must equal."""
    db = suite_file.parent / "one-worker.db"
    r = swarmpath("bench", str(suite_file), "--store", str(db), "--workers", "1", "--json")
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert (doc["jobs"], doc["ran"], doc["already"]) == (N_JOBS, N_JOBS, 0)
    # failing on purpose: 10 errors, runs that are not a success, no timeouts
    assert (doc["ok"], doc["error"], doc["timeout"]) == (190, 10, 0)
    with Store(db).open() as s:
        rows = s.rows()
        failed = [r for r in rows if r["status"] == "ok" and not r["success"]]
        assert len(failed) >= 20
        assert sum(1 for r in failed if r["scenario"] == "antipodal-short") == 10        # no time to arrive
        assert any(r["contacts"] for r in failed if r["method"] == "astar+follow")     # blind plans collide
        assert {r["scenario"] for r in rows if r["n_moving"] == 0 and r["status"] == "ok"} >= {"empty-8-8",
                                                                                             "antipodal"}
        return s.outcomes()


def stored_outcomes(db: Path) -> list[tuple]:
    with Store(db).open() as s:
        return s.outcomes()


def test_the_suite_has_200_jobs(suite_file: Path) -> None:
    assert len(expand(load_suite(suite_file)).jobs) == N_JOBS


def test_two_workers_store_the_same_results(suite_file: Path, reference: list[tuple], tmp_path: Path) -> None:
    db = tmp_path / "two.db"
    r = swarmpath("bench", str(suite_file), "--store", str(db), "--workers", "2")
    assert r.returncode == 0, r.stderr
    assert stored_outcomes(db) == reference


def test_dask_local_stores_the_same_results(suite_file: Path, reference: list[tuple], tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    db = tmp_path / "dask.db"
    r = swarmpath("bench", str(suite_file), "--store", str(db), "--dask", "local", "--workers", "2")
    assert r.returncode == 0, r.stderr
    assert stored_outcomes(db) == reference
    with Store(db).open() as s:
        assert {row["engine"] for row in s.rows()} == {"dask"}


def _count(db: Path) -> int:
    try:
        con = sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=1.0)
        try:
            return con.execute("SELECT count(*) FROM results").fetchone()[0]
        finally:
            con.close()
    except sqlite3.Error:
        return 0


def _children(pid: int) -> list[int]:
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _stop_halfway(suite_file: Path, db: Path, how: signal.Signals) -> subprocess.Popen:
    proc = subprocess.Popen([*swarmpath_argv(), "bench", str(suite_file), "--store", str(db), "--workers", "1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while _count(db) < N_JOBS // 2:
        assert proc.poll() is None, proc.stderr.read()
        assert time.monotonic() < deadline
        time.sleep(0.02)
    workers = _children(proc.pid) if Path("/proc").is_dir() else []
    proc.send_signal(how)
    proc.wait(timeout=60)
    if workers:                                  # no worker outlives the sweep
        deadline = time.monotonic() + 10
        while any(_alive(w) for w in workers) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not any(_alive(w) for w in workers)
    return proc


@pytest.mark.parametrize("how", [signal.SIGKILL, signal.SIGINT], ids=["killed", "interrupted"])
def test_stopped_halfway_and_resumed_every_job_once(suite_file: Path, reference: list[tuple], tmp_path: Path,
                                                    how: signal.Signals) -> None:
    db = tmp_path / "resume.db"
    proc = _stop_halfway(suite_file, db, how)
    kept = _count(db)
    assert N_JOBS // 2 <= kept < N_JOBS, kept
    if how == signal.SIGINT:
        assert proc.returncode == 130
        assert "run the same command again to resume" in proc.stderr.read()
    r = swarmpath("bench", str(suite_file), "--store", str(db), "--workers", "2", "--json")
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    # nothing finished was lost (all kept jobs are "already" there), nothing ran twice
    assert (doc["already"], doc["ran"]) == (kept, N_JOBS - kept)
    keys = [row[0] for row in stored_outcomes(db)]
    assert len(keys) == len(set(keys)) == N_JOBS
    assert set(keys) == {j.key for j in expand(load_suite(suite_file)).jobs}
    assert stored_outcomes(db) == reference
    with Store(db).open() as s:
        states = [x["state"] for x in s.sweeps()]
    assert states[-1] == "finished"
    if how == signal.SIGINT:
        assert states[0] == "interrupted"


TIMEOUT_SUITE = """\
name: timeouts
scenarios:
  - scenario: karim2014
    controllers: [fish-swarm, pibt]
  - map: den312d.map
    scen: den312d-even-10.scen
    agents: [60]
    methods: [{controller: pibt}, {controller: pso-predictive}]   # the PSO takes about a minute here
max_steps: 400
timeout_s: 3
"""


@pytest.mark.parametrize("engine", [["--workers", "1"], ["--dask", "local", "--workers", "1"]], ids=["local", "dask"])
def test_a_job_over_its_limit_is_a_timeout_and_the_sweep_goes_on(tmp_path: Path, engine: list[str]) -> None:
    if "--dask" in engine:
        pytest.importorskip("distributed")
    p = tmp_path / "t.yaml"
    p.write_text(TIMEOUT_SUITE)
    t0 = time.monotonic()
    r = swarmpath("bench", str(p), "--store", str(tmp_path / "t.db"), *engine, "--json")
    assert r.returncode == 0, r.stderr
    assert time.monotonic() - t0 < 90          # generous for a loaded machine: wall_s below shows the cut
    doc = json.loads(r.stdout)
    assert (doc["ok"], doc["timeout"], doc["error"]) == (3, 1, 0)
    with Store(tmp_path / "t.db").open() as s:
        (late,) = [row for row in s.rows() if row["status"] == "timeout"]
    assert late["controller"] == "pso-predictive" and late["error"] == "over the time limit of 3 s"
    assert 3.0 <= late["wall_s"] < 10 and late["success"] is None


def test_dask_connects_to_a_running_scheduler(tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    from sweep_support import TINY_SUITE

    (tmp_path / "suite.yaml").write_text(TINY_SUITE)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1") as cluster:
        r = swarmpath("bench", "suite.yaml", "--store", "r.db", "--dask", cluster.scheduler_address, "--json",
                      cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert (doc["engine"], doc["ran"], doc["ok"]) == ("dask", 2, 2)
