"""Reproduction of the PSO-prediction paper's experiments (2013, sections 5 and 7).

``swarmpath reproduce prediction2013 --out DIR [--runs N]`` runs, on the ``prediction2013``
world (5 static obstacles, one moving obstacle that turns every 10 steps; robots are the first
n of ``prediction2013-14``), ``runs`` seeds (10 by default, the paper's k) of:

1. UTD vs steps for 2..14 robots with prediction, for both initial obstacle positions
   (Figures 15 and 16: pixel (200, 300) -> (10, 15), pixel (50, 300) -> (2.5, 15));
2. UTD vs steps for several robot speeds (Figures 17 and 18), 6 robots;
3. steps and collisions with vs without prediction on the same seeds (Figure 19), for every
   robot count and both positions, plus two ablations at even robot counts: prediction with
   the paper's terms only (no turn guard, no path buffer) and no prediction with a fixed
   safety margin of one obstacle step;
4. APD: path length among the obstacles minus path length without any obstacle (same seeds).

It writes DIR/report.md with the tables and the paper's claims beside ours, and PNG figures.
Same seed, same numbers (CPU times aside).
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from swarmpath.control.pso_predictive import PredictivePSOController, ReactivePSOController
from swarmpath.metrics.paths import executed_lengths
from swarmpath.metrics.utd import average_path_deviation, steps_to_reach_goals, uncovered_target_distance
from swarmpath.registry import register_reproduction
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import ALL_REACHED
from swarmpath.world import World, load_scenario

PAPER_RUNS = 10
#: The paper's pixel world is 640 x 480; we use 20 pixels per world unit.
PIXELS_PER_UNIT = 20.0
#: Initial obstacle positions of Figures 15/17 and 16/18, in the paper's pixels.
OBSTACLE_STARTS_PX: dict[str, tuple[float, float]] = {"fig15": (200.0, 300.0), "fig16": (50.0, 300.0)}
ROBOT_COUNTS = tuple(range(2, 15))
ABLATION_COUNTS = (2, 4, 6, 8, 10, 12, 14)
SPEEDS = (0.3, 0.4, 0.5, 0.6, 0.8)
SPEED_ROBOTS = 6

#: Controllers compared: label -> factory.
CONTROLLERS: dict[str, Callable[[], object]] = {
    "with prediction": PredictivePSOController,
    "without prediction": ReactivePSOController,
}
ABLATIONS: dict[str, Callable[[], object]] = {
    "prediction, paper terms only": lambda: PredictivePSOController(turn_guard="never", buffer_steps=0),
    "no prediction, margin of one obstacle step": lambda: ReactivePSOController(obstacle_margin=0.05 + 0.25),
}


@dataclass(frozen=True)
class RunRecord:
    """What one simulation gives the report."""

    reached: bool           # every robot at its goal at the end
    steps: int              # steps to reach all goals (n_steps when not reached)
    n_steps: int
    collisions: int         # contacts found by the simulator's checker
    moving_collisions: int
    robot_collisions: int
    static_collisions: int
    utd: np.ndarray         # (n_steps + 1,)
    length: float           # sum of executed path lengths
    positions: np.ndarray   # (n_steps + 1, n, 2)
    cpu_s: float


def paper_world(n_robots: int, figure: str = "fig15", speed: float | None = None,
                obstacles: bool = True) -> World:
    """The prediction2013 world with the first ``n_robots`` robots, the moving obstacle at the
    start of ``figure`` ("fig15" or "fig16"), robots' speed ``speed`` (default: the
    scenario's), and optionally no obstacles at all (for the APD)."""
    full = load_scenario("prediction2013-14")
    robots = full.robots[:n_robots]
    if speed is not None:
        robots = tuple(dataclasses.replace(r, max_speed=speed) for r in robots)
    px = OBSTACLE_STARTS_PX[figure]
    mover = dataclasses.replace(full.moving_obstacles[0], start=(px[0] / PIXELS_PER_UNIT, px[1] / PIXELS_PER_UNIT))
    world = full.replace(robots=robots, moving_obstacles=(mover,), name=f"prediction2013-{figure}-{n_robots}")
    if not obstacles:
        world = world.replace(obstacles=(), moving_obstacles=(), name=world.name + "-free")
    return world


