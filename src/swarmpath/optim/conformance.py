"""``check_optimizer``: the conformance checks every optimiser (built-in or plug-in) should pass.

Returns a list of problems (empty = conforms), like swarmpath.testing's planner and controller
checks: same seed gives the same result, the evaluation count is honest and the budget is kept,
the best value never gets worse, bad arguments raise ConfigError, a seeded initial swarm is
used, and the optimiser beats random search on a 10-D sphere at equal evaluations.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.optim.base import Optimizer
from swarmpath.optim.functions import sphere
from swarmpath.optim.problem import Problem


class _Counting:
    def __init__(self) -> None:
        self.points = 0

    def __call__(self, X: np.ndarray) -> np.ndarray:
        self.points += X.shape[0]
        return sphere(X)


def _sphere(dim: int, counter: _Counting | None = None) -> Problem:
    return Problem(counter or sphere, -100.0, 100.0, dim=dim, name="sphere")


def check_optimizer(make_optimizer: Callable[[], Optimizer], seeds: tuple[int, ...] = (0, 1, 2, 3, 4)) -> list[str]:
    """Run the conformance checks on optimisers made by ``make_optimizer()``; list the problems."""
    problems: list[str] = []
    opt = make_optimizer()
    # determinism
    a = opt.minimize(_sphere(10), iterations=20, particles=10, rng=7)
    b = make_optimizer().minimize(_sphere(10), iterations=20, particles=10, rng=7)
    if not (np.array_equal(a.x, b.x) and np.array_equal(a.history, b.history) and a.f == b.f):
        problems.append("same seed gave different results")
    # consistency of the result
    if a.f != a.f or abs(a.f - float(sphere(a.x))) > 1e-9 * max(1.0, abs(a.f)):
        problems.append(f"result.f = {a.f} is not the objective at result.x ({float(sphere(a.x))})")
    if np.any(np.diff(a.history) > 0):
        problems.append("the best-so-far history gets worse")
    if np.any(a.x < -100) or np.any(a.x > 100):
        problems.append("result.x lies outside the box")
    # honest evaluation count and the budget
    counter = _Counting()
    res = opt.minimize(_sphere(10, counter), iterations=12, particles=10, rng=2)
    if res.n_evaluations != counter.points:
        problems.append(f"reported {res.n_evaluations} evaluations, made {counter.points}")
    capped = _Counting()
    res = opt.minimize(_sphere(10, capped), iterations=10_000, particles=10, rng=2, max_evaluations=255)
    if capped.points > 255 or res.stop_reason != "max_evaluations":
        problems.append(f"max_evaluations=255 not respected ({capped.points} evaluations, stop {res.stop_reason!r})")
    # bad input is reported
    for kwargs in (dict(iterations=0, particles=10), dict(iterations=5, particles=1),
                   dict(iterations=5, particles=10, initial=np.zeros((11, 10)))):
        try:
            opt.minimize(_sphere(10), **kwargs)
        except ConfigError:
            pass
        except Exception as exc:  # noqa: BLE001 - we report what went wrong
            problems.append(f"{kwargs}: raised {type(exc).__name__} instead of ConfigError")
        else:
            problems.append(f"{kwargs}: accepted")
    # a seeded initial swarm is used
    start = np.zeros((1, 10))
    if opt.minimize(_sphere(10), iterations=3, particles=10, rng=0, initial=start).f > 1e-20:
        problems.append("the optimum given in `initial` was lost")
    # better than random search at equal evaluations
    ours, rand = [], []
    for seed in seeds:
        r = opt.minimize(_sphere(10), iterations=250, particles=20, rng=seed, max_evaluations=5000)
        ours.append(r.f)
        n = max(1, min(r.n_evaluations, 5000))
        pts = np.random.default_rng(1000 + seed).uniform(-100, 100, size=(n, 10))
        rand.append(float(sphere(pts).min()))
    if not np.median(ours) < 0.5 * np.median(rand):
        problems.append(f"median {np.median(ours):.3g} is not below half of random search's {np.median(rand):.3g}")
    return problems
