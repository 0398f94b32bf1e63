"""Reproduction of the path-planning cases of Abbas & Abdulsahab (section 5.3, Tables 5 and 6).

``swarmpath reproduce amopso-paths --out DIR [--runs N]`` writes DIR/report.md (template
``templates/amopso-paths.md``) and PNGs:

- Table 5 in kind (case 1, ``abbas-case1``): for every velocity rule (SPSO and AMOPSO1-4),
  Pareto mode and weighted sum, with and without the A* initialisation, at our budget, at the
  paper's budget and at the paper's whole set-up (``amopso-path-paper``: random swarm, 8 x 120,
  no mutation), ``runs`` seeded runs (30 by default): path length, closest approach to each
  danger zone (d1, d2), the paper's f1 = 1 / (d1 + d2), clearance from the zones, front size
  and CPU time; a paired Wilcoxon test of each AMOPSO variant's length against SPSO on the
  same seeds; the shortest collision-free path (visibility graph) and the shortest one that
  keeps out of both zones as yardsticks; the paper's Table 5 beside ours.
- A weighted-sum sweep (W_danger from 0.5 to 0.99) showing eq. 13 moving along the front.
- The ladder of case 1 from ``amopso-path-paper`` to ``amopso-path`` (:func:`ladder_case1`).
- Table 6 in kind (case 2, ``abbas-case2``): per robot, the planned length, its ratio to the
  shortest collision-free length (visibility graph), the executed length in the simulator
  with the ``amopso-follow`` controller, CPU planning time, arrivals and collisions (the
  simulator's checker), for Pareto and weighted sum; the paper's Table 6 beside ours; the
  paper's method (``amopso-path-paper`` + ``amopso-follow-paper``) next to ours and the ladder
  between them (:func:`ladder_case2`).
- Figures: case 1 paths per rule, Pareto fronts (length vs f1) with the choices, case 2 planned
  and executed paths.

Run r of every configuration uses seed ``seed + r`` (so SPSO and AMOPSO runs with the same r
start from the same random swarm). Times are CPU seconds (the machine is shared).
"""
from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from swarmpath.bench.formatting import fmt, render, table
from swarmpath.bench.progress import Progress
from swarmpath.bench.stats import wilcoxon_vs
from swarmpath.control.amopso_follow import AMOPSOFollowController
from swarmpath.control.amopso_follow_paper import AMOPSOFollowPaperController
from swarmpath.errors import ConfigError
from swarmpath.planning.amopso_path import AMOPSOPathPlanner
from swarmpath.planning.amopso_path_paper import AMOPSOPathPaperPlanner
from swarmpath.planning.base import Planner
from swarmpath.registry import register_reproduction

UPDATES: tuple[str, ...] = ("spso", "amopso1", "amopso2", "amopso3", "amopso4")
LABELS = {"spso": "SPSO", "pso": "PSO (constriction)", "amopso1": "AMOPSO1", "amopso2": "AMOPSO2", "amopso3": "AMOPSO3", "amopso4": "AMOPSO4"}
MODES: tuple[str, ...] = ("pareto", "weighted-sum")
INITS: tuple[str, ...] = ("astar", "random")
#: Case-1 set-up keys beyond the inits: A* at the paper's budget, and the paper's whole set-up.
PAPER_BUDGET_KEY, PAPER_SETUP_KEY = "astar-8x120", "paper"
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


def case1_planner(update: str, mode: str, init: str, weights: Sequence[float] | None = None,
                  budget: tuple[int, int] | None = None) -> Planner:
    """The planner of one case-1 configuration: ``init="paper"`` is ``amopso-path-paper``,
    else ``amopso-path`` with that initialisation (``budget`` = (particles, iterations),
    default the planner's)."""
    if init == PAPER_SETUP_KEY:
        return AMOPSOPathPaperPlanner(update=update, mode=mode, weights=weights)
    extra = {} if budget is None else {"particles": budget[0], "iterations": budget[1]}
    return AMOPSOPathPlanner(update=update, mode=mode, init=init, weights=weights, **extra)


def plan_case1(world, planner: Planner, seed: int) -> Case1Run:
    """Plan ``abbas-case1`` once with ``planner`` (see :class:`Case1Run`)."""
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


