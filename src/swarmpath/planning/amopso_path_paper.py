"""The ``amopso-path-paper`` planner: Abbas & Abdulsahab's path planning at the paper's own
set-up (section 5.1 and Figure 2), with only the interpretations the paper needs.

- every particle starts uniformly in the box (eq. 31), no A* particle;
- N = 8 particles, T_max = 120 iterations per robot (section 5.1);
- the MOPSO of Figure 2: an external archive of non-dominated positions, a leader drawn
  from it, personal bests replaced by better positions; no mutation operator;
- the velocity rule of Table 1 (AMOPSO4 by default; ``update`` chooses any of SPSO,
  AMOPSO1-4), in Pareto mode (eq. 14) or weighted sum (eq. 13).

The interpretations it shares with ``amopso-path`` (the paper is silent on them; docs/papers/
amopso.md): K = 4 intermediate waypoints per particle, path length as the second objective,
static obstacles as a penalty that every collision-free path dominates, the crowding-distance
archive and leader tournament of Coello's MOPSO, and the choice from the front (the shortest
member outside every danger zone). ``amopso-path`` adds the A*-seeded particle, 30 particles
and Coello's mutation.
"""
from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from swarmpath.capabilities import Capabilities
from swarmpath.errors import ConfigError
from swarmpath.optim.mopso import MODES, MOPSO, UPDATE_RULES, check_weights
from swarmpath.planning.amopso_path import DANGER_OBJECTIVES, plan_robots, swarm_path
from swarmpath.planning.base import Plan, Planner, RobotPlan
from swarmpath.registry import register_planner
from swarmpath.types import SeedLike

#: The paper's budget per robot (section 5.1): N = 8 particles, T_max = 120 iterations.
PAPER_PARTICLES, PAPER_ITERATIONS = 8, 120


@register_planner("amopso-path-paper")
class AMOPSOPathPaperPlanner(Planner):
    """AMOPSO path planning at the paper's set-up: random initial swarm (eq. 31), 8 particles
    x 120 iterations, no mutation (see the module docstring).

    Parameters
    ----------
    update : str
        Velocity rule: ``"spso"`` or ``"amopso1"`` .. ``"amopso4"`` (Table 1; default AMOPSO4).
    mode : str
        ``"pareto"`` (eq. 14) or ``"weighted-sum"`` (eq. 13).
    weights : sequence of two floats, optional
        (W_length, W_danger) of eq. 13; equal by default.
    danger_objective : str
        ``"inverse-sum"`` (the paper's f1, eq. 1) or ``"clearance"``.
    """

    capabilities = Capabilities(continuous=True, multi_robot=False, randomized=True, multi_objective=True)

    #: The interpretations shared with ``amopso-path`` (fixed here, not tuned).
    waypoints = 4
    particles = PAPER_PARTICLES
    iterations = PAPER_ITERATIONS
    danger_margin = 0.0
    archive_size = 100

    def __init__(self, update: str = "amopso4", mode: str = "pareto", weights: Sequence[float] | None = None,
                 danger_objective: str = "inverse-sum"):
        self.update = update
        self.mode = mode
        self.weights = None if weights is None else tuple(float(w) for w in weights)
        self.danger_objective = danger_objective
        owner = "amopso-path-paper"
        if update not in UPDATE_RULES or update == "pso":
            rules = ", ".join(r for r in UPDATE_RULES if r != "pso")
            raise ConfigError(f"{owner}: update must be one of {rules} (the paper's rules); got {update!r}")
        if mode not in MODES:
            raise ConfigError(f"{owner}: mode must be one of {', '.join(MODES)}; got {mode!r}")
        if danger_objective not in DANGER_OBJECTIVES:
            raise ConfigError(f"{owner}: danger_objective must be one of {', '.join(DANGER_OBJECTIVES)}; "
                              f"got {danger_objective!r}")
        if self.weights is not None:
            check_weights(owner, self.weights, 2)

    def optimizer(self) -> MOPSO:
        """The MOPSO of the paper's Figure 2: the chosen rule, no mutation."""
        return MOPSO(update=self.update, mode=self.mode, weights=self.weights, archive_size=self.archive_size,
                     mutation_rate=0.0)

    def params(self) -> dict[str, Any]:
        """The hyperparameters, for reports."""
        return {"update": self.update, "mode": self.mode, "weights": self.weights, "waypoints": self.waypoints,
                "particles": self.particles, "iterations": self.iterations, "init": "random",
                "danger_objective": self.danger_objective, "danger_margin": self.danger_margin,
                "archive_size": self.archive_size, "mutation_rate": 0.0}

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        return plan_robots(self, world, rng)

    def plan_robot(self, world, robot, *, rng: np.random.Generator) -> RobotPlan:
        """One robot's plan (statuses and diagnostics as ``amopso-path``)."""
        return swarm_path(world, robot, self.optimizer(), mode=self.mode, waypoints=self.waypoints,
                          particles=self.particles, iterations=self.iterations, init="random",
                          danger_objective=self.danger_objective, danger_margin=self.danger_margin, rng=rng)