def run_once(world: World, make_controller: Callable[[], object], seed: int) -> RunRecord:
    """One seeded simulation, summarised."""
    t0 = time.process_time()
    traj = Simulator(world, make_controller(), seed=seed).run()
    cpu = time.process_time() - t0
    kinds = [c.kind for c in traj.contacts]
    reached = traj.status == ALL_REACHED
    steps = steps_to_reach_goals(traj.positions, traj.goals) if reached else None
    return RunRecord(reached=reached, steps=int(steps if steps is not None else traj.n_steps), n_steps=traj.n_steps,
                     collisions=len(kinds), moving_collisions=kinds.count("robot_moving"),
                     robot_collisions=kinds.count("robot_robot"), static_collisions=kinds.count("robot_static"),
                     utd=uncovered_target_distance(traj.positions, traj.goals),
                     length=float(executed_lengths(traj.positions).sum()), positions=traj.positions, cpu_s=cpu)


class _Counter:
    def __init__(self, total: int, progress: Callable[[int, int], None] | None):
        self.done, self.total, self.progress = 0, total, progress

    def tick(self) -> None:
        self.done += 1
        if self.progress is not None:
            self.progress(self.done, self.total)


def _runs(world: World, factory, seeds: range, counter: _Counter) -> list[RunRecord]:
    out = []
    for s in seeds:
        out.append(run_once(world, factory, s))
        counter.tick()
    return out


def _mean(values) -> float:
    v = np.asarray(list(values), float)
    return float(v.mean()) if v.size else float("nan")


def _summary(records: list[RunRecord]) -> dict:
    ok = [r for r in records if r.reached]
    return {
        "reached": sum(r.reached for r in records), "runs": len(records),
        "steps": _mean(r.steps for r in ok), "steps_all": _mean(r.steps for r in records),
        "collisions": _mean(r.collisions for r in records),
        "moving": _mean(r.moving_collisions for r in records),
        "robot": _mean(r.robot_collisions for r in records),
        "static": _mean(r.static_collisions for r in records),
        "runs_with_collision": sum(r.collisions > 0 for r in records),
        "cpu": _mean(r.cpu_s for r in records),
    }


def _paired_steps(a: list[RunRecord], b: list[RunRecord]) -> tuple[int, int, int]:
    """Seeds where a needed fewer / as many / more steps than b (both runs reached)."""
    fewer = same = more = 0
    for x, y in zip(a, b):
        if not (x.reached and y.reached):
            continue
        fewer += x.steps < y.steps
        same += x.steps == y.steps
        more += x.steps > y.steps
    return fewer, same, more


# ------------------------------------------------------------------------------ figures
def _utd_figure(curves: dict[str, list[np.ndarray]], title: str, legend_title: str, path: Path) -> None:
    from swarmpath.viz.curves import plot_utd_curves
    from swarmpath.viz.style import save_figure

    save_figure(plot_utd_curves(curves, title=title, spread=None, legend_title=legend_title), path, dpi=110)


def _bars_figure(counts, with_pred: dict, without_pred: dict, figure: str, path: Path) -> None:
    from swarmpath.viz.curves import plot_grouped_bars
    from swarmpath.viz.style import new_figure, save_figure

    fig = new_figure(12.0, 4.4)
    left, right = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    plot_grouped_bars(counts, {"with prediction": [with_pred[n]["steps_all"] for n in counts],
                               "without prediction": [without_pred[n]["steps_all"] for n in counts]},
                      xlabel="robots", ylabel="mean steps to reach all goals",
                      title=f"steps, obstacle start {figure}", ax=left)
    plot_grouped_bars(counts, {"with prediction": [with_pred[n]["collisions"] for n in counts],
                               "without prediction": [without_pred[n]["collisions"] for n in counts]},
                      xlabel="robots", ylabel="mean collisions per run",
                      title=f"collisions (simulator's checker), obstacle start {figure}", ax=right)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)


