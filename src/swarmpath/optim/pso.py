"""Global-best PSO (section 3.2.1 of Abbas & Abdulsahab): kernels and the ``pso`` / ``spso`` optimisers.

Kernels (pure functions, paper equation in each docstring):
:func:`pso_velocity_update` (eq. 9-10), :func:`pso_position_update` (eq. 11-12, with an
absorbing box), :func:`linear_inertia_eq32` (eq. 32), :func:`clamp_velocity`.
:class:`SPSORule` turns them into the per-iteration coefficients of the shared swarm loop.

Two registered parameterisations of the same algorithm:

- ``spso`` (:class:`SPSO`): the paper's SPSO baseline (section 5.2), w 0.9 -> 0.4 linearly by
  eq. 32 and c1 = c2 = 2. It is the Table 3 reference and what pyswarms' GlobalBestPSO runs with
  the same options. With c1 = c2 = 2 the swarm is second-order unstable while w > 0.5 (Poli
  2009: c1 + c2 < 24 (1 - w^2) / (7 - 5 w)), so it converges only in the last fifth of a run
  (30-D sphere, 30 x 1000: ~3e-4).
- ``pso`` (:class:`PSO`): the same loop with the constriction coefficients of Clerc & Kennedy
  (2002), w = 0.72984, c1 = c2 = 1.49618 -- the "standard PSO" of Bratton & Kennedy (2007) and
  the library default for users' own problems (30-D sphere, 30 x 1000: ~1e-12). Every
  coefficient can be set, so ``PSO(w_max=0.9, w_min=0.4, c1=2, c2=2)`` is SPSO again.
"""
from __future__ import annotations

import abc
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np
from numpy.typing import NDArray

from swarmpath.optim import _swarmstep  # type: ignore[attr-defined]
from swarmpath.optim._budget import BudgetExhausted, Evaluator
from swarmpath.optim._checks import check_float
from swarmpath.optim.base import Optimizer, RunOutput, initial_positions
from swarmpath.optim.problem import Problem
from swarmpath.registry import register_optimizer

Array = NDArray[np.float64]


class Coefficients(NamedTuple):
    """Coefficients of one velocity update (eq. 9-10): floats or arrays of shape (n, 1) / (n, dim)."""

    w: float | Array
    c1: float | Array
    c2: float | Array
    r1: Array
    r2: Array


class UpdateRule(Protocol):
    """How a PSO variant chooses w, c1, c2, r1, r2 at each iteration (SPSO or AMOPSO1-4)."""

    def coefficients(
        self,
        t: int,
        t_max: int,
        pbest_f: Array,
        gbest_f: float,
        rng: np.random.Generator,
        shape: tuple[int, int],
    ) -> Coefficients:
        """Coefficients of the update that produces iteration ``t`` (1 <= t < t_max).

        ``pbest_f`` (n,) are the personal-best costs, ``gbest_f`` the best of them, ``shape``
        is (n, dim).
        """
        ...


def pso_velocity_update(
    v: Array,
    x: Array,
    pbest: Array,
    gbest: Array,
    w: float | Array,
    c1: float | Array,
    c2: float | Array,
    r1: Array,
    r2: Array,
) -> Array:
    """Eq. 9-10: v' = w v + c1 r1 (pbest - x) + c2 r2 (gbest - x).

    Parameters
    ----------
    v, x, pbest : ndarray of shape (n, dim)
        Velocities, positions and personal-best positions.
    gbest : ndarray of shape (dim,) or (n, dim)
        The global best (or each particle's leader, for MOPSO).
    w, c1, c2 : float or ndarray of shape (n, 1)
        Inertia and acceleration coefficients, shared or per particle.
    r1, r2 : ndarray of shape (n, dim)
        Random factors (U(0, 1) in SPSO; eq. 23-24 in AMOPSO).

    Returns
    -------
    ndarray of shape (n, dim): the new velocities.
    """
    cognitive = pbest - x
    cognitive *= r1
    cognitive *= c1
    social = gbest - x
    social *= r2
    social *= c2
    cognitive += social
    social = np.multiply(v, w, out=social)
    cognitive += social
    return cognitive


def clamp_velocity(v: Array, v_max: Array) -> Array:
    """Velocity clamping: each component limited to [-v_max_d, v_max_d]; v (n, dim), v_max (dim,)."""
    out = np.maximum(v, -v_max)
    return np.minimum(out, v_max, out=out)


def pso_position_update(x: Array, v: Array, lower: Array, upper: Array) -> tuple[Array, Array]:
    """Eq. 11-12, x' = x + v', inside an absorbing box.

    A component that would leave [lower, upper] stops on the wall and its velocity becomes 0
    (the "absorbing wall" boundary handling): the particle stays feasible and does not keep
    pushing against the wall.

    Parameters
    ----------
    x, v : ndarray of shape (n, dim)
    lower, upper : ndarray of shape (dim,)

    Returns
    -------
    (x', v') : ndarrays of shape (n, dim)
    """
    moved = x + v
    clipped = np.maximum(moved, lower)
    np.minimum(clipped, upper, out=clipped)
    hit = clipped != moved
    if hit.any():
        v = np.where(hit, 0.0, v)
    return clipped, v


