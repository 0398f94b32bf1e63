"""Grid robots among obstacles that never stop: how often every robot gets home with no contact.

Run on demand (not a test):
    python benchmarks/bench_moving.py [--seeds 3000:3200] [--controllers pibt cat-swarm]
                                      [--peers] [--workers 2]

Test: the grid controllers' acceptance world (``random_grid_with_movers``, also used by
tests/sim/test_acceptance_online.py on seeds 0-19): 100 point robots on a 64 x 64 map with
10 % of the cells blocked, among 20 one-cell obstacles that never stop (bounce8 and random
walkers in turn), each seed its own map, robots and obstacles. Every run is the simulator's
own, with its step budget, its checker counting every contact, and success meaning every
robot on its goal at the end AND no contact of any kind (robot-robot, robot-static,
robot-moving). The seeds default to 3000-3199, which no test uses and no choice in the
controllers was tuned on, so the rate is an honest estimate for an unseen seed.

Printed per method: successes out of runs with a 95 % Wilson interval, the chance that ten
seeds in a row succeed (rate^10, with the interval's ends), runs with a contact by kind, runs
ending with some robot away from its goal, steps (median, 95th percentile), wall time a run,
and the seeds that failed.

Peers (``--peers``, needs pymapf: pip install ".[bench]"): the anchors of the field plan for
static maps only. Their plan, computed for the same starts and goals and followed step by
step by the ``follow`` controller, shows what a static multi-agent plan meets among moving
obstacles: pymapf's LaCAM (4-connected, its own time limit 10 s) and swarmpath's own
``lacam`` (8-connected). Measured in the same run, on the same seeds.

Target (issue 14): 100 % of robots home at the end and zero contacts on 10 seeds, i.e. a
rate whose tenth power is near 1.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from multiprocessing import Pool
from pathlib import Path
from typing import Any, Callable, NoReturn

import numpy as np

from swarmpath.metrics.summary import run_summary
from swarmpath.planning.base import Plan, PlanStatus, RobotPlan
from swarmpath.registry import CONTROLLERS, PLANNERS
from swarmpath.runner import run_world, simulate
from swarmpath.world.generators import random_grid_with_movers

PEERS = ("pymapf-lacam+follow", "lacam+follow")
#: Most seeds one run of the script takes (a run is a few seconds each).
MAX_SEEDS = 100_000


def pair_of(method: str) -> tuple[str, str]:
    """(planner, controller) of a method: 'planner+controller', or a controller with astar."""
    return tuple(method.split("+", 1)) if "+" in method else ("astar", method)  # type: ignore[return-value]


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The 95 % Wilson score interval of a rate k / n."""
    if n == 0:
        return 0.0, 1.0
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def pymapf_plan(world, time_limit: float = 10.0) -> Plan | None:
    """pymapf's LaCAM (4-connected, unit costs) on the world's grid: a timed plan, or None."""
    from pymapf.algorithms.lacam import LaCAM
    from pymapf.core.grid import GridMap
    from pymapf.core.solver import Agent, MAPFProblem

    blocked = world.static_map.blocked
    starts = np.floor(world.starts).astype(int)
    goals = np.floor(world.goals).astype(int)
    agents = [Agent(f"a{i}", (int(s[1]), int(s[0])), (int(g[1]), int(g[0]))) for i, (s, g) in
              enumerate(zip(starts, goals))]
    t0 = time.perf_counter()
    sol = LaCAM(time_limit=time_limit, seed=0).solve(MAPFProblem(GridMap(blocked.astype(int).tolist()), agents,
                                                                 allow_diagonals=False))
    wall = time.perf_counter() - t0
    if sol is None or sol.first_conflict() is not None:
        return None
    length = max(len(p) for p in sol.paths.values())
    robots = []
    for i, r in enumerate(world.robots):
        cells = sol.paths[f"a{i}"]
        cells = cells + [cells[-1]] * (length - len(cells))                     # parked on the goal
        path = np.array([(c + 0.5, row + 0.5) for row, c in cells], float)
        robots.append(RobotPlan(r.id, PlanStatus.EXACT, path, {}, np.arange(length, dtype=np.int64)))
    return Plan("pymapf-lacam", tuple(robots), wall)


def one(job: tuple[str, int]) -> dict:
    """One run of ``method`` on ``seed``'s world: its outcome as plain numbers."""
    method, seed = job
    world = random_grid_with_movers(seed)
    t0 = time.perf_counter()
    if method == "pymapf-lacam+follow":
        plan = pymapf_plan(world)
        if plan is None:
            return dict(method=method, seed=seed, ok=False, planned=False, wall=time.perf_counter() - t0)
        traj = simulate(world, "follow", plan, seed=seed)
        summary = run_summary(world, traj, plan, planner="pymapf-lacam", controller="follow", clearance=False)
    else:
        planner, controller = pair_of(method)
        summary = run_world(world, planner=planner, controller=controller, seed=seed, clearance=False).summary
    return dict(method=method, seed=seed, ok=bool(summary.success), planned=True, steps=int(summary.steps),
                home=int(summary.reached), n=int(summary.n_robots), collisions=dict(summary.collisions),
                wall=time.perf_counter() - t0)


