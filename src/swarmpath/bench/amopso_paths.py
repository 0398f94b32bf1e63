"""Reproduction of the path-planning cases of Abbas & Abdulsahab (section 5.3, Tables 5 and 6).

``swarmpath reproduce amopso-paths --out DIR [--runs N]`` writes DIR/report.md and PNGs:

- Table 5 in kind (case 1, ``abbas-case1``): for every velocity rule (SPSO and AMOPSO1-4),
  Pareto mode and weighted sum, with and without the A* initialisation, ``runs`` seeded runs
  (30 by default) of the ``amopso-path`` planner: path length, closest approach to each danger
  zone (d1, d2), the paper's f1 = 1 / (d1 + d2), clearance from the zones, front size and CPU
  time; a paired Wilcoxon test of each AMOPSO variant's length against SPSO on the same seeds;
  the shortest collision-free path (visibility graph) and the shortest one that keeps out of
  both zones as yardsticks; the paper's Table 5 beside ours.
- A weighted-sum sweep (W_danger from 0.5 to 0.99) showing eq. 13 moving along the front.
- Table 6 in kind (case 2, ``abbas-case2``): per robot, the planned length, its ratio to the
  shortest collision-free length (visibility graph), the executed length in the simulator
  with the ``amopso-follow`` controller, CPU planning time, arrivals and collisions (the
  simulator's checker), for Pareto and weighted sum; the paper's Table 6 beside ours.
- Figures: case 1 paths per rule, Pareto fronts (length vs f1) with the choices, case 2 planned
  and executed paths.

Run r of every configuration uses seed ``seed + r`` (so SPSO and AMOPSO runs with the same r
start from the same random swarm). Times are CPU seconds (the machine is shared).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.registry import register_reproduction

UPDATES: tuple[str, ...] = ("spso", "amopso1", "amopso2", "amopso3", "amopso4")
LABELS = {"spso": "SPSO", "pso": "PSO (constriction)", "amopso1": "AMOPSO1", "amopso2": "AMOPSO2", "amopso3": "AMOPSO3", "amopso4": "AMOPSO4"}
MODES: tuple[str, ...] = ("pareto", "weighted-sum")
INITS: tuple[str, ...] = ("astar", "random")
DEFAULT_RUNS = 30
#: The paper's budget (section 5.1): N = 8 particles, Tmax = 120 iterations.
PAPER_BUDGET = (8, 120)
#: W_danger values of the weighted-sum sweep (W_length = 1 - W_danger).
SWEEP = (0.5, 0.8, 0.9, 0.95, 0.97, 0.99)

#: Table 5 of the paper: rule -> (max distance from danger zone Pareto, weighted sum,
#: min distance from start to target Pareto, weighted sum).
PAPER_TABLE5: dict[str, tuple[float, float, float, float]] = {
    "amopso1": (46.251, 39.963, 14.725, 14.437),
    "amopso2": (38.472, 33.893, 14.72, 14.431),
    "amopso3": (37.867, 33.38, 14.729, 14.439),
    "amopso4": (37.576, 33.165, 14.724, 14.436),
}
#: Table 6 of the paper: robot -> length (the same in Pareto and weighted sum); times: Pareto
#: 0.0011602, weighted sum 0.051955 (units not stated).
PAPER_TABLE6: dict[str, float] = {"R1": 14.7, "R2": 10.041, "R3": 10.308, "R4": 10.889, "R5": 12.571}
PAPER_TIME6 = {"pareto": 0.0011602, "weighted-sum": 0.051955}
#: Table 6 configurations: (update, mode, init).
CASE2_CONFIGS: tuple[tuple[str, str, str], ...] = (
    ("amopso4", "pareto", "astar"), ("amopso4", "weighted-sum", "astar"),
    ("amopso1", "pareto", "astar"), ("amopso4", "pareto", "random"),
)


@dataclass(frozen=True)
class Case1Run:
    """One case-1 plan: ``length`` (nan without a path), closest approach ``d`` (2,) to the
    danger zones, ``f1`` = 1 / sum(d), ``clearance`` (min over zones of d - radius),
    ``front`` objective vectors of the collision-free archive (k, 2), the ``path``, CPU s."""

    length: float
    d: np.ndarray
    f1: float
    clearance: float
    front: np.ndarray
    path: np.ndarray | None
    cpu_s: float


@dataclass(frozen=True)
class Case2Run:
    """One case-2 run: planned and executed lengths per robot (nan without a plan), CPU
    planning time per robot, whether all arrived, contacts, makespan, side steps, paths."""

    planned: np.ndarray
    executed: np.ndarray
    cpu_s: np.ndarray
    success: bool
    collisions: int
    makespan: int | None
    sidesteps: int
    plan_paths: list
    executed_paths: np.ndarray


def run_case1(world, update: str, mode: str, init: str, seed: int, weights: Sequence[float] | None = None,
              budget: tuple[int, int] | None = None) -> Case1Run:
    """Plan ``abbas-case1`` once with ``amopso-path`` (see :class:`Case1Run`); ``budget`` =
    (particles, iterations), default the planner's."""
    from swarmpath.planning.amopso_path import AMOPSOPathPlanner

    extra = {} if budget is None else {"particles": budget[0], "iterations": budget[1]}
    planner = AMOPSOPathPlanner(update=update, mode=mode, init=init, weights=weights, **extra)
    t0 = time.process_time()
    plan = planner.plan(world, rng=seed)
    cpu = time.process_time() - t0
    r = plan.robots[0]
    d = r.diagnostics
    front = np.asarray(d.get("front_objectives", np.zeros((0, 2))), float).reshape(-1, 2)
    if not r:
        return Case1Run(float("nan"), np.full(2, np.nan), float("nan"), float("nan"), front, None, cpu)
    return Case1Run(float(d["length"]), np.asarray(d["danger_distances"], float), float(d["f1"]),
                    float(d["danger_clearance"]), front, r.path, cpu)