def run_case1(world, update: str, mode: str, init: str, seed: int, weights: Sequence[float] | None = None,
              budget: tuple[int, int] | None = None) -> Case1Run:
    """Plan ``abbas-case1`` once (see :class:`Case1Run` and :func:`case1_planner`)."""
    return plan_case1(world, case1_planner(update, mode, init, weights, budget), seed)


def plan_case2(world, planner: Planner, seed: int):
    """Each robot of ``abbas-case2`` planned alone (timed per robot); (plan, CPU s per robot)."""
    from swarmpath.planning.base import Plan
    from swarmpath.rng import make_rng

    cpu = np.full(world.n_robots, np.nan)
    robots = []
    for k, robot in enumerate(world.robots):
        t0 = time.process_time()
        robots.append(planner.plan_robot(world, robot, rng=make_rng(seed, "amopso-path", robot.id)))
        cpu[k] = time.process_time() - t0
    return Plan(planner.registered_name, tuple(robots), float(np.nansum(cpu)), {}), cpu


def execute_case2(world, plan, follower: Callable[[], object], seed: int, cpu=None) -> Case2Run:
    """Execute a case-2 plan with the controller ``follower`` in the simulator."""
    from swarmpath.metrics.paths import executed_lengths
    from swarmpath.metrics.summary import run_summary
    from swarmpath.sim.simulator import Simulator

    traj = Simulator(world, follower(), plan, seed=seed).run()
    summary = run_summary(world, traj, plan, clearance=False)
    planned = np.array([r.length if r else np.nan for r in plan.robots], float)
    return Case2Run(planned, executed_lengths(traj.positions), np.full(world.n_robots, np.nan) if cpu is None else cpu,
                    summary.success, summary.contacts, summary.makespan,
                    sum(1 for e in traj.events if e.get("kind") == "sidestep"), list(plan.paths),
                    np.asarray(traj.positions))


def run_case2(world, update: str, mode: str, init: str, seed: int, plan=None,
              follower: Callable[[], object] = AMOPSOFollowController) -> tuple[Case2Run, object]:
    """Plan ``abbas-case2`` with ``amopso-path`` (or use ``plan``) and execute it with
    ``follower`` (``amopso-follow``); returns the run and the plan."""
    cpu = None
    if plan is None:
        plan, cpu = plan_case2(world, AMOPSOPathPlanner(update=update, mode=mode, init=init), seed)
    return execute_case2(world, plan, follower, seed, cpu), plan


# ------------------------------------------------------------------------------------ ladders
@dataclass(frozen=True)
class PlannerRung:
    """A rung of the case-1 ladder: the addition, what it fixes, the planner."""

    addition: str
    fixes: str
    planner: Callable[[], Planner]


def case1_rungs(update: str = "amopso4", mode: str = "pareto") -> list[PlannerRung]:
    """From ``amopso-path-paper`` to ``amopso-path`` (same rule and mode), one addition a rung."""
    return [
        PlannerRung("`amopso-path-paper` (random swarm by eq. 31, 8 x 120, no mutation)", "-",
                    lambda: AMOPSOPathPaperPlanner(update=update, mode=mode)),
        PlannerRung("Coello's mutation (`mutation_rate=0.2`)", "a small swarm converging early on a poor front",
                    lambda: AMOPSOPathPlanner(update=update, mode=mode, init="random", particles=8)),
        PlannerRung("30 particles (`particles=30`)", "8 particles sampling too little of the box",
                    lambda: AMOPSOPathPlanner(update=update, mode=mode, init="random")),
        PlannerRung("one particle on the A* path (`init=\"astar\"`) = `amopso-path`",
                    "runs that never find the short way around the obstacles",
                    lambda: AMOPSOPathPlanner(update=update, mode=mode)),
    ]


def ladder_case1(world, seeds: Sequence[int], progress: Progress | None = None) -> list[str]:
    """Run the case-1 ladder over ``seeds``; its Markdown table."""
    rungs = case1_rungs()
    cells = []
    for r in rungs:
        if progress is not None:
            progress.stage(f"case 1 ladder: {r.addition}", len(seeds))
        cell = []
        for s in seeds:
            cell.append(plan_case1(world, r.planner(), s))
            if progress is not None:
                progress.tick()
        cells.append(cell)
    return ladder1_table(rungs, cells)


