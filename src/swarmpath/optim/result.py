"""What an optimiser returns: a frozen record of the best point, its value and how it got there."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class OptimizeResult:
    """The outcome of one optimiser run.

    Attributes
    ----------
    x : ndarray of shape (dim,)
        The best position found.
    f : float
        The scalar value ``x`` minimises: the objective for one-objective problems, the weighted
        sum (eq. 13) in weighted-sum mode, and for a Pareto run the weighted sum of the archive
        member chosen as ``x`` (equal weights unless the optimiser was given some).
    history : ndarray
        Best-so-far value after each iteration, shape (n_iterations,). A Pareto run with several
        objectives records the archive's per-objective minima instead: shape
        (n_iterations, n_objectives).
    n_evaluations : int
        Number of points the objective function was evaluated on.
    n_iterations : int
        Iterations completed (the initial swarm counts as iteration 1).
    wall_time_s : float
        Wall-clock time of the run in seconds.
    algorithm : str
        Registered name of the optimiser.
    seed : int or None
        The integer seed of the run (None when a Generator was passed).
    stop_reason : str
        ``"iterations"`` (the budget of iterations was used up) or ``"max_evaluations"``.
    objectives : ndarray of shape (n_objectives,)
        The raw objective vector at ``x``.
    pareto_x : ndarray of shape (n_archive, dim), or None
        The external archive of non-dominated positions (eq. 14); None for single-swarm
        optimisers that keep no archive.
    pareto_f : ndarray of shape (n_archive, n_objectives), or None
        Objective vectors of ``pareto_x``.
    params : mapping
        The optimiser's hyperparameters, for reports.
    """

    x: NDArray[np.float64]
    f: float
    history: NDArray[np.float64]
    n_evaluations: int
    n_iterations: int
    wall_time_s: float
    algorithm: str
    seed: int | None
    stop_reason: str
    objectives: NDArray[np.float64]
    pareto_x: NDArray[np.float64] | None = None
    pareto_f: NDArray[np.float64] | None = None
    params: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("x", "history", "objectives", "pareto_x", "pareto_f"):
            value = getattr(self, name)
            if value is not None:
                value = np.array(value, dtype=float)
                value.flags.writeable = False
                object.__setattr__(self, name, value)
        object.__setattr__(self, "f", float(self.f))
        object.__setattr__(self, "params", MappingProxyType(dict(self.params)))
