"""The ``pso-predictive-paper`` and ``pso-reactive-paper`` controllers: the PSO-prediction
paper (2013) with only its own objective (eq. 3-7) and its linear prediction.

Each step every robot runs its own 10-particle PSO (eq. 8) over its heading and speed
fraction (eq. 1-2) and minimises :func:`~.step_problem.paper_objective`: the distance to
its goal, the kin penalty against the other robots' next positions, the constant f_st when
its local trajectory (the step, or the line from the new position to the goal) touches a
static obstacle, and f_dy / distance to the moving obstacle's predicted next position for
every obstacle within the sensing radius n (R + r). Nothing is a hard constraint.

What ``pso-predictive`` adds, and this does not: hard safety constraints (swept discs,
the obstacle's next sweep), the turn guard, the buffer around the obstacle's predicted
path, yielding, detours, the clearance ramp of the static term, robots resolved one after
the other by index, the informed particle, and keeping point robots a cell diagonal apart.
docs/papers/pso-prediction-2013.md ("The paper-pure variants") gives each reading.

Interpretations this variant needs (the paper is silent or garbled):

- robots decide simultaneously; the other robots' next positions in the kin term are their
  linear predictions (position + last displacement), the predictor the paper uses for the
  obstacle;
- the obstacle's prediction is eq. 4's x_p' = x_p + u dt' with dt' = arr[i] / arr[j];
- the search space is (heading, speed fraction in [0, 1]) and the exact goal is a candidate
  when within reach, so that a robot can stop on its goal (the paper's ||x - G|| <= eps).

``pso-reactive-paper`` is the same with the obstacle's current position in eq. 7 (the
paper's "classical non-prediction approach"). Neither promises zero contacts.
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.control.pso_predictive import prediction as pred
from swarmpath.control.pso_predictive.step_problem import StepProblem, Weights, paper_objective
from swarmpath.control.pso_predictive.step_solver import SwarmSettings, solve_step
from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import register_controller
from swarmpath.world.static_geometry import static_geometry
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]

#: The paper's swarm: 10 particles initialised at random (no informed particle).
PAPER_SWARM = SwarmSettings(informed=False)


def predicted_obstacles(track: pred.ObstacleTrack, obs: Observation) -> tuple[pred.ObstacleTrack, FloatArray]:
    """The obstacles' track after this observation and their predicted next positions (m, 2):
    eq. 4, x_p' = x_p + u dt', u from the last two positions, dt' the sampling time."""
    now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
    prev = np.asarray(obs.obstacle_previous, float).reshape(-1, 2)
    track = pred.update_track(track, obs.step, prev, now, obs.dt)
    dt_s = track.sampling_times(obs.dt)
    predicted = [pred.predict_linear(prev[j:j + 1], now[j:j + 1], obs.dt, dt_s[j])[0] for j in range(len(now))]
    return track, np.array(predicted, float).reshape(-1, 2)


@register_controller("pso-predictive-paper")
class PaperPredictivePSOController(Controller):
    """Per-robot PSO over the paper's own objective (eq. 3-7) with linear prediction of the
    moving obstacle (section 2.C); see the module docstring.

    Parameters (hyperparameters only):
    sensing_factor : n of the sensing radius n (R + r), n > 1 (3)
    eps : the robot-robot threshold epsilon of eq. 5 (world units, 0.05)
    weights : f_dp, f_st, f_dy as ``Weights.kin``, ``.static``, ``.moving`` (10, 2, 2; the
        paper gives no values); the other fields are not used
    swarm : the PSO (10 particles, 20 iterations, random initialisation)
    """

    capabilities = Capabilities(continuous=True, moving_obstacles=True, multi_robot=True, randomized=True,
                                contact_free=False)
    predictive: ClassVar[bool] = True

    def __init__(self, *, sensing_factor: float = 3.0, eps: float = 0.05, weights: Weights | None = None,
                 swarm: SwarmSettings | None = None):
        self.sensing_factor = sensing_factor
        self.eps = eps
        self.weights = weights or Weights()
        self.swarm = swarm or PAPER_SWARM

    def _check_parameters(self) -> None:
        name = self.registered_name
        if not self.sensing_factor > 1:
            raise ConfigError(f"{name}: sensing_factor must be > 1 (the paper's n), got {self.sensing_factor}")
        if not self.eps > 0:
            raise ConfigError(f"{name}: eps must be > 0, got {self.eps}")
        if self.swarm.n_particles < 1 or self.swarm.n_iterations < 1:
            raise ConfigError(f"{name}: swarm needs n_particles >= 1 and n_iterations >= 1")

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self._check_parameters()
        self.static_ = static_geometry(world)
        self.rng_ = rng
        self.radii_ = world.radii
        self.reach_ = world.max_speeds * world.dt
        self.goals_ = world.goals
        self.room_ = self.radii_[:, None] + self.radii_[None, :] + self.eps   # r_i + r_j + eps
        # beyond this centre distance no next positions can come within r_i + r_j + eps
        self.kin_range_ = self.room_ + 2 * (self.reach_[:, None] + self.reach_[None, :])
        self.extent_ = np.array([ob.extent for ob in world.moving_obstacles], float)
        self.previous_positions_ = world.starts.copy()
        self.track_ = pred.ObstacleTrack()

    def _problem(self, obs: Observation) -> StepProblem:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        if self.predictive:
            self.track_, target = predicted_obstacles(self.track_, obs)
        else:
            target = now
        dist = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
        pair_row, pair_other = np.nonzero((dist <= self.kin_range_) & ~np.eye(n, dtype=bool))
        announced = pos + (pos - self.previous_positions_)  # the others' linear prediction
        sensed = np.linalg.norm(pos[:, None] - now[None], axis=-1) <= \
            self.sensing_factor * (self.extent_[None, :] + self.radii_[:, None])
        room = self.room_[pair_row, pair_other]
        return StepProblem(start=pos, goal=self.goals_, radius=self.radii_, reach=self.reach_, robot=np.arange(n),
                           pair_row=pair_row, pair_other=pair_other, pair_from=pos[pair_other],
                           pair_to=pos[pair_other], pair_announced=announced[pair_other], pair_separation=room,
                           pair_room=room, obstacle_now=now, obstacle_next=target, obstacle_target=target,
                           guard=np.zeros(len(now)), path_end=target, buffer=np.zeros(len(now)),
                           obstacle_clear=np.zeros((n, len(now))), obstacle_mask=sensed,
                           static_near=np.ones(n, bool))

    def act(self, obs: Observation) -> Decision:
        pos = np.asarray(obs.positions, float)
        if len(pos) == 0:
            return Decision(pos.copy(), [])
        problem = self._problem(obs)
        choice = solve_step(problem, self.static_, self.weights, self.swarm, self.rng_, evaluate=paper_objective)
        self.previous_positions_ = pos.copy()
        new = choice.positions
        at_goal = np.linalg.norm(new - self.goals_, axis=1) <= 1e-9
        moved = np.any(new != pos, axis=1)
        avoiding = problem.obstacle_mask.any(axis=1)
        modes = np.where(at_goal, "arrived", np.where(~moved, "wait", np.where(avoiding, "avoid", "seek")))
        return Decision(new.copy(), modes.tolist())


@register_controller("pso-reactive-paper")
class PaperReactivePSOController(PaperPredictivePSOController):
    """The same paper objective without prediction: eq. 7 uses the moving obstacle's current
    position (the paper's "classical non-prediction approach")."""

    capabilities = Capabilities(continuous=True, moving_obstacles=False, multi_robot=True, randomized=True,
                                contact_free=False)
    predictive = False
