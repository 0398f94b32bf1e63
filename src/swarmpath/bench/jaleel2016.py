"""Reproduction of Jaleel & Hassan 2016, section IV (Table 1 and Figure 7) in kind.

``swarmpath reproduce jaleel2016 --out DIR [--runs N]`` plans the ``jaleel2016`` world (12 point
robots of the paper's Table 1 in a circular 30 x 30 workspace, our obstacle layout, 3 moving
blocks) offline with ``hybrid-apf`` (``astar`` if that planner is not installed), then runs the
``cat-swarm`` controller online over ``runs`` seeds (20 by default) and writes:

1. Table 1 in kind: per robot start, goal, offline length and executed length (mean, min, max
   over the seeds), in world units and in grid cells, next to the paper's grid-point lengths;
2. the offline planning time (the paper: 0.935 s in MATLAB) and the time spent in seek mode
   (the paper: 1.31 s), as robot-steps in seek mode and controller time;
3. collisions of every kind found by the simulator's checker, with the paper's claim of none,
   and the same plan followed without avoidance (``follow``) for contrast;
4. figures: the paths before (offline) and after (executed) the online phase, snapshots of
   one run coloured by behaviour, and the length change per robot;
5. the paper-pure ``cat-swarm-paper`` on the same plan and seeds next to ``cat-swarm`` (Table 1
   in kind, contacts, deadlocks) and the ablation ladder from the one to the other
   (:func:`ladder`, also run alone for the docs page).

It writes DIR/report.md (template ``templates/jaleel2016.md``) and PNG files. Same seed, same
numbers (times aside).
"""
from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from swarmpath.bench.formatting import fmt, point, render, table
from swarmpath.bench.ladder import Outcome, Rung, ladder_table, outcome_of, run_ladder, side_by_side
from swarmpath.bench.progress import Progress
from swarmpath.bench.runner import run_batch
from swarmpath.control.cat_swarm import CatSwarmController, CatSwarmPaperController
from swarmpath.control.follow import FollowController
from swarmpath.metrics.paths import arrival_steps, executed_lengths
from swarmpath.metrics.summary import RunSummary, run_summary
from swarmpath.planning.base import Plan
from swarmpath.registry import PLANNERS, register_reproduction
from swarmpath.sim.trajectory import Trajectory
from swarmpath.world import World, load_scenario

RUNS = 20
#: The paper's Table 1: robot -> (start, goal, length before, length after), lengths in grid points.
PAPER_TABLE1 = {
    "R1": ((4, 12.5), (9, 24), 82, 83), "R2": ((6.1, 12.5), (11, 21), 38, 39),
    "R3": ((8, 11), (10, 27), 58, 60), "R4": ((11, 4), (7, 8), 6, 6),
    "R5": ((12, 6), (5.5, 7), 15, 15), "R6": ((14, 7), (14, 20), 65, 65),
    "R7": ((16.5, 5.5), (23, 8), 11, 10), "R8": ((17, 4), (25, 7), 13, 13),
    "R9": ((22.5, 11), (17, 21), 18, 20), "R10": ((24, 12.3), (18, 22), 29, 31),
    "R11": ((26, 12.3), (19, 29), 70, 74), "R12": ((27.5, 11), (18, 27), 64, 66),
}
PAPER_OFFLINE_S = 0.935330
PAPER_SEEK_S = 1.3082


def default_planner() -> str:
    """``hybrid-apf`` (the paper's offline phase) when it is installed, else ``astar``."""
    return "hybrid-apf" if "hybrid-apf" in PLANNERS else "astar"


@dataclass(frozen=True)
class OnlineRuns:
    """The online phase over several seeds.

    lengths : (n_runs, n_robots) executed length (world units)
    arrival : (n_runs, n_robots) step after which the robot stays on its goal (nan if not)
    seek_steps : (n_runs, n_robots) steps spent in seek mode
    contacts : (n_runs,) contacts found by the checker
    controller_s : (n_runs,) controller time (reset and every act), seconds
    summaries : the run summaries (success, contacts by kind, deadlocked robots)
    """

    seeds: tuple[int, ...]
    status: tuple[str, ...]
    lengths: NDArray[np.float64]
    arrival: NDArray[np.float64]
    seek_steps: NDArray[np.int64]
    contacts: NDArray[np.int64]
    contact_kinds: dict[str, int]
    controller_s: NDArray[np.float64]
    steps: NDArray[np.int64]
    mode_share: dict[str, float]
    summaries: tuple[RunSummary, ...] = ()


