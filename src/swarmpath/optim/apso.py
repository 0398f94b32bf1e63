"""Adaptive PSO of Zhan, Zhang, Li & Chung (IEEE Trans. SMC-B 39(6), 2009): ``apso``.

The adaptive PSO that pymoo's ``PSO`` also follows; here it is the library's strong adaptive
global optimiser, next to the paper-faithful AMOPSO1-4 (whose printed eq. 15-24 damp the swarm,
see docs/papers/amopso.md). Each iteration:

1. Evolutionary state estimation (ESE, Zhan section III-B; :func:`evolutionary_factor`): the
   mean distance d_i of every particle to the others, d_g that of the global best position,
   f = (d_g - d_min) / (d_max - d_min) in [0, 1].
2. Fuzzy classification of f into S1 exploration, S2 exploitation, S3 convergence, S4
   jumping-out (membership functions eq. 11a-d, :func:`state_memberships`); where two states
   overlap, the singleton rule keeps the swarm on its cycle S1 -> S2 -> S3 -> S4 -> S1
   (:func:`classify_state`).
3. Adaptation (:func:`adapt_acceleration`, :func:`adaptive_inertia`): w = 1 / (1 + 1.5
   exp(-2.6 f)) (eq. 10) and c1, c2 moved by delta ~ U(0.05, 0.1) as Table I prescribes per
   state, clamped to [1.5, 2.5] and rescaled to sum 4 when they exceed it.
4. Elitist learning (ELS, section IV-B; :func:`elitist_learning_candidate`) in the convergence
   state: one random dimension of the global best is pushed by a Gaussian of standard deviation
   sigma (1.0 -> 0.1 of the range, linearly over the run); a better candidate becomes the global
   best, a worse one replaces the worst particle.
5. The usual velocity and position update (eq. 9-12 of Abbas & Abdulsahab, shared kernels),
   velocity clamp 0.2 of the range, absorbing walls.

Evaluations: ``particles`` per iteration plus one per ELS step (only in the convergence state);
use ``max_evaluations`` to compare at an exactly equal budget.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.distance import cdist

from swarmpath.optim._budget import BudgetExhausted, Evaluator
from swarmpath.optim._checks import check_float
from swarmpath.optim.base import Optimizer, RunOutput
from swarmpath.optim.problem import Problem
from swarmpath.optim.pso import Coefficients, GlobalBestSwarm
from swarmpath.registry import register_optimizer

Array = NDArray[np.float64]

EXPLORATION, EXPLOITATION, CONVERGENCE, JUMPING_OUT = 0, 1, 2, 3
STATE_NAMES = ("exploration", "exploitation", "convergence", "jumping-out")

# Singleton defuzzification (Zhan III-B step 3): when f lies where two memberships overlap, the
# state is chosen from the previous one. Rows: the overlapping pair; columns: previous state.
_OVERLAP_RULE = {
    (EXPLORATION, EXPLOITATION): (EXPLORATION, EXPLOITATION, EXPLOITATION, EXPLORATION),
    (EXPLORATION, JUMPING_OUT): (EXPLORATION, JUMPING_OUT, JUMPING_OUT, JUMPING_OUT),
    (EXPLOITATION, CONVERGENCE): (EXPLOITATION, EXPLOITATION, CONVERGENCE, EXPLOITATION),
}


def evolutionary_factor(x: Array, gbest: Array) -> float:
    """Zhan eq. 9-10: f = (d_g - d_min) / (d_max - d_min), 0 when all d_i are equal.

    d_i is particle i's mean Euclidean distance to the other N - 1 particles; d_g is the same
    mean for the global best position (its own particle, if it sits there, adds 0).
    """
    n = x.shape[0]
    d = cdist(x, x).sum(axis=1) / (n - 1)
    d_g = float(np.linalg.norm(x - gbest, axis=1).sum()) / (n - 1)
    d_min, d_max = float(d.min()), float(d.max())
    if d_max - d_min <= 1e-12 * d_max:  # equal up to rounding: no information, factor 0
        return 0.0
    return min(1.0, max(0.0, (d_g - d_min) / (d_max - d_min)))


def state_memberships(f: float) -> tuple[float, float, float, float]:
    """Zhan eq. 11a-d: memberships of f in S1 exploration, S2 exploitation, S3 convergence, S4 jumping-out."""
    s1 = float(np.interp(f, [0.4, 0.6, 0.7, 0.8], [0.0, 1.0, 1.0, 0.0]))
    s2 = float(np.interp(f, [0.2, 0.3, 0.4, 0.6], [0.0, 1.0, 1.0, 0.0]))
    s3 = float(np.interp(f, [0.1, 0.3], [1.0, 0.0]))
    s4 = float(np.interp(f, [0.7, 0.9], [0.0, 1.0]))
    return s1, s2, s3, s4


def classify_state(f: float, previous: int) -> int:
    """The evolutionary state for factor f, given the previous state (0..3, see STATE_NAMES)."""
    members = [k for k, m in enumerate(state_memberships(f)) if m > 0.0]
    if len(members) == 1:
        return members[0]
    pair = tuple(sorted(members))
    if pair in _OVERLAP_RULE:
        return _OVERLAP_RULE[pair][previous]
    return int(np.argmax(state_memberships(f)))


def adaptive_inertia(f: float) -> float:
    """Zhan eq. 10: w(f) = 1 / (1 + 1.5 exp(-2.6 f)), from 0.4 (converged) to 0.9 (spread out)."""
    return 1.0 / (1.0 + 1.5 * np.exp(-2.6 * f))


def adapt_acceleration(c1: float, c2: float, state: int, delta: float) -> tuple[float, float]:
    """Zhan Table I and eq. 12-13: move (c1, c2) by delta for ``state``; clamp; rescale to sum <= 4.

    Exploration: c1 up, c2 down; exploitation: c1 up and c2 down slightly (delta / 2);
    convergence: both up slightly; jumping-out: c1 down, c2 up.
    """
    step = {
        EXPLORATION: (delta, -delta),
        EXPLOITATION: (0.5 * delta, -0.5 * delta),
        CONVERGENCE: (0.5 * delta, 0.5 * delta),
        JUMPING_OUT: (-delta, delta),
    }[state]
    c1 = min(2.5, max(1.5, c1 + step[0]))
    c2 = min(2.5, max(1.5, c2 + step[1]))
    total = c1 + c2
    if total > 4.0:
        c1, c2 = 4.0 * c1 / total, 4.0 * c2 / total
    return c1, c2


def elitist_learning_candidate(
    gbest: Array, lower: Array, upper: Array, sigma: float, rng: np.random.Generator
) -> Array:
    """Zhan section IV-B: gbest with one random dimension d moved by (upper_d - lower_d) N(0, sigma^2).

    The moved coordinate is clipped to the box.
    """
    candidate = gbest.copy()
    d = int(rng.integers(gbest.shape[0]))
    candidate[d] += (upper[d] - lower[d]) * rng.normal(0.0, sigma)
    candidate[d] = min(upper[d], max(lower[d], candidate[d]))
    return candidate


def run_progress(t: int, iterations: int, evaluate: Evaluator) -> float:
    """Share of the run spent (g / G in Zhan's sigma schedule), in [0, 1].

    Measured by iterations or by the evaluation budget, whichever is further along.
    """
    progress = t / iterations
    if evaluate.max_evaluations is not None:
        progress = max(progress, evaluate.count / evaluate.max_evaluations)
    return min(1.0, progress)


@register_optimizer("apso")
@dataclass(frozen=True)
class APSO(Optimizer):
    """Adaptive PSO (Zhan et al. 2009): ESE-driven w, c1, c2 and elitist learning (see module doc).

    Parameters
    ----------
    c1, c2 : float
        Initial acceleration coefficients (2.0, 2.0); adapted within [1.5, 2.5] afterwards.
    sigma_max, sigma_min : float
        Elitist-learning step (fraction of the range), decreasing linearly over the run (1.0 -> 0.1).
    velocity_clamp : float
        Largest speed per component as a fraction of the box width (0.2, Zhan's setting).
    elitist_learning : bool
        Turn ELS off to study the adaptation alone.
    """

    c1: float = 2.0
    c2: float = 2.0
    sigma_max: float = 1.0
    sigma_min: float = 0.1
    velocity_clamp: float = 0.2
    elitist_learning: bool = True

    def _check_hyperparameters(self, problem: Problem) -> None:
        owner = self.name
        check_float(owner, "c1", self.c1, 1.5, 2.5)
        check_float(owner, "c2", self.c2, 1.5, 2.5)
        check_float(owner, "sigma_min", self.sigma_min, 0.0, 10.0)
        check_float(owner, "sigma_max", self.sigma_max, self.sigma_min, 10.0)
        check_float(owner, "velocity_clamp", self.velocity_clamp, 0.0, 1.0, low_open=True)

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
        swarm = GlobalBestSwarm(problem, evaluate, particles=particles, rng=rng, initial=initial,
                                velocity_clamp=self.velocity_clamp)
        history = np.empty(iterations)
        history[0] = swarm.gbest_f
        done, stop = 1, "iterations"
        c1, c2, state = self.c1, self.c2, EXPLORATION
        for t in range(1, iterations):
            factor = evolutionary_factor(swarm.x, swarm.gbest_x)
            state = classify_state(factor, state)
            w = adaptive_inertia(factor)
            c1, c2 = adapt_acceleration(c1, c2, state, float(rng.uniform(0.05, 0.1)))
            try:
                if state == CONVERGENCE and self.elitist_learning:
                    self._elitist_learning(swarm, evaluate, run_progress(t, iterations, evaluate), rng)
                r = rng.random((2, *swarm.x.shape))
                swarm.move(Coefficients(w, c1, c2, r[0], r[1]))
                f = evaluate(swarm.x)
            except BudgetExhausted:
                stop = "max_evaluations"
                break
            swarm.record(f)
            history[done] = swarm.gbest_f
            done += 1
        return swarm.output(history[:done], stop)

    def _elitist_learning(
        self, swarm: GlobalBestSwarm, evaluate: Evaluator, progress: float, rng: np.random.Generator
    ) -> None:
        """Zhan IV-B: a better candidate becomes the global best, a worse one the worst particle."""
        sigma = self.sigma_max - (self.sigma_max - self.sigma_min) * progress
        candidate = elitist_learning_candidate(swarm.gbest_x, swarm.lower, swarm.upper, sigma, rng)
        cand_f = float(evaluate(candidate[None, :])[0])
        if cand_f < swarm.gbest_f:
            swarm.gbest_x, swarm.gbest_f = candidate, cand_f
        else:
            worst = int(np.argmax(swarm.pbest_f))
            swarm.x[worst] = candidate
            swarm.pbest_x[worst], swarm.pbest_f[worst] = candidate, cand_f
