"""Artificial fish swarm algorithm (Li Xiaolei 2002, in its continuous form; docs/papers/karim-2014.md has the grid form).

Each fish looks around within its visual range and, every iteration, tries:

- swarm: move a step towards the centre X_c of the fish it sees, if the centre is better than
  where it is and the neighbourhood is not crowded (nf / n < delta);
- follow: move a step towards the best fish it sees, under the same two conditions;
  the better of the two outcomes is taken;
- prey (when neither applies): try up to ``try_number`` random points within the visual range
  and move a step towards the first better one; when none is better, swim a random step.

A bulletin board keeps the best position ever seen. Distances are measured in coordinates
normalised to the box ([0, 1] per dimension) and ``visual`` and ``step`` are fractions of the
box diagonal, so one setting works for any box. Kernels: :func:`afsa_neighbours`,
:func:`afsa_move_towards`, :func:`afsa_random_within`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.optim._budget import BudgetExhausted, Evaluator
from swarmpath.optim._checks import check_float, check_int
from swarmpath.optim.base import Optimizer, RunOutput, initial_positions
from swarmpath.optim.problem import Problem
from swarmpath.registry import register_optimizer

Array = NDArray[np.float64]


def afsa_neighbours(U: Array, radius: float) -> NDArray[np.bool_]:
    """Which fish each fish sees: N[i, j] = (||U_i - U_j|| < radius) and i != j.

    U : ndarray of shape (n, dim), normalised positions -> ndarray of bools (n, n).
    """
    sq = np.einsum("ij,ij->i", U, U)
    d2 = sq[:, None] + sq[None, :] - 2.0 * (U @ U.T)
    N = d2 < radius * radius
    np.fill_diagonal(N, False)
    return N


def afsa_move_towards(U: Array, target: Array, step: float, rand: Array) -> Array:
    """One step towards a target: U + step * rand * (target - U) / ||target - U||.

    U, target : ndarrays of shape (k, dim); rand : (k,) in [0, 1). A fish already at its
    target stays. Returns (k, dim), not yet clipped to the box.
    """
    d = target - U
    norm = np.sqrt(np.einsum("ij,ij->i", d, d))
    scale = np.where(norm > 0, step * rand / np.where(norm > 0, norm, 1.0), 0.0)
    return U + d * scale[:, None]


def afsa_random_within(U: Array, radius: float, rng: np.random.Generator) -> Array:
    """A random point within ``radius`` of each row of U (k, dim): uniform direction, U(0, 1) radius."""
    d = rng.standard_normal(U.shape)
    norm = np.sqrt(np.einsum("ij,ij->i", d, d))
    norm = np.where(norm > 0, norm, 1.0)
    return U + d * (radius * rng.random(U.shape[0]) / norm)[:, None]


@register_optimizer("afsa")
@dataclass(frozen=True)
class AFSA(Optimizer):
    """Artificial fish swarm.

    Parameters
    ----------
    visual : float
        Visual range as a fraction of the box diagonal (0.1).
    step : float
        Largest step as a fraction of the box diagonal (0.02).
    crowd_factor : float
        delta: a neighbourhood is crowded when nf / n >= delta (0.618).
    try_number : int
        Random tries of the prey behaviour before a random swim (5).

    Evaluations per iteration vary between n and about (4 + try_number) * n; use
    ``max_evaluations`` to compare with other optimisers at equal evaluations.
    """

    visual: float = 0.1
    step: float = 0.02
    crowd_factor: float = 0.618
    try_number: int = 5

    def _check_hyperparameters(self, problem: Problem) -> None:
        owner = self.name
        check_float(owner, "visual", self.visual, 0.0, 1.0, low_open=True)
        check_float(owner, "step", self.step, 0.0, 1.0, low_open=True)
        check_float(owner, "crowd_factor", self.crowd_factor, 0.0, 1.0, low_open=True)
        check_int(owner, "try_number", self.try_number, 1)

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
        span = upper - lower
        n, d = particles, problem.dim
        diag = float(np.sqrt(d))  # diagonal of the unit cube
        vis, stp = self.visual * diag, self.step * diag

        def to_x(U: Array) -> Array:
            return lower + span * np.clip(U, 0.0, 1.0)

        U = (initial_positions(lower, upper, n, rng, initial) - lower) / span
        f = evaluate(to_x(U))
        g = int(np.argmin(f))
        best_x, best_f = to_x(U[g]), float(f[g])
        history = np.empty(iterations)
        history[0] = best_f
        done, stop = 1, "iterations"
        idx = np.arange(n)
        try:
            for _ in range(1, iterations):
                N = afsa_neighbours(U, vis)
                nf = N.sum(axis=1)
                ok = (nf > 0) & (nf / n < self.crowd_factor)
                newU, newf = U.copy(), f.copy()
                moved = np.zeros(n, dtype=bool)
                # swarm: towards the centre of the visible fish
                sw = np.nonzero(ok)[0]
                if sw.size:
                    centre = (N[sw] @ U) / nf[sw, None]
                    fc = evaluate(to_x(centre))
                    sw_good = fc < f[sw]
                    sw, centre = sw[sw_good], centre[sw_good]
                # follow: towards the best visible fish
                fo = np.nonzero(ok)[0]
                if fo.size:
                    masked = np.where(N[fo], f[None, :], np.inf)
                    j = np.argmin(masked, axis=1)
                    fo_good = masked[np.arange(fo.size), j] < f[fo]
                    fo, leader = fo[fo_good], U[j[fo_good]]
                cand_U = []
                if sw.size:
                    cand_U.append(np.clip(afsa_move_towards(U[sw], centre, stp, rng.random(sw.size)), 0, 1))
                if fo.size:
                    cand_U.append(np.clip(afsa_move_towards(U[fo], leader, stp, rng.random(fo.size)), 0, 1))
                if cand_U:
                    CU = np.concatenate(cand_U)
                    cf = evaluate(to_x(CU))
                    who = np.concatenate([sw, fo])
                    # the better of the swarm and follow outcomes of each fish
                    order = np.lexsort((cf, who))
                    who, CU, cf = who[order], CU[order], cf[order]
                    first = np.ones(who.size, dtype=bool)
                    first[1:] = who[1:] != who[:-1]
                    who, CU, cf = who[first], CU[first], cf[first]
                    newU[who], newf[who], moved[who] = CU, cf, True
                # prey for the rest: try random points in view, step towards the first better one
                pending = idx[~moved]
                target = np.empty((n, d))
                found = np.zeros(n, dtype=bool)
                for _try in range(self.try_number):
                    if pending.size == 0:
                        break
                    T = np.clip(afsa_random_within(U[pending], vis, rng), 0, 1)
                    ft = evaluate(to_x(T))
                    better = ft < f[pending]
                    target[pending[better]] = T[better]
                    found[pending[better]] = True
                    pending = pending[~better]
                rest = idx[~moved]
                if rest.size:
                    R = U[rest]
                    step_to = np.where(
                        found[rest, None],
                        afsa_move_towards(R, np.where(found[rest, None], target[rest], R), stp, rng.random(rest.size)),
                        afsa_random_within(R, stp, rng),
                    )
                    R = np.clip(step_to, 0, 1)
                    newU[rest], newf[rest] = R, evaluate(to_x(R))
                U, f = newU, newf
                g = int(np.argmin(f))
                if f[g] < best_f:
                    best_x, best_f = to_x(U[g]), float(f[g])
                history[done] = best_f
                done += 1
        except BudgetExhausted:
            stop = "max_evaluations"
        return RunOutput(best_x, best_f, history[:done], done, stop, np.array([best_f]))