def ladder1_table(rungs: Sequence[PlannerRung], cells: Sequence[list[Case1Run]]) -> list[str]:
    rows = []
    prev = None
    for k, (r, cell) in enumerate(zip(rungs, cells)):
        L = np.array([c.length for c in cell], float)
        clear = np.array([c.clearance for c in cell], float)
        ok = np.isfinite(L)
        if prev is None:
            test = "-"
        else:
            p, verdict = wilcoxon_vs(L, prev)
            test = f"{verdict} (p = {p:.2g})"
        rows.append([k, r.addition if k == 0 else f"+ {r.addition}", r.fixes, _s(np.nanmedian, L),
                     f"{_s(np.nanmean, L)} +- {_s(np.nanstd, L)}", _s(np.nanmax, L), int(np.sum(clear[ok] < 0)),
                     int(np.sum(~ok)), test])
        prev = L
    return table(["rung", "addition (cumulative)", "what it fixes", "length median", "mean +- std", "worst",
                  "in zone", "no path", "vs the rung above"], rows)


@dataclass(frozen=True)
class Case2Rung:
    """A rung of the case-2 ladder: the addition, what it fixes, whose plans, the follower."""

    addition: str
    fixes: str
    plans: str          # "paper" (amopso-path-paper) or "ours" (amopso-path)
    follower: Callable[[], object]


def case2_rungs() -> list[Case2Rung]:
    """From ``amopso-path-paper`` + ``amopso-follow-paper`` to ``amopso-path`` + ``amopso-follow``."""
    return [
        Case2Rung("`amopso-path-paper` plans, `amopso-follow-paper`", "-", "paper", AMOPSOFollowPaperController),
        Case2Rung("`amopso-path` plans (A* particle, 30 particles, mutation)", "long detours in the plans",
                  "ours", AMOPSOFollowPaperController),
        Case2Rung("shorter moves along the path before turning (`amopso-follow`, `max_waits=0, separation=0`)",
                  "side steps where slowing down would do", "ours",
                  lambda: AMOPSOFollowController(max_waits=0, separation=0.0)),
        Case2Rung("0.25 m of extra room between robots (`separation=0.25`)", "robots passing within a hair",
                  "ours", lambda: AMOPSOFollowController(max_waits=0)),
        Case2Rung("wait up to 2 steps before turning (`max_waits=2`) = `amopso-follow`",
                  "detours where the other robot is gone a step later", "ours", AMOPSOFollowController),
    ]


def ladder_case2(world, seeds: Sequence[int], progress: Progress | None = None,
                 ours: Sequence[object] | None = None) -> list[str]:
    """Run the case-2 ladder over ``seeds`` (``ours``: the ``amopso-path`` plans of those
    seeds when already made); its Markdown table."""
    plans = {"paper": [], "ours": list(ours) if ours is not None else []}
    if progress is not None:
        progress.stage("case 2: amopso-path-paper plans", len(seeds))
    for s in seeds:
        plans["paper"].append(plan_case2(world, AMOPSOPathPaperPlanner(), s)[0])
    if not plans["ours"]:
        plans["ours"] = [plan_case2(world, AMOPSOPathPlanner(), s)[0] for s in seeds]
    rungs = case2_rungs()
    cells = []
    for r in rungs:
        if progress is not None:
            progress.stage(f"case 2 ladder: {r.addition}", len(seeds))
        cell = []
        for s, plan in zip(seeds, plans[r.plans]):
            cell.append(execute_case2(world, plan, r.follower, s))
            if progress is not None:
                progress.tick()
        cells.append(cell)
    return ladder2_table(world, rungs, cells)


def ladder2_table(world, rungs: Sequence[Case2Rung], cells: Sequence[list[Case2Run]]) -> list[str]:
    from swarmpath.planning.reference_paths import visibility_shortest_path

    shortest = np.array([visibility_shortest_path(world, r)[1] for r in world.robots], float)
    rows = []
    for k, (r, cell) in enumerate(zip(rungs, cells)):
        P = np.array([c.planned for c in cell])
        E = np.array([c.executed for c in cell])
        mk = [c.makespan for c in cell if c.makespan is not None]
        rows.append([k, r.addition if k == 0 else f"+ {r.addition}", r.fixes,
                     f"{sum(c.success for c in cell)}/{len(cell)}", sum(c.collisions for c in cell),
                     sum(c.sidesteps for c in cell), f"{np.median(mk):.0f}" if mk else "-",
                     _s(np.nanmedian, P / shortest), _s(np.nanmax, P / shortest), _s(np.nanmax, E / P)])
    return table(["rung", "addition (cumulative)", "what it fixes", "all at their goals, no contact", "contacts",
                  "side steps", "makespan (median)", "planned / shortest (median)", "planned / shortest (max)",
                  "executed / planned (max)"], rows)


