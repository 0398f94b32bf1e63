"""Multi-robot PSO with linear prediction of moving obstacles (PSO-prediction paper, 2013):
the ``pso-predictive`` and ``pso-reactive`` controllers and their parts.

- :mod:`.prediction`: linear prediction of obstacles from two samples (section 2.C);
- :mod:`.kernels`: eq. 1-8 as pure functions;
- :mod:`.step_problem`: one step's objective and hard constraints;
- :mod:`.step_solver`: the batched per-robot swarm;
- :mod:`.controller`: the registered controllers (``pso-predictive``, ``pso-reactive``);
- :mod:`.paper`: the paper-pure ``pso-predictive-paper`` and ``pso-reactive-paper``.
"""
from swarmpath.control.pso_predictive.controller import PredictivePSOController, ReactivePSOController
from swarmpath.control.pso_predictive.kernels import (goal_distance, inverse_obstacle_distance, kin_penalty,
                                                      next_position, path_buffer_penalty, pso_velocity_update_wrapped,
                                                      static_clearance_penalty, wrap_angle)
from swarmpath.control.pso_predictive.paper import PaperPredictivePSOController, PaperReactivePSOController
from swarmpath.control.pso_predictive.step_problem import (StepProblem, Weights, hard_violation, objective,
                                                           paper_objective)
from swarmpath.control.pso_predictive.step_solver import StepChoice, SwarmSettings, solve_step

__all__ = ["PredictivePSOController", "ReactivePSOController", "PaperPredictivePSOController",
           "PaperReactivePSOController", "paper_objective", "goal_distance", "inverse_obstacle_distance",
           "kin_penalty", "next_position", "path_buffer_penalty", "pso_velocity_update_wrapped",
           "static_clearance_penalty", "wrap_angle", "StepProblem", "Weights", "hard_violation", "objective",
           "StepChoice", "SwarmSettings", "solve_step"]
