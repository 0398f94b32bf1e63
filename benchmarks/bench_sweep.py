"""Sweeps: speed-up of 2 workers over 1 on a CPU-bound suite, and what the harness adds per job.

Run on demand (not a test):  nice python benchmarks/bench_sweep.py [--seeds 24] [--tiny 200] [--dask]

1. CPU-bound suite: ``prediction2013`` with ``pso-predictive`` and ``jaleel2016`` with
   ``hybrid-apf`` + ``cat-swarm`` (0.3-2 s per job), ``--seeds`` seeds each, into a fresh store
   with 1 worker, then 2 workers (and ``--dask local`` with 2 workers when asked). Printed:
   wall time of each, the speed-up 1 -> 2 (target >= 1.8 on an otherwise idle 2-core machine),
   and whether the stored results are identical.
   Also printed: how busy the workers were (the jobs' own time / workers / wall time): a
   harness that keeps its workers fed is near 100 % whatever else the machine runs.
2. Harness overhead: ``--tiny`` jobs of 1-10 ms (``karim2014``, 8 steps) with 1 worker. The
   harness is everything but the job itself: expanding the suite, starting the worker,
   sending each job and its result over a pipe, writing the store. Printed: the sweep's wall
   time, the sum of the jobs' own times (measured in the worker, building their worlds
   included), the worker start-up, and (wall - jobs - start-up) / jobs (target < 50 ms), next
   to a plain in-process Python loop over ``run_world`` for the same jobs.

First a control: one pure-Python loop alone, then two copies in two processes. On a machine
whose cores are shared with other work, the control's ratio is the most any 2-worker run can
gain there; the sweep's speed-up is printed beside it.
"""
from __future__ import annotations

import argparse
import sqlite3
import tempfile
import time
from pathlib import Path

from swarmpath.bench.sweep.jobs import expand
from swarmpath.bench.sweep.pool import Worker
from swarmpath.bench.sweep.run import run_sweep
from swarmpath.bench.sweep.suite import load_suite

CPU_SUITE = """\
name: cpu-bound
scenarios:
  - scenario: prediction2013
    controllers: [pso-predictive]
  - scenario: jaleel2016
    methods: [{{planner: hybrid-apf, controller: cat-swarm}}]
seeds: {{count: {seeds}}}
timeout_s: 600
"""

TINY_SUITE = """\
name: tiny-jobs
scenarios: [karim2014]
controllers: [fish-swarm, pibt]
seeds: {{count: {half}}}
max_steps: 8
timeout_s: 60
"""


def outcomes(db: Path) -> list[tuple]:
    con = sqlite3.connect(db)
    try:
        return con.execute("SELECT * FROM results ORDER BY key").fetchall()
    finally:
        con.close()


def job_seconds(db: Path) -> float:
    con = sqlite3.connect(db)
    try:
        return float(con.execute("SELECT sum(wall_s + setup_s) FROM timings").fetchone()[0] or 0.0)
    finally:
        con.close()


def _burn(n: int) -> float:
    t0 = time.perf_counter()
    s = 0
    for i in range(n):
        s += i * i
    return time.perf_counter() - t0


def parallel_control(n: int = 20_000_000) -> float:
    """How much faster two processes finish two equal pure-Python loops than one process
    finishes one, times two: 2.0 on two idle cores."""
    import multiprocessing as mp

    alone = _burn(n)
    t0 = time.perf_counter()
    with mp.get_context("spawn").Pool(2) as pool:
        pool.map(_burn, [n, n])
    return 2 * alone / (time.perf_counter() - t0)


def timed_sweep(suite_path: Path, db: Path, workers: int, dask: str | None = None) -> float:
    suite = load_suite(suite_path)
    t0 = time.perf_counter()
    outcome = run_sweep(suite, db, workers=workers, dask=dask)
    wall = time.perf_counter() - t0
    assert outcome.ran == outcome.total, outcome
    return wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=24, help="seeds per method of the CPU-bound suite")
    ap.add_argument("--tiny", type=int, default=200, help="tiny jobs for the overhead measurement")
    ap.add_argument("--dask", action="store_true", help="also run the CPU-bound suite with --dask local")
    args = ap.parse_args()
    control = parallel_control()
    print(f"control: two pure-Python loops in two processes run {control:.2f}x as fast as one "
          f"(2.00 on two idle cores)", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cpu = folder / "cpu.yaml"
        cpu.write_text(CPU_SUITE.format(seeds=args.seeds))
        n = len(expand(load_suite(cpu)).jobs)
        walls = {}
        for workers in (1, 2):
            walls[workers] = timed_sweep(cpu, folder / f"cpu-{workers}.db", workers)
            own = job_seconds(folder / f"cpu-{workers}.db")
            print(f"CPU-bound suite, {n} jobs, {workers} worker{'s' if workers > 1 else ''}: {walls[workers]:.2f} s "
                  f"(jobs' own time {own:.2f} s: the workers were busy {100 * own / workers / walls[workers]:.0f} % "
                  "of the wall time)", flush=True)
        same = outcomes(folder / "cpu-1.db") == outcomes(folder / "cpu-2.db")
        speedup = walls[1] / walls[2]
        print(f"  speed-up 1 -> 2 workers: {speedup:.2f}x (target >= 1.8: {'met' if speedup >= 1.8 else 'NOT met'}; "
              f"the control reached {control:.2f}x); stored results identical: {same}", flush=True)
        if args.dask:
            wall = timed_sweep(cpu, folder / "cpu-dask.db", 2, dask="local")
            same = outcomes(folder / "cpu-1.db") == outcomes(folder / "cpu-dask.db")
            print(f"  --dask local, 2 workers: {wall:.2f} s ({walls[1] / wall:.2f}x over 1 local worker, cluster "
                  f"start-up included); stored results identical: {same}", flush=True)

        tiny = folder / "tiny.yaml"
        tiny.write_text(TINY_SUITE.format(half=max(1, args.tiny // 2)))
        jobs = expand(load_suite(tiny)).jobs
        t0 = time.perf_counter()
        Worker().start().wait_ready()
        startup = time.perf_counter() - t0
        wall = timed_sweep(tiny, folder / "tiny.db", 1)
        own = job_seconds(folder / "tiny.db")
        overhead = (wall - own - startup) / len(jobs)
        print(f"\n{len(jobs)} tiny jobs, 1 worker: sweep {wall:.2f} s, jobs' own time {own:.2f} s, worker start-up "
              f"{startup:.2f} s", flush=True)
        print(f"  harness overhead per job: {1000 * overhead:.2f} ms (target < 50 ms: "
              f"{'met' if overhead < 0.05 else 'NOT met'}); with the start-up spread over the jobs: "
              f"{1000 * (wall - own) / len(jobs):.2f} ms", flush=True)

        from swarmpath.runner import run_world
        from swarmpath.world import load_scenario

        world = load_scenario("karim2014")
        t0 = time.perf_counter()
        for job in jobs:
            run_world(world, planner=job.planner, controller=job.controller, seed=job.seed, max_steps=job.max_steps)
        loop = time.perf_counter() - t0
        print(f"  the same jobs as a plain Python loop over run_world (in memory, no store, no limits): {loop:.2f} s",
              flush=True)


if __name__ == "__main__":
    main()
