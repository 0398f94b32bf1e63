"""Cat swarm optimisation (Chu & Tsai 2006/2007): seeking mode, tracing mode, mixture ratio.

Each iteration a fraction ``mixture_ratio`` (MR) of the cats, chosen at random, is in tracing
mode and the rest in seeking mode (Chu & Tsai's convention: MR is the share of tracing cats and
is kept small, so that cats mostly "rest and look around"; the Jaleel 2016 controller counts
seeking cats instead, so its MR = 0.4 corresponds to 0.6 here).

- Seeking mode (:func:`cso_seek_candidates`, :func:`cso_selection_probabilities`): a cat makes
  SMP candidate copies of itself (with SPC, one of them is its present position); in each
  mutated copy CDC of the dimensions are moved "randomly plus or minus SRD percent of the
  present value" (x_d * (1 +- SRD), Chu & Tsai's rule, also mealpy's); the cat moves to a copy
  drawn with probability P_i = |FS_i - FS_max| / (FS_max - FS_min) (minimisation: the worst
  copy never wins; all equal -> uniform). The relative step shrinks near 0, which favours
  problems whose optimum is at the origin (all of Table 2): say so when comparing.
- Tracing mode (:func:`cso_trace_velocity`): v = w v + r c (x_best - x), clamped; x = x + v.

The best position ever seen is kept (Chu & Tsai's "memory"). Kernels are pure functions; the
registered class ``cso`` wires them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.optim._budget import BudgetExhausted, Evaluator
from swarmpath.optim._checks import check_float, check_int
from swarmpath.optim.base import Optimizer, RunOutput, initial_positions
from swarmpath.optim.problem import Problem
from swarmpath.optim.pso import clamp_velocity, pso_position_update
from swarmpath.registry import register_optimizer

Array = NDArray[np.float64]


def cso_seek_candidates(
    x: Array,
    lower: Array,
    upper: Array,
    *,
    smp: int,
    srd: float,
    cdc: float,
    spc: bool,
    rng: np.random.Generator,
) -> Array:
    """Seeking-mode candidate copies of each cat (Chu & Tsai, seeking mode steps 1-2).

    Parameters
    ----------
    x : ndarray of shape (n, dim)
        Positions of the seeking cats.
    lower, upper : ndarray of shape (dim,)
    smp : int
        Seeking memory pool: copies per cat.
    srd : float
        Seeking range of the selected dimension: a mutated coordinate becomes x_d * (1 + srd)
        or x_d * (1 - srd) (sign at random), clipped to the box.
    cdc : float
        Counts of dimension to change, as a fraction of dim: round(cdc * dim) dimensions
        (at least 1), chosen at random per copy, are mutated.
    spc : bool
        Self-position considering: copy 0 stays at the present position.

    Returns
    -------
    ndarray of shape (n, smp, dim)
    """
    n, d = x.shape
    k = min(d, max(1, int(round(cdc * d))))
    copies = np.repeat(x[:, None, :], smp, axis=1)
    # k random dimensions per copy: the k smallest of d uniform keys
    keys = rng.random((n, smp, d))
    if k < d:
        kth = np.partition(keys, k - 1, axis=-1)[..., k - 1 : k]
        chosen = keys <= kth
    else:
        chosen = np.ones((n, smp, d), dtype=bool)
    factor = np.where(rng.random((n, smp, d)) < 0.5, 1.0 + srd, 1.0 - srd)
    copies = np.where(chosen, copies * factor, copies)
    if spc:
        copies[:, 0, :] = x
    return np.minimum(np.maximum(copies, lower), upper)


def cso_selection_probabilities(fs: Array) -> Array:
    """Probability of moving to each candidate copy (Chu & Tsai, seeking step 4, minimisation).

    P_i = |FS_i - FS_max| / (FS_max - FS_min), normalised to sum 1 per cat; when all the
    copies of a cat have the same fitness, each has probability 1/SMP. Non-finite fitness gets
    probability 0 (unless every copy is non-finite: then uniform).

    fs : ndarray of shape (n, smp) -> ndarray of shape (n, smp)
    """
    fs = np.asarray(fs, dtype=float)
    finite = np.isfinite(fs)
    safe = np.where(finite, fs, np.nan)
    with np.errstate(invalid="ignore"):
        fmax = np.nanmax(np.where(finite.any(axis=1, keepdims=True), safe, 0.0), axis=1, keepdims=True)
        fmin = np.nanmin(np.where(finite.any(axis=1, keepdims=True), safe, 0.0), axis=1, keepdims=True)
    span = fmax - fmin
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(finite, np.abs(fs - fmax) / np.where(span > 0, span, 1.0), 0.0)
    flat = (span[:, 0] <= 0) | (p.sum(axis=1) <= 0)
    p[flat] = np.where(finite[flat] | ~finite[flat].any(axis=1, keepdims=True), 1.0, 0.0)
    return p / p.sum(axis=1, keepdims=True)


def roulette(p: Array, rng: np.random.Generator) -> NDArray[np.intp]:
    """One index per row drawn with the row's probabilities; p (n, k) rows sum to 1 -> (n,)."""
    cum = np.cumsum(p, axis=1)
    u = rng.random((p.shape[0], 1)) * cum[:, -1:]
    return np.minimum((cum <= u).sum(axis=1), p.shape[1] - 1)