def _example_figure(world: World, seed: int, path: Path) -> None:
    from swarmpath.viz.style import save_figure
    from swarmpath.viz.world_plot import plot_trajectory

    traj = Simulator(world, PredictivePSOController(), seed=seed).run()
    fig = plot_trajectory(traj, y_down=True, legend=False)
    save_figure(fig, path, dpi=100)


# ------------------------------------------------------------------------------ the report
def _fmt(v: float, digits: int = 1) -> str:
    return "n/a" if not np.isfinite(v) else f"{v:.{digits}f}"


@register_reproduction("prediction2013")
def reproduce(out: Path, *, runs: int | None = None, seed: int = 0,
              progress: Callable[[int, int], None] | None = None) -> Path:
    """Run the experiments and write ``out``/report.md plus figures; returns the report path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    k = runs or PAPER_RUNS
    seeds = range(seed, seed + k)
    figures = tuple(OBSTACLE_STARTS_PX)
    total = k * (len(figures) * len(ROBOT_COUNTS) * 2                       # with / without prediction
                 + len(figures) * (len(SPEEDS) - 1)                         # speeds (0.5 is shared)
                 + len(ROBOT_COUNTS)                                        # obstacle-free runs (APD)
                 + len(ABLATIONS) * len(ABLATION_COUNTS))
    counter = _Counter(total, progress)
    t_start = time.process_time()

    main: dict[tuple[str, str, int], list[RunRecord]] = {}
    for fig in figures:
        for n in ROBOT_COUNTS:
            world = paper_world(n, fig)
            for label, factory in CONTROLLERS.items():
                main[(label, fig, n)] = _runs(world, factory, seeds, counter)
    free = {n: _runs(paper_world(n, obstacles=False), PredictivePSOController, seeds, counter) for n in ROBOT_COUNTS}
    speed_runs: dict[tuple[str, float], list[RunRecord]] = {}
    for fig in figures:
        for v in SPEEDS:
            if v == 0.5:
                speed_runs[(fig, v)] = main[("with prediction", fig, SPEED_ROBOTS)]
            else:
                speed_runs[(fig, v)] = _runs(paper_world(SPEED_ROBOTS, fig, speed=v), PredictivePSOController, seeds,
                                             counter)
    ablation = {(label, n): _runs(paper_world(n, "fig15"), factory, seeds, counter)
                for label, factory in ABLATIONS.items() for n in ABLATION_COUNTS}
    cpu_total = time.process_time() - t_start

    # figures
    fig_no = {"fig15": (15, 17), "fig16": (16, 18)}
    for fig in figures:
        start = paper_world(2, fig).moving_obstacles[0].start
        curves = {f"{n}": [r.utd for r in main[("with prediction", fig, n)]] for n in ROBOT_COUNTS}
        _utd_figure(curves, f"Figure {fig_no[fig][0]}: AUTD vs steps, obstacle starts at {start}", "robots",
                    out / f"utd_robots_{fig}.png")
        curves = {f"{v:g}": [r.utd for r in speed_runs[(fig, v)]] for v in SPEEDS}
        _utd_figure(curves, f"Figure {fig_no[fig][1]}: AUTD vs steps, {SPEED_ROBOTS} robots, obstacle at {start}",
                    "robot speed", out / f"utd_speed_{fig}.png")
        _bars_figure(list(ROBOT_COUNTS), {n: _summary(main[("with prediction", fig, n)]) for n in ROBOT_COUNTS},
                     {n: _summary(main[("without prediction", fig, n)]) for n in ROBOT_COUNTS}, fig,
                     out / f"prediction_bars_{fig}.png")
    _example_figure(paper_world(10, "fig15"), seed, out / "example_run.png")

    lines = _report_lines(k, seeds, figures, main, free, speed_runs, ablation, cpu_total)
    report = out / "report.md"
    report.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return report


def _claims(figures, main, speed_runs) -> list[str]:
    """The paper's claims, each with our measurement and a verdict computed from the runs."""
    with_all = [r for f in figures for n in ROBOT_COUNTS for r in main[("with prediction", f, n)]]
    without_all = [r for f in figures for n in ROBOT_COUNTS for r in main[("without prediction", f, n)]]
    sw, so = _summary(with_all), _summary(without_all)
    fewer, same, more = _paired_steps(with_all, without_all)
    coll_w = sum(r.collisions for r in with_all)
    coll_o = sum(r.collisions for r in without_all)
    out = [f"1. *With prediction every robot reaches its goal without hitting any obstacle* (sections 5, 8): "
           f"{sw['reached']}/{sw['runs']} runs reached all goals, {coll_w} collisions in total -> "
           f"{'reproduced' if sw['reached'] == sw['runs'] and coll_w == 0 else 'not reproduced'}."]
    areas = []
    for f in figures:
        area = [float(np.mean([r.utd.sum() for r in main[("with prediction", f, n)]])) for n in ROBOT_COUNTS]
        areas.append(bool(np.all(np.diff(area) > 0)))
    out.append("2. *UTD increases with the number of robots* (Figures 15-16): the area under the AUTD curve grows "
               f"from each robot count to the next at both starts: {'yes' if all(areas) else 'not strictly'} "
               "(UTD is a sum over robots, so this is expected by construction).")
    mono = []
    for f in figures:
        steps = [_summary(speed_runs[(f, v)])["steps"] for v in SPEEDS]
        mono.append(bool(np.all(np.diff(steps) < 0)))
    out.append(f"3. *Faster robots need fewer steps* (Figures 17-18): mean steps fall with every speed increase "
               f"{'at both obstacle starts' if all(mono) else 'not at every speed'} -> "
               f"{'reproduced' if all(mono) else 'partly reproduced'}.")
    verdict = "reproduced" if sw["steps"] < so["steps"] and fewer > more else "not reproduced"
    out.append(f"4. *Fewer steps with prediction than without* (Figure 19): mean {_fmt(sw['steps'])} with vs "
               f"{_fmt(so['steps'])} without over all counts and both starts; paired seeds: fewer {fewer}, "
               f"same {same}, more {more} -> {verdict}.")
    verdict = "reproduced" if coll_w < coll_o else "not reproduced"
    out.append(f"5. *Prediction reduces the risk of collision* (section 7): {coll_w} collisions in "
               f"{sw['runs_with_collision']} of {sw['runs']} runs with prediction vs {coll_o} in "
               f"{so['runs_with_collision']} of {so['runs']} runs without -> {verdict}.")
    return out