@dataclass(frozen=True)
class _Run:
    status: str
    lengths: NDArray[np.float64]
    arrival: list[float]
    seek: NDArray[np.int64]
    modes: dict[str, int]
    kinds: dict[str, int]
    controller_s: float
    steps: int
    summary: RunSummary


def _measure(world: World, plan: Plan) -> Callable[[Trajectory, float], _Run]:
    def measure(traj: Trajectory, _cpu: float) -> _Run:
        counts = np.zeros(world.n_robots, np.int64)
        modes: dict[str, int] = {}
        if traj.modes is not None:
            for idx, name in enumerate(traj.mode_names):
                hit = traj.modes == idx
                modes[name] = int(hit.sum())
                if name == "seek":
                    counts = hit.sum(axis=0).astype(np.int64)
        kinds: dict[str, int] = {}
        for c in traj.contacts:
            kinds[c.kind] = kinds.get(c.kind, 0) + 1
        return _Run(traj.status, executed_lengths(traj.positions),
                    [np.nan if a is None else a for a in arrival_steps(traj.positions, traj.goals)], counts, modes,
                    kinds, float(traj.meta.get("controller_time_s", 0.0)), traj.n_steps,
                    run_summary(world, traj, plan, clearance=False))

    return measure


def run_online(world: World, plan: Plan, seeds, *, controller: Callable[[], object] = CatSwarmController,
               progress: Progress | None = None, keep: int = 1) -> tuple[OnlineRuns, list[Trajectory]]:
    """Simulate ``world`` with ``plan`` once per seed; returns statistics and the first
    ``keep`` trajectories."""
    batch = run_batch(world, controller, seeds, _measure(world, plan), plan=plan, keep=keep, progress=progress)
    runs = batch.records
    kinds: dict[str, int] = {}
    modes: dict[str, int] = {}
    for r in runs:
        for k, v in r.kinds.items():
            kinds[k] = kinds.get(k, 0) + v
        for k, v in r.modes.items():
            modes[k] = modes.get(k, 0) + v
    total = sum(modes.values())
    online = OnlineRuns(batch.seeds, tuple(r.status for r in runs), np.asarray([r.lengths for r in runs], float),
                        np.asarray([r.arrival for r in runs], float), np.asarray([r.seek for r in runs], np.int64),
                        np.asarray([sum(r.kinds.values()) for r in runs], np.int64), kinds,
                        np.asarray([r.controller_s for r in runs]), np.asarray([r.steps for r in runs], np.int64),
                        {k: v / total for k, v in sorted(modes.items())} if total else {},
                        tuple(r.summary for r in runs))
    return online, list(batch.kept)


def ladder_rungs() -> list[Rung]:
    """From ``cat-swarm-paper`` to ``cat-swarm``, one addition a rung. ``cat-swarm`` has no
    switch for the PIBT core (joint decision), its obstacle forecast and its exact check, so
    rung 2 brings them together with every switchable addition at the paper's value (or off);
    the rest are its switches, the core's guarantees first."""
    paper_values = {"lookahead": 1, "leave_early": 0, "hazard_weight": 0.0, "obstacle_alert": "medium"}
    bare = {**paper_values, "lead": False, "patience": None, "swap": False}

    def ours(**kw):
        return lambda: CatSwarmController(**kw)

    return [
        Rung("`cat-swarm-paper`", "-", CatSwarmPaperController),
        Rung("mixture split per conflict group (`split=\"group\"`)",
             "two robots in conflict that both trace (the split over all robots gives seek to the 5 longest "
             "paths of the world)", lambda: CatSwarmPaperController(split="group")),
        Rung("the PIBT core (no switch): the swarm's rules rank each robot's 9 candidates, the core decides for "
             "all robots at once (one robot per cell, no swap or crossing, priority inheritance, backtracking); "
             "every possible obstacle move forecast; exact check of off-centre moves (`lookahead=1, leave_early=0, "
             "hazard_weight=0, obstacle_alert=\"medium\", lead=False, patience=None, swap=False`)",
             "two robots entering one cell, swapping or crossing; a robot in another's way that does not move; an "
             "obstacle that turns into a robot's cell", ours(**bare)),
        Rung("the robot of highest priority ranks by exact distance first (`lead=True`)",
             "nobody sure to progress: PIBT's reachability needs its ranking for the top robot",
             ours(**{**bare, "lead": True})),
        Rung("robots without progress for 6 steps rank by exact distance first (`patience=6`)",
             "robots whose swarm preference keeps them waiting behind others",
             ours(**{**bare, "lead": True, "patience": 6})),
        Rung("swap emulation (`swap=True`)", "two robots that must pass each other in a corridor",
             ours(**paper_values)),
        Rung("alert at the long class (`obstacle_alert=\"long\"`)", "reacting one class later than the "
             "obstacle's reach", ours(**{**paper_values, "obstacle_alert": "long"})),
        Rung("look-ahead escape over 3 steps (`lookahead=3`; 2 for a robot without progress for 20 steps)",
             "a robot cornered in a dead end or on an obstacle's line",
             ours(lookahead=3, leave_early=0, hazard_weight=0.0)),
        Rung("warning term in the fitness (`hazard_weight=2`) = `cat-swarm`", "robots drifting into an "
             "obstacle's path before the hard rules bind", CatSwarmController),
    ]


