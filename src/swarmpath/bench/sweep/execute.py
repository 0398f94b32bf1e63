"""One job, run where a worker runs it: build (or reuse) the world, run the planner and
controller through the runner (or a peer through its adapter), summarise, and return a plain
dict that the parent stores. Whatever the job raises becomes ``status: "error"`` with one
line saying what; nothing a job does can stop the sweep.

The result holds the run's outcome (the ``run --json`` object without its timings) apart from
its timings, so that stored outcomes can be compared across engines and worker counts.
"""
from __future__ import annotations

import dataclasses
import time
import traceback
from collections import OrderedDict
from pathlib import Path
from typing import Any

from swarmpath.bench.sweep.jobs import Job

#: Fields of ``run --json`` that are timings, not outcomes.
TIMING_FIELDS = ("planning_time_s", "sim_time_s")
#: Worlds (and their lower bounds) a worker keeps for the jobs that follow.
WORLD_CACHE = 16
_WORLDS: "OrderedDict[tuple[str, int | None], tuple[Any, int | None]]" = OrderedDict()


def _world(job: Job) -> tuple[Any, int | None, float]:
    """The job's world, its lower bound and the seconds spent building them (0 when this
    worker built them for an earlier job: worlds are immutable)."""
    from swarmpath.bench.sweep.bounds import lower_bound
    from swarmpath.bench.sweep.worlds import build_world

    cache_key = (job.world_key, job.seed if job.seeded_world else None)
    hit = _WORLDS.get(cache_key)
    if hit is not None:
        _WORLDS.move_to_end(cache_key)
        return (*hit, 0.0)
    t0 = time.perf_counter()
    world = build_world(job.spec, job.seed)
    entry = (world, lower_bound(world))
    _WORLDS[cache_key] = entry
    while len(_WORLDS) > WORLD_CACHE:
        _WORLDS.popitem(last=False)
    return (*entry, time.perf_counter() - t0)


def _run_ours(world: Any, job: Job):
    """The run's summary: ``run_world`` itself when no parameters are given, else the same
    steps with configured instances (plan, simulate, summarise)."""
    from swarmpath.registry import CONTROLLERS, PLANNERS
    from swarmpath.runner import choose_pair, run_world, simulate

    if not job.planner_params and not job.controller_params:
        return run_world(world, planner=job.planner, controller=job.controller, seed=job.seed,
                         max_steps=job.max_steps).summary
    from swarmpath.bench.sweep.params import construct
    from swarmpath.metrics.summary import run_summary

    planner, controller = choose_pair(world, job.planner, job.controller)
    plan = None
    planning_time = 0.0
    if planner != "none":
        t0 = time.perf_counter()
        plan = construct(PLANNERS.get(planner), job.planner_params).plan(world, rng=job.seed)
        planning_time = time.perf_counter() - t0
        if not plan.robots:
            plan = None
    traj = simulate(world, construct(CONTROLLERS.get(controller), job.controller_params), plan, seed=job.seed,
                    max_steps=job.max_steps)
    traj = dataclasses.replace(traj, meta={**traj.meta, "planning_time_s": planning_time})
    return run_summary(world, traj, plan, planner=planner, controller=controller, planning_time_s=planning_time)


def _run_peer(world: Any, job: Job) -> tuple[Any, int, str]:
    """A peer's run as a swarmpath summary, its contacts found by swarmpath's checker; also
    the number of violations ``validate_trajectory`` finds and the peer's name and version."""
    import numpy as np

    from swarmpath.bench.sweep.params import construct
    from swarmpath.bench.sweep.peers import PEERS
    from swarmpath.metrics.summary import run_summary
    from swarmpath.sim.collisions import step_contacts
    from swarmpath.sim.simulator import default_max_steps
    from swarmpath.sim.trajectory import Termination, Trajectory
    from swarmpath.testing import validate_trajectory

    peer = construct(PEERS[job.controller], job.controller_params)
    budget = job.max_steps or default_max_steps(world)
    positions, info = peer.solve(world, seed=job.seed, max_steps=budget, time_limit=0.9 * job.timeout_s)
    positions = np.asarray(positions, float)
    n_rows = positions.shape[0]
    obstacles = np.zeros((n_rows, 0, 2))
    contacts = []
    for t in range(1, n_rows):
        contacts += step_contacts(world, t, positions[t - 1], positions[t], obstacles[t - 1], obstacles[t])
    reached = bool(np.all(np.linalg.norm(positions[-1] - world.goals, axis=1) <= 1e-9))
    traj = Trajectory(scenario=world.name, seed=job.seed, dt=world.dt, resolution=world.resolution,
                      robot_ids=[r.id for r in world.robots], radii=world.radii, goals=world.goals,
                      positions=positions, obstacle_ids=[], obstacle_positions=obstacles, contacts=contacts,
                      status=Termination.ALL_REACHED if reached else Termination.TRUNCATED, world=world.to_dict(),
                      static_map=world.static_map.blocked if world.static_map is not None else None,
                      meta={"sim_time_s": float(info.get("sim_time_s", 0.0)), "peer": job.controller})
    planning = float(info.get("planning_time_s", 0.0))
    summary = run_summary(world, traj, None, planner=job.planner, controller=job.controller, planning_time_s=planning)
    violations = len(validate_trajectory(world, traj))
    return summary, violations, f"{peer.dist} {peer.version()}"


def describe_error(exc: BaseException) -> str:
    """One line: a swarmpath error's own message; anything else with its type and the last
    line of swarmpath code it passed through (a bug to report)."""
    from swarmpath.errors import SwarmpathError
    from swarmpath.world.limits import clean_text

    if isinstance(exc, SwarmpathError):
        text = str(exc) or type(exc).__name__
    else:
        where = ""
        for frame in reversed(traceback.extract_tb(exc.__traceback__)):
            parts = Path(frame.filename).parts
            if "swarmpath" in parts:
                rel = "/".join(parts[len(parts) - 1 - parts[::-1].index("swarmpath"):])
                where = f" (at {rel}:{frame.lineno})"
                break
        text = f"{type(exc).__name__}: {exc}{where}"
    line = " ".join(clean_text(text).split())
    return line if len(line) <= 1000 else line[:997] + "..."


def run_job(job: Job) -> dict[str, Any]:
    """Run ``job`` and return its result: ``status`` ("ok" or "error"), ``error``, the
    ``outcome`` (the ``run --json`` object without timings), ``lower_bound``, ``violations``
    (peers), ``source`` and ``timings``: ``setup_s`` (building the world and its lower bound,
    0 when this worker already had them), ``wall_s`` (the run itself: plan, simulate,
    summarise), and the run's own planning and simulation times."""
    t0 = time.perf_counter()
    out: dict[str, Any] = {"key": job.key, "status": "ok", "error": None, "outcome": None, "lower_bound": None,
                           "violations": None, "source": "swarmpath", "timings": {}}
    setup = 0.0
    try:
        world, bound, setup = _world(job)
        if job.peer:
            summary, out["violations"], out["source"] = _run_peer(world, job)
        else:
            summary = _run_ours(world, job)
        doc = summary.to_dict()
        out["timings"] = {k: doc.pop(k) for k in TIMING_FIELDS}
        out["outcome"] = doc
        out["lower_bound"] = bound
    except Exception as exc:   # noqa: BLE001 - a job's failure is its result, never the sweep's
        out.update(status="error", error=describe_error(exc), outcome=None)
    out["timings"]["setup_s"] = setup
    out["timings"]["wall_s"] = max(0.0, time.perf_counter() - t0 - setup)
    return out
