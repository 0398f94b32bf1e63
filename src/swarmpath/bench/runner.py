"""The seeded batch runner every reproduction uses: one world, one controller, many seeds.

A reproduction describes *what* to measure of a run (a function of the trajectory and the
run's CPU time that returns a small record) and gets back one record per seed, the first
``keep`` trajectories and the CPU time of the batch. Seed s of every batch gives the same
obstacles and the same random streams, so batches over the same seeds are paired.
"""
from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Generic, TypeVar

from swarmpath.bench.progress import Progress
from swarmpath.control.base import Controller
from swarmpath.planning.base import Plan
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import Trajectory
from swarmpath.world.world import World

R = TypeVar("R")
Measure = Callable[[Trajectory, float], R]


@dataclass(frozen=True)
class Batch(Generic[R]):
    """The runs of one configuration: ``records[k]`` measures the run with ``seeds[k]``;
    ``kept`` holds the first trajectories (as many as asked for); ``cpu_s`` is the CPU time
    of the whole batch (simulation and measuring)."""

    label: str
    seeds: tuple[int, ...]
    records: tuple[R, ...]
    kept: tuple[Trajectory, ...]
    cpu_s: float

    @property
    def n_runs(self) -> int:
        return len(self.seeds)


def run_batch(world: World, make_controller: Callable[[], Controller], seeds: Iterable[int], measure: Measure[R], *,
              plan: Plan | None = None, label: str = "", keep: int = 0, max_steps: int | None = None,
              progress: Progress | None = None) -> Batch[R]:
    """Simulate ``world`` with a fresh controller from ``make_controller`` once per seed.

    Parameters
    ----------
    world, plan : the world and its offline plan (None: the controller needs none)
    make_controller : builds the controller of one run (hyperparameters only)
    seeds : the runs' seeds, in order
    measure : ``measure(trajectory, cpu_s)`` -> the record of one run (``cpu_s`` is the
        CPU time of that simulation)
    keep : how many of the first trajectories to return
    progress : ticked once per run

    Returns
    -------
    Batch with one record per seed.
    """
    seeds = tuple(int(s) for s in seeds)
    records: list[R] = []
    kept: list[Trajectory] = []
    t_batch = time.process_time()
    for s in seeds:
        t0 = time.process_time()
        traj = Simulator(world, make_controller(), plan, seed=s, max_steps=max_steps).run()
        records.append(measure(traj, time.process_time() - t0))
        if len(kept) < keep:
            kept.append(traj)
        if progress is not None:
            progress.tick()
    return Batch(label, seeds, tuple(records), tuple(kept), time.process_time() - t_batch)