def run_case2(world, update: str, mode: str, init: str, seed: int, patience: int = 2,
              plan=None) -> tuple[Case2Run, object]:
    """Plan ``abbas-case2`` with ``amopso-path`` (or use ``plan``) and execute it with
    ``amopso-follow``; returns the run and the plan."""
    from swarmpath.control.amopso_follow import AMOPSOFollowController
    from swarmpath.metrics.paths import executed_lengths
    from swarmpath.metrics.summary import run_summary
    from swarmpath.planning.amopso_path import AMOPSOPathPlanner
    from swarmpath.rng import make_rng
    from swarmpath.sim.simulator import Simulator

    n = world.n_robots
    cpu = np.full(n, np.nan)
    if plan is None:
        planner = AMOPSOPathPlanner(update=update, mode=mode, init=init)
        robots = []
        for k, robot in enumerate(world.robots):
            t0 = time.process_time()
            robots.append(planner.plan_robot(world, robot, rng=make_rng(seed, "amopso-path", robot.id)))
            cpu[k] = time.process_time() - t0
        from swarmpath.planning.base import Plan

        plan = Plan("amopso-path", tuple(robots), float(np.nansum(cpu)), {})
    traj = Simulator(world, AMOPSOFollowController(max_waits=patience), plan, seed=seed).run()
    summary = run_summary(world, traj, plan, clearance=False)
    planned = np.array([r.length if r else np.nan for r in plan.robots], float)
    run = Case2Run(planned, executed_lengths(traj.positions), cpu, summary.success,
                   summary.contacts, summary.makespan,
                   sum(1 for e in traj.events if e.get("kind") == "sidestep"), list(plan.paths),
                   np.asarray(traj.positions))
    return run, plan


