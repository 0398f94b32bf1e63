"""Worker processes: a job runs in a child that can be killed; a child that dies under a job
gives that job an 'error' result and is replaced; a job past its limit is killed and stored as
a timeout; the next job runs in a fresh child."""
from __future__ import annotations

import dataclasses
import os
import signal
import time
from pathlib import Path

from swarmpath.bench.sweep.jobs import expand
from swarmpath.bench.sweep.pool import LocalEngine, Worker
from swarmpath.bench.sweep.suite import load_suite

SUITE = """\
name: pool
scenarios:
  - karim2014
  - {map: empty-8-8.map, scen: empty-8-8-even-10.scen, agents: [8], controllers: [pso-predictive]}
controllers: [fish-swarm]
max_steps: 400
timeout_s: 60
"""


def jobs(tmp_path: Path):
    (tmp_path / "s.yaml").write_text(SUITE)
    js = expand(load_suite(tmp_path / "s.yaml")).jobs
    quick = next(j for j in js if j.controller == "fish-swarm")
    slow = next(j for j in js if j.controller == "pso-predictive")   # tens of seconds
    return quick, slow


def test_a_worker_killed_under_a_job_is_replaced(tmp_path: Path) -> None:
    quick, slow = jobs(tmp_path)
    w = Worker().start()
    try:
        w.wait_ready()
        first_pid = w.proc.pid
        w.submit(slow)
        time.sleep(0.5)
        os.kill(first_pid, signal.SIGKILL)
        assert w.rx.poll(10)
        result = w.collect()
        assert result["status"] == "error" and "SIGKILL" in result["error"] and result["key"] == slow.key
        assert w.proc.pid != first_pid and w.job is None
        assert w.run(quick)["status"] == "ok"
    finally:
        w.stop(kill=True)


def test_the_engine_kills_an_overdue_job_and_goes_on(tmp_path: Path) -> None:
    quick, slow = jobs(tmp_path)
    slow = dataclasses.replace(slow, timeout_s=1.0)
    seen: list[tuple[str, str]] = []
    t0 = time.monotonic()
    LocalEngine(1).run([slow, quick], lambda job, result: seen.append((job.controller, result["status"])))
    assert seen == [("pso-predictive", "timeout"), ("fish-swarm", "ok")]
    assert time.monotonic() - t0 < 15


def test_results_do_not_depend_on_the_worker(tmp_path: Path) -> None:
    quick, _ = jobs(tmp_path)
    from swarmpath.bench.sweep.execute import run_job

    here = run_job(quick)
    w = Worker().start()
    try:
        w.wait_ready()
        there = w.run(quick)
    finally:
        w.stop()
    assert here["outcome"] == there["outcome"] and here["lower_bound"] == there["lower_bound"]


def test_a_worker_that_died_while_idle_is_replaced(tmp_path: Path) -> None:
    quick, _ = jobs(tmp_path)
    w = Worker().start()
    try:
        w.wait_ready()
        os.kill(w.proc.pid, signal.SIGKILL)
        w.proc.wait()
        assert w.run(quick)["status"] == "ok"
    finally:
        w.stop(kill=True)