def report(method: str, rows: list[dict]) -> None:
    n = len(rows)
    k = sum(r["ok"] for r in rows)
    lo, hi = wilson(k, n)
    planned = [r for r in rows if r["planned"]]
    kinds = {kind: sum(r["collisions"][kind] > 0 for r in planned) for kind in ("robot_robot", "robot_static",
                                                                                 "robot_moving")}
    short = sum(r["home"] < r["n"] for r in planned)
    steps = np.array([r["steps"] for r in planned]) if planned else np.zeros(1)
    print(f"\n{method}: {k} of {n} runs succeed ({100 * k / n:.1f} %, 95 % interval {100 * lo:.1f}-{100 * hi:.1f} %)")
    print(f"  ten seeds in a row: {(k / n) ** 10:.2f} (interval {lo ** 10:.2f}-{hi ** 10:.2f})")
    if len(planned) < n:
        print(f"  no plan: {n - len(planned)} runs")
    per_run = np.mean([sum(r["collisions"].values()) for r in planned]) if planned else 0.0
    print(f"  runs with a contact: robot-robot {kinds['robot_robot']}, robot-static {kinds['robot_static']}, "
          f"robot-moving {kinds['robot_moving']} ({per_run:.2f} contacts a run); runs ending with a robot away "
          f"from its goal: {short}")
    print(f"  steps: median {np.median(steps):.0f}, 95th percentile {np.percentile(steps, 95):.0f}; "
          f"wall time a run {np.mean([r['wall'] for r in rows]):.2f} s")
    failed = [r["seed"] for r in rows if not r["ok"]]
    if failed and len(failed) == n:
        print("  failed seeds: all")
    else:
        print(f"  failed seeds: {' '.join(map(str, failed[:40])) or 'none'}{' ...' if len(failed) > 40 else ''}")


def fail(message: str) -> NoReturn:
    """Bad input: one line on standard error naming the script, exit code 2."""
    print(f"{Path(sys.argv[0]).name}: {message}", file=sys.stderr)
    raise SystemExit(2)


def seeds_of(text: str) -> list[int]:
    """'a:b' (a to b - 1) or a comma list."""
    try:
        if ":" in text:
            a, b = (int(v) for v in text.split(":"))
            if b - a > MAX_SEEDS:
                fail(f"--seeds names {b - a} seeds (at most {MAX_SEEDS})")
            return list(range(a, b))
        return [int(v) for v in text.split(",")]
    except ValueError:
        fail(f"--seeds must be 'a:b' or a comma list of whole numbers, got {text!r}")


def checked_seeds(text: str) -> list[int]:
    """The seeds of ``--seeds`` (:func:`seeds_of`): at least one, none below 0, else one line
    and exit code 2."""
    seeds = seeds_of(text)
    if not seeds:
        fail(f"--seeds {text!r} names no seed (in 'a:b', b must be above a)")
    if min(seeds) < 0:
        fail(f"--seeds must be whole numbers >= 0, got {min(seeds)}")
    return seeds


def run_all(one: Callable[[Any], dict], jobs: list, workers: int) -> list[dict]:
    """``one`` of every job on ``workers`` processes, in the order they finish; a progress bar
    in a terminal, a plain line every 30 s (and at the end) in logs and pipes."""
    results: list[dict] = []
    t0 = last = time.perf_counter()
    with Pool(workers) as pool:
        if sys.stderr.isatty():
            from rich.progress import Progress

            with Progress(transient=True) as bar:
                task = bar.add_task("runs", total=len(jobs))
                for r in pool.imap_unordered(one, jobs):
                    results.append(r)
                    bar.advance(task)
        else:
            for r in pool.imap_unordered(one, jobs):
                results.append(r)
                if time.perf_counter() - last >= 30 or len(results) == len(jobs):
                    last = time.perf_counter()
                    print(f"{len(results)}/{len(jobs)} runs, {last - t0:.0f} s", file=sys.stderr, flush=True)
    return results


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="3000:3200", help="'a:b' (a to b - 1) or a comma list (default 3000:3200)")
    ap.add_argument("--controllers", nargs="+", default=["pibt", "cat-swarm"],
                    help="controllers (with the astar planner) or planner+controller pairs")
    ap.add_argument("--peers", action="store_true", help="also the static MAPF plans followed blindly (pymapf)")
    ap.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    args = ap.parse_args()
    seeds = checked_seeds(args.seeds)
    if args.workers < 1:
        fail(f"--workers must be >= 1, got {args.workers}")
    for method in args.controllers:
        planner, controller = pair_of(method)
        if planner not in PLANNERS or controller not in CONTROLLERS:
            fail(f"--controllers: {method!r} is not a controller or planner+controller pair "
                 f"(controllers: {', '.join(CONTROLLERS.names())})")
    if args.peers:
        try:
            import pymapf  # noqa: F401
        except ImportError:
            fail('--peers needs pymapf (pip install ".[bench]")')
    methods = list(args.controllers) + (list(PEERS) if args.peers else [])
    jobs = [(m, s) for m in methods for s in seeds]
    print(f"{len(seeds)} seeds x {len(methods)} methods on the 64 x 64 world with 100 robots and 20 moving obstacles")
    results = run_all(one, jobs, args.workers)
    for m in methods:
        report(m, sorted((r for r in results if r["method"] == m), key=lambda r: r["seed"]))


if __name__ == "__main__":
    main()
