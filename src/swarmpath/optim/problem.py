"""The problem an optimiser solves: objective function(s) over a box, evaluated a swarm at a time.

A :class:`Problem` wraps a *vectorised* callable: it receives the positions of a whole swarm,
an ndarray of shape (n_points, dim), and returns one row of objective values per point. This is
what makes the optimisers fast (one numpy call per iteration instead of one Python call per
particle) and it is the only thing an optimiser knows about the problem (STYLE habit 1: problem,
algorithm and stopping rule are separate things).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.errors import ConfigError

#: A vectorised objective: ndarray (n_points, dim) -> ndarray (n_points,) or (n_points, n_objectives).
ObjectiveFunction = Callable[[NDArray[np.float64]], ArrayLike]


@dataclass(frozen=True, init=False)
class Problem:
    """Minimise ``func`` over the box ``lower <= x <= upper``.

    Parameters
    ----------
    func : callable
        Vectorised objective: takes X, ndarray of shape (n_points, dim), and returns an array of
        shape (n_points,) for one objective or (n_points, n_objectives) for several. Lower is
        better for every objective.
    lower, upper : array_like of shape (dim,), or scalars together with ``dim``
        Bounds of the search box; ``lower < upper`` componentwise, both finite.
    n_objectives : int
        Number of objectives (columns) ``func`` returns.
    name : str, optional
        Shown in error messages and reports.
    dim : int, optional
        Only needed when ``lower`` and ``upper`` are both scalars.

    Examples
    --------
    >>> p = Problem(lambda X: (X**2).sum(axis=1), [-5, -5], [5, 5])
    >>> p.evaluate(np.zeros((3, 2)))
    array([0., 0., 0.])
    """

    func: ObjectiveFunction
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    n_objectives: int
    name: str | None

    def __init__(
        self,
        func: ObjectiveFunction,
        lower: ArrayLike,
        upper: ArrayLike,
        n_objectives: int = 1,
        *,
        name: str | None = None,
        dim: int | None = None,
    ) -> None:
        label = f"problem {name!r}" if name else "problem"
        if not callable(func):
            raise ConfigError(f"{label}: func must be callable, got {type(func).__name__}")
        lo = np.asarray(lower, dtype=float)
        hi = np.asarray(upper, dtype=float)
        if dim is not None:
            if isinstance(dim, bool) or not isinstance(dim, (int, np.integer)) or dim < 1:
                raise ConfigError(f"{label}: dim must be a positive integer, got {dim!r}")
            lo = np.broadcast_to(lo, (int(dim),)) if lo.ndim == 0 else lo
            hi = np.broadcast_to(hi, (int(dim),)) if hi.ndim == 0 else hi
        elif lo.ndim == 0 and hi.ndim == 0:
            raise ConfigError(f"{label}: scalar bounds need dim")
        if lo.ndim == 0 and hi.ndim == 1:
            lo = np.broadcast_to(lo, hi.shape)
        elif hi.ndim == 0 and lo.ndim == 1:
            hi = np.broadcast_to(hi, lo.shape)
        if lo.shape != hi.shape:
            raise ConfigError(f"{label}: lower has shape {lo.shape} but upper has shape {hi.shape}")
        if lo.ndim != 1 or lo.size == 0:
            raise ConfigError(f"{label}: bounds must be 1-D with at least one entry, got shape {lo.shape}")
        if dim is not None and lo.shape[0] != dim:
            raise ConfigError(f"{label}: bounds have {lo.shape[0]} entries but dim is {dim}")
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
            raise ConfigError(f"{label}: bounds must be finite")
        if np.any(lo >= hi):
            i = int(np.argmax(lo >= hi))
            raise ConfigError(f"{label}: lower[{i}] = {lo[i]} must be < upper[{i}] = {hi[i]}")
        if isinstance(n_objectives, bool) or not isinstance(n_objectives, (int, np.integer)) or n_objectives < 1:
            raise ConfigError(f"{label}: n_objectives must be a positive integer, got {n_objectives!r}")
        lo = np.array(lo, dtype=float)
        hi = np.array(hi, dtype=float)
        lo.flags.writeable = False
        hi.flags.writeable = False
        object.__setattr__(self, "func", func)
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", hi)
        object.__setattr__(self, "n_objectives", int(n_objectives))
        object.__setattr__(self, "name", name)

    @property
    def dim(self) -> int:
        """Number of decision variables."""
        return int(self.lower.shape[0])

    def _label(self) -> str:
        return f"problem {self.name!r}" if self.name else "problem"

    def evaluate(self, X: ArrayLike) -> NDArray[np.float64]:
        """Objective values of the points ``X``.

        Parameters
        ----------
        X : array_like of shape (n_points, dim)

        Returns
        -------
        ndarray of shape (n_points,) for one objective, (n_points, n_objectives) for several.
        NaN values become +inf (the worst possible value), so that a failing evaluation can
        never become a best position.
        """
        X = np.asarray(X, dtype=float)
        if X.ndim != 2 or X.shape[1] != self.dim:
            raise ConfigError(f"{self._label()}: expected points of shape (n, {self.dim}), got {X.shape}")
        F = np.asarray(self.func(X), dtype=float)
        n = X.shape[0]
        if self.n_objectives == 1:
            if F.shape == (n, 1):
                F = F[:, 0]
            if F.shape != (n,):
                raise ConfigError(f"{self._label()}: objective returned shape {F.shape}, expected ({n},)")
        elif F.shape != (n, self.n_objectives):
            raise ConfigError(
                f"{self._label()}: objective returned shape {F.shape}, expected ({n}, {self.n_objectives})"
            )
        total = F.sum()
        if total != total:  # NaN somewhere (or inf - inf): replace NaN by +inf
            F = np.where(np.isnan(F), np.inf, F)
        return F
