"""Running jobs with a time limit each: a :class:`Worker` is one child process
(:mod:`swarmpath.bench.sweep.child`) that runs one job at a time and is killed and replaced
when a job outlives its limit; :class:`LocalEngine` keeps N of them busy.

The Dask engine runs each job through :func:`run_in_worker_process` on the cluster's
workers, which keep a Worker of their own: a job gets the same limit, the same process
isolation and the same result on a cluster as on the local pool.

Workers are plain subprocesses talking over pipes (not multiprocessing children), so they can
be started from anywhere, a Dask worker's daemon process included; each is told to use one
thread for numerical libraries, so N workers use N cores.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any, Callable, Iterable

from swarmpath.bench.sweep.jobs import Job
from swarmpath.errors import ConfigError

#: Seconds a new worker may take to import swarmpath and say it is ready.
STARTUP_S = 120.0
#: Environment variables that keep numerical libraries to one thread per worker (a value the
#: user set is kept).
ONE_THREAD = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS",
              "VECLIB_MAXIMUM_THREADS")

OnResult = Callable[[Job, dict[str, Any]], None]


def _child_env() -> dict[str, str]:
    env = dict(os.environ)
    for name in ONE_THREAD:
        env.setdefault(name, "1")
    root = str(Path(__file__).resolve().parents[3])   # the folder holding the swarmpath package
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def timeout_result(job: Job, elapsed: float) -> dict[str, Any]:
    """The stored result of a job that outlived its limit."""
    return {"key": job.key, "status": "timeout", "error": f"over the time limit of {job.timeout_s:g} s",
            "outcome": None, "lower_bound": None, "violations": None, "source": "",
            "timings": {"wall_s": elapsed, "setup_s": 0.0}}


def died_result(job: Job, code: int | None, elapsed: float) -> dict[str, Any]:
    """The stored result of a job whose worker process died under it (a crash in C code,
    the machine's memory killer)."""
    how = f"signal {signal.Signals(-code).name}" if code is not None and code < 0 else f"exit code {code}"
    return {"key": job.key, "status": "error", "error": f"the worker process died while running the job ({how})",
            "outcome": None, "lower_bound": None, "violations": None, "source": "",
            "timings": {"wall_s": elapsed, "setup_s": 0.0}}


class Worker:
    """One child process that runs jobs one at a time (started by :meth:`start`)."""

    def __init__(self, name: str = "worker"):
        self.name = name
        self.proc: subprocess.Popen | None = None
        self.rx: Connection | None = None
        self.tx: Connection | None = None
        self.job: Job | None = None
        self.started = 0.0

    # ------------------------------------------------------------------ life
    def start(self) -> "Worker":
        """Start the process (returns at once; :meth:`wait_ready` waits for it)."""
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        try:
            self.proc = subprocess.Popen([sys.executable, "-m", "swarmpath.bench.sweep.child"], stdin=to_child_r,
                                         stdout=from_child_w, env=_child_env(), close_fds=True)
        finally:
            os.close(to_child_r)
            os.close(from_child_w)
        self.tx = Connection(to_child_w, readable=False)
        self.rx = Connection(from_child_r, writable=False)
        return self

    def wait_ready(self, timeout: float = STARTUP_S) -> None:
        """Block until the process has imported swarmpath (ConfigError if it cannot)."""
        try:
            ready = self.rx.poll(timeout)
            message = self.rx.recv() if ready else None
        except (EOFError, OSError):
            message = None
        if not (isinstance(message, tuple) and message and message[0] == "ready"):
            code = self.proc.poll() if self.proc else None
            self.stop()
            raise ConfigError(f"a sweep worker did not start (exit code {code}); run "
                              f"'{sys.executable} -m swarmpath.bench.sweep.child' to see why")

    def stop(self, kill: bool = False) -> int | None:
        """End the process: ask it to finish (or kill it), and reap it."""
        code = None
        if self.proc is not None:
            if not kill and self.proc.poll() is None:
                try:
                    self.tx.send(None)
                except OSError:
                    pass
                try:
                    code = self.proc.wait(timeout=2.0)
                except subprocess.TimeoutExpired:
                    kill = True
            if kill or self.proc.poll() is None:
                self.proc.kill()
            code = self.proc.wait()
        for conn in (self.rx, self.tx):
            if conn is not None:
                conn.close()
        self.proc = self.rx = self.tx = None
        self.job = None
        return code

    # ------------------------------------------------------------------ jobs
    def submit(self, job: Job) -> None:
        """Hand ``job`` to the process (it must be idle); a process that died while idle is
        replaced first."""
        if self.proc is None or self.proc.poll() is not None:
            self.stop(kill=True)
            self.start().wait_ready()
        self.job = job
        self.started = time.perf_counter()
        try:
            self.tx.send(job)
        except OSError:                      # it died between the check and the send
            self.stop(kill=True)
            self.start().wait_ready()
            self.job, self.started = job, time.perf_counter()
            self.tx.send(job)

    @property
    def deadline(self) -> float:
        return self.started + self.job.timeout_s if self.job is not None else float("inf")

    def collect(self) -> dict[str, Any]:
        """The finished job's result (after :meth:`rx` is readable), or a 'died' result when
        the process ended instead; either way the worker is then idle."""
        job = self.job
        try:
            result = self.rx.recv()
        except (EOFError, OSError):
            code = self.stop(kill=True)
            self.start().wait_ready()
            return died_result(job, code, time.perf_counter() - self.started)
        self.job = None
        return result

    def expire(self) -> dict[str, Any]:
        """Kill the process running an overdue job, start a fresh one, and return the job's
        'timeout' result."""
        job, elapsed = self.job, time.perf_counter() - self.started
        self.stop(kill=True)
        self.start().wait_ready()
        return timeout_result(job, elapsed)

    def run(self, job: Job) -> dict[str, Any]:
        """Run one job to its end or its limit (blocking)."""
        self.submit(job)
        if self.rx.poll(max(0.0, self.deadline - time.perf_counter())):
            return self.collect()
        return self.expire()


class LocalEngine:
    """N worker processes on this machine; each job goes to the next idle one."""

    name = "local"

    def __init__(self, workers: int):
        if workers < 1:
            raise ConfigError(f"--workers must be at least 1, got {workers}")
        self.workers = workers

    def run(self, jobs: Iterable[Job], on_result: OnResult) -> None:
        """Run every job, calling ``on_result(job, result)`` in this process as each ends."""
        pending = list(jobs)
        pending.reverse()                       # pop() from the end hands out in order
        pool = [Worker(f"local-{k}") for k in range(min(self.workers, len(pending)))]
        try:
            for w in pool:
                w.start()
            for w in pool:
                w.wait_ready()
            busy: dict[int, Worker] = {}
            while pending or busy:
                for w in pool:
                    if w.job is None and pending:
                        w.submit(pending.pop())
                        busy[id(w)] = w
                now = time.perf_counter()
                soonest = min(w.deadline for w in busy.values())
                ready = wait([w.rx for w in busy.values()], timeout=max(0.0, soonest - now))
                for w in list(busy.values()):
                    if w.rx in ready:
                        job = w.job
                        result = w.collect()
                        del busy[id(w)]
                        on_result(job, result)
                now = time.perf_counter()
                for w in list(busy.values()):
                    if w.deadline <= now and w.job is not None:
                        job = w.job
                        result = w.expire()
                        del busy[id(w)]
                        on_result(job, result)
        finally:
            for w in pool:
                w.stop(kill=w.job is not None)


_DASK_WORKER: Worker | None = None


def run_in_worker_process(job: Job) -> dict[str, Any]:
    """Run ``job`` in this process's own worker child (a Dask task's body): the same time
    limit and isolation as the local pool. The child is started on first use and lives as
    long as this process."""
    global _DASK_WORKER
    if _DASK_WORKER is None:
        _DASK_WORKER = Worker(f"dask-{os.getpid()}")
    return _DASK_WORKER.run(job)
