"""The front door: ``minimize(problem, "amopso3", iterations=..., particles=..., seed=...)``."""
from __future__ import annotations

import dataclasses
from typing import Any

from numpy.typing import ArrayLike

from swarmpath.errors import ConfigError
from swarmpath.optim.base import Optimizer
from swarmpath.optim.problem import Problem
from swarmpath.optim.result import OptimizeResult
from swarmpath.registry import OPTIMIZERS
from swarmpath.types import SeedLike


def make_optimizer(algorithm: str, **hyper: Any) -> Optimizer:
    """The registered optimiser ``algorithm`` configured with ``hyper``.

    Unknown names raise UnknownNameError (listing the known ones); unknown hyperparameters
    raise ConfigError naming the accepted ones, so a typo never passes silently.
    """
    cls = OPTIMIZERS.get(algorithm)
    if dataclasses.is_dataclass(cls):
        accepted = {f.name for f in dataclasses.fields(cls) if f.init}
        unknown = sorted(set(hyper) - accepted)
        if unknown:
            raise ConfigError(
                f"{algorithm}: unknown hyperparameter {unknown[0]!r}; accepted: {', '.join(sorted(accepted)) or 'none'}"
            )
    try:
        return cls(**hyper)
    except TypeError as exc:
        raise ConfigError(f"{algorithm}: {exc}") from None


def minimize(
    problem: Problem,
    algorithm: str | Optimizer = "pso",
    *,
    iterations: int,
    particles: int,
    seed: SeedLike = 0,
    initial: ArrayLike | None = None,
    max_evaluations: int | None = None,
    **hyper: Any,
) -> OptimizeResult:
    """Minimise ``problem`` with the optimiser ``algorithm`` (a registered name or an instance).

    Parameters
    ----------
    problem : Problem
    algorithm : str or Optimizer
        ``pso``, ``amopso1`` .. ``amopso4``, ``mopso``, ``cso``, ``afsa`` or a configured
        optimiser (then ``hyper`` must be empty).
    iterations, particles : int
        The budget: swarm iterations (the initial swarm is the first) and swarm size.
    seed : int or numpy.random.Generator
        The run's seed; the same seed gives the same result, bit for bit.
    initial : array_like of shape (k, dim), optional
        Starting positions of the first k particles.
    max_evaluations : int, optional
        Stop before exceeding this many evaluations.
    **hyper
        Hyperparameters of the optimiser (e.g. ``c1=1.5`` for ``pso``, ``update="amopso3"``
        and ``mode="weighted-sum"`` for ``mopso``).

    Examples
    --------
    >>> from swarmpath.optim import Problem, minimize
    >>> p = Problem(lambda X: (X**2).sum(axis=1), [-5] * 3, [5] * 3)
    >>> minimize(p, "pso", iterations=200, particles=20, seed=1).f < 1e-3
    True
    """
    if isinstance(algorithm, Optimizer):
        if hyper:
            raise ConfigError(f"{algorithm.name}: pass hyperparameters to the optimiser's constructor, not to minimize")
        optimizer = algorithm
    else:
        optimizer = make_optimizer(algorithm, **hyper)
    return optimizer.minimize(
        problem,
        iterations=iterations,
        particles=particles,
        rng=seed,
        initial=initial,
        max_evaluations=max_evaluations,
    )
