"""Write a controller, register it, and run the conformance checks on it.

    python examples/custom_controller.py
"""
import numpy as np

from swarmpath.control import Controller, Decision
from swarmpath.capabilities import Capabilities
from swarmpath.registry import register_controller
from swarmpath.runner import run_world
from swarmpath.testing import check_controller
from swarmpath.world import load_scenario


@register_controller("greedy-wait")
class GreedyWait(Controller):
    """Steps straight toward the goal, one cell at most, and waits when the next cell is
    blocked or taken by another robot this step. Simple, and it can deadlock."""

    capabilities = Capabilities(grid_based=True)

    def reset(self, world, plan, rng):
        self.grid_ = world.grid()
        self.step_ = world.max_speeds * world.dt

    def act(self, obs):
        new = obs.positions.copy()
        taken = set()
        for i in np.argsort(np.linalg.norm(obs.goals - obs.positions, axis=1)):
            delta = obs.goals[i] - obs.positions[i]
            dist = float(np.linalg.norm(delta))
            target = obs.goals[i] if dist <= self.step_[i] else obs.positions[i] + delta * (self.step_[i] / dist)
            cell = tuple(self.grid_.cell_of(target))
            if self.grid_.is_free(cell) and cell not in taken:
                new[i] = target
            taken.add(tuple(self.grid_.cell_of(new[i])))
        return Decision(new, modes=["go" if not np.array_equal(a, b) else "wait" for a, b in zip(new, obs.positions)])


if __name__ == "__main__":
    print("conformance problems:", check_controller(GreedyWait, planner=None, require_collision_free=False))
    result = run_world(load_scenario("karim2014"), planner="none", controller="greedy-wait", seed=1)
    print("karim2014 with greedy-wait:", result.summary.verdict(), dict(result.summary.collisions))
