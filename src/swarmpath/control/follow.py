"""The ``follow`` controller: each robot follows its offline path at full speed and avoids
nothing. It is the baseline that shows why online avoidance is needed."""
from __future__ import annotations

import numpy as np

from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.control.path_tracking import advance_along
from swarmpath.errors import ConfigError
from swarmpath.capabilities import Capabilities
from swarmpath.registry import register_controller
from swarmpath.planning.base import Plan
from swarmpath.world.world import World


@register_controller("follow")
class FollowController(Controller):
    """Moves every robot along its planned polyline, up to ``max_speed * dt`` per step,
    passing through every vertex (so grid paths are followed cell by cell). A timed plan
    (``RobotPlan.times``) is followed on its schedule: at step t the robot heads for the
    vertex planned for step t, waiting where the plan waits."""

    capabilities = Capabilities(needs_plan=True, multi_robot=False)

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        if plan is None:
            raise ConfigError("controller 'follow' needs an offline plan (choose a planner)")
        self.paths_ = [p if p is not None else np.asarray([r.start], float) for p, r in zip(plan.paths, world.robots)]
        self.times_ = [rp.times if rp.path is not None else None for rp in plan.robots]
        self.next_vertex_ = np.ones(world.n_robots, dtype=np.int64)
        self.budget_ = world.max_speeds * world.dt

    def act(self, obs: Observation) -> Decision:
        new = obs.positions.copy()
        for i, path in enumerate(self.paths_):
            times = self.times_[i]
            if times is not None:  # the vertex planned for this step (the last one once the plan ends)
                k = int(np.searchsorted(times, obs.step, side="right")) - 1
                path = path[:max(k, 0) + 1]
                self.next_vertex_[i] = min(int(self.next_vertex_[i]), len(path))
            new[i], self.next_vertex_[i] = advance_along(path, obs.positions[i], int(self.next_vertex_[i]),
                                                         float(self.budget_[i]))
        modes = ["arrived" if at else "follow" for at in (np.linalg.norm(new - obs.goals, axis=1) <= 1e-9)]
        return Decision(new, modes)