def _per_particle(c: float | Array, n: int) -> Array | None:
    """A coefficient as a contiguous float64 array of length 1 or n, or None if it varies per component."""
    arr = np.ascontiguousarray(c, dtype=np.float64).reshape(-1)
    return arr if arr.shape[0] in (1, n) else None


def swarm_move(
    x: Array,
    v: Array,
    pbest: Array,
    leaders: Array,
    coefficients: Coefficients,
    v_max: Array,
    lower: Array,
    upper: Array,
) -> tuple[Array, Array]:
    """One move of every particle: eq. 9-10, :func:`clamp_velocity`, eq. 11-12 with walls.

    Returns the new (x, v), as ``pso_position_update(x, clamp_velocity(pso_velocity_update(...)))``
    would, bit for bit, but in one pass of the C extension when the coefficients are shared or
    per particle (the numpy kernels above are the reference and the fallback for coefficients
    that vary per component). ``v`` may be overwritten; ``x`` is not (an objective function may
    keep the array it was given).
    """
    w, c1, c2, r1, r2 = coefficients
    n = x.shape[0]
    scalars = [_per_particle(c, n) for c in (w, c1, c2)]
    if any(c is None for c in scalars) or not (x.flags.c_contiguous and v.flags.c_contiguous):
        v = clamp_velocity(pso_velocity_update(v, x, pbest, leaders, w, c1, c2, r1, r2), v_max)
        return pso_position_update(x, v, lower, upper)
    x = x.copy()
    _swarmstep.step(
        x, v, np.ascontiguousarray(pbest), np.ascontiguousarray(leaders), *scalars,
        np.ascontiguousarray(r1), np.ascontiguousarray(r2), v_max, lower, upper,
    )
    return x, v


def linear_inertia_eq32(t: int, t_max: int, w_max: float = 0.9, w_min: float = 0.4) -> float:
    """Eq. 32: w(t) = w_max - (w_max - w_min) / t_max * t, linearly from w_max to w_min."""
    return w_max - (w_max - w_min) / t_max * t


@dataclass(frozen=True)
class SPSORule:
    """SPSO coefficients: w by eq. 32, constant c1 and c2, r1 and r2 ~ U(0, 1) per component."""

    w_max: float = 0.9
    w_min: float = 0.4
    c1: float = 2.0
    c2: float = 2.0

    def coefficients(
        self,
        t: int,
        t_max: int,
        pbest_f: Array,
        gbest_f: float,
        rng: np.random.Generator,
        shape: tuple[int, int],
    ) -> Coefficients:
        """(w, c1, c2, r1, r2) for the update that produces iteration ``t`` (1 <= t < t_max)."""
        w = linear_inertia_eq32(t, t_max, self.w_max, self.w_min)
        r = rng.random((2, *shape))
        return Coefficients(w, self.c1, self.c2, r[0], r[1])


class GlobalBestSwarm:
    """The state of a global-best swarm: positions, velocities, personal and global bests.

    Shared by every global-best loop (SPSO, AMOPSO1-4 through :func:`run_gbest_swarm`, and
    APSO), so that starting the swarm, moving it and keeping the bests is written once.
    """

    def __init__(
        self,
        problem: Problem,
        evaluate: Evaluator,
        *,
        particles: int,
        rng: np.random.Generator,
        initial: Array | None,
        velocity_clamp: float,
    ) -> None:
        """Eq. 31: the initial swarm, random velocities within the clamp, one evaluation each."""
        self.lower, self.upper = problem.lower, problem.upper
        self.v_max = velocity_clamp * (self.upper - self.lower)
        self.x = initial_positions(self.lower, self.upper, particles, rng, initial)
        self.v = self.v_max * (2.0 * rng.random(self.x.shape) - 1.0)
        f = evaluate(self.x)
        self.pbest_x = self.x.copy()
        self.pbest_f = f.copy()
        g = int(np.argmin(self.pbest_f))
        self.gbest_x = self.pbest_x[g].copy()
        self.gbest_f = float(self.pbest_f[g])

    def move(self, coefficients: Coefficients) -> None:
        """Eq. 9-12 for every particle towards its personal best and the global best."""
        self.x, self.v = swarm_move(
            self.x, self.v, self.pbest_x, self.gbest_x, coefficients, self.v_max, self.lower, self.upper
        )

    def record(self, f: Array) -> None:
        """Keep the better of each personal best and the new position, then the global best."""
        better = f < self.pbest_f
        np.copyto(self.pbest_x, self.x, where=better[:, None])
        np.minimum(self.pbest_f, f, out=self.pbest_f)
        g = int(np.argmin(self.pbest_f))
        if self.pbest_f[g] < self.gbest_f:
            self.gbest_x = self.pbest_x[g].copy()
            self.gbest_f = float(self.pbest_f[g])

    def output(self, history: Array, stop: str) -> RunOutput:
        """The run's result, with the best-so-far ``history`` of the iterations done."""
        return RunOutput(self.gbest_x, self.gbest_f, history, len(history), stop, np.array([self.gbest_f]))


