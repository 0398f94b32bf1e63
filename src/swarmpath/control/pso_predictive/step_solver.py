"""The per-step search: one batched particle swarm (k robots x n particles) over each robot's
heading and speed fraction (eq. 1-2 and eq. 8 of the PSO-prediction paper, 2013)."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.pso_predictive.kernels import next_position, pso_velocity_update_wrapped, wrap_angle
from swarmpath.control.pso_predictive.step_problem import StepProblem, Weights, objective

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class SwarmSettings:
    """PSO hyperparameters of the per-step search (eq. 8): particles, iterations, inertia w,
    confidences C1 and C2, the velocity limits of heading (rad) and speed fraction, and
    whether one particle starts straight toward the goal at full speed (``informed``, ours;
    the paper initialises every particle at random)."""

    n_particles: int = 10
    n_iterations: int = 20
    w: float = 0.7298
    c1: float = 1.49618
    c2: float = 1.49618
    v_max_heading: float = np.pi / 2
    v_max_speed: float = 0.5
    informed: bool = True


@dataclass(frozen=True)
class StepChoice:
    """Chosen next positions of k robots with their cost and hard-constraint violation."""

    positions: FloatArray
    cost: FloatArray
    violation: FloatArray


def solve_step(problem: StepProblem, world, weights: Weights, settings: SwarmSettings,
               rng: np.random.Generator, evaluate: Callable[..., tuple[FloatArray, FloatArray]] = objective
               ) -> StepChoice:
    """One batched PSO (k robots x n_particles) over (heading, speed fraction), then the best
    of the swarm's result, standing still and (within reach) stepping exactly onto the goal.
    ``evaluate(problem, world, x_next, weights) -> (cost, violation)`` is the objective
    (:func:`~.step_problem.objective`, ours, by default)."""
    k = problem.start.shape[0]
    p = settings.n_particles
    to_goal = problem.goal - problem.start
    goal_heading = np.arctan2(to_goal[:, 1], to_goal[:, 0])
    theta = rng.uniform(-np.pi, np.pi, (k, p))
    sigma = rng.uniform(0.0, 1.0, (k, p))
    if settings.informed:
        theta[:, 0], sigma[:, 0] = goal_heading, 1.0   # one informed particle: straight to the goal
    x = np.stack([theta, sigma], axis=-1)
    vmax = np.array([settings.v_max_heading, settings.v_max_speed])
    v = rng.uniform(-1.0, 1.0, (k, p, 2)) * vmax * 0.5
    cost, viol = evaluate(problem, world, next_position(problem.start, x[..., 0], x[..., 1], problem.reach), weights)
    pbest, pbest_f, pbest_v = x.copy(), cost.copy(), viol.copy()
    rows = np.arange(k)
    for _ in range(settings.n_iterations - 1):
        g = np.argmin(pbest_f, axis=1)
        gbest = pbest[rows, g][:, None, :]
        r = rng.random((2, k, p, 2))
        v = pso_velocity_update_wrapped(v, x, pbest, gbest, settings.w, settings.c1, settings.c2, r[0], r[1])
        v = np.clip(v, -vmax, vmax)
        x = x + v
        x[..., 0] = wrap_angle(x[..., 0])
        x[..., 1] = np.clip(x[..., 1], 0.0, 1.0)
        cost, viol = evaluate(problem, world, next_position(problem.start, x[..., 0], x[..., 1], problem.reach),
                              weights)
        better = cost < pbest_f
        pbest[better], pbest_f[better], pbest_v[better] = x[better], cost[better], viol[better]
    g = np.argmin(pbest_f, axis=1)
    best = next_position(problem.start, pbest[rows, g][:, None, 0], pbest[rows, g][:, None, 1], problem.reach)[:, 0]
    # exact extra candidates: stand still, and the goal itself when it is within reach
    gap = np.linalg.norm(to_goal, axis=1)
    snap = np.where((gap <= problem.reach)[:, None], problem.goal, problem.start)
    cands = np.stack([best, problem.start, snap], axis=1)                     # (k, 3, 2)
    c_cost, c_viol = evaluate(problem, world, cands, weights)
    pick = np.argmin(c_cost, axis=1)
    return StepChoice(cands[rows, pick].copy(), c_cost[rows, pick], c_viol[rows, pick])
