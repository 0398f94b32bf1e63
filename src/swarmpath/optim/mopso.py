"""Multi-objective PSO (section 3.2.2-3.2.3, Fig. 2): Pareto archive (eq. 14) or weighted sum (eq. 13).

Pareto mode follows Coello Coello, Pulido & Lechuga (2004) "Handling multiple objectives with
particle swarm optimization", with the crowding-distance archive of Raquel & Naval (2005):

- an external archive keeps the non-dominated positions found so far (eq. 14), at most
  ``archive_size`` of them, pruned by crowding distance;
- each particle's leader (the ``gbest`` of eq. 9-10) is drawn from the archive by a binary
  tournament on crowding distance (less crowded wins), which spreads the swarm along the front;
- a personal best is replaced by a new position that dominates it, kept if it dominates the
  new one, and otherwise replaced with probability 1/2;
- Coello's mutation perturbs a shrinking share of the particles early in the run.

Weighted-sum mode scalarises the objectives with weights that sum to 1 (eq. 13) and runs the
global-best update on the sum, still recording the archive of everything it evaluated.

The velocity rule is any of the single-objective ones: ``update="spso"`` (the paper's SPSO),
``"pso"`` (constriction) or ``"amopso1"`` ... ``"amopso4"``; the adaptive rules need one cost
per particle, which in Pareto mode is the mean of the objectives normalised by the archive's
ideal and nadir points.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError
from swarmpath.optim._budget import BudgetExhausted, Evaluator
from swarmpath.optim._checks import check_choice, check_float, check_int
from swarmpath.optim.amopso import AMOPSO_VARIANTS, amopso_rule
from swarmpath.optim.base import Optimizer, RunOutput, initial_positions
from swarmpath.optim.pareto import crowding_distance, dominates, non_dominated, truncate_by_crowding, unique_rows
from swarmpath.optim.problem import Problem
from swarmpath.optim.pso import (
    CONSTRICTION_ACCELERATION,
    CONSTRICTION_INERTIA,
    SPSORule,
    UpdateRule,
    swarm_move,
)
from swarmpath.registry import register_optimizer

Array = NDArray[np.float64]

UPDATE_RULES = ("spso", "pso", *(f"amopso{k}" for k in AMOPSO_VARIANTS))
MODES = ("pareto", "weighted-sum")


def update_rule(name: str) -> UpdateRule:
    """The velocity-update rule called ``name``, as the optimiser of that name uses it.

    "spso" (the paper's SPSO: eq. 32, c1 = c2 = 2), "pso" (constriction coefficients) or
    "amopso1".."amopso4" (Table 1).
    """
    if name == "spso":
        return SPSORule()
    if name == "pso":
        return SPSORule(CONSTRICTION_INERTIA, CONSTRICTION_INERTIA, CONSTRICTION_ACCELERATION, CONSTRICTION_ACCELERATION)
    if name.startswith("amopso") and name[6:].isdigit() and int(name[6:]) in AMOPSO_VARIANTS:
        return amopso_rule(int(name[6:]))
    raise ConfigError(f"mopso: update must be one of {', '.join(UPDATE_RULES)}; got {name!r}")


def weighted_sum(F: ArrayLike, weights: ArrayLike) -> Array:
    """Eq. 13: f(x) = sum_m W_m f_m(x); F (n, m), weights (m,) -> (n,)."""
    return np.asarray(F, dtype=float) @ np.asarray(weights, dtype=float)


def check_weights(owner: str, weights: ArrayLike, n_objectives: int) -> Array:
    """Weights of eq. 13 as an array (m,): each in [0, 1], summing to 1 (within 1e-9)."""
    w = np.asarray(weights, dtype=float)
    if w.shape != (n_objectives,):
        raise ConfigError(f"{owner}: weights must have {n_objectives} entries (one per objective), got {w.tolist()}")
    if not np.all(np.isfinite(w)) or np.any(w < 0) or np.any(w > 1):
        raise ConfigError(f"{owner}: weights must lie in [0, 1], got {w.tolist()}")
    if abs(w.sum() - 1.0) > 1e-9:
        raise ConfigError(f"{owner}: weights must sum to 1 (eq. 13), got sum {w.sum():.6g}")
    return w


def crowding_tournament(cd: Array, n: int, rng: np.random.Generator) -> NDArray[np.intp]:
    """Leader selection: for each of n particles, the less crowded of two random archive members.

    cd : ndarray of shape (n_archive,), crowding distances. Returns n archive indices.
    """
    k = cd.shape[0]
    if k == 1:
        return np.zeros(n, dtype=np.intp)
    a = rng.integers(0, k, n)
    b = rng.integers(0, k, n)
    return np.where(cd[b] > cd[a], b, a)


def pareto_pbest_update(pbest_F: Array, F: Array, rng: np.random.Generator) -> NDArray[np.bool_]:
    """Which personal bests to replace by the new objective vectors (Coello et al. 2004).

    pbest_F, F : ndarrays of shape (n, m). Replace when F dominates pbest_F; keep when pbest_F
    dominates F; otherwise replace with probability 1/2. Returns a mask of shape (n,).
    """
    new_wins = dominates(F, pbest_F)
    old_wins = dominates(pbest_F, F)
    coin = rng.random(F.shape[0]) < 0.5
    return np.asarray(new_wins | (~old_wins & coin))


def coello_mutation(
    x: Array,
    t: int,
    t_max: int,
    rate: float,
    lower: Array,
    upper: Array,
    rng: np.random.Generator,
) -> Array:
    """Coello's MOPSO mutation (Coello Coello, Pulido & Lechuga 2004, section 3.3).

    Strength p = (1 - t / (t_max * rate))^1.5 (0 once t >= t_max * rate): each particle is
    mutated with probability p; a mutated particle gets one random coordinate redrawn
    uniformly in [x_d - R, x_d + R] within the box, R = p * (upper_d - lower_d).

    x : ndarray of shape (n, dim) -> mutated copy of the same shape.
    """
    if rate <= 0.0 or t >= t_max * rate:
        return x
    p = (1.0 - t / (t_max * rate)) ** 1.5
    n, d = x.shape
    hit = rng.random(n) < p
    dims = rng.integers(0, d, n)
    u = rng.random(n)
    if not hit.any():
        return x
    rows = np.nonzero(hit)[0]
    cols = dims[rows]
    R = p * (upper[cols] - lower[cols])
    lo = np.maximum(x[rows, cols] - R, lower[cols])
    hi = np.minimum(x[rows, cols] + R, upper[cols])
    x = x.copy()
    x[rows, cols] = lo + (hi - lo) * u[rows]
    return x


def normalised_cost(F: Array, archive_F: Array) -> Array:
    """One cost per point for the adaptive rules: mean over objectives of (F - ideal) / (nadir - ideal).

    F (n, m); ideal and nadir are the per-objective min and max of archive_F (k, m); an
    objective with nadir = ideal is left unscaled. Returns (n,).
    """
    ideal = archive_F.min(axis=0)
    span = archive_F.max(axis=0) - ideal
    span = np.where(span > 0, span, 1.0)
    return np.mean((F - ideal) / span, axis=1)


class _Archive:
    """The external archive (positions and objective vectors of non-dominated points)."""

    def __init__(self, size: int, dim: int, m: int) -> None:
        self.size = size
        self.X = np.empty((0, dim))
        self.F = np.empty((0, m))

    def add(self, X: Array, F: Array) -> None:
        """Merge new points, keep the non-dominated distinct ones, prune to ``size``."""
        allX = np.vstack([self.X, X])
        allF = np.vstack([self.F, F])
        finite = np.all(np.isfinite(allF), axis=1)
        allX, allF = allX[finite], allF[finite]
        nd = non_dominated(allF)
        allX, allF = allX[nd], allF[nd]
        first = unique_rows(allF)
        allX, allF = allX[first], allF[first]
        keep = truncate_by_crowding(allF, self.size)
        self.X, self.F = allX[keep], allF[keep]


@register_optimizer("mopso")
@dataclass(frozen=True)
class MOPSO(Optimizer):
    """Multi-objective PSO with an external Pareto archive, or weighted-sum scalarisation.

    Parameters
    ----------
    update : str
        Velocity rule: "spso" (the paper's SPSO: w 0.9 -> 0.4, c1 = c2 = 2), "pso" (constriction
        coefficients) or "amopso1" .. "amopso4".
    mode : str
        "pareto" (archive, eq. 14) or "weighted-sum" (eq. 13).
    weights : sequence of float, optional
        One weight per objective in [0, 1], summing to 1. Required meaning in weighted-sum
        mode (default: equal weights); in Pareto mode they only choose which archive member is
        reported as ``x`` (the one with the smallest weighted sum).
    archive_size : int
        Largest number of archive members (100).
    mutation_rate : float
        Fraction of the run during which Coello's mutation acts (0.2; Coello et al. use 0.5;
        0 disables it).
    velocity_clamp : float
        Largest speed per component as a fraction of the box width (0.5, SMPSO's bound of
        half the range; the single-objective optimisers use 0.2).
    """

    multi_objective = True

    update: str = "spso"
    mode: str = "pareto"
    weights: Sequence[float] | None = None
    archive_size: int = 100
    mutation_rate: float = 0.2
    velocity_clamp: float = 0.5

    def _check_hyperparameters(self, problem: Problem) -> None:
        owner = self.name
        check_choice(owner, "update", self.update, UPDATE_RULES)
        check_choice(owner, "mode", self.mode, MODES)
        if self.weights is not None:
            check_weights(owner, self.weights, problem.n_objectives)
        check_int(owner, "archive_size", self.archive_size, 1)
        check_float(owner, "mutation_rate", self.mutation_rate, 0.0, 1.0)
        check_float(owner, "velocity_clamp", self.velocity_clamp, 0.0, 1.0, low_open=True)

    def _weights(self, m: int) -> Array:
        if self.weights is None:
            return np.full(m, 1.0 / m)
        return np.asarray(self.weights, dtype=float)

    def _run(
        self,
        problem: Problem,
        evaluate: Evaluator,
        *,
        iterations: int,
        particles: int,
        rng: np.random.Generator,
        initial: Array | None,
    ) -> RunOutput:
        m = problem.n_objectives
        weights = self._weights(m)
        rule = update_rule(self.update)
        pareto = self.mode == "pareto"
        lower, upper = problem.lower, problem.upper
        v_max = self.velocity_clamp * (upper - lower)

        def objectives(X: Array) -> Array:
            F = evaluate(X)
            return F[:, None] if m == 1 else F

        x = initial_positions(lower, upper, particles, rng, initial)
        v = v_max * (2.0 * rng.random(x.shape) - 1.0)
        F = objectives(x)
        archive = _Archive(self.archive_size, problem.dim, m)
        archive.add(x, F)
        pbest_x, pbest_F = x.copy(), F.copy()
        pbest_s = weighted_sum(pbest_F, weights)
        def record() -> Array:
            if not pareto:
                return np.array([pbest_s.min()])
            return archive.F.min(axis=0) if archive.F.shape[0] else np.full(m, np.inf)

        history = [record()]
        done, stop = 1, "iterations"
        for t in range(1, iterations):
            if pareto:
                cost = normalised_cost(pbest_F, archive.F) if archive.F.shape[0] else pbest_s
                best_cost = float(normalised_cost(archive.F, archive.F).min()) if archive.F.shape[0] else float(cost.min())
                if archive.F.shape[0]:
                    leaders = archive.X[crowding_tournament(crowding_distance(archive.F), particles, rng)]
                else:  # every evaluation so far was NaN/inf: follow the best personal best
                    leaders = pbest_x[int(np.argmin(pbest_s))]
            else:
                cost = pbest_s
                best_cost = float(cost.min())
                leaders = pbest_x[int(np.argmin(pbest_s))]
            coefficients = rule.coefficients(t, iterations, cost, best_cost, rng, x.shape)
            x, v = swarm_move(x, v, pbest_x, leaders, coefficients, v_max, lower, upper)
            x = coello_mutation(x, t, iterations, self.mutation_rate, lower, upper, rng)
            try:
                F = objectives(x)
            except BudgetExhausted:
                stop = "max_evaluations"
                break
            s = weighted_sum(F, weights)
            replace = pareto_pbest_update(pbest_F, F, rng) if pareto else s < pbest_s
            pbest_x[replace] = x[replace]
            pbest_F[replace] = F[replace]
            pbest_s[replace] = s[replace]
            archive.add(x, F)
            history.append(record())
            done += 1

        if pareto and archive.F.shape[0]:
            k = int(np.argmin(weighted_sum(archive.F, weights)))
            best_x, best_F = archive.X[k], archive.F[k]
        else:
            k = int(np.argmin(pbest_s))
            best_x, best_F = pbest_x[k], pbest_F[k]
        hist = np.asarray(history, dtype=float)
        if hist.shape[1] == 1:
            hist = hist[:, 0]
        return RunOutput(
            x=best_x.copy(),
            f=float(weighted_sum(best_F[None, :], weights)[0]),
            history=hist,
            n_iterations=done,
            stop_reason=stop,
            objectives=best_F.copy(),
            pareto_x=archive.X.copy(),
            pareto_f=archive.F.copy(),
        )
