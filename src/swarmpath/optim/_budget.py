"""Counting evaluations and enforcing an evaluation budget (the stopping rule's other half)."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.optim.problem import Problem


class BudgetExhausted(Exception):
    """Raised (and caught inside the optimiser) when the next batch would exceed the budget."""


class Evaluator:
    """Evaluates batches of points on ``problem`` and counts them.

    A batch that would take the count above ``max_evaluations`` is not evaluated at all:
    :class:`BudgetExhausted` is raised instead and the optimiser ends the run with the best it
    has, so ``count <= max_evaluations`` always holds.
    """

    def __init__(self, problem: Problem, max_evaluations: int | None) -> None:
        self.problem = problem
        self.max_evaluations = max_evaluations
        self.count = 0

    def remaining(self) -> int | None:
        """Evaluations left, or None without a limit."""
        return None if self.max_evaluations is None else self.max_evaluations - self.count

    def __call__(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        """Objective values of X, shape (n_points,) or (n_points, n_objectives)."""
        n = int(X.shape[0])
        if self.max_evaluations is not None and self.count + n > self.max_evaluations:
            raise BudgetExhausted
        F = self.problem.evaluate(X)
        self.count += n
        return F