def ladder(world: World, plan: Plan, seeds, progress: Progress | None = None) -> list[str]:
    """Run the ladder on ``world`` with ``plan`` over ``seeds``; its Markdown table."""
    rungs = ladder_rungs()
    return ladder_table(rungs, run_ladder(world, rungs, seeds, plan=plan, progress=progress))


# ---------------------------------------------------------------------------------- figures
def figure_paths(world: World, traj: Trajectory, plan: Plan, path: Path) -> Path:
    """Two panels: the offline paths (before) and the executed paths of one run (after)."""
    from swarmpath.viz import style
    from swarmpath.viz.world_plot import executed_paths, plot_paths

    fig = style.new_figure(13.5, 6.2)
    left = fig.add_subplot(1, 2, 1)
    right = fig.add_subplot(1, 2, 2)
    plot_paths(world, planned=plan.paths, ax=left, legend=False,
               title=f"before: offline paths ({plan.planner})")
    plot_paths(traj, planned=plan.paths, executed=executed_paths(traj.positions), ax=right,
               obstacle_history=traj.obstacle_positions, legend=True,
               title=f"after: executed with cat-swarm (seed {traj.seed}, {traj.n_steps} steps)")
    fig.tight_layout()
    return style.save_figure(fig, path, dpi=110)


