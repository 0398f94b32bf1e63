"""Swarm optimisers and benchmark functions (issue 5; paper: Abbas & Abdulsahab, AMOPSO).

Problem -> optimiser -> result, tied by :func:`minimize`::

    from swarmpath.optim import Problem, minimize
    p = Problem(lambda X: (X ** 2).sum(axis=1), lower=[-5] * 10, upper=[5] * 10)
    res = minimize(p, "amopso3", iterations=200, particles=30, seed=1)
    res.x, res.f, res.history

Registered optimisers: ``pso`` (constriction coefficients), ``spso`` (the paper's SPSO),
``apso`` (Zhan et al.'s adaptive PSO), ``amopso1`` .. ``amopso4``, ``mopso``, ``cso``, ``afsa``.
Registered functions: ``sphere``, ``quadric``, ``quartic-noise``, ``rastrigin``, ``ackley``,
``griewank``, ``rosenbrock``. The equations as implemented and every interpretation are in
docs/papers/amopso.md.
"""
from swarmpath.optim.afsa import AFSA
from swarmpath.optim.amopso import (
    AMOPSO,
    AMOPSO1,
    AMOPSO2,
    AMOPSO3,
    AMOPSO4,
    AMOPSO_VARIANTS,
    AMOPSORule,
    amopso_acceleration,
    amopso_inertia_eq15,
    amopso_inertia_eq16,
    amopso_l_factor,
    amopso_random_factors,
    amopso_rule,
)
from swarmpath.optim.apso import APSO
from swarmpath.optim.base import Optimizer
from swarmpath.optim.benchmark import benchmark_results, run_benchmark
from swarmpath.optim.cso import CSO, cso_seek_candidates, cso_selection_probabilities, cso_trace_velocity
from swarmpath.optim.functions import (
    PAPER_FUNCTIONS,
    BenchmarkFunction,
    ackley,
    get_function,
    griewank,
    quadric,
    quartic,
    quartic_noise,
    rastrigin,
    rosenbrock,
    sphere,
    zdt1,
    zdt2,
    zdt_problem,
)
from swarmpath.optim.minimize import make_optimizer, minimize
from swarmpath.optim.mopso import MOPSO, coello_mutation, crowding_tournament, update_rule, weighted_sum
from swarmpath.optim.pareto import crowding_distance, dominates, hypervolume_2d, non_dominated
from swarmpath.optim.problem import Problem
from swarmpath.optim.pso import (
    PSO,
    SPSO,
    SPSORule,
    UpdateRule,
    clamp_velocity,
    linear_inertia_eq32,
    pso_position_update,
    pso_velocity_update,
)
from swarmpath.optim.result import OptimizeResult

__all__ = [
    "AFSA", "AMOPSO", "APSO", "AMOPSO1", "AMOPSO2", "AMOPSO3", "AMOPSO4", "AMOPSO_VARIANTS", "AMOPSORule",
    "BenchmarkFunction", "CSO", "MOPSO", "OptimizeResult", "Optimizer", "PAPER_FUNCTIONS", "PSO",
    "Problem", "SPSO", "SPSORule", "UpdateRule", "ackley", "amopso_acceleration", "amopso_inertia_eq15",
    "amopso_inertia_eq16", "amopso_l_factor", "amopso_random_factors", "amopso_rule",
    "benchmark_results", "clamp_velocity", "coello_mutation", "crowding_distance",
    "crowding_tournament", "cso_seek_candidates", "cso_selection_probabilities",
    "cso_trace_velocity", "dominates", "get_function", "griewank", "hypervolume_2d",
    "linear_inertia_eq32", "make_optimizer", "minimize", "non_dominated", "pso_position_update",
    "pso_velocity_update", "quadric", "quartic", "quartic_noise", "rastrigin", "rosenbrock",
    "run_benchmark", "sphere", "update_rule", "weighted_sum", "zdt1", "zdt2", "zdt_problem",
]