def cso_trace_velocity(v: Array, x: Array, best: Array, w: float, c: float, r: Array) -> Array:
    """Tracing mode (Chu & Tsai eq. 1 with an inertia weight): v' = w v + r c (x_best - x).

    v, x, r : ndarrays of shape (n, dim); best : (dim,). Returns (n, dim).
    """
    return w * v + r * c * (best - x)


@register_optimizer("cso")
@dataclass(frozen=True)
class CSO(Optimizer):
    """Cat swarm optimisation.

    Parameters
    ----------
    mixture_ratio : float
        MR: fraction of cats in tracing mode each iteration (0.3; the others seek).
    smp : int
        Seeking memory pool (5 copies).
    srd : float
        Seeking range of the selected dimension: relative change of a coordinate (0.2).
    cdc : float
        Fraction of dimensions changed per copy (0.8).
    spc : bool
        Self-position considering (True: one copy is the present position, not re-evaluated).
    inertia : float
        w of the tracing velocity (0.5).
    c : float
        Acceleration constant of tracing mode (1.5; Chu & Tsai use 2.0 without inertia).
    velocity_clamp : float
        Largest tracing speed per component as a fraction of the box width (0.2).

    Evaluations per iteration: n_seek * (smp - 1 if spc else smp) + n_trace, so a CSO run
    uses more evaluations than a PSO run of the same swarm and iterations; use
    ``max_evaluations`` in :meth:`minimize` to compare at equal evaluations.
    """

    mixture_ratio: float = 0.3
    smp: int = 5
    srd: float = 0.2
    cdc: float = 0.8
    spc: bool = True
    inertia: float = 0.5
    c: float = 1.5
    velocity_clamp: float = 0.2

    def _check_hyperparameters(self, problem: Problem) -> None:
        owner = self.name
        check_float(owner, "mixture_ratio", self.mixture_ratio, 0.0, 1.0)
        check_int(owner, "smp", self.smp, 2 if self.spc else 1)
        check_float(owner, "srd", self.srd, 0.0, 1.0, low_open=True)
        check_float(owner, "cdc", self.cdc, 0.0, 1.0, low_open=True)
        check_float(owner, "inertia", self.inertia, 0.0, 1.5)
        check_float(owner, "c", self.c, 0.0, 4.0)
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
        lower, upper = problem.lower, problem.upper
        v_max = self.velocity_clamp * (upper - lower)
        n = particles
        x = initial_positions(lower, upper, n, rng, initial)
        v = v_max * (2.0 * rng.random(x.shape) - 1.0)
        f = evaluate(x)
        g = int(np.argmin(f))
        best_x, best_f = x[g].copy(), float(f[g])
        n_trace = int(round(self.mixture_ratio * n))
        history = np.empty(iterations)
        history[0] = best_f
        done, stop = 1, "iterations"
        for _ in range(1, iterations):
            tracing = np.zeros(n, dtype=bool)
            tracing[rng.permutation(n)[:n_trace]] = True
            seek = np.nonzero(~tracing)[0]
            trace = np.nonzero(tracing)[0]
            new_x, new_f = x.copy(), f.copy()
            batch = []
            if seek.size:
                cand = cso_seek_candidates(
                    x[seek], lower, upper, smp=self.smp, srd=self.srd, cdc=self.cdc, spc=self.spc, rng=rng
                )
                start = 1 if self.spc else 0
                batch.append(cand[:, start:, :].reshape(-1, problem.dim))
            if trace.size:
                r = rng.random((trace.size, problem.dim))
                vt = clamp_velocity(cso_trace_velocity(v[trace], x[trace], best_x, self.inertia, self.c, r), v_max)
                xt, vt = pso_position_update(x[trace], vt, lower, upper)
                v[trace] = vt
                batch.append(xt)
            try:
                fb = evaluate(np.concatenate(batch, axis=0))
            except BudgetExhausted:
                stop = "max_evaluations"
                break
            if seek.size:
                m = seek.size * (self.smp - start)
                fs = fb[:m].reshape(seek.size, self.smp - start)
                if self.spc:
                    fs = np.concatenate([f[seek, None], fs], axis=1)
                pick = roulette(cso_selection_probabilities(fs), rng)
                new_x[seek] = cand[np.arange(seek.size), pick]
                new_f[seek] = fs[np.arange(seek.size), pick]
            else:
                m = 0
            if trace.size:
                new_x[trace] = xt
                new_f[trace] = fb[m:]
            x, f = new_x, new_f
            g = int(np.argmin(f))
            if f[g] < best_f:
                best_x, best_f = x[g].copy(), float(f[g])
            history[done] = best_f
            done += 1
        return RunOutput(best_x, best_f, history[:done], done, stop, np.array([best_f]))
