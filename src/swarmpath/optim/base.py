"""The interface every optimiser shares, and the bookkeeping around one run.

An optimiser is a frozen dataclass of hyperparameters (STYLE habit 2): the problem, the budget
and the random generator arrive through :meth:`Optimizer.minimize`, so one configured optimiser
can run over many problems and seeds. Subclasses implement ``_run`` (the algorithm) and
``_check_hyperparameters``; this class validates the common arguments, measures time, counts
evaluations and assembles the frozen :class:`~swarmpath.optim.result.OptimizeResult`.
"""
from __future__ import annotations

import abc
import dataclasses
import time
from typing import Any, ClassVar, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError
from swarmpath.optim._budget import Evaluator
from swarmpath.optim._checks import check_int
from swarmpath.optim.problem import Problem
from swarmpath.optim.result import OptimizeResult
from swarmpath.rng import make_rng
from swarmpath.types import SeedLike


class RunOutput(NamedTuple):
    """What an algorithm's ``_run`` hands back to :meth:`Optimizer.minimize`."""

    x: NDArray[np.float64]
    f: float
    history: NDArray[np.float64]
    n_iterations: int
    stop_reason: str
    objectives: NDArray[np.float64]
    pareto_x: NDArray[np.float64] | None = None
    pareto_f: NDArray[np.float64] | None = None


#: Largest swarm (particles x dimensions) a run may ask for: a few arrays of this many floats
#: must fit in memory several times over.
MAX_SWARM_VALUES = 50_000_000


@dataclasses.dataclass(frozen=True)
class Optimizer(abc.ABC):
    """Base class: ``minimize(problem, *, iterations, particles, rng)`` -> OptimizeResult.

    Class attributes
    ----------------
    multi_objective : bool
        Whether the optimiser accepts problems with several objectives (capabilities as data,
        STYLE habit 8).
    min_particles : int
        Smallest swarm the algorithm works with.
    """

    multi_objective: ClassVar[bool] = False
    min_particles: ClassVar[int] = 2

    @property
    def name(self) -> str:
        """The registered name (``pso``, ``amopso3``, ...), used in messages and results."""
        return getattr(type(self), "registered_name", type(self).__name__.lower())

    def params(self) -> dict[str, Any]:
        """The hyperparameters as a plain dict."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def minimize(
        self,
        problem: Problem,
        *,
        iterations: int,
        particles: int,
        rng: SeedLike = None,
        initial: ArrayLike | None = None,
        max_evaluations: int | None = None,
    ) -> OptimizeResult:
        """Minimise ``problem`` with a swarm of ``particles`` for ``iterations`` iterations.

        Parameters
        ----------
        problem : Problem
        iterations : int
            Number of swarm iterations; the initial swarm is iteration 1, so a PSO run evaluates
            exactly ``iterations * particles`` points (the paper's N = 8, Tmax = 120 is 960).
        particles : int
            Swarm size (cats, fish).
        rng : int or numpy.random.Generator, optional
            Seed or generator of the run; an int is recorded in the result. None means seed 0.
        initial : array_like of shape (k, dim), k <= particles, optional
            Positions for the first k particles (e.g. waypoints of an A* path); the others start
            uniformly at random in the box (eq. 31). Must lie inside the box.
        max_evaluations : int, optional
            A second stopping rule: the run ends before any batch of evaluations that would
            exceed it (``n_evaluations <= max_evaluations`` always).
        """
        owner = self.name
        if not isinstance(problem, Problem):
            raise ConfigError(f"{owner}: problem must be a swarmpath.optim.Problem, got {type(problem).__name__}")
        if problem.n_objectives > 1 and not self.multi_objective:
            raise ConfigError(
                f"{owner}: handles one objective, the problem has {problem.n_objectives} (use mopso)"
            )
        iterations = check_int(owner, "iterations", iterations, 1)
        particles = check_int(owner, "particles", particles, self.min_particles)
        if particles * problem.dim > MAX_SWARM_VALUES:
            raise ConfigError(f"{owner}: a swarm of {particles:,} particles in {problem.dim:,} dimensions holds "
                              f"{particles * problem.dim:,} numbers per array; at most {MAX_SWARM_VALUES:,}")
        if max_evaluations is not None:
            max_evaluations = check_int(owner, "max_evaluations", max_evaluations, 1)
            if max_evaluations < particles:
                raise ConfigError(
                    f"{owner}: max_evaluations ({max_evaluations}) is smaller than one swarm "
                    f"({particles} particles)"
                )
        init = self._check_initial(problem, initial, particles)
        self._check_hyperparameters(problem)
        if isinstance(rng, np.random.Generator):
            seed = None
        elif rng is None:
            seed = 0
        else:
            seed = rng  # make_rng validates it
        gen = make_rng(rng)
        evaluator = Evaluator(problem, max_evaluations)
        start = time.perf_counter()
        out = self._run(problem, evaluator, iterations=iterations, particles=particles, rng=gen, initial=init)
        wall = time.perf_counter() - start
        return OptimizeResult(
            x=out.x,
            f=out.f,
            history=out.history,
            n_evaluations=evaluator.count,
            n_iterations=out.n_iterations,
            wall_time_s=wall,
            algorithm=owner,
            seed=None if seed is None else int(seed),
            stop_reason=out.stop_reason,
            objectives=out.objectives,
            pareto_x=out.pareto_x,
            pareto_f=out.pareto_f,
            params=self.params(),
        )

    # -- for subclasses -------------------------------------------------------------------
    def _check_hyperparameters(self, problem: Problem) -> None:
        """Raise ConfigError for an invalid hyperparameter (called at the start of minimize)."""

    @abc.abstractmethod
    def _run(
        self,
        problem: Problem,
        evaluate: Evaluator,
        *,
        iterations: int,
        particles: int,
        rng: np.random.Generator,
        initial: NDArray[np.float64] | None,
    ) -> RunOutput:
        """The algorithm: run on ``evaluate`` (a counting wrapper of the problem) and report."""

    def _check_initial(
        self, problem: Problem, initial: ArrayLike | None, particles: int
    ) -> NDArray[np.float64] | None:
        if initial is None:
            return None
        owner = self.name
        arr = np.asarray(initial, dtype=float)
        if arr.ndim == 1:
            arr = arr[None, :]
        if arr.ndim != 2 or arr.shape[1] != problem.dim:
            raise ConfigError(f"{owner}: initial must have shape (k, {problem.dim}), got {np.shape(initial)}")
        if arr.shape[0] > particles:
            raise ConfigError(f"{owner}: initial has {arr.shape[0]} rows but there are only {particles} particles")
        if not np.all(np.isfinite(arr)):
            raise ConfigError(f"{owner}: initial positions must be finite")
        tol = 1e-9 * (problem.upper - problem.lower)
        outside = np.any((arr < problem.lower - tol) | (arr > problem.upper + tol), axis=1)
        if outside.any():
            k = int(np.argmax(outside))
            raise ConfigError(f"{owner}: initial[{k}] lies outside the problem's bounds")
        return np.clip(arr, problem.lower, problem.upper)


def initial_positions(
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
    particles: int,
    rng: np.random.Generator,
    initial: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Eq. 31: x = (b - a) * U(0, 1) + a, per particle and dimension; shape (particles, dim).

    The first ``len(initial)`` rows are replaced by ``initial``. All rows are drawn in any case,
    so that the random stream (and hence everything after it) does not depend on ``initial``.
    """
    x = lower + (upper - lower) * rng.random((particles, lower.shape[0]))
    if initial is not None:
        x[: initial.shape[0]] = initial
    return x
