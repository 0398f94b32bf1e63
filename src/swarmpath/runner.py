"""The front doors that tie planner, controller, simulator and metrics together for one seed:
:func:`simulate` (a controller on a world) and :func:`run_world` (plan, simulate, summarise).

This module sits above the simulator and the metrics, so neither of them needs the other's
caller: sim produces a :class:`~swarmpath.sim.trajectory.Trajectory`, metrics reads it, and
the runner joins them into a :class:`RunResult`.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import Callable

from swarmpath.control.base import Controller
from swarmpath.control.observation import SensingConfig
from swarmpath.errors import ConfigError
from swarmpath.metrics.summary import RunSummary, run_summary
from swarmpath.planning.base import Plan
from swarmpath.registry import CONTROLLERS, PLANNERS
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import Trajectory
from swarmpath.world.world import World


@dataclass(frozen=True)
class RunResult:
    """Everything one run produced: the world, the offline plan (None without a planner),
    the trajectory and its summary, and the names of the planner and controller used."""

    world: World
    plan: Plan | None
    trajectory: Trajectory
    summary: RunSummary
    planner: str | None
    controller: str


def choose_pair(world: World, planner: str | None, controller: str | None) -> tuple[str, str]:
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


def simulate(world: World, controller: str | Controller, plan: Plan | None = None, *, seed: int = 0,
             max_steps: int | None = None, sensing: SensingConfig | None = None,
             progress: Callable[[int, int], None] | None = None) -> Trajectory:
    """Run ``controller`` (a registered name or a configured Controller) on ``world``."""
    if not isinstance(world, World):
        raise ConfigError(f"simulate needs a World, got {type(world).__name__}")
    if isinstance(controller, str):
        controller = CONTROLLERS.get(controller)()
    return Simulator(world, controller, plan, seed=seed, max_steps=max_steps, sensing=sensing,
                     progress=progress).run()


def run_world(world: World, *, planner: str | None = None, controller: str | None = None, seed: int = 0,
              max_steps: int | None = None, sensing: SensingConfig | None = None,
              progress: Callable[[int, int], None] | None = None, clearance: bool = True) -> RunResult:
    """Plan (if the pair needs it), simulate and summarise one run."""
    if not isinstance(world, World):
        raise ConfigError(f"run_world needs a World, got {type(world).__name__} (load_scenario() makes one)")
    for name, value in (("planner", planner), ("controller", controller)):
        if value is not None and not isinstance(value, str):
            raise ConfigError(f"{name} must be a registered name, got {type(value).__name__}")
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
    traj = dataclasses.replace(traj, meta={**traj.meta, "planning_time_s": planning_time})
    summary = run_summary(world, traj, plan, planner=planner, controller=controller, planning_time_s=planning_time,
                          clearance=clearance)
    return RunResult(world, plan, traj, summary, planner, controller)