def run_gbest_swarm(
    problem: Problem,
    evaluate: Evaluator,
    rule: UpdateRule,
    *,
    iterations: int,
    particles: int,
    rng: np.random.Generator,
    initial: Array | None,
    velocity_clamp: float,
) -> RunOutput:
    """The global-best swarm loop of Fig. 1, shared by SPSO and the AMOPSO variants.

    Iteration 1 evaluates the initial swarm (eq. 31, random velocities within the clamp); each
    further iteration t = 1 .. iterations-1 updates velocities with ``rule``'s coefficients
    (eq. 9-10), clamps them, moves the particles (eq. 11-12) and evaluates them, then updates
    the personal and global bests. Evaluations: exactly iterations * particles, unless the
    evaluator's budget ends the run first.
    """
    swarm = GlobalBestSwarm(problem, evaluate, particles=particles, rng=rng, initial=initial,
                            velocity_clamp=velocity_clamp)
    history = np.empty(iterations)
    history[0] = swarm.gbest_f
    done = 1
    stop = "iterations"
    for t in range(1, iterations):
        swarm.move(rule.coefficients(t, iterations, swarm.pbest_f, swarm.gbest_f, rng, swarm.x.shape))
        try:
            f = evaluate(swarm.x)
        except BudgetExhausted:
            stop = "max_evaluations"
            break
        swarm.record(f)
        history[done] = swarm.gbest_f
        done += 1
    return swarm.output(history[:done], stop)


def check_inertia_bounds(owner: str, w_min: float, w_max: float) -> None:
    """ConfigError unless 0 <= w_min <= w_max <= 1.5 (beyond, the swarm diverges)."""
    check_float(owner, "w_min", w_min, 0.0, 1.5)
    check_float(owner, "w_max", w_max, 0.0, 1.5)
    if w_min > w_max:
        check_float(owner, "w_min", w_min, 0.0, w_max)


CONSTRICTION_INERTIA = 0.72984
"""Clerc & Kennedy's constriction factor chi for phi = 4.1, used as a constant inertia."""
CONSTRICTION_ACCELERATION = 1.49618
"""chi * 2.05: the acceleration coefficients that go with :data:`CONSTRICTION_INERTIA`."""


class GlobalBestOptimizer(Optimizer):
    """An optimiser that is one global-best swarm driven by an update rule (PSO, SPSO, the
    AMOPSO variants): subclasses give :meth:`rule` and a ``velocity_clamp`` field."""

    velocity_clamp: float

    @abc.abstractmethod
    def rule(self) -> UpdateRule:
        """The update rule (the coefficients of eq. 9-10 at every iteration)."""

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
        return run_gbest_swarm(
            problem,
            evaluate,
            self.rule(),
            iterations=iterations,
            particles=particles,
            rng=rng,
            initial=initial,
            velocity_clamp=self.velocity_clamp,
        )


@register_optimizer("pso")
@dataclass(frozen=True)
class PSO(GlobalBestOptimizer):
    """Global-best PSO, by default with constriction coefficients (see the module doc).

    Parameters
    ----------
    w_max, w_min : float
        Inertia weight, decreasing linearly from w_max to w_min over the run (eq. 32); equal
        values give a constant inertia (default 0.72984 for both).
    c1, c2 : float
        Cognitive and social acceleration coefficients (default 1.49618 each).
    velocity_clamp : float
        Largest speed per component as a fraction of the box width (0.2, as pymoo's PSO).
    """

    w_max: float = CONSTRICTION_INERTIA
    w_min: float = CONSTRICTION_INERTIA
    c1: float = CONSTRICTION_ACCELERATION
    c2: float = CONSTRICTION_ACCELERATION
    velocity_clamp: float = 0.2

    def _check_hyperparameters(self, problem: Problem) -> None:
        owner = self.name
        check_inertia_bounds(owner, self.w_min, self.w_max)
        check_float(owner, "c1", self.c1, 0.0, 4.0)
        check_float(owner, "c2", self.c2, 0.0, 4.0)
        check_float(owner, "velocity_clamp", self.velocity_clamp, 0.0, 1.0, low_open=True)

    def rule(self) -> SPSORule:
        """The update rule with this optimiser's coefficients."""
        return SPSORule(self.w_max, self.w_min, self.c1, self.c2)


@register_optimizer("spso")
@dataclass(frozen=True)
class SPSO(PSO):
    """The paper's SPSO (section 5.2): :class:`PSO` with w 0.9 -> 0.4 by eq. 32 and c1 = c2 = 2."""

    w_max: float = 0.9
    w_min: float = 0.4
    c1: float = 2.0
    c2: float = 2.0
