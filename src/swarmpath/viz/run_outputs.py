"""What ``swarmpath run --out DIR`` writes: the summary, the trajectory and the pictures.

    summary.json         the run's summary (the same object as ``--json``)
    trajectory.npz       the Trajectory (``swarmpath replay`` reads it)
    world.png            the world: workspace, obstacles, danger zones, moving obstacles, starts, goals
    paths.png            the world with planned (dashed) and executed (solid) paths, collisions
    potential_field.png  the planner's potential field (planners apf and hybrid-apf, when
                         swarmpath.viz.potential_field provides it)
    animation.gif        the run, with trails, moving obstacles and a step counter
    replay.html          the interactive replay (one self-contained file)
"""
from __future__ import annotations

import json
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from swarmpath.viz import style

FIELD_PLANNERS = ("apf", "hybrid-apf")


def write_run_outputs(out_dir: str | Path, result: Any, *, figures: bool = True, animation: bool = True,
                      replay: bool = True, progress: Callable[[int, int], None] | None = None) -> list[Path]:
    """Write the files listed in the module docstring for a :class:`~swarmpath.runner.RunResult`;
    returns their paths. ``progress(done, total)`` follows the animation's frames."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    summary_path = out / "summary.json"
    summary_path.write_text(json.dumps(result.summary.to_dict(), indent=2, default=_json_default), encoding="utf-8")
    written.append(summary_path)
    traj = result.trajectory
    written.append(traj.save(out / "trajectory.npz"))
    if figures:
        written += write_figures(out, result)
    if replay:
        from swarmpath.viz.html_replay import write_replay_html

        written.append(write_replay_html(traj, out / "replay.html"))
    if animation:
        from swarmpath.viz.animation import save_animation

        written.append(save_animation(traj, out / "animation.gif", progress=progress))
    return written


def write_figures(out: Path, result: Any) -> list[Path]:
    """world.png, paths.png and (for potential-field planners) potential_field.png."""
    from swarmpath.viz.world_plot import plot_trajectory, plot_world

    traj = result.trajectory
    title = style.run_title(traj.scenario, result.planner, result.controller, traj.seed)
    written = [style.save_figure(plot_world(traj, title=f"{traj.scenario}: world"), out / "world.png"),
               style.save_figure(plot_trajectory(traj), out / "paths.png")]
    if result.planner in FIELD_PLANNERS:
        fig = potential_field_figure(result, title=title)
        if fig is not None:
            written.append(style.save_figure(fig, out / "potential_field.png"))
    return written


def potential_field_figure(result: Any, *, title: str | None = None, robot: int = 0) -> Any:
    """The potential field toward robot ``robot``'s goal (heatmap, arrows along -grad U) with
    every robot's planned path, drawn by swarmpath.viz.potential_field (the APF planner's
    module); None when that module is absent or the world has no robots.

    The field uses the paper's parameters (the registered planners' defaults, which
    ``swarmpath run`` uses). A failure here is reported as a warning, so that one optional
    figure never costs the run's other outputs."""
    try:
        from swarmpath.planning.potential_field import potential_field
        from swarmpath.viz.potential_field import plot_potential_field
    except ImportError:
        return None
    world = result.world
    if world.n_robots == 0:
        return None
    r = world.robots[robot]
    paths = None if result.plan is None else result.plan.paths
    heading = f"{title}\n" if title else ""
    try:
        field = potential_field(world, r.goal, radius=r.radius)
        return plot_potential_field(world, field, paths, title=f"{heading}potential field toward {r.id}'s goal")
    except Exception as exc:  # noqa: BLE001 - see the docstring
        warnings.warn(f"potential field figure failed: {type(exc).__name__}: {exc}", RuntimeWarning, stacklevel=2)
        return None


def _json_default(obj: Any) -> Any:
    import math

    import numpy as np

    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
