"""``simulate`` and ``run_world``: the front doors that tie planner, controller and simulator
together for one seed."""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Callable

from swarmpath.errors import ConfigError
from swarmpath.planning.base import Plan
from swarmpath.registry import CONTROLLERS, PLANNERS
from swarmpath.sim.sensing import SensingConfig
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import Trajectory


@dataclass(frozen=True)
class RunResult:
    """Everything one run produced."""

    world: Any
    plan: Plan | None
    trajectory: Trajectory
    summary: dict
    planner: str | None
    controller: str


def choose_pair(world, planner: str | None, controller: str | None) -> tuple[str | None, str]:
    """The planner and controller to use: the ones given, else the scenario's defaults, else
    a sensible choice (cat swarm on a grid for point robots, predictive PSO for discs)."""
    controller = controller or world.defaults.get("controller")
    if controller is None:
        continuous = world.n_robots > 0 and all(r.radius > 0 for r in world.robots)
        controller = "pso-predictive" if continuous and "pso-predictive" in CONTROLLERS else "cat-swarm"
    ctrl_cls = CONTROLLERS.get(controller)
    if planner is None:
        planner = world.defaults.get("planner")
        if planner is None:
            planner = "astar" if ctrl_cls.capabilities.needs_plan else "none"
    PLANNERS.get(planner)
    if ctrl_cls.capabilities.needs_plan and planner == "none":
        raise ConfigError(f"controller {controller!r} needs an offline plan; choose a planner other than 'none'")
    return planner, controller


def simulate(world, controller, plan: Plan | None = None, *, seed: int = 0, max_steps: int | None = None,
             sensing: SensingConfig | None = None, progress: Callable[[int, int], None] | None = None) -> Trajectory:
    """Run ``controller`` (a name or a configured Controller) on ``world``."""
    if isinstance(controller, str):
        controller = CONTROLLERS.get(controller)()
    return Simulator(world, controller, plan, seed=seed, max_steps=max_steps, sensing=sensing,
                     progress=progress).run()


def run_world(world, *, planner: str | None = None, controller: str | None = None, seed: int = 0,
              max_steps: int | None = None, sensing: SensingConfig | None = None,
              progress: Callable[[int, int], None] | None = None, clearance: bool = True) -> RunResult:
    """Plan (if the pair needs it), simulate and summarise one run."""
    from swarmpath.metrics.summary import run_summary

    planner, controller = choose_pair(world, planner, controller)
    plan = None
    planning_time = 0.0
    if planner != "none":
        t0 = time.perf_counter()
        plan = PLANNERS.get(planner)().plan(world, rng=seed)
        planning_time = time.perf_counter() - t0
        if not plan.robots:
            plan = None
    traj = simulate(world, controller, plan, seed=seed, max_steps=max_steps, sensing=sensing, progress=progress)
    traj.meta["planning_time_s"] = planning_time
    summary = run_summary(world, traj, plan, planner=planner, controller=controller, planning_time_s=planning_time,
                          clearance=clearance)
    return RunResult(world, plan, traj, summary, planner, controller)
