"""Adaptive PSO of Abbas & Abdulsahab (section 4, eq. 15-24, Table 1): AMOPSO1 ... AMOPSO4.

Every particle gets its own inertia, acceleration and random factors from how its personal
best compares with the swarm's (a particle near the swarm's mean cost has L close to 1, an
outlier - very good or very bad - has L close to 0):

    M = mean(Pbest), V = sample std(Pbest), Y_i = (Pbest_i - M) / V, L_i = exp(-|Y_i|)

Kernels (pure functions): :func:`amopso_l_factor`, :func:`amopso_inertia_eq15`,
:func:`amopso_inertia_eq16`, :func:`amopso_acceleration` (eq. 17-22),
:func:`amopso_random_factors` (eq. 23-24). :class:`AMOPSORule` wires them into the swarm loop
of :mod:`swarmpath.optim.pso`; ``amopso1`` .. ``amopso4`` are the registered variants of
Table 1. Interpretations where the paper is unclear are listed in docs/papers/amopso.md.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from swarmpath.optim._checks import check_choice, check_float, check_int
from swarmpath.optim.problem import Problem
from swarmpath.optim.pso import Coefficients, GlobalBestOptimizer, check_inertia_bounds
from swarmpath.registry import register_optimizer

Array = NDArray[np.float64]

#: Table 1 of the paper: variant -> (inertia equation, acceleration equations).
AMOPSO_VARIANTS: dict[int, tuple[str, str]] = {
    1: ("eq15", "eq17-18"),
    2: ("eq15", "eq19-20"),
    3: ("eq16", "eq19-20"),
    4: ("eq16", "eq21-22"),
}
INERTIA_RULES = ("eq15", "eq16")
ACCELERATION_RULES = ("eq17-18", "eq19-20", "eq21-22")


def amopso_l_factor(pbest_f: Array) -> Array:
    """L_i = exp(-|Y_i|), Y_i = (Pbest_i - M) / V (section 4, the definitions under eq. 24).

    M is the mean and V the sample standard deviation (1/(N-1)) of the personal-best costs.
    Guard: when V is 0 or not finite (all personal bests equal, a single particle, or infinite
    costs) every particle is "typical" and L = 1.

    Parameters
    ----------
    pbest_f : ndarray of shape (n,)
        Personal-best costs (lower is better).

    Returns
    -------
    ndarray of shape (n,), values in (0, 1].
    """
    pbest_f = np.asarray(pbest_f, dtype=float)
    n = pbest_f.shape[0]
    if n < 2 or not np.isfinite(pbest_f).all():
        return np.ones(n)
    dev = pbest_f - pbest_f.sum() / n
    V = math.sqrt(float(dev @ dev) / (n - 1))
    if not math.isfinite(V) or V <= 0.0:
        return np.ones(n)
    dev /= -V
    return np.exp(-np.abs(dev, out=dev), out=dev)


def log_progress(t: int, t_max: int) -> float:
    """log_Tmax(T + 1), the time factor of eq. 15-16, clipped to [0, 1].

    It is 0 at T = 0 and 1 at T = Tmax - 1 (the last update of a run of Tmax iterations).
    Guard: for Tmax <= 1 the logarithm base is degenerate and the factor is 1.
    """
    if t_max <= 1:
        return 1.0
    return min(1.0, max(0.0, math.log(t + 1) / math.log(t_max)))


def amopso_inertia_eq15(
    pbest_f: Array, gbest_f: float, t: int, t_max: int, w_min: float = 0.4, w_max: float = 0.9
) -> float:
    """Eq. 15: w = (w_max - w_min) exp(-(max(Pbest) / Gbest)^2) log_Tmax(T + 1) + w_min.

    One value for the whole swarm (max(Pbest) is the worst personal best). Guards: Gbest = 0
    gives a ratio of +inf (so w = w_min), unless max(Pbest) is 0 too (all particles at the
    optimum), when the ratio is taken as 1; the result is clipped to [w_min, w_max] as the
    paper requires.

    Parameters
    ----------
    pbest_f : ndarray of shape (n,)
    gbest_f : float
    t, t_max : int
        Current iteration T and the number of iterations Tmax.
    """
    worst = float(np.max(pbest_f))
    if gbest_f == 0.0:
        ratio = 1.0 if worst == 0.0 else math.inf
    else:
        ratio = worst / gbest_f
    with np.errstate(over="ignore"):
        decay = math.exp(-min(ratio * ratio, 745.0)) if math.isfinite(ratio) else 0.0
    w = (w_max - w_min) * decay * log_progress(t, t_max) + w_min
    return min(w_max, max(w_min, w))


def amopso_inertia_eq16(
    L: Array, t: int, t_max: int, w_min: float = 0.4, w_max: float = 0.9
) -> Array:
    """Eq. 16: w_i = (w_max - w_min) L_i log_Tmax(T + 1) + w_min, per particle, in [w_min, w_max].

    Parameters
    ----------
    L : ndarray of shape (n,)
        From :func:`amopso_l_factor`.

    Returns
    -------
    ndarray of shape (n,)
    """
    w = ((w_max - w_min) * log_progress(t, t_max)) * np.asarray(L, dtype=float) + w_min
    return np.minimum(np.maximum(w, w_min), w_max)


def amopso_acceleration(
    L: Array, t: int, t_max: int, rule: str, z: float = 1.5
) -> tuple[Array, Array]:
    """Adaptive acceleration coefficients c1_i, c2_i (eq. 17-22), Z = 1.5.

    ``rule`` = "eq17-18": c1 = c2 = Z + L T/Tmax;  "eq19-20": c1 = c2 = Z - L T/Tmax;
    "eq21-22": c1 = Z - L T/Tmax, c2 = Z + L T/Tmax. (The formulas as printed; the paper's
    captions "C1 decrease, C2 increase" above eq. 17-18 contradict eq. 17 and are not used.)
    With L in (0, 1] every coefficient stays in [0.5, 2.5], the range of section 5.1.

    Parameters
    ----------
    L : ndarray of shape (n,)

    Returns
    -------
    (c1, c2) : ndarrays of shape (n,)
    """
    step = np.asarray(L, dtype=float) * (t / t_max)
    if rule == "eq17-18":
        return z + step, z + step
    if rule == "eq19-20":
        return z - step, z - step
    if rule == "eq21-22":
        return z - step, z + step
    raise ValueError(f"unknown acceleration rule {rule!r}; choose from {', '.join(ACCELERATION_RULES)}")


def amopso_random_factors(
    L: Array, t: int, t_max: int, rng: np.random.Generator, dim: int
) -> tuple[Array, Array]:
    """Eq. 23-24: r1 = rand1 L T/Tmax, r2 = rand2 L T/Tmax, rand ~ U(0, 1).

    rand1 and rand2 are drawn per particle and per dimension (as r1, r2 in SPSO) and the
    results replace r1, r2 in eq. 9-10, i.e. they multiply c1 and c2.

    Parameters
    ----------
    L : ndarray of shape (n,)
    dim : int

    Returns
    -------
    (r1, r2) : ndarrays of shape (n, dim)
    """
    scale = (np.asarray(L, dtype=float) * (t / t_max))[:, None]
    r = rng.random((2, scale.shape[0], dim))
    r *= scale
    return r[0], r[1]


@dataclass(frozen=True)
class AMOPSORule:
    """AMOPSO coefficients for the shared swarm loop: w (eq. 15 or 16), c (17-22), r (23-24)."""

    inertia: str = "eq16"
    acceleration: str = "eq19-20"
    z: float = 1.5
    w_min: float = 0.4
    w_max: float = 0.9

    def coefficients(
        self,
        t: int,
        t_max: int,
        pbest_f: Array,
        gbest_f: float,
        rng: np.random.Generator,
        shape: tuple[int, int],
    ) -> Coefficients:
        """(w, c1, c2, r1, r2) for the update that produces iteration ``t`` (1 <= t < t_max).

        w, c1, c2 have shape (n, 1) (or w is a float for eq. 15), r1, r2 shape (n, dim).
        """
        L = amopso_l_factor(pbest_f)
        if self.inertia == "eq15":
            w: float | Array = amopso_inertia_eq15(pbest_f, gbest_f, t, t_max, self.w_min, self.w_max)
        else:
            w = amopso_inertia_eq16(L, t, t_max, self.w_min, self.w_max)[:, None]
        c1, c2 = amopso_acceleration(L, t, t_max, self.acceleration, self.z)
        r1, r2 = amopso_random_factors(L, t, t_max, rng, shape[1])
        return Coefficients(w, c1[:, None], c2[:, None], r1, r2)


def amopso_rule(variant: int, *, z: float = 1.5, w_min: float = 0.4, w_max: float = 0.9) -> AMOPSORule:
    """The update rule of AMOPSO``variant`` (Table 1)."""
    inertia, acceleration = AMOPSO_VARIANTS[variant]
    return AMOPSORule(inertia, acceleration, z, w_min, w_max)


@dataclass(frozen=True)
class AMOPSO(GlobalBestOptimizer):
    """Adaptive PSO, one of the four variants of Table 1 (single objective; see MOPSO for several).

    Parameters
    ----------
    variant : int
        1-4: AMOPSO1 = w eq. 15 + c eq. 17-18; AMOPSO2 = eq. 15 + 19-20; AMOPSO3 = eq. 16 +
        19-20; AMOPSO4 = eq. 16 + 21-22; all use r from eq. 23-24.
    w_min, w_max : float
        Range of the adaptive inertia (0.4, 0.9).
    z : float
        The constant Z of eq. 17-22 (1.5).
    velocity_clamp : float
        Largest speed per component as a fraction of the box width (0.2, as for PSO).
    """

    variant: int = 3
    w_min: float = 0.4
    w_max: float = 0.9
    z: float = 1.5
    velocity_clamp: float = 0.2

    def _check_hyperparameters(self, problem: Problem) -> None:
        owner = self.name
        if self.variant not in AMOPSO_VARIANTS:
            check_int(owner, "variant", self.variant, 1)
            check_choice(owner, "variant", str(self.variant), tuple(str(k) for k in AMOPSO_VARIANTS))
        check_inertia_bounds(owner, self.w_min, self.w_max)
        check_float(owner, "z", self.z, 1.0, 3.0)
        check_float(owner, "velocity_clamp", self.velocity_clamp, 0.0, 1.0, low_open=True)

    def rule(self) -> AMOPSORule:
        """The update rule of this variant with this optimiser's coefficients."""
        return amopso_rule(self.variant, z=self.z, w_min=self.w_min, w_max=self.w_max)


@register_optimizer("amopso1")
@dataclass(frozen=True)
class AMOPSO1(AMOPSO):
    """AMOPSO1 of Table 1: inertia eq. 15, acceleration eq. 17-18, random factors eq. 23-24."""

    variant: int = field(default=1, init=False)


@register_optimizer("amopso2")
@dataclass(frozen=True)
class AMOPSO2(AMOPSO):
    """AMOPSO2 of Table 1: inertia eq. 15, acceleration eq. 19-20, random factors eq. 23-24."""

    variant: int = field(default=2, init=False)


@register_optimizer("amopso3")
@dataclass(frozen=True)
class AMOPSO3(AMOPSO):
    """AMOPSO3 of Table 1: inertia eq. 16, acceleration eq. 19-20, random factors eq. 23-24."""

    variant: int = field(default=3, init=False)


@register_optimizer("amopso4")
@dataclass(frozen=True)
class AMOPSO4(AMOPSO):
    """AMOPSO4 of Table 1: inertia eq. 16, acceleration eq. 21-22, random factors eq. 23-24."""

    variant: int = field(default=4, init=False)