def wilcoxon_vs(variant: np.ndarray, baseline: np.ndarray) -> tuple[float, str]:
    """Two-sided paired Wilcoxon p-value and verdict ("better" / "worse" / "no difference" at
    5 %, lower is better) of two samples of the same seeds; pairs with a nan are dropped."""
    from scipy.stats import wilcoxon

    ok = np.isfinite(variant) & np.isfinite(baseline)
    diff = variant[ok] - baseline[ok]
    if diff.shape[0] < 2 or np.all(diff == 0):
        return 1.0, "no difference"
    p = float(wilcoxon(variant[ok], baseline[ok]).pvalue)
    if not np.isfinite(p) or p >= 0.05:
        return p, "no difference"
    return p, "better" if np.median(diff) < 0 else "worse"


def _f(v: float, digits: int = 3) -> str:
    return "-" if not np.isfinite(v) else f"{v:.{digits}f}"


def _s(fn: Callable[[np.ndarray], float], values: np.ndarray, digits: int = 3) -> str:
    """``fn`` (a nan-ignoring statistic) of ``values`` formatted, "-" when all are nan."""
    values = np.asarray(values, float)
    return _f(float(fn(values)), digits) if np.isfinite(values).any() else "-"


@register_reproduction("amopso-paths")
def reproduce(out: Path, *, runs: int | None = None, seed: int = 0,
              progress: Callable[[int, int], None] | None = None,
              updates: Sequence[str] = UPDATES, inits: Sequence[str] = INITS,
              case2_configs: Sequence[tuple[str, str, str]] = CASE2_CONFIGS,
              sweep: Sequence[float] = SWEEP) -> Path:
    """Run the case-1 and case-2 experiments and write ``out``/report.md plus PNGs.

    Parameters
    ----------
    out : Path
        Directory for the report (created if missing).
    runs : int, optional
        Seeded runs per configuration (30 by default).
    seed : int
        Run r uses seed ``seed + r``.
    progress : callable, optional
        ``progress(done, total)`` after every run.
    updates, inits, case2_configs, sweep
        Smaller settings for quick checks; the defaults are the full experiment.

    Returns
    -------
    Path of report.md.
    """
    from swarmpath.planning.reference_paths import visibility_shortest_path
    from swarmpath.world import Circle, load_scenario

    runs = DEFAULT_RUNS if runs is None else runs
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise ConfigError(f"amopso-paths: runs must be an integer >= 1, got {runs!r}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    w1, w2 = load_scenario("abbas-case1"), load_scenario("abbas-case2")
    sweep_runs = max(1, min(runs, 10))
    total = (len(updates) * len(MODES) * (len(inits) + 1) * runs + len(sweep) * sweep_runs
             + len(case2_configs) * runs + runs)
    done = 0
    cpu0, wall0 = time.process_time(), time.perf_counter()

    def tick() -> None:
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    if progress is not None:
        progress(0, total)
    case1: dict[tuple[str, str, str], list[Case1Run]] = {}
    for init in inits:
        for mode in MODES:
            for update in updates:
                cell = []
                for r in range(runs):
                    cell.append(run_case1(w1, update, mode, init, seed + r))
                    tick()
                case1[(update, mode, init)] = cell
    for mode in MODES:           # the paper's budget, A* initialisation: init key "astar-8x120"
        for update in updates:
            cell = []
            for r in range(runs):
                cell.append(run_case1(w1, update, mode, "astar", seed + r, budget=PAPER_BUDGET))
                tick()
            case1[(update, mode, "astar-8x120")] = cell
    sweep_res: dict[float, list[Case1Run]] = {}
    for wd in sweep:
        sweep_res[wd] = []
        for r in range(sweep_runs):
            sweep_res[wd].append(run_case1(w1, "amopso4", "weighted-sum", "astar", seed + r, (1 - wd, wd)))
            tick()
    case2: dict[tuple[str, str, str], list[Case2Run]] = {}
    plans0: list = []
    for cfg in case2_configs:
        cell = []
        for r in range(runs):
            run, plan = run_case2(w2, *cfg, seed + r)
            cell.append(run)
            if cfg == case2_configs[0]:
                plans0.append(plan)
            tick()
        case2[cfg] = cell
    literal = []  # the paper's rule taken literally: side step at once (patience 0)
    for r, plan in enumerate(plans0):
        literal.append(run_case2(w2, *case2_configs[0], seed + r, patience=0, plan=plan)[0])
        tick()
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0

    robot = w1.robots[0]
    ref1, ref1_len = visibility_shortest_path(w1, robot)
    zones = tuple(Circle(z.center, z.radius) for z in w1.danger_zones)
    ref1s, ref1s_len = visibility_shortest_path(w1.replace(obstacles=w1.obstacles + zones), robot)
    ref2 = [visibility_shortest_path(w2, r) for r in w2.robots]

    images = _figures(out, w1, w2, case1, sweep_res, case2, updates, inits, case2_configs, ref1, ref1s)
    text = _report(case1, sweep_res, case2, literal, updates, inits, case2_configs, runs, sweep_runs, seed,
                   (wall, cpu), ref1_len, ref1s_len, [x[1] for x in ref2], w1, w2, images)
    report = out / "report.md"
    report.write_text(text, encoding="utf-8")
    return report


# ------------------------------------------------------------------------------------ report
def _case1_rows(case1, updates, mode, init, ref_safe: float) -> list[str]:
    rows = []
    base = np.array([c.length for c in case1.get(("spso", mode, init), [])], float)
    for update in updates:
        cell = case1[(update, mode, init)]
        L = np.array([c.length for c in cell], float)
        d = np.array([c.d for c in cell], float)
        clear = np.array([c.clearance for c in cell], float)
        fronts = np.array([len(c.front) for c in cell], float)
        cpu = np.mean([c.cpu_s for c in cell])
        ok = np.isfinite(L)
        if update != "spso" and len(base):
            p, verdict = wilcoxon_vs(L, base)
            test = f"{verdict} (p = {p:.2g})"
        else:
            test = "baseline"
        med = np.nanmedian
        rows.append(
            f"| {LABELS[update]} | {_s(med, L)} | {_s(np.nanmean, L)} +- {_s(np.nanstd, L)} | "
            f"{_s(np.nanmin, L)} | {_s(med, L / ref_safe)} | {_s(med, d[:, 0])} | {_s(med, d[:, 1])} | "
            f"{_s(med, d.sum(axis=1))} | {_s(np.nanmin, clear)} | {int(np.sum(clear[ok] < 0))} | "
            f"{int(np.sum(~ok))} | {int(np.median(fronts))} | {1000 * cpu:.0f} | {test} |")
    return rows


def _report(case1, sweep_res, case2, literal, updates, inits, case2_configs, runs, sweep_runs, seed, elapsed,
            ref1_len, ref1s_len, ref2_len, w1, w2, images) -> str:
    from swarmpath.planning.amopso_path import AMOPSOPathPlanner

    defaults = AMOPSOPathPlanner().params()
    radii = sorted({z.radius for z in w1.danger_zones})
    lines = [
        "# AMOPSO path planning (Abbas & Abdulsahab, section 5.3, Tables 5 and 6)",
        "",
        f"{runs} runs per configuration (run r uses seed {seed} + r), `amopso-path` with K = "
        f"{defaults['waypoints']} waypoints, {defaults['particles']} particles x {defaults['iterations']} "
        f"iterations per robot, archive {defaults['archive_size']}. Run time {elapsed[0]:.0f} s wall, "
        f"{elapsed[1]:.0f} s CPU. Times below are CPU seconds.",
        "",
        "## Case 1: one robot, two obstacles, two danger zones (Table 5 in kind)",
        "",
        f"`abbas-case1`: 11 x 11, start (0, 0), goal (10, 10), circles (1, 2) r 1 and (5.5, 5.5) r 1.5, "
        f"danger zones at (1, 4) and (2, 5.5) with radius {', '.join(f'{r:g}' for r in radii)}. "
        f"Shortest collision-free path (visibility graph): **{ref1_len:.3f}** (straight line 14.142); "
        f"shortest path that also stays out of both zones: **{ref1s_len:.3f}**. "
        "Pareto mode returns the shortest front member that keeps out of every zone (clearance >= 0); "
        "weighted sum minimises 0.5 length + 0.5 f1 (eq. 13).",
        "",
        "Columns: length median, mean +- std and best over the runs; ratio = median / the shortest path "
        "outside the zones; d1, d2 = closest approach of the path to danger zone 1 and 2 (median); "
        "d1 + d2 = 1 / f1 (the paper's eq. 1 over the polyline); min clear = the smallest clearance "
        "from the zones over the runs (negative: a run entered a zone); in zone = runs whose path "
        "enters a zone; no path = runs without a collision-free path; front = collision-free archive "
        "size (median); CPU per plan; paired Wilcoxon of the length against SPSO on the same seeds.",
        "",
    ]
    head = ("| rule | median | mean +- std | best | ratio | d1 | d2 | d1 + d2 | min clear | in zone | no path "
            "| front | CPU ms | vs SPSO |")
    sep = "|---|" + "---|" * 13
    names = {"astar": "A* initialisation", "random": "random initialisation (eq. 31)",
             "astar-8x120": f"A* initialisation, the paper's budget ({PAPER_BUDGET[0]} particles x "
                            f"{PAPER_BUDGET[1]} iterations)"}
    for init in (*inits, "astar-8x120"):
        for mode in MODES:
            lines += [f"### {mode}, {names[init]}", "", head, sep]
            lines += _case1_rows(case1, updates, mode, init, ref1s_len)
            lines.append("")
    lines += [
        "### The paper's Table 5",
        "",
        "| rule | max distance from danger zone, Pareto | weighted sum | min distance start-target, Pareto "
        "| weighted sum |",
        "|---|---|---|---|---|",
    ]
    for u, (a, b, c, d) in PAPER_TABLE5.items():
        lines.append(f"| {LABELS[u]} | {a:g} | {b:g} | {c:g} | {d:g} |")
    lines += [
        "",
        "The paper does not say how its \"max distance from danger zone\" (33-46) is computed; it cannot "
        "be a single distance in an 11 x 11 m workspace, so we report the closest approaches d1, d2 "
        "and their sum instead. Its lengths 14.43-14.44 (weighted sum) are below the shortest "
        "collision-free length with our reading of the garbled obstacle table; see docs/papers/amopso.md.",
        "",
        f"### Weighted sum moving along the front (AMOPSO4, A* initialisation, {sweep_runs} runs each)",
        "",
        "| W_length, W_danger | length (median) | d1 (median) | d2 (median) | f1 (median) | min clear |",
        "|---|---|---|---|---|---|",
    ]
    for wd, cell in sweep_res.items():
        L = np.array([c.length for c in cell])
        d = np.array([c.d for c in cell])
        f1 = np.array([c.f1 for c in cell])
        cl = np.array([c.clearance for c in cell])
        lines.append(f"| {1 - wd:.2f}, {wd:.2f} | {_f(np.nanmedian(L))} | {_f(np.nanmedian(d[:, 0]))} | "
                     f"{_f(np.nanmedian(d[:, 1]))} | {np.nanmedian(f1):.4f} | {_f(np.nanmin(cl))} |")
    lines += [
        "",
        "## Case 2: five robots, five obstacles (Table 6 in kind)",
        "",
        "`abbas-case2`: 10 x 10, the paper's starts and goals (R3's goal read as (5, 10)), our five "
        "obstacles (see the scenario file). Each robot is planned alone by `amopso-path`; the plans "
        "are executed in the simulator by `amopso-follow` (follow the path; on a conflict slow "
        "down, wait up to 2 steps, then side step by the threshold; see docs/papers/amopso.md). "
        "Shortest = visibility-graph shortest collision-free length; ratio = planned / shortest "
        "(median and max over runs); executed = length driven in the simulator (median).",
        "",
    ]
    ids = [r.id for r in w2.robots]
    for cfg in case2_configs:
        cell = case2[cfg]
        P = np.array([c.planned for c in cell])
        E = np.array([c.executed for c in cell])
        C = np.array([c.cpu_s for c in cell])
        lines += [f"### {LABELS[cfg[0]]}, {cfg[1]}, {'A*' if cfg[2] == 'astar' else 'random'} initialisation", "",
                  "| robot | paper | shortest | planned (median) | ratio median | ratio max | executed (median) "
                  "| CPU s per plan (mean) | no path |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for k, rid in enumerate(ids):
            ratio = P[:, k] / ref2_len[k]
            lines.append(f"| {rid} | {PAPER_TABLE6.get(rid, float('nan')):g} | {ref2_len[k]:.3f} | "
                         f"{_s(np.nanmedian, P[:, k])} | {_s(np.nanmedian, ratio)} | {_s(np.nanmax, ratio)} | "
                         f"{_s(np.nanmedian, E[:, k])} | {np.nanmean(C[:, k]):.3f} | "
                         f"{int(np.sum(~np.isfinite(ratio)))} |")
        succ = sum(c.success for c in cell)
        coll = sum(c.collisions for c in cell)
        mk = [c.makespan for c in cell if c.makespan is not None]
        lines += ["", f"All five at their goals in {succ} of {len(cell)} runs; contacts (simulator's checker) "
                      f"{coll}; makespan median {np.median(mk) if mk else float('nan'):.0f} steps; side steps "
                      f"{sum(c.sidesteps for c in cell)} in all runs; planning CPU time for the five robots "
                      f"{np.nanmean(np.nansum(C, axis=1)):.2f} s (mean).", ""]
    if literal:
        E = np.array([c.executed for c in literal])
        P = np.array([c.planned for c in literal])
        lines += [
            f"### The paper's rule taken literally: side step at once (patience 0), plans of "
            f"{LABELS[case2_configs[0][0]]}, {case2_configs[0][1]}",
            "",
            f"All five at their goals in {sum(c.success for c in literal)} of {len(literal)} runs; contacts "
            f"{sum(c.collisions for c in literal)}; side steps {sum(c.sidesteps for c in literal)}; "
            f"makespan median {np.median([c.makespan for c in literal if c.makespan is not None] or [np.nan]):.0f}; "
            f"executed / planned length, max over robots and runs: {np.nanmax(E / P):.3f} "
            "(waiting two steps first: see the tables above).",
            "",
        ]
    lines += [
        "### The paper's Table 6",
        "",
        "| robot | length (Pareto = weighted sum) |",
        "|---|---|",
    ]
    lines += [f"| {rid} | {v:g} |" for rid, v in PAPER_TABLE6.items()]
    lines += [
        "",
        f"Time: Pareto {PAPER_TIME6['pareto']:g}, weighted sum {PAPER_TIME6['weighted-sum']:g} (units and "
        "what was timed are not stated). The paper's obstacles are not given, so lengths compare in "
        "kind only: ours are measured against the shortest path among our obstacles.",
        "",
        "## Figures",
        "",
    ]
    lines += [f"![{img}]({img})" for img in images]
    lines.append("")
    return "\n".join(lines)


# ----------------------------------------------------------------------------------- figures
def _median_run(cell: list[Case1Run]) -> Case1Run | None:
    L = np.array([c.length for c in cell], float)
    if not np.isfinite(L).any():
        return None
    k = int(np.nanargmin(np.abs(L - np.nanmedian(L))))
    return cell[k]


def _figures(out: Path, w1, w2, case1, sweep_res, case2, updates, inits, case2_configs, ref1, ref1s) -> list[str]:
    from swarmpath.viz import style
    from swarmpath.viz.curves import plot_pareto_fronts
    from swarmpath.viz.world_plot import draw_paths, plot_paths, plot_world

    images = []
    init = inits[0]
    # case 1 paths: the median run of each rule, Pareto (solid) and weighted sum (dashed)
    fig = style.new_figure(7.2, 6.6)
    ax = fig.add_subplot(1, 1, 1)
    plot_world(w1, ax=ax, legend=False, title=f"abbas-case1: median-length paths ({init} initialisation)")
    colors = style.robot_colors(len(updates) + 2)
    for k, update in enumerate(updates):
        for mode, ls in (("pareto", "-"), ("weighted-sum", (0, (3, 2)))):
            run = _median_run(case1[(update, mode, init)])
            if run is not None and run.path is not None:
                draw_paths(ax, [run.path], [colors[k]], linestyle=ls, linewidth=1.3)
                if mode == "pareto":
                    ax.plot([], [], color=colors[k], label=f"{LABELS[update]} ({run.length:.2f})")
    for path, c, label in ((ref1, "black", "shortest"), (ref1s, "#616161", "shortest outside the zones")):
        if path is not None:
            ax.plot(path[:, 0], path[:, 1], color=c, linewidth=0.8, linestyle=":", label=label, zorder=3)
    ax.plot([], [], color="#9e9e9e", linestyle="--", label="weighted sum (dashed)")
    ax.legend(fontsize=7, loc="lower right", frameon=False)
    style.save_figure(fig, out / "case1-paths.png")
    images.append("case1-paths.png")

    # Pareto fronts of run 0 per rule, with the chosen paths and the weighted-sum sweep
    fronts = {LABELS[u]: case1[(u, "pareto", init)][0].front for u in updates
              if len(case1[(u, "pareto", init)][0].front)}
    chosen = case1[(updates[-1], "pareto", init)][0]
    highlight = {}
    if np.isfinite(chosen.length):
        highlight[f"chosen by the rule ({LABELS[updates[-1]]})"] = (chosen.length, chosen.f1)
    fig = style.new_figure(7.2, 5.0)
    ax = fig.add_subplot(1, 1, 1)
    plot_pareto_fronts(fronts, objectives=("path length", "f1 = 1 / (d1 + d2)"),
                       title="abbas-case1: Pareto archives of run 0 (collision-free members)",
                       highlight=highlight, ax=ax)
    pts = np.array([(c.length, c.f1) for cell in sweep_res.values() for c in cell], float).reshape(-1, 2)
    if len(pts):
        ax.scatter(pts[:, 0], pts[:, 1], marker="x", s=22, color="black", label="weighted sum, W_danger 0.5-0.99",
                   zorder=5)
        ax.legend(fontsize=7, frameon=False)
    if len(fronts):
        allf = np.vstack(list(fronts.values()))
        ax.set_xlim(allf[:, 0].min() - 0.1, min(allf[:, 0].max(), allf[:, 0].min() + 6) + 0.1)
    style.save_figure(fig, out / "case1-front.png")
    images.append("case1-front.png")

    # case 2: planned (dashed) and executed (solid) paths of run 0 of the first configuration
    run = case2[case2_configs[0]][0]
    executed = [run.executed_paths[:, k] for k in range(run.executed_paths.shape[1])]
    fig = plot_paths(w2, planned=run.plan_paths, executed=executed,
                     title=f"abbas-case2: {LABELS[case2_configs[0][0]]}, {case2_configs[0][1]}, run 0")
    style.save_figure(fig, out / "case2-paths.png")
    images.append("case2-paths.png")
    return images
