"""Repeated runs of one optimiser on one benchmark function: what ``swarmpath optimize`` prints.

Run r of a benchmark with seed s draws its optimiser stream from ``make_rng(s, "run", r,
"optimizer")`` and the function's noise from ``make_rng(s, "run", r, "function")``: every run is
reproducible on its own, and two algorithms run with the same seed start run r from the same
initial swarm (the PSO family draws the swarm first), which makes paired tests fair.
"""
from __future__ import annotations

import math
import time
from typing import Any, Callable

#: progress(done, total): called after each finished run (the CLI's progress bar).
Progress = Callable[[int, int], None]

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.optim._checks import check_int
from swarmpath.optim.functions import get_function
from swarmpath.optim.minimize import make_optimizer
from swarmpath.optim.result import OptimizeResult
from swarmpath.rng import make_rng


def run_rngs(seed: int, run: int) -> tuple[np.random.Generator, np.random.Generator]:
    """(optimiser generator, function-noise generator) of run ``run`` under ``seed``."""
    return make_rng(seed, "run", str(run), "optimizer"), make_rng(seed, "run", str(run), "function")


def benchmark_results(
    algorithm: str,
    function: str,
    dim: int,
    particles: int,
    iterations: int,
    runs: int,
    seed: int,
    progress: Progress | None = None,
    *,
    max_evaluations: int | None = None,
    **hyper: Any,
) -> list[OptimizeResult]:
    """The :class:`OptimizeResult` of each of ``runs`` runs (see :func:`run_benchmark`).

    ``hyper`` configures the optimiser (e.g. ``c1=1.5``); ``max_evaluations`` caps each run.
    """
    optimizer = make_optimizer(algorithm, **hyper)
    bench = get_function(function)
    dim = check_int("benchmark", "dim", dim, bench.min_dim)
    particles = check_int("benchmark", "particles", particles, optimizer.min_particles)
    iterations = check_int("benchmark", "iterations", iterations, 1)
    runs = check_int("benchmark", "runs", runs, 1)
    seed = check_int("benchmark", "seed", seed, 0)
    if progress is not None and not callable(progress):
        raise ConfigError("benchmark: progress must be callable or None")
    results = []
    for r in range(runs):
        opt_rng, noise_rng = run_rngs(seed, r)
        problem = bench.problem(dim, rng=noise_rng)
        results.append(
            optimizer.minimize(
                problem, iterations=iterations, particles=particles, rng=opt_rng, max_evaluations=max_evaluations
            )
        )
        if progress is not None:
            progress(r + 1, runs)
    return results


def summarise(values: list[float]) -> dict[str, float]:
    """min, mean, std (population, ddof = 0, so one run gives 0) and median of ``values``."""
    a = np.asarray(values, dtype=float)
    return {
        "min": float(a.min()),
        "mean": float(a.mean()),
        "std": float(a.std()),
        "median": float(np.median(a)),
    }


def run_benchmark(
    algorithm: str,
    function: str,
    dim: int,
    particles: int,
    iterations: int,
    runs: int,
    seed: int,
    progress: Progress | None = None,
) -> dict[str, Any]:
    """Run ``algorithm`` ``runs`` times on the registered ``function`` in ``dim`` dimensions.

    Returns the JSON object of ``swarmpath optimize --json`` (docs/guide.md):
    {"algorithm", "function", "dim", "runs", "min", "mean", "std", "best_per_run"}, plus
    "median", "particles", "iterations", "seed", "evaluations" (total over the runs) and
    "wall_time_s" (total). ``std`` is the population standard deviation of best_per_run.
    ``progress(done, total)`` is called after each finished run (done = runs so far,
    total = ``runs``).

    Raises UnknownNameError for an unknown algorithm or function and ConfigError for a bad
    number (one-line messages).
    """
    start = time.perf_counter()
    results = benchmark_results(algorithm, function, dim, particles, iterations, runs, seed, progress)
    best = [float(r.f) for r in results]
    stats = summarise(best)
    return {
        "algorithm": algorithm,
        "function": function,
        "dim": int(dim),
        "runs": int(runs),
        "min": stats["min"],
        "mean": stats["mean"],
        "std": stats["std"],
        "best_per_run": [b if math.isfinite(b) else None for b in best],
        "median": stats["median"],
        "particles": int(particles),
        "iterations": int(iterations),
        "seed": int(seed),
        "evaluations": int(sum(r.n_evaluations for r in results)),
        "wall_time_s": time.perf_counter() - start,
    }