# ------------------------------------------------------------------------------------ runs
@dataclass(frozen=True)
class Results:
    """Every run of the report (keys as in the tables)."""

    runs: int
    seed: int
    sweep_runs: int
    case1: dict[tuple[str, str, str], list[Case1Run]]
    sweep: dict[float, list[Case1Run]]
    case2: dict[tuple[str, str, str], list[Case2Run]]
    waitless: list[Case2Run]
    ladder1: list[str]
    ladder2: list[str]
    elapsed: tuple[float, float]


def run_experiments(w1, w2, runs: int, seed: int, updates: Sequence[str], inits: Sequence[str],
                    case2_configs: Sequence[tuple[str, str, str]], sweep: Sequence[float],
                    progress: Progress) -> Results:
    """All plans and runs of the report."""
    sweep_runs = max(1, min(runs, 10))
    cpu0, wall0 = time.process_time(), time.perf_counter()
    case1: dict[tuple[str, str, str], list[Case1Run]] = {}
    setups = [(init, None) for init in inits] + [(PAPER_BUDGET_KEY, PAPER_BUDGET), (PAPER_SETUP_KEY, None)]
    for init, budget in setups:
        progress.stage(f"case 1: {init}", len(MODES) * len(updates) * runs)
        for mode in MODES:
            for update in updates:
                planner_init = "astar" if init == PAPER_BUDGET_KEY else init
                cell = []
                for r in range(runs):
                    cell.append(run_case1(w1, update, mode, planner_init, seed + r, budget=budget))
                    progress.tick()
                case1[(update, mode, init)] = cell
    progress.stage("case 1: weighted-sum sweep", len(sweep) * sweep_runs)
    sweep_res: dict[float, list[Case1Run]] = {}
    for wd in sweep:
        sweep_res[wd] = []
        for r in range(sweep_runs):
            sweep_res[wd].append(run_case1(w1, "amopso4", "weighted-sum", "astar", seed + r, (1 - wd, wd)))
            progress.tick()
    ladder1 = ladder_case1(w1, range(seed, seed + runs), progress)
    progress.stage("case 2: Table 6 configurations", len(case2_configs) * runs)
    case2: dict[tuple[str, str, str], list[Case2Run]] = {}
    plans0: list = []
    for cfg in case2_configs:
        cell = []
        for r in range(runs):
            run, plan = run_case2(w2, *cfg, seed + r)
            cell.append(run)
            if cfg == case2_configs[0]:
                plans0.append(plan)
            progress.tick()
        case2[cfg] = cell
    progress.stage("case 2: side steps without waiting", runs)
    waitless = []
    for r, plan in enumerate(plans0):
        waitless.append(run_case2(w2, *case2_configs[0], seed + r, plan=plan,
                                  follower=lambda: AMOPSOFollowController(max_waits=0))[0])
        progress.tick()
    default = case2_configs[0] == ("amopso4", "pareto", "astar")
    ladder2 = ladder_case2(w2, range(seed, seed + runs), progress, ours=plans0 if default else None)
    return Results(runs, seed, sweep_runs, case1, sweep_res, case2, waitless, ladder1, ladder2,
                   (time.perf_counter() - wall0, time.process_time() - cpu0))