def _report_lines(k, seeds, figures, main, free, speed_runs, ablation, cpu_total) -> list[str]:
    L: list[str] = []
    L += ["# Reproduction: multi-robot PSO with linear prediction of a moving obstacle (2013)", "",
          f"{k} runs (seeds {seeds.start}..{seeds.stop - 1}) per configuration; world `prediction2013` "
          "(32 x 24 units = the paper's 640 x 480 pixels at 20 px/unit; 5 static discs; one disc obstacle of "
          "radius 1 moving at 0.25/step that turns to a random heading every 10 steps); robots of radius 0.5, "
          "speed 0.5/step, the first n of `prediction2013-14`. Collisions are counted by the simulator's own "
          "checker (one per robot, other object and step). Steps = steps until every robot is at its goal "
          "(mean over runs that reached; runs that did not are counted in 'reached').",
          f"CPU time of all runs: {cpu_total:.0f} s.", ""]
    for fig in figures:
        start = main[("with prediction", fig, 2)][0]
        pos = paper_world(2, fig).moving_obstacles[0].start
        px = OBSTACLE_STARTS_PX[fig]
        L += [f"## Robots 2..14, obstacle starting at pixel {px} = world {pos} ({fig})", "",
              "| robots | reached (pred) | steps with prediction | steps without | fewer/same/more steps with pred "
              "(paired seeds) | collisions/run with | collisions/run without | runs with a collision (with / "
              "without) | APD with prediction |",
              "|---:|---:|---:|---:|:---:|---:|---:|:---:|---:|"]
        for n in ROBOT_COUNTS:
            a, b = main[("with prediction", fig, n)], main[("without prediction", fig, n)]
            sa, sb = _summary(a), _summary(b)
            apd = average_path_deviation([r.positions for r in a], [r.positions for r in free[n]])
            f, s, m = _paired_steps(a, b)
            L.append(f"| {n} | {sa['reached']}/{sa['runs']} | {_fmt(sa['steps'])} | {_fmt(sb['steps'])} "
                     f"({sb['reached']}/{sb['runs']} reached) | {f}/{s}/{m} | {_fmt(sa['collisions'], 2)} | "
                     f"{_fmt(sb['collisions'], 2)} | {sa['runs_with_collision']} / {sb['runs_with_collision']} | "
                     f"{_fmt(apd, 2)} |")
        del start
        tot_a = [r for n in ROBOT_COUNTS for r in main[("with prediction", fig, n)]]
        tot_b = [r for n in ROBOT_COUNTS for r in main[("without prediction", fig, n)]]
        sa, sb = _summary(tot_a), _summary(tot_b)
        f, s, m = _paired_steps(tot_a, tot_b)
        L += [f"| all | {sa['reached']}/{sa['runs']} | {_fmt(sa['steps'])} | {_fmt(sb['steps'])} "
              f"({sb['reached']}/{sb['runs']} reached) | {f}/{s}/{m} | {_fmt(sa['collisions'], 2)} | "
              f"{_fmt(sb['collisions'], 2)} | {sa['runs_with_collision']} / {sb['runs_with_collision']} | |", "",
              f"Collisions without prediction by kind (all counts): robot-moving {sb['moving'] * sb['runs']:.0f}, "
              f"robot-robot {sb['robot'] * sb['runs']:.0f}, robot-static {sb['static'] * sb['runs']:.0f}; "
              f"with prediction: {sa['collisions'] * sa['runs']:.0f} in total.", "",
              f"![UTD vs steps, robots]({'utd_robots_' + fig}.png)", "",
              f"![with vs without prediction]({'prediction_bars_' + fig}.png)", ""]
    L += [f"## Robot speed ({SPEED_ROBOTS} robots, with prediction)", "",
          "| obstacle start | " + " | ".join(f"speed {v:g}: steps (reached)" for v in SPEEDS) + " |",
          "|---|" + "---:|" * len(SPEEDS)]
    for fig in figures:
        cells = []
        for v in SPEEDS:
            sm = _summary(speed_runs[(fig, v)])
            cells.append(f"{_fmt(sm['steps'])} ({sm['reached']}/{sm['runs']}, {_fmt(sm['collisions'], 2)} coll.)")
        L.append(f"| {fig} | " + " | ".join(cells) + " |")
    L += ["", "![UTD vs steps, speeds, fig15](utd_speed_fig15.png)", "",
          "![UTD vs steps, speeds, fig16](utd_speed_fig16.png)", ""]
    L += ["## Ablations (obstacle start fig15)", "",
          "| robots | " + " | ".join(f"{lab}: steps / collisions per run / reached"
                                     for lab in ("with prediction", "without prediction", *ABLATIONS)) + " |",
          "|---:|" + "---|" * (2 + len(ABLATIONS))]
    for n in ABLATION_COUNTS:
        cells = []
        for recs in (main[("with prediction", "fig15", n)], main[("without prediction", "fig15", n)],
                     *[ablation[(lab, n)] for lab in ABLATIONS]):
            sm = _summary(recs)
            cells.append(f"{_fmt(sm['steps'])} / {_fmt(sm['collisions'], 2)} / {sm['reached']}/{sm['runs']}")
        L.append(f"| {n} | " + " | ".join(cells) + " |")
    L += ["", "## The paper's claims next to ours", ""]
    L += _claims(figures, main, speed_runs)
    L += ["", "![one run with prediction, 10 robots](example_run.png)", ""]
    return L
