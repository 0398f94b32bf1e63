"""Regenerate the reference figures in docs/figures/ (one per paper, and the README picture).

    python docs/figures/make_figures.py            # all that can be made now
    python docs/figures/make_figures.py jaleel2016 # just one

Each figure needs its scenario and its planner/controller to be registered; a figure whose
parts do not exist yet is reported as skipped (and made on a later run, once they do). Seeds
are fixed, so the figures only change when the algorithms do.

    jaleel2016.png      `swarmpath run jaleel2016` (hybrid APF plans, cat swarm online):
                        planned (dashed) and executed (solid) paths; the README shows it
    karim2014.png       the fish-swarm robot among obstacles that are redrawn every step,
                        at four moments of one run
    prediction2013.png  PSO with obstacle prediction: executed paths, and UTD(t) with and
                        without prediction over 10 seeds
    abbas-case1.png     AMOPSO path planning, case 1: the path among obstacles and danger zones
"""
from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


class Skip(Exception):
    """A figure whose ingredients do not exist yet."""


def _need(scenario: str, planner: str | None = None, controller: str | None = None):
    from swarmpath.registry import CONTROLLERS, PLANNERS
    from swarmpath.world.scenario import builtin_scenarios

    if scenario not in builtin_scenarios():
        raise Skip(f"scenario {scenario!r} does not exist yet")
    if planner and planner not in PLANNERS.names():
        raise Skip(f"planner {planner!r} is not registered yet")
    if controller and controller not in CONTROLLERS.names():
        raise Skip(f"controller {controller!r} is not registered yet")
    from swarmpath.world import load_scenario

    return load_scenario(scenario)


def jaleel2016(out: Path) -> Path:
    """The README picture: what `swarmpath run jaleel2016` does (the scenario's defaults)."""
    from swarmpath.runner import run_world
    from swarmpath.viz.style import save_figure
    from swarmpath.viz.world_plot import plot_trajectory

    world = _need("jaleel2016", "hybrid-apf", "cat-swarm")
    result = run_world(world, seed=0)
    return save_figure(plot_trajectory(result.trajectory), out / "jaleel2016.png", dpi=130)


def karim2014(out: Path) -> Path:
    from swarmpath.runner import run_world
    from swarmpath.viz.style import save_figure
    from swarmpath.viz.world_plot import plot_snapshots

    world = _need("karim2014", None, "fish-swarm")
    result = run_world(world, seed=0)
    traj = result.trajectory
    title = (f"karim2014 - controller fish-swarm, seed 0: {traj.n_steps} steps, "
             f"path length {result.summary.sum_of_lengths:.2f}, "
             f"{result.summary.contacts} collisions")
    return save_figure(plot_snapshots(traj, n_panels=4, title=title), out / "karim2014.png", dpi=120)


def prediction2013(out: Path) -> Path:
    from swarmpath.metrics.utd import uncovered_target_distance
    from swarmpath.runner import run_world
    from swarmpath.viz.curves import plot_utd_curves
    from swarmpath.viz.style import new_figure, save_figure
    from swarmpath.viz.world_plot import plot_trajectory

    world = _need("prediction2013", None, "pso-predictive")
    _need("prediction2013", None, "pso-reactive")
    fig = new_figure(13.0, 5.4)
    left, right = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    first = run_world(world, controller="pso-predictive", seed=0)
    plot_trajectory(first.trajectory, ax=left, legend=False, y_down=True)   # as on the paper's screen
    curves: dict[str, list[np.ndarray]] = {"with prediction": [], "without prediction": []}
    for seed in range(10):
        for label, controller in (("with prediction", "pso-predictive"), ("without prediction", "pso-reactive")):
            traj = run_world(world, controller=controller, seed=seed, clearance=False).trajectory
            curves[label].append(uncovered_target_distance(traj.positions, traj.goals))
    plot_utd_curves(curves, ax=right, title="UTD(t), mean +- 1 std over seeds 0-9")
    fig.tight_layout()
    return save_figure(fig, out / "prediction2013.png", dpi=110)


def abbas_case1(out: Path) -> Path:
    from swarmpath.runner import run_world
    from swarmpath.viz.style import save_figure
    from swarmpath.viz.world_plot import plot_trajectory

    world = _need("abbas-case1", "amopso-path", "follow")
    result = run_world(world, planner="amopso-path", controller="follow", seed=0)
    length = result.summary.robots[0].planned_length
    extra = f"planned length {length:.2f} (paper 14.4-14.7; straight line 14.14)" if length else None
    fig = plot_trajectory(result.trajectory)
    if extra:
        fig.axes[0].set_title(fig.axes[0].get_title() + f"\n{extra}", fontsize=10)
    return save_figure(fig, out / "abbas-case1.png", dpi=120)


FIGURES: dict[str, Callable[[Path], Path]] = {
    "jaleel2016": jaleel2016, "karim2014": karim2014, "prediction2013": prediction2013, "abbas-case1": abbas_case1,
}


def main(argv: list[str]) -> int:
    names = argv or list(FIGURES)
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        print(f"unknown figure(s): {', '.join(unknown)}; known: {', '.join(FIGURES)}", file=sys.stderr)
        return 2
    for name in names:
        try:
            path = FIGURES[name](HERE)
        except Skip as why:
            print(f"skipped {name}: {why}")
            continue
        print(f"wrote {path.relative_to(HERE.parent.parent)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
