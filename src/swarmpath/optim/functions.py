"""Benchmark functions: the paper's Table 2 (f1-f6), Rosenbrock, and ZDT1/ZDT2 for MOPSO.

Every function is vectorised over the last axis: ``X`` of shape (..., dim) gives values of shape
(...), so one call evaluates a whole swarm. Definitions are the standard ones of Vesterstrom &
Thomsen (2004), the source the paper cites; the paper's printed f2 (eq. 26, sum of x_j^2 inside
the square) and f5 (eq. 29, cos outside the sum and 1/D misplaced) are typos of these.

The single-objective functions are registered by name (``sphere``, ``quadric``,
``quartic-noise``, ``rastrigin``, ``ackley``, ``griewank``, ``rosenbrock``) as
:class:`BenchmarkFunction` entries that carry their default box (the paper's ranges) and
optimum; ``FUNCTIONS.get("ackley").problem(30)`` is a ready :class:`Problem`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError, UnknownNameError
from swarmpath.optim.problem import Problem
from swarmpath.registry import FUNCTIONS, register_function
from swarmpath.rng import make_rng
from swarmpath.types import SeedLike

Array = NDArray[np.float64]


def sphere(X: ArrayLike) -> Array:
    """f1, eq. 25: sum_i x_i^2. X of shape (..., dim) -> shape (...). Minimum 0 at x = 0."""
    X = np.asarray(X, dtype=float)
    return np.einsum("...i,...i->...", X, X)


def quadric(X: ArrayLike) -> Array:
    """f2, Schwefel's problem 1.2 (eq. 26 corrected): sum_i (sum_{j<=i} x_j)^2.

    X of shape (..., dim) -> shape (...). Minimum 0 at x = 0.
    """
    S = np.cumsum(np.asarray(X, dtype=float), axis=-1)
    return np.einsum("...i,...i->...", S, S)


def quartic(X: ArrayLike) -> Array:
    """The noise-free part of f3: sum_i i * x_i^4 (i from 1). X (..., dim) -> (...)."""
    X = np.asarray(X, dtype=float)
    i = np.arange(1, X.shape[-1] + 1, dtype=float)
    X2 = X * X
    return (X2 * X2) @ i


def quartic_noise(X: ArrayLike, rng: np.random.Generator) -> Array:
    """f3, eq. 27: sum_i i * x_i^4 + U[0, 1), one noise draw per point from ``rng``.

    X of shape (..., dim) -> shape (...). The noise comes from the given generator, never from
    global state, so a seeded run is reproducible. Expected minimum 0.5 (at x = 0); the best
    sample over many evaluations approaches 0.
    """
    base = quartic(X)
    return base + rng.random(np.shape(base))


def rastrigin(X: ArrayLike) -> Array:
    """f4, eq. 28: sum_i [x_i^2 - 10 cos(2 pi x_i) + 10]. X (..., dim) -> (...). Minimum 0 at 0.

    Computed as sum x^2 + 10 (dim - sum cos 2 pi x): four array operations instead of seven;
    exactly 0 at x = 0, absolute rounding error about 10 * dim * 1e-16 elsewhere.
    """
    X = np.asarray(X, dtype=float)
    d = X.shape[-1]
    return np.einsum("...i,...i->...", X, X) + 10.0 * (d - np.cos((2.0 * np.pi) * X).sum(axis=-1))


def ackley(X: ArrayLike) -> Array:
    """f5, Ackley (eq. 29 corrected).

    -20 exp(-0.2 sqrt(mean_i x_i^2)) - exp(mean_i cos(2 pi x_i)) + 20 + e.
    X (..., dim) -> (...). Minimum 0 at x = 0 (about 4e-16 in floating point).
    """
    X = np.asarray(X, dtype=float)
    d = X.shape[-1]
    a = -20.0 * np.exp(-0.2 * np.sqrt(np.einsum("...i,...i->...", X, X) / d))
    b = -np.exp(np.sum(np.cos(2.0 * np.pi * X), axis=-1) / d)
    return a + b + 20.0 + np.e


def griewank(X: ArrayLike) -> Array:
    """f6, eq. 30: sum_i x_i^2 / 4000 - prod_i cos(x_i / sqrt(i)) + 1. X (..., dim) -> (...)."""
    X = np.asarray(X, dtype=float)
    i = np.sqrt(np.arange(1, X.shape[-1] + 1, dtype=float))
    return np.einsum("...i,...i->...", X, X) / 4000.0 - np.prod(np.cos(X / i), axis=-1) + 1.0


def rosenbrock(X: ArrayLike) -> Array:
    """Rosenbrock: sum_{i<dim} 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2. Minimum 0 at x = 1.

    X (..., dim) -> (...); dim >= 2.
    """
    X = np.asarray(X, dtype=float)
    a = X[..., 1:] - X[..., :-1] ** 2
    b = 1.0 - X[..., :-1]
    return np.sum(100.0 * a * a + b * b, axis=-1)


# ---- registered single-objective benchmarks --------------------------------------------------


@dataclass(frozen=True)
class BenchmarkFunction:
    """A named benchmark: the function, its default box and its known optimum.

    Attributes
    ----------
    name : str
        Registered name.
    func : callable
        ``func(X)`` for deterministic functions, ``func(X, rng)`` when ``noisy``; X (n, dim).
    lower, upper : float
        Default box [lower, upper]^dim (the paper's Table 2 ranges).
    optimum_f : float
        The global minimum value (the noise-free value for noisy functions).
    optimum_at : float
        Every coordinate of the global minimiser (0 or 1).
    paper_label : str
        f1..f6 in the paper's Table 2/3, or "" when the paper does not use the function.
    noisy : bool
        True when ``func`` needs a random generator.
    min_dim : int
        Smallest dimension the function is defined for.
    """

    name: str
    func: Callable[..., Array]
    lower: float
    upper: float
    optimum_f: float = 0.0
    optimum_at: float = 0.0
    paper_label: str = ""
    noisy: bool = False
    min_dim: int = 1

    def __call__(self, X: ArrayLike, rng: SeedLike = None) -> Array:
        """Values at X (..., dim); ``rng`` (seed or Generator) feeds the noise of noisy functions."""
        if self.noisy:
            return self.func(X, make_rng(rng))
        return self.func(X)

    def optimum_x(self, dim: int) -> Array:
        """The global minimiser in ``dim`` dimensions, shape (dim,)."""
        return np.full(dim, self.optimum_at, dtype=float)

    def problem(
        self,
        dim: int,
        *,
        rng: SeedLike = None,
        lower: float | None = None,
        upper: float | None = None,
    ) -> Problem:
        """A :class:`Problem` over [lower, upper]^dim (default: the paper's range).

        ``rng`` is the generator (or seed) of the noise for noisy functions; it is bound to the
        problem, so every evaluation draws the next noise values from it.
        """
        if isinstance(dim, bool) or not isinstance(dim, (int, np.integer)) or dim < self.min_dim:
            raise ConfigError(f"function {self.name!r}: dim must be an integer >= {self.min_dim}, got {dim!r}")
        lo = self.lower if lower is None else lower
        hi = self.upper if upper is None else upper
        if self.noisy:
            gen = make_rng(rng)
            func = self.func

            def noisy(X: Array) -> Array:
                return func(X, gen)

            return Problem(noisy, lo, hi, name=self.name, dim=int(dim))
        return Problem(self.func, lo, hi, name=self.name, dim=int(dim))


SPHERE = register_function("sphere")(BenchmarkFunction("sphere", sphere, -100.0, 100.0, paper_label="f1"))
QUADRIC = register_function("quadric")(BenchmarkFunction("quadric", quadric, -100.0, 100.0, paper_label="f2"))
QUARTIC_NOISE = register_function("quartic-noise")(
    BenchmarkFunction("quartic-noise", quartic_noise, -1.28, 1.28, paper_label="f3", noisy=True)
)
RASTRIGIN = register_function("rastrigin")(
    BenchmarkFunction("rastrigin", rastrigin, -5.12, 5.12, paper_label="f4")
)
ACKLEY = register_function("ackley")(BenchmarkFunction("ackley", ackley, -32.0, 32.0, paper_label="f5"))
GRIEWANK = register_function("griewank")(
    BenchmarkFunction("griewank", griewank, -600.0, 600.0, paper_label="f6")
)
ROSENBROCK = register_function("rosenbrock")(
    BenchmarkFunction("rosenbrock", rosenbrock, -30.0, 30.0, optimum_at=1.0, min_dim=2)
)

#: The paper's Table 2 functions in order f1..f6.
PAPER_FUNCTIONS: tuple[str, ...] = ("sphere", "quadric", "quartic-noise", "rastrigin", "ackley", "griewank")


def get_function(name: str) -> BenchmarkFunction:
    """The registered benchmark ``name``; UnknownNameError lists the known ones."""
    return FUNCTIONS.get(name)


# ---- ZDT bi-objective problems (Zitzler, Deb & Thiele 2000), for the MOPSO tests ------------


def _zdt_g(X: Array) -> Array:
    return 1.0 + 9.0 * np.sum(X[..., 1:], axis=-1) / (X.shape[-1] - 1)


def zdt1(X: ArrayLike) -> Array:
    """ZDT1: f1 = x1, f2 = g (1 - sqrt(f1 / g)), g = 1 + 9 sum_{i>=2} x_i / (n - 1).

    X of shape (..., n_var) in [0, 1]^n_var, n_var >= 2 -> shape (..., 2). Convex front
    f2 = 1 - sqrt(f1) where g = 1 (x_2..x_n = 0).
    """
    X = np.asarray(X, dtype=float)
    f1 = X[..., 0]
    g = _zdt_g(X)
    return np.stack([f1, g * (1.0 - np.sqrt(f1 / g))], axis=-1)


def zdt2(X: ArrayLike) -> Array:
    """ZDT2: f1 = x1, f2 = g (1 - (f1 / g)^2); X (..., n_var) -> (..., 2). Concave front."""
    X = np.asarray(X, dtype=float)
    f1 = X[..., 0]
    g = _zdt_g(X)
    return np.stack([f1, g * (1.0 - (f1 / g) ** 2)], axis=-1)


_ZDT = {"zdt1": zdt1, "zdt2": zdt2}


def zdt_problem(name: str, n_var: int = 30) -> Problem:
    """The bi-objective :class:`Problem` ``zdt1`` or ``zdt2`` over [0, 1]^n_var."""
    if name not in _ZDT:
        raise UnknownNameError(f"unknown ZDT problem {name!r}; choose from: {', '.join(_ZDT)}")
    if isinstance(n_var, bool) or not isinstance(n_var, (int, np.integer)) or n_var < 2:
        raise ConfigError(f"{name}: n_var must be an integer >= 2, got {n_var!r}")
    return Problem(_ZDT[name], 0.0, 1.0, n_objectives=2, name=name, dim=int(n_var))


def zdt_front(name: str, n_points: int = 100) -> Array:
    """Points of the true Pareto front, shape (n_points, 2), f1 evenly spaced in [0, 1]."""
    f1 = np.linspace(0.0, 1.0, n_points)
    if name == "zdt1":
        return np.stack([f1, 1.0 - np.sqrt(f1)], axis=1)
    if name == "zdt2":
        return np.stack([f1, 1.0 - f1**2], axis=1)
    raise UnknownNameError(f"unknown ZDT problem {name!r}; choose from: {', '.join(_ZDT)}")


def zdt_front_hypervolume(name: str, reference: tuple[float, float] = (1.1, 1.1)) -> float:
    """Exact hypervolume of the whole (continuous) true front w.r.t. ``reference`` (r1, r2 >= 1).

    Area dominated = integral over f1 in [0, 1] of (r2 - front(f1)) plus (r1 - 1) * r2:
    ZDT1: (r2 - 1) + 2/3 + (r1 - 1) r2;  ZDT2: (r2 - 1) + 1/3 + (r1 - 1) r2.
    For (1.1, 1.1): 0.876667 and 0.543333.
    """
    r1, r2 = reference
    if r1 < 1.0 or r2 < 1.0:
        raise ConfigError(f"{name}: reference point must be >= (1, 1), got {reference}")
    integral = {"zdt1": 2.0 / 3.0, "zdt2": 1.0 / 3.0}
    if name not in integral:
        raise UnknownNameError(f"unknown ZDT problem {name!r}; choose from: {', '.join(_ZDT)}")
    return (r2 - 1.0) + integral[name] + (r1 - 1.0) * r2
