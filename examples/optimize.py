"""Minimise your own vectorised function with an adaptive PSO.

    python examples/optimize.py
"""
import numpy as np

from swarmpath.optim import Problem, minimize


def styblinski_tang(X: np.ndarray) -> np.ndarray:
    """X : (n_particles, dim) -> (n_particles,); minimum -39.166 * dim at x_i = -2.9035."""
    return 0.5 * np.sum(X**4 - 16 * X**2 + 5 * X, axis=1)


problem = Problem(styblinski_tang, lower=[-5] * 5, upper=[5] * 5)
for algorithm in ("pso", "apso", "amopso3"):
    res = minimize(problem, algorithm, iterations=300, particles=30, seed=1)
    print(f"{algorithm:8}: f = {res.f:.4f} (optimum {-39.16617 * 5:.4f}) after {res.n_evaluations} evaluations")