def figure_modes(traj: Trajectory, path: Path) -> Path:
    """Snapshots of one run; each robot's marker coloured by its behaviour at that step."""
    from swarmpath.viz import style
    from swarmpath.viz.world_plot import (
        draw_moving,
        draw_paths,
        draw_static,
        executed_paths,
        setup_world_axes,
        world_view,
    )

    view = world_view(traj)
    names = traj.mode_names
    colors = dict(zip(names, style.mode_colors(names)))
    seek_steps = np.flatnonzero(np.any(traj.modes == names.index("seek"), axis=1)) + 1 if "seek" in names else []
    picks = sorted({1, *(list(seek_steps[:: max(1, len(seek_steps) // 4)][:4]) if len(seek_steps) else []),
                    traj.n_steps})[:6]
    fig = style.new_figure(3.2 * len(picks), 3.6)
    for k, step in enumerate(picks):
        ax = fig.add_subplot(1, len(picks), k + 1)
        draw_static(ax, view)
        draw_moving(ax, view, traj.obstacle_positions[step])
        draw_paths(ax, executed_paths(traj.positions[:step + 1]), style.robot_colors(traj.n_robots), linewidth=1.0)
        pos = traj.positions[step]
        modes = [names[m] for m in traj.modes[step - 1]]
        ax.scatter(pos[:, 0], pos[:, 1], s=36, c=[colors[m] for m in modes], edgecolors="#263238", linewidths=0.6,
                   zorder=6)
        setup_world_axes(ax, view)
        ax.set_title(f"step {step}", fontsize=9)
    handles = [__import__("matplotlib.lines", fromlist=["Line2D"]).Line2D(
        [], [], marker="o", linestyle="", color=colors[m], label=m) for m in names]
    fig.legend(handles=handles, loc="lower center", ncol=len(names), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return style.save_figure(fig, path, dpi=110)


def figure_length_change(ids: list[str], offline_cells: NDArray, online: OnlineRuns, resolution: float,
                         path: Path) -> Path:
    """Executed minus offline length per robot (cells): mean and min-max over the seeds, with
    the paper's change (after - before, grid points)."""
    from swarmpath.viz import style

    change = online.lengths / resolution - offline_cells[None]
    x = np.arange(len(ids))
    fig = style.new_figure(9.0, 3.8)
    ax = fig.add_subplot(1, 1, 1)
    mean = change.mean(axis=0)
    ax.bar(x - 0.2, mean, width=0.4, color="#1e88e5", label="ours: mean over seeds")
    ax.errorbar(x - 0.2, mean, yerr=[mean - change.min(axis=0), change.max(axis=0) - mean], fmt="none",
                ecolor="#0d47a1", capsize=3, linewidth=1)
    paper = [PAPER_TABLE1[i][3] - PAPER_TABLE1[i][2] if i in PAPER_TABLE1 else 0 for i in ids]
    ax.bar(x + 0.2, paper, width=0.4, color="#ffb300", label="paper: after - before")
    ax.axhline(0, color="#90a4ae", linewidth=0.8)
    ax.set_xticks(x, ids)
    ax.set_ylabel("executed - offline length (cells)")
    style.style_axes(ax, equal=False, grid=True)
    ax.legend(fontsize=8, frameon=False)
    fig.tight_layout()
    return style.save_figure(fig, path, dpi=110)


# ---------------------------------------------------------------------------------- report
def _table1(world: World, offline: NDArray, online: OnlineRuns) -> list[str]:
    res = world.resolution
    rows = []
    for i, r in enumerate(world.robots):
        L = online.lengths[:, i]
        paper = PAPER_TABLE1.get(r.id)
        rows.append([r.id, point(r.start), point(r.goal), fmt(offline[i]), fmt(offline[i] / res, 1),
                     f"{fmt(L.mean())} [{fmt(L.min())}-{fmt(L.max())}]", fmt(L.mean() / res, 1),
                     fmt(L.mean() / res - offline[i] / res, 1), fmt(online.seek_steps[:, i].mean(), 1),
                     *((paper[2], paper[3], f"{paper[3] - paper[2]:+d}") if paper else ("-", "-", "-"))])
    paper_before = sum(v[2] for v in PAPER_TABLE1.values())
    paper_after = sum(v[3] for v in PAPER_TABLE1.values())
    total = online.lengths.sum(axis=1).mean()
    rows.append(["all", "", "", fmt(offline.sum()), fmt(offline.sum() / res, 1), fmt(total), fmt(total / res, 1),
                 fmt((total - offline.sum()) / res, 1), fmt(online.seek_steps.sum(axis=1).mean(), 1),
                 paper_before, paper_after, f"{paper_after - paper_before:+d}"])
    return table(["robot", "start", "goal", "offline", "offline (cells)", "executed", "executed (cells)",
                  "change (cells)", "seek steps", "paper before", "paper after", "paper change"], rows)


def _outcome(online: OnlineRuns, follow: OnlineRuns, plan_times: list[float], n_runs: int) -> list[str]:
    seek_total = online.seek_steps.sum(axis=1)
    kinds = ", ".join(f"{k} {v}" for k, v in sorted(follow.contact_kinds.items()))
    return table(["", "paper", "ours"], [
        ["runs where every robot reached its goal", "1/1",
         f"{sum(s == 'all_reached' for s in online.status)}/{n_runs}"],
        ["collision-free runs (robot-robot, robot-static, robot-moving)", "1/1 (claimed)",
         f"{int(np.sum(online.contacts == 0))}/{n_runs}"],
        ["steps until all arrived", "-", f"{int(online.steps.min())}-{int(online.steps.max())} "
                                         f"(median {np.median(online.steps):.0f})"],
        ["offline planning time, 12 robots", f"{PAPER_OFFLINE_S:.3f} s (MATLAB)",
         f"{plan_times[0]:.3f} s first call, {np.median(plan_times[1:]):.3f} s median of 4 more"],
        ["time in seek mode", f"{PAPER_SEEK_S:.2f} s",
         f"{seek_total.mean():.0f} robot-steps per run ({100 * online.mode_share.get('seek', 0.0):.1f}% of "
         f"robot-steps); the whole controller {np.median(online.controller_s):.2f} s per run (median)"],
        ["the same plans without avoidance (`follow`, 3 runs): contacts", "-",
         f"{int(follow.contacts.sum())} ({kinds})"]])


def _pure_table1(world: World, offline: NDArray, pure: OnlineRuns, ours: OnlineRuns) -> list[str]:
    res = world.resolution
    rows = []
    for i, r in enumerate(world.robots):
        cells = []
        for runs in (pure, ours):
            L = runs.lengths[:, i]
            cells += [f"{fmt(L.mean())} [{fmt(L.min())}-{fmt(L.max())}]", fmt(L.mean() / res - offline[i] / res, 1),
                      f"{int(np.sum(np.isfinite(runs.arrival[:, i])))}/{len(L)}"]
        paper = PAPER_TABLE1.get(r.id)
        rows.append([r.id, fmt(offline[i]), *cells, f"{paper[3] - paper[2]:+d}" if paper else "-"])
    return table(["robot", "offline", "`cat-swarm-paper`: executed", "change (cells)", "on its goal at the end",
                  "`cat-swarm`: executed", "change (cells)", "on its goal at the end", "paper change"], rows)


def _pure_reading(pure: Outcome) -> str:
    c = pure.contacts.sum(axis=0)
    return (f"{pure.runs_with_contact} of {pure.n_runs} runs had contacts ({int(c[0])} robot-robot, {int(c[1])} "
            f"robot-moving, {int(c[2])} robot-static in all), {pure.runs_with_deadlock} ended with a robot "
            f"stuck, and {int(pure.success.sum())} were a success (every robot at its goal, no contact).")


def render_report(world: World, planner: str, seed: int, n_runs: int, offline: NDArray, online: OnlineRuns,
                  follow: OnlineRuns, pure: OnlineRuns, plan_times: list[float], ladder_lines: list[str],
                  files: dict[str, Path]) -> str:
    """The report's Markdown from the runs (template ``jaleel2016.md``)."""
    paper_before = sum(v[2] for v in PAPER_TABLE1.values())
    paper_after = sum(v[3] for v in PAPER_TABLE1.values())
    pure_out = outcome_of("`cat-swarm-paper`", pure.summaries)
    ours_out = outcome_of("`cat-swarm`", online.summaries)
    return render("jaleel2016", resolution=f"{world.resolution:g}", planner=planner, first=seed,
                  last=seed + n_runs - 1, n_runs=n_runs, table1=_table1(world, offline, online),
                  ratio=fmt(online.lengths.sum(axis=1).mean() / offline.sum(), 3),
                  paper_ratio=f"{paper_after / paper_before:.3f}", paths=files["paths"].name,
                  change=files["change"].name, outcome=_outcome(online, follow, plan_times, n_runs),
                  shares=", ".join(f"{k} {100 * v:.1f}" for k, v in online.mode_share.items()),
                  modes=files["modes"].name, pure_table1=_pure_table1(world, offline, pure, online),
                  pure_outcome=side_by_side([pure_out, ours_out]), ladder=ladder_lines,
                  pure_reading=_pure_reading(pure_out))


def plan_offline(world: World, planner: str, seed: int) -> tuple[Plan, list[float]]:
    """The offline phase: the planners are deterministic, so plan once; time it five times (the
    first call also builds what later calls reuse, e.g. the repulsive field)."""
    plan_times = []
    plan = None
    for k in range(5):
        t0 = time.perf_counter()
        plan = PLANNERS.get(planner)().plan(world, rng=seed + k)
        plan_times.append(time.perf_counter() - t0)
    assert plan is not None
    return plan, plan_times


@register_reproduction("jaleel2016")
def reproduce(out: Path, *, runs: int | None = None, seed: int = 0,
              progress: Callable[[int, int], None] | None = None) -> Path:
    """Run the experiment and write ``out``/report.md with its figures; returns its path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    n_runs = runs or RUNS
    planner = default_planner()
    world = load_scenario("jaleel2016")
    bar = Progress("jaleel2016", n_runs * (2 + len(ladder_rungs())) + 3, progress)
    bar.stage(f"offline planning ({planner}), timed 5 times")
    plan, plan_times = plan_offline(world, planner, seed)
    offline = np.array([r.length if r.length is not None else np.nan for r in plan.robots])
    seeds = range(seed, seed + n_runs)
    bar.stage("cat-swarm", n_runs)
    online, kept = run_online(world, plan, seeds, progress=bar)
    bar.stage("follow (no avoidance)", 3)
    follow, _ = run_online(world, plan, range(seed, seed + 3), controller=FollowController, progress=bar, keep=0)
    bar.stage("cat-swarm-paper", n_runs)
    pure, _ = run_online(world, plan, seeds, controller=CatSwarmPaperController, progress=bar, keep=0)
    ladder_lines = ladder(world, plan, seeds, bar)
    bar.stage("figures and report")
    ids = [r.id for r in world.robots]
    traj = kept[0]
    files = {
        "paths": figure_paths(world, traj, plan, out / "jaleel2016-paths-before-after.png"),
        "modes": figure_modes(traj, out / "jaleel2016-behaviours.png"),
        "change": figure_length_change(ids, offline / world.resolution, online, world.resolution,
                                       out / "jaleel2016-length-change.png"),
    }
    report = out / "report.md"
    report.write_text(render_report(world, planner, seed, n_runs, offline, online, follow, pure, plan_times,
                                    ladder_lines, files), encoding="utf-8")
    bar.finish()
    return report
