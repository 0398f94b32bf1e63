"""Reproduction of the PSO-prediction paper's experiments (2013, sections 5 and 7).

``swarmpath reproduce prediction2013 --out DIR [--runs N]`` runs, on the ``prediction2013``
world (5 static obstacles, one moving obstacle that turns every 10 steps; robots are the first
n of ``prediction2013-14``), ``runs`` seeds (10 by default, the paper's k) of:

1. UTD vs steps for 2..14 robots with prediction, for both initial obstacle positions
   (Figures 15 and 16: pixel (200, 300) -> (10, 15), pixel (50, 300) -> (2.5, 15));
2. UTD vs steps for several robot speeds (Figures 17 and 18), 6 robots;
3. steps and collisions with vs without prediction on the same seeds (Figure 19), for every
   robot count and both positions, plus two ablations at even robot counts: prediction with
   hard constraints but no turn guard or path buffer, and no prediction with a fixed safety
   margin of one obstacle step;
4. APD: path length among the obstacles minus path length without any obstacle (same seeds);
5. with vs without prediction inside the paper's own objective (``pso-predictive-paper`` vs
   ``pso-reactive-paper``) for every robot count and both positions, next to ours, and the
   ablation ladder from ``pso-predictive-paper`` to ``pso-predictive`` (:func:`ladder`).

It writes DIR/report.md (templates ``prediction2013.md``, ``prediction2013-start.md``) with the
tables and the paper's claims beside ours, and PNG figures. Same seed, same numbers (CPU times
aside).
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from swarmpath.bench.formatting import fmt, render, table
from swarmpath.bench.ladder import Rung, ladder_table, merge_outcomes, run_ladder
from swarmpath.bench.progress import Progress
from swarmpath.bench.runner import run_batch
from swarmpath.bench.stats import mean, paired_counts
from swarmpath.control.pso_predictive import (PaperPredictivePSOController, PaperReactivePSOController,
                                              PredictivePSOController, ReactivePSOController, Weights)
from swarmpath.metrics.paths import executed_lengths
from swarmpath.metrics.utd import average_path_deviation, steps_to_reach_goals, uncovered_target_distance
from swarmpath.registry import register_reproduction
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import ALL_REACHED, Trajectory
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
#: The paper's objective alone, with and without prediction.
PAPER_CONTROLLERS: dict[str, Callable[[], object]] = {
    "paper, with prediction": PaperPredictivePSOController,
    "paper, without prediction": PaperReactivePSOController,
}
ABLATIONS: dict[str, Callable[[], object]] = {
    "prediction with hard constraints, no turn guard or buffer":
        lambda: PredictivePSOController(turn_guard="never", buffer_steps=0),
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


def measure(traj: Trajectory, cpu: float) -> RunRecord:
    """One seeded simulation, summarised."""
    kinds = [c.kind for c in traj.contacts]
    reached = traj.status == ALL_REACHED
    steps = steps_to_reach_goals(traj.positions, traj.goals) if reached else None
    return RunRecord(reached=reached, steps=int(steps if steps is not None else traj.n_steps), n_steps=traj.n_steps,
                     collisions=len(kinds), moving_collisions=kinds.count("robot_moving"),
                     robot_collisions=kinds.count("robot_robot"), static_collisions=kinds.count("robot_static"),
                     utd=uncovered_target_distance(traj.positions, traj.goals),
                     length=float(executed_lengths(traj.positions).sum()), positions=traj.positions, cpu_s=cpu)


def run_once(world: World, make_controller: Callable[[], object], seed: int) -> RunRecord:
    """One seeded simulation, summarised."""
    return _runs(world, make_controller, range(seed, seed + 1), None)[0]


def _runs(world: World, factory, seeds: range, progress: Progress | None) -> list[RunRecord]:
    return list(run_batch(world, factory, seeds, measure, progress=progress).records)


def _summary(records: list[RunRecord]) -> dict:
    ok = [r for r in records if r.reached]
    return {
        "reached": sum(r.reached for r in records), "runs": len(records),
        "steps": mean(r.steps for r in ok), "steps_all": mean(r.steps for r in records),
        "collisions": mean(r.collisions for r in records),
        "moving": mean(r.moving_collisions for r in records),
        "robot": mean(r.robot_collisions for r in records),
        "static": mean(r.static_collisions for r in records),
        "runs_with_collision": sum(r.collisions > 0 for r in records),
        "cpu": mean(r.cpu_s for r in records),
    }


def _paired_steps(a: list[RunRecord], b: list[RunRecord]) -> tuple[int, int, int]:
    """Seeds where a needed fewer / as many / more steps than b (both runs reached)."""
    both = [(x.steps, y.steps) for x, y in zip(a, b) if x.reached and y.reached]
    return paired_counts([x for x, _ in both], [y for _, y in both])


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


# ------------------------------------------------------------------------------ runs
def ladder_rungs() -> list[Rung]:
    """From ``pso-predictive-paper`` to ``pso-predictive``, one addition a rung (rung 1: our
    soft formulation, which has no switch of its own; then ``pso-predictive``'s switches)."""
    off = {"turn_guard": "never", "buffer_steps": 0, "yield_reach": 0.0, "stuck_steps": 0, "guidance": False,
           "safety": False, "side_bias": 0.0, "yield_after": 0}
    on = {"turn_guard": "learned", "buffer_steps": 2, "yield_reach": 2.0, "stuck_steps": 10}

    def ours(weights: Weights | None = None, **kw):
        return lambda: PredictivePSOController(weights=weights, **{**off, **kw})

    soft = Weights(hard=0.0)
    return [
        Rung("`pso-predictive-paper`", "-", PaperPredictivePSOController),
        Rung("our soft terms (`Weights(hard=0)`, every switch off): a clearance ramp for f_st instead of a "
             "constant per touching segment, robots decided one after the other by index, one particle "
             "aimed at the goal, point robots a cell diagonal apart",
             "no slope toward clearance (a constant penalty); robots choosing the same spot at once", ours(soft)),
        Rung("hard safety constraints (H = 1000): swept discs, the obstacle's predicted sweep",
             "contacts that a soft penalty only discourages", ours()),
        Rung("turn guard (`turn_guard=\"learned\"`)", "an obstacle turning into a robot at its turning step",
             ours(turn_guard="learned")),
        Rung("buffer around the predicted path (`buffer_steps=2`)", "robots crowding the obstacle's path and "
             "getting cornered", ours(turn_guard="learned", buffer_steps=2)),
        Rung("yielding (`yield_reach=2`)", "a robot pressed by the obstacle with no room because of its "
             "neighbours", ours(turn_guard="learned", buffer_steps=2, yield_reach=2.0)),
        Rung("detours (`stuck_steps=10`)", "robots stuck in a local minimum of eq. 3 "
             "(a flat face, two robots crossing on an obstacle)", ours(**on)),
        Rung("guidance (`guidance=True`): eq. 3 aims at the steering point along the distance field",
             "walls, doors and corridors between a robot and its goal", ours(**on, guidance=True)),
        Rung("ORCA safety layer and coordination (`safety=True`, side preference, yielding) = "
             "`pso-predictive`", "contacts the swarm's choice still risks; symmetric jams",
             PredictivePSOController),
    ]


def ladder(seeds, counts=ABLATION_COUNTS, figure: str = "fig15", progress: Progress | None = None) -> list[str]:
    """Run the ladder at each robot count in ``counts`` over ``seeds`` (obstacle start
    ``figure``); the Markdown table, outcomes summed over the counts."""
    rungs = ladder_rungs()
    per_count = [run_ladder(paper_world(n, figure), rungs, seeds, progress=progress) for n in counts]
    merged = [merge_outcomes(o.label, [c[k] for c in per_count]) for k, o in enumerate(per_count[0])]
    return ladder_table(rungs, merged)


@dataclass(frozen=True)
class Results:
    """Every batch of the reproduction, keyed as in the report."""

    k: int
    seeds: range
    figures: tuple[str, ...]
    main: dict[tuple[str, str, int], list[RunRecord]]
    free: dict[int, list[RunRecord]]
    speed_runs: dict[tuple[str, float], list[RunRecord]]
    ablation: dict[tuple[str, int], list[RunRecord]]
    pure: dict[tuple[str, str, int], list[RunRecord]]
    ladder: list[str]
    cpu_s: float


def n_runs(k: int) -> int:
    """Runs of the whole reproduction with ``k`` seeds per configuration."""
    figures = len(OBSTACLE_STARTS_PX)
    return k * (figures * len(ROBOT_COUNTS) * 2                       # with / without prediction
                + figures * (len(SPEEDS) - 1)                         # speeds (0.5 is shared)
                + len(ROBOT_COUNTS)                                   # obstacle-free runs (APD)
                + len(ABLATIONS) * len(ABLATION_COUNTS)
                + figures * len(ROBOT_COUNTS) * 2                     # the paper's objective
                + len(ladder_rungs()) * len(ABLATION_COUNTS))


def run_experiments(k: int, seed: int, progress: Progress | None = None) -> Results:
    """All runs of the report."""
    def stage(name: str, runs: int) -> None:
        if progress is not None:
            progress.stage(name, runs)

    seeds = range(seed, seed + k)
    figures = tuple(OBSTACLE_STARTS_PX)
    t_start = time.process_time()
    main: dict[tuple[str, str, int], list[RunRecord]] = {}
    stage("pso-predictive and pso-reactive, 2..14 robots, both starts", k * len(figures) * len(ROBOT_COUNTS) * 2)
    for fig in figures:
        for n in ROBOT_COUNTS:
            world = paper_world(n, fig)
            for label, factory in CONTROLLERS.items():
                main[(label, fig, n)] = _runs(world, factory, seeds, progress)
    stage("obstacle-free runs (APD)", k * len(ROBOT_COUNTS))
    free = {n: _runs(paper_world(n, obstacles=False), PredictivePSOController, seeds, progress) for n in ROBOT_COUNTS}
    speed_runs: dict[tuple[str, float], list[RunRecord]] = {}
    stage("robot speeds", k * len(figures) * (len(SPEEDS) - 1))
    for fig in figures:
        for v in SPEEDS:
            if v == 0.5:
                speed_runs[(fig, v)] = main[("with prediction", fig, SPEED_ROBOTS)]
            else:
                speed_runs[(fig, v)] = _runs(paper_world(SPEED_ROBOTS, fig, speed=v), PredictivePSOController, seeds,
                                             progress)
    stage("ablations", k * len(ABLATIONS) * len(ABLATION_COUNTS))
    ablation = {(label, n): _runs(paper_world(n, "fig15"), factory, seeds, progress)
                for label, factory in ABLATIONS.items() for n in ABLATION_COUNTS}
    cpu_total = time.process_time() - t_start
    stage("the paper's objective with and without prediction", k * len(figures) * len(ROBOT_COUNTS) * 2)
    pure = {(label, fig, n): _runs(paper_world(n, fig), factory, seeds, progress)
            for fig in figures for n in ROBOT_COUNTS for label, factory in PAPER_CONTROLLERS.items()}
    steps = ladder(seeds, progress=progress)
    return Results(k, seeds, figures, main, free, speed_runs, ablation, pure, steps, cpu_total)


def write_figures(r: Results, out: Path, seed: int) -> None:
    """Figures 15-19 in kind and one example run."""
    fig_no = {"fig15": (15, 17), "fig16": (16, 18)}
    for fig in r.figures:
        start = paper_world(2, fig).moving_obstacles[0].start
        curves = {f"{n}": [x.utd for x in r.main[("with prediction", fig, n)]] for n in ROBOT_COUNTS}
        _utd_figure(curves, f"Figure {fig_no[fig][0]}: AUTD vs steps, obstacle starts at {start}", "robots",
                    out / f"utd_robots_{fig}.png")
        curves = {f"{v:g}": [x.utd for x in r.speed_runs[(fig, v)]] for v in SPEEDS}
        _utd_figure(curves, f"Figure {fig_no[fig][1]}: AUTD vs steps, {SPEED_ROBOTS} robots, obstacle at {start}",
                    "robot speed", out / f"utd_speed_{fig}.png")
        _bars_figure(list(ROBOT_COUNTS), {n: _summary(r.main[("with prediction", fig, n)]) for n in ROBOT_COUNTS},
                     {n: _summary(r.main[("without prediction", fig, n)]) for n in ROBOT_COUNTS}, fig,
                     out / f"prediction_bars_{fig}.png")
    _example_figure(paper_world(10, "fig15"), seed, out / "example_run.png")


@register_reproduction("prediction2013")
def reproduce(out: Path, *, runs: int | None = None, seed: int = 0,
              progress: Callable[[int, int], None] | None = None) -> Path:
    """Run the experiments and write ``out``/report.md plus figures; returns the report path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    k = runs or PAPER_RUNS
    bar = Progress("prediction2013", n_runs(k), progress)
    results = run_experiments(k, seed, bar)
    bar.stage("figures and report")
    write_figures(results, out, seed)
    report = out / "report.md"
    report.write_text(render_report(results), encoding="utf-8")
    bar.finish()
    return report


# ------------------------------------------------------------------------------ the report
def _fmt(v: float, digits: int = 1) -> str:
    return fmt(v, digits, missing="n/a")


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


def _start_section(r: Results, fig: str) -> str:
    rows = []
    for n in ROBOT_COUNTS:
        a, b = r.main[("with prediction", fig, n)], r.main[("without prediction", fig, n)]
        sa, sb = _summary(a), _summary(b)
        apd = average_path_deviation([x.positions for x in a], [x.positions for x in r.free[n]])
        f, s_, m = _paired_steps(a, b)
        rows.append([n, f"{sa['reached']}/{sa['runs']}", _fmt(sa["steps"]),
                     f"{_fmt(sb['steps'])} ({sb['reached']}/{sb['runs']} reached)", f"{f}/{s_}/{m}",
                     _fmt(sa["collisions"], 2), _fmt(sb["collisions"], 2),
                     f"{sa['runs_with_collision']} / {sb['runs_with_collision']}", _fmt(apd, 2)])
    tot_a = [x for n in ROBOT_COUNTS for x in r.main[("with prediction", fig, n)]]
    tot_b = [x for n in ROBOT_COUNTS for x in r.main[("without prediction", fig, n)]]
    sa, sb = _summary(tot_a), _summary(tot_b)
    f, s_, m = _paired_steps(tot_a, tot_b)
    rows.append(["all", f"{sa['reached']}/{sa['runs']}", _fmt(sa["steps"]),
                 f"{_fmt(sb['steps'])} ({sb['reached']}/{sb['runs']} reached)", f"{f}/{s_}/{m}",
                 _fmt(sa["collisions"], 2), _fmt(sb["collisions"], 2),
                 f"{sa['runs_with_collision']} / {sb['runs_with_collision']}", ""])
    lines = table(["robots", "reached (pred)", "steps with prediction", "steps without",
                   "fewer/same/more steps with pred (paired seeds)", "collisions/run with", "collisions/run without",
                   "runs with a collision (with / without)", "APD with prediction"], rows,
                  ["---:", "---:", "---:", "---:", ":---:", "---:", "---:", ":---:", "---:"])
    return render("prediction2013-start", px=OBSTACLE_STARTS_PX[fig], pos=paper_world(2, fig).moving_obstacles[0].start,
                  fig=fig, table=lines, moving=f"{sb['moving'] * sb['runs']:.0f}",
                  robot=f"{sb['robot'] * sb['runs']:.0f}", static=f"{sb['static'] * sb['runs']:.0f}",
                  with_total=f"{sa['collisions'] * sa['runs']:.0f}")


def _pure_tables(r: Results) -> tuple[list[str], list[str]]:
    labels = ("paper, with prediction", "paper, without prediction")

    def cell(recs: list[RunRecord]) -> str:
        sm = _summary(recs)
        return f"{_fmt(sm['collisions'], 2)} ({sm['runs_with_collision']})"

    rows = []
    for fig in r.figures:
        for n in ROBOT_COUNTS:
            rows.append([fig, n, *(cell(r.pure[(lab, fig, n)]) for lab in labels),
                         *(cell(r.main[(lab, fig, n)]) for lab in CONTROLLERS)])
    lines = table(["start", "robots", "paper's objective, with prediction", "paper's objective, without",
                   "ours (`pso-predictive`)", "ours without (`pso-reactive`)"], rows,
                  ["---", "---:", "---:", "---:", "---:", "---:"])

    def totals(recs: list[RunRecord]) -> list[str]:
        sm = _summary(recs)
        n = sm["runs"]
        return [f"{sm['reached']}/{n}", f"{sum(x.collisions for x in recs)} in {sm['runs_with_collision']}/{n}",
                f"{sum(x.moving_collisions for x in recs)}", f"{sum(x.robot_collisions for x in recs)}",
                f"{sum(x.static_collisions for x in recs)}", _fmt(sm["steps"])]

    groups = {
        "`pso-predictive-paper`": [x for key, v in r.pure.items() if key[0] == labels[0] for x in v],
        "`pso-reactive-paper`": [x for key, v in r.pure.items() if key[0] == labels[1] for x in v],
        "`pso-predictive`": [x for key, v in r.main.items() if key[0] == "with prediction" for x in v],
        "`pso-reactive`": [x for key, v in r.main.items() if key[0] == "without prediction" for x in v],
    }
    head = ["every robot at its goal", "contacts in runs", "robot-moving", "robot-robot", "robot-static",
            "steps (mean, runs that reached)"]
    tot = table(["all robot counts, both starts", *groups],
                [[h, *(totals(v)[k] for v in groups.values())] for k, h in enumerate(head)])
    return lines, tot


def render_report(r: Results) -> str:
    """The report's Markdown from the runs (templates ``prediction2013*.md``)."""
    speed = table(["obstacle start", *(f"speed {v:g}: steps (reached)" for v in SPEEDS)], [
        [fig, *(f"{_fmt(sm['steps'])} ({sm['reached']}/{sm['runs']}, {_fmt(sm['collisions'], 2)} coll.)"
                for sm in (_summary(r.speed_runs[(fig, v)]) for v in SPEEDS))] for fig in r.figures],
        ["---", *["---:"] * len(SPEEDS)])
    rows = []
    for n in ABLATION_COUNTS:
        cells = []
        for recs in (r.main[("with prediction", "fig15", n)], r.main[("without prediction", "fig15", n)],
                     *[r.ablation[(lab, n)] for lab in ABLATIONS]):
            sm = _summary(recs)
            cells.append(f"{_fmt(sm['steps'])} / {_fmt(sm['collisions'], 2)} / {sm['reached']}/{sm['runs']}")
        rows.append([n, *cells])
    ablations = table(["robots", *(f"{lab}: steps / collisions per run / reached"
                                   for lab in ("with prediction", "without prediction", *ABLATIONS))], rows,
                      ["---:", *["---"] * (2 + len(ABLATIONS))])
    pure_table, pure_totals = _pure_tables(r)
    return render("prediction2013", k=r.k, first=r.seeds.start, last=r.seeds.stop - 1, cpu=f"{r.cpu_s:.0f}",
                  starts="\n".join(_start_section(r, fig) for fig in r.figures), speed_robots=SPEED_ROBOTS,
                  speed_table=speed, ablations=ablations, claims=_claims(r.figures, r.main, r.speed_runs),
                  pure_table=pure_table, pure_totals=pure_totals,
                  ladder_counts=", ".join(str(n) for n in ABLATION_COUNTS), ladder=r.ladder)