def n_runs(runs: int, updates, inits, case2_configs, sweep) -> int:
    """Plans and runs of the whole reproduction (the progress total)."""
    return (len(updates) * len(MODES) * (len(inits) + 2) * runs + len(sweep) * max(1, min(runs, 10))
            + len(case1_rungs()) * runs + len(case2_configs) * runs + runs + len(case2_rungs()) * runs)


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
    from swarmpath.world import load_scenario

    runs = DEFAULT_RUNS if runs is None else runs
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise ConfigError(f"amopso-paths: runs must be an integer >= 1, got {runs!r}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    w1, w2 = load_scenario("abbas-case1"), load_scenario("abbas-case2")
    bar = Progress("amopso-paths", n_runs(runs, updates, inits, case2_configs, sweep), progress)
    results = run_experiments(w1, w2, runs, seed, updates, inits, case2_configs, sweep, bar)
    bar.stage("figures and report")
    report = out / "report.md"
    report.write_text(render_report(results, w1, w2, updates, inits, case2_configs, out), encoding="utf-8")
    bar.finish()
    return report


# ------------------------------------------------------------------------------------ report
def _f(v: float, digits: int = 3) -> str:
    return fmt(v, digits)


def _s(fn: Callable[[np.ndarray], float], values: np.ndarray, digits: int = 3) -> str:
    """``fn`` (a nan-ignoring statistic) of ``values`` formatted, "-" when all are nan."""
    values = np.asarray(values, float)
    return _f(float(fn(values)), digits) if np.isfinite(values).any() else "-"


CASE1_TITLES = {"astar": "A* initialisation", "random": "random initialisation (eq. 31)",
                PAPER_BUDGET_KEY: f"A* initialisation, the paper's budget ({PAPER_BUDGET[0]} particles x "
                                  f"{PAPER_BUDGET[1]} iterations)",
                PAPER_SETUP_KEY: f"the paper's set-up (`amopso-path-paper`: random initialisation, "
                                 f"{PAPER_BUDGET[0]} particles x {PAPER_BUDGET[1]} iterations, no mutation)"}


def _case1_rows(case1, updates, mode, init, ref_safe: float) -> list[list[object]]:
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
        rows.append([LABELS[update], _s(med, L), f"{_s(np.nanmean, L)} +- {_s(np.nanstd, L)}", _s(np.nanmin, L),
                     _s(med, L / ref_safe), _s(med, d[:, 0]), _s(med, d[:, 1]), _s(med, d.sum(axis=1)),
                     _s(np.nanmin, clear), int(np.sum(clear[ok] < 0)), int(np.sum(~ok)), int(np.median(fronts)),
                     f"{1000 * cpu:.0f}", test])
    return rows


def _case1_sections(case1, updates, inits, ref_safe: float) -> list[str]:
    head = ["rule", "median", "mean +- std", "best", "ratio", "d1", "d2", "d1 + d2", "min clear", "in zone",
            "no path", "front", "CPU ms", "vs SPSO"]
    lines: list[str] = []
    for init in (*inits, PAPER_BUDGET_KEY, PAPER_SETUP_KEY):
        for mode in MODES:
            lines += [f"### {mode}, {CASE1_TITLES[init]}", ""]
            lines += table(head, _case1_rows(case1, updates, mode, init, ref_safe))
            lines.append("")
    return lines[:-1]


def _sweep_table(sweep_res) -> list[str]:
    rows = []
    for wd, cell in sweep_res.items():
        L = np.array([c.length for c in cell])
        d = np.array([c.d for c in cell])
        f1 = np.array([c.f1 for c in cell])
        cl = np.array([c.clearance for c in cell])
        rows.append([f"{1 - wd:.2f}, {wd:.2f}", _f(np.nanmedian(L)), _f(np.nanmedian(d[:, 0])),
                     _f(np.nanmedian(d[:, 1])), f"{np.nanmedian(f1):.4f}", _f(np.nanmin(cl))])
    return table(["W_length, W_danger", "length (median)", "d1 (median)", "d2 (median)", "f1 (median)",
                  "min clear"], rows)


def _case2_sections(case2, case2_configs, ids, ref2_len) -> list[str]:
    lines: list[str] = []
    for cfg in case2_configs:
        cell = case2[cfg]
        P = np.array([c.planned for c in cell])
        E = np.array([c.executed for c in cell])
        C = np.array([c.cpu_s for c in cell])
        rows = []
        for k, rid in enumerate(ids):
            ratio = P[:, k] / ref2_len[k]
            rows.append([rid, f"{PAPER_TABLE6.get(rid, float('nan')):g}", f"{ref2_len[k]:.3f}",
                         _s(np.nanmedian, P[:, k]), _s(np.nanmedian, ratio), _s(np.nanmax, ratio),
                         _s(np.nanmedian, E[:, k]), f"{np.nanmean(C[:, k]):.3f}", int(np.sum(~np.isfinite(ratio)))])
        mk = [c.makespan for c in cell if c.makespan is not None]
        lines += [f"### {LABELS[cfg[0]]}, {cfg[1]}, {'A*' if cfg[2] == 'astar' else 'random'} initialisation", ""]
        lines += table(["robot", "paper", "shortest", "planned (median)", "ratio median", "ratio max",
                        "executed (median)", "CPU s per plan (mean)", "no path"], rows)
        lines += ["", f"All five at their goals in {sum(c.success for c in cell)} of {len(cell)} runs; contacts "
                      f"(simulator's checker) {sum(c.collisions for c in cell)}; makespan median "
                      f"{np.median(mk) if mk else float('nan'):.0f} steps; side steps "
                      f"{sum(c.sidesteps for c in cell)} in all runs; planning CPU time for the five robots "
                      f"{np.nanmean(np.nansum(C, axis=1)):.2f} s (mean).", ""]
    return lines[:-1]


def _waitless(waitless: list[Case2Run], cfg) -> list[str]:
    if not waitless:
        return []
    E = np.array([c.executed for c in waitless])
    P = np.array([c.planned for c in waitless])
    mk = [c.makespan for c in waitless if c.makespan is not None] or [np.nan]
    return [f"### Side steps without waiting (`amopso-follow`, `max_waits=0`: shorter moves along the path, "
            f"then a side step at once), plans of {LABELS[cfg[0]]}, {cfg[1]}", "",
            f"All five at their goals in {sum(c.success for c in waitless)} of {len(waitless)} runs; contacts "
            f"{sum(c.collisions for c in waitless)}; side steps {sum(c.sidesteps for c in waitless)}; "
            f"makespan median {np.median(mk):.0f}; executed / planned length, max over robots and runs: "
            f"{np.nanmax(E / P):.3f} (waiting two steps first: see the tables above; the paper's rule, without "
            "the shorter moves, is `amopso-follow-paper` below)."]


def render_report(r: Results, w1, w2, updates, inits, case2_configs, out: Path) -> str:
    """Figures and the report's Markdown (template ``amopso-paths.md``)."""
    from swarmpath.planning.reference_paths import visibility_shortest_path
    from swarmpath.world import Circle

    robot = w1.robots[0]
    ref1, ref1_len = visibility_shortest_path(w1, robot)
    zones = tuple(Circle(z.center, z.radius) for z in w1.danger_zones)
    ref1s, ref1s_len = visibility_shortest_path(w1.replace(obstacles=w1.obstacles + zones), robot)
    ref2_len = [visibility_shortest_path(w2, x)[1] for x in w2.robots]
    images = _figures(out, w1, w2, r.case1, r.sweep, r.case2, updates, inits, case2_configs, ref1, ref1s)
    defaults = AMOPSOPathPlanner().params()
    return render(
        "amopso-paths", runs=r.runs, seed=r.seed, waypoints=defaults["waypoints"], particles=defaults["particles"],
        iterations=defaults["iterations"], archive=defaults["archive_size"], wall=f"{r.elapsed[0]:.0f}",
        cpu=f"{r.elapsed[1]:.0f}", radii=", ".join(f"{x:g}" for x in sorted({z.radius for z in w1.danger_zones})),
        ref1=f"{ref1_len:.3f}", ref1s=f"{ref1s_len:.3f}", case1=_case1_sections(r.case1, updates, inits, ref1s_len),
        paper_table5=table(["rule", "max distance from danger zone, Pareto", "weighted sum",
                            "min distance start-target, Pareto", "weighted sum"],
                           [[LABELS[u], f"{a:g}", f"{b:g}", f"{c:g}", f"{d:g}"]
                            for u, (a, b, c, d) in PAPER_TABLE5.items()]),
        sweep_runs=r.sweep_runs, sweep=_sweep_table(r.sweep), ladder1=r.ladder1,
        case2=_case2_sections(r.case2, case2_configs, [x.id for x in w2.robots], ref2_len),
        waitless=_waitless(r.waitless, case2_configs[0]),
        paper_table6=table(["robot", "length (Pareto = weighted sum)"], [[k, f"{v:g}"] for k, v in PAPER_TABLE6.items()]),
        time_pareto=f"{PAPER_TIME6['pareto']:g}", time_ws=f"{PAPER_TIME6['weighted-sum']:g}", ladder2=r.ladder2,
        images=[f"![{img}]({img})" for img in images])


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
