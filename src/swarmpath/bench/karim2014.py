"""Reproduction of Karim 2014 (artificial fish swarm among moving obstacles, section "Results").

``swarmpath reproduce karim2014 --out DIR [--runs N]`` runs the ``fish-swarm`` controller on the
``karim2014`` world (10x10 grid, start cell (1,1), goal cell (10,10) in the paper's numbering,
obstacles redrawn at random free cells every step, w = 3, delta = 0.5):

1. Table 1: path length (steps) over ``runs`` seeds (200 by default) with 10 obstacles, next to
   the paper's four runs (9, 10, 11, 10);
2. Table 2: path length for 10, 15, ..., 50 obstacles, ``runs`` seeds each (100 by default),
   next to the paper's one value per count; with two ablations that explain the trend: prey
   only (delta = 0: follow and swarm never pass the crowd test) and, for 10/30/50 obstacles,
   food from the distance field instead of the Euclidean distance;
3. not in the paper: random-walk obstacles (they move to a neighbouring cell each step and may
   step onto the robot), contacts counted by the simulator's checker;
4. the paper's uniform redraw (obstacles may land on the robot and its goal) next to ours, on
   the seeds of Tables 1 and 2, and the ablation ladder from the one to the other;
5. Figure 1 like the paper's: the behaviour at each step of one run and the path; the path
   length against the number of obstacles; the behaviour mix; an animation (GIF).

It writes DIR/report.md (template ``templates/karim2014.md``) and the PNG/GIF files. Same seed,
same numbers (CPU times aside). :func:`ladder` runs the ladder alone (the docs page's table).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from swarmpath.bench.formatting import fmt, pct, render, table
from swarmpath.bench.ladder import Rung, ladder_table, run_ladder
from swarmpath.bench.progress import Progress
from swarmpath.bench.runner import run_batch as common_run_batch
from swarmpath.control.fish_swarm import FishSwarmController
from swarmpath.metrics.paths import executed_lengths
from swarmpath.registry import register_reproduction
from swarmpath.sim.trajectory import ALL_REACHED, Trajectory
from swarmpath.world import World, load_scenario
from swarmpath.world.moving import MovingObstacle, RandomWalk, Redraw
from swarmpath.world.shapes import Rect

#: Paper, Table 1: path length of four runs with 10 obstacles.
PAPER_TABLE1 = (9, 10, 11, 10)
#: Paper, Table 2: path length (one value) per number of obstacles.
PAPER_TABLE2 = {10: 10, 15: 13, 20: 12, 25: 14, 30: 14, 35: 13, 40: 14, 45: 12, 50: 15}
PAPER_RANGE = (10, 15)
OBSTACLE_COUNTS = tuple(PAPER_TABLE2)
TABLE1_RUNS, TABLE2_RUNS = 200, 100
DISTANCE_FIELD_COUNTS = (10, 30, 50)
RANDOM_WALK_COUNTS = (1, 5, 10, 20)
#: Shortest possible path from cell (1,1) to (10,10) with 8-connected moves.
OPTIMAL_STEPS = 9

#: Controller variants: label -> factory.
VARIANTS: dict[str, Callable[[], FishSwarmController]] = {
    "paper": lambda: FishSwarmController(w=3, delta=0.5, food="euclidean"),
    "prey only": lambda: FishSwarmController(w=3, delta=0.0, food="euclidean"),
    "distance field": lambda: FishSwarmController(w=3, delta=0.5, food="distance-field"),
}


def karim_world(n_obstacles: int = 10, motion: str = "redraw", avoid_robots: bool = True) -> World:
    """The ``karim2014`` world with ``n_obstacles`` one-cell obstacles moving by ``motion``
    (``"redraw"``, the paper's, or ``"random-walk"``). The first 10 start where the scenario
    puts them, the others at fixed cells in a fixed shuffled order (start positions only matter
    at step 0 for redraw obstacles). At most 98 obstacles (every cell but start and goal).
    ``avoid_robots=False`` gives the paper's uniform redraw (``Redraw(avoid_robots=False)``:
    obstacles may land on the robot's cell and goal)."""
    base = load_scenario("karim2014")
    if motion not in ("redraw", "random-walk"):
        raise ValueError(f"motion must be 'redraw' or 'random-walk', got {motion!r}")
    if (n_obstacles, motion, avoid_robots) == (10, "redraw", True):
        return base
    grid = base.grid()
    model = Redraw(avoid_robots=avoid_robots) if motion == "redraw" else RandomWalk()
    keep = {tuple(grid.cell_of(np.asarray(p, float)).tolist()) for r in base.robots for p in (r.start, r.goal)}
    if motion == "random-walk":   # walkers must not start next to the robot: they could step onto it
        sx, sy = grid.cell_of(np.asarray(base.robots[0].start, float))
        keep |= {(sx + dx, sy + dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)}
    starts = [tuple(o.start) for o in base.moving_obstacles]
    starts = [s for s in starts if tuple(grid.cell_of(np.asarray(s)).tolist()) not in keep]
    used = {tuple(grid.cell_of(np.asarray(s)).tolist()) for s in starts}
    order = np.random.default_rng(2014).permutation(grid.width * grid.height)
    for flat in order:
        cell = (int(flat % grid.width), int(flat // grid.width))
        if cell not in used and cell not in keep and not grid.blocked[cell[1], cell[0]]:
            starts.append((cell[0] + 0.5, cell[1] + 0.5))
            used.add(cell)
    if n_obstacles > len(starts):
        raise ValueError(f"at most {len(starts)} obstacles fit, asked for {n_obstacles}")
    shape = Rect((-0.5, -0.5), (0.5, 0.5))
    obstacles = tuple(MovingObstacle(f"o{k + 1}", shape, starts[k], (0.0, 0.0), model) for k in range(n_obstacles))
    name = f"karim2014-{motion}-{n_obstacles}" + ("" if avoid_robots else "-paper")
    return base.replace(moving_obstacles=obstacles, name=name)


@dataclass(frozen=True)
class BatchStats:
    """Outcomes of one controller on one world over many seeds.

    steps : (n_runs,) moves until the goal was reached (waits included), nan if not reached
    lengths : (n_runs,) Euclidean length of the executed path (cells), nan if not reached
    contacts : (n_runs,) contacts the simulator's checker found
    waits : (n_runs,) steps the robot stood still before arriving
    """

    label: str
    n_obstacles: int
    seeds: tuple[int, ...]
    status: tuple[str, ...]
    steps: NDArray[np.float64]
    lengths: NDArray[np.float64]
    contacts: NDArray[np.int64]
    waits: NDArray[np.int64]
    modes: dict[str, int] = field(default_factory=dict)
    cpu_s: float = 0.0

    @property
    def n_runs(self) -> int:
        return len(self.seeds)

    @property
    def reached(self) -> NDArray[np.float64]:
        return self.steps[np.isfinite(self.steps)]

    @property
    def success_rate(self) -> float:
        return float(np.mean([s == ALL_REACHED for s in self.status])) if self.status else 0.0

    @property
    def safe_success_rate(self) -> float:
        """Share of runs that ended on the goal without any contact (``RunSummary.success``)."""
        ok = [st == ALL_REACHED and c == 0 for st, c in zip(self.status, self.contacts)]
        return float(np.mean(ok)) if ok else 0.0

    def stat(self, name: str) -> float:
        """mean / median / std / min / max of the steps of the runs that arrived (nan if none)."""
        r = self.reached
        if len(r) == 0:
            return float("nan")
        return float({"mean": np.mean, "median": np.median, "std": np.std, "min": np.min, "max": np.max}[name](r))

    def share_within(self, lo: float, hi: float) -> float:
        """Fraction of arrived runs whose path length lies in [lo, hi]."""
        r = self.reached
        return float(np.mean((r >= lo) & (r <= hi))) if len(r) else float("nan")

    def mode_shares(self) -> dict[str, float]:
        total = sum(self.modes.values())
        return {k: v / total for k, v in sorted(self.modes.items())} if total else {}


@dataclass(frozen=True)
class _Run:
    status: str
    steps: float
    length: float
    contacts: int
    waits: int
    modes: dict[str, int]


def _measure(traj: Trajectory, _cpu: float) -> _Run:
    """One run of the single robot: steps and length if it arrived, contacts, waits, modes."""
    arrived = traj.status == ALL_REACHED
    moved = np.any(np.diff(traj.positions[:, 0], axis=0) != 0, axis=1)
    modes: dict[str, int] = {}
    if traj.modes is not None:
        for idx, name in enumerate(traj.mode_names):
            modes[name] = int(np.count_nonzero(traj.modes[:, 0] == idx))
    return _Run(traj.status, float(traj.n_steps) if arrived else np.nan,
                float(executed_lengths(traj.positions)[0]) if arrived else np.nan, len(traj.contacts),
                int(np.count_nonzero(~moved)), modes)


def run_batch(world: World, seeds, make_controller: Callable[[], FishSwarmController], *, label: str = "",
              progress: Progress | None = None, keep: int = 0) -> tuple[BatchStats, list[Trajectory]]:
    """Simulate ``world`` once per seed; returns the statistics and the first ``keep``
    trajectories."""
    batch = common_run_batch(world, make_controller, seeds, _measure, label=label, keep=keep, progress=progress)
    modes: dict[str, int] = {}
    for r in batch.records:
        for name, count in r.modes.items():
            modes[name] = modes.get(name, 0) + count
    rec = batch.records
    stats = BatchStats(label, len(world.moving_obstacles), batch.seeds, tuple(r.status for r in rec),
                       np.array([r.steps for r in rec], float), np.array([r.length for r in rec], float),
                       np.array([r.contacts for r in rec], np.int64), np.array([r.waits for r in rec], np.int64),
                       modes, batch.cpu_s)
    return stats, list(batch.kept)


#: The ladder from the paper's redraw to ours (the fish swarm is the paper's in both).
def ladder_rungs() -> list[Rung]:
    """Rung 0: the paper (uniform redraw); rung 1: our redraw, never on a robot's cell or goal."""
    paper = VARIANTS["paper"]
    return [Rung("paper: `fish-swarm` (w 3, delta 0.5), uniform redraw", "-", paper,
                 karim_world(10, avoid_robots=False)),
            Rung("redraw never on a robot's cell or goal cell (`redraw`, `avoid_robots: true`)",
                 "an obstacle landing on the robot (unavoidable: obstacles move first) or covering its goal",
                 paper, karim_world(10))]


def ladder(seeds, progress: Progress | None = None) -> list[str]:
    """Run the ladder over ``seeds`` (10 obstacles) and return its Markdown table."""
    rungs = ladder_rungs()
    return ladder_table(rungs, run_ladder(karim_world(10), rungs, seeds, progress=progress))


@dataclass(frozen=True)
class Results:
    """Every batch of the reproduction (see :func:`run_experiments`)."""

    n1: int
    n2: int
    seed: int
    table1: BatchStats
    kept: list[Trajectory]
    table2: dict[str, dict[int, BatchStats]]
    walks: dict[int, BatchStats]
    paper_table1: BatchStats
    paper_table2: dict[int, BatchStats]
    ladder: list[str]


def run_experiments(n1: int, n2: int, seed: int, progress: Progress | None = None) -> Results:
    """All runs of the report: Tables 1 and 2 with the ablations, random walkers, the paper's
    redraw and the ladder."""
    def stage(name: str, runs: int) -> None:
        if progress is not None:
            progress.stage(name, runs)

    seeds1, seeds2 = range(seed, seed + n1), range(seed, seed + n2)
    stage("Table 1: 10 obstacles", n1)
    t1, kept = run_batch(karim_world(10), seeds1, VARIANTS["paper"], label="paper", progress=progress, keep=n1)
    table2: dict[str, dict[int, BatchStats]] = {"paper": {}, "prey only": {}, "distance field": {}}
    stage("Table 2: 10-50 obstacles, three variants", n2 * (2 * len(OBSTACLE_COUNTS) + len(DISTANCE_FIELD_COUNTS)))
    for n in OBSTACLE_COUNTS:
        world = karim_world(n)
        for label in ("paper", "prey only"):
            table2[label][n], _ = run_batch(world, seeds2, VARIANTS[label], label=label, progress=progress)
        if n in DISTANCE_FIELD_COUNTS:
            table2["distance field"][n], _ = run_batch(world, seeds2, VARIANTS["distance field"],
                                                       label="distance field", progress=progress)
    stage("random-walk obstacles", n2 * len(RANDOM_WALK_COUNTS))
    walks = {n: run_batch(karim_world(n, "random-walk"), seeds2, VARIANTS["paper"], label="random walk",
                          progress=progress)[0] for n in RANDOM_WALK_COUNTS}
    stage("the paper's uniform redraw, Tables 1 and 2", n1 + n2 * len(OBSTACLE_COUNTS))
    p1, _ = run_batch(karim_world(10, avoid_robots=False), seeds1, VARIANTS["paper"], label="paper redraw",
                      progress=progress)
    p2 = {n: run_batch(karim_world(n, avoid_robots=False), seeds2, VARIANTS["paper"], label="paper redraw",
                       progress=progress)[0] for n in OBSTACLE_COUNTS}
    steps = ladder(seeds1, progress)
    return Results(n1, n2, seed, t1, kept, table2, walks, p1, p2, steps)


# ---------------------------------------------------------------------------------- figures
def _draw_grid(ax, world: World) -> None:
    w, h = world.grid().width, world.grid().height
    for k in range(w + 1):
        ax.plot([k, k], [0, h], color="#cfd8dc", linewidth=0.6, zorder=0)
    for k in range(h + 1):
        ax.plot([0, w], [k, k], color="#cfd8dc", linewidth=0.6, zorder=0)
    ax.set_xlim(0, w)
    ax.set_ylim(0, h)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def figure_steps(traj: Trajectory, world: World, path: Path) -> Path:
    """Like the paper's Figure 1: one panel per step (the obstacles after their move, the robot
    before its move, an arrow to where it goes, the behaviour), then the whole path."""
    from swarmpath.viz import style

    n = traj.n_steps
    panels = n + 1
    ncols = min(5, panels)
    nrows = -(-panels // ncols)
    fig = style.new_figure(2.3 * ncols, 2.5 * nrows)
    goal = traj.goals[0]
    letters = "abcdefghijklmnopqrstuvwxyz"
    for k in range(1, n + 1):
        ax = fig.add_subplot(nrows, ncols, k)
        _draw_grid(ax, world)
        obs = traj.obstacle_positions[k]
        ax.scatter(obs[:, 0], obs[:, 1], s=55, c="#d32f2f", marker="s", zorder=2)
        a, b = traj.positions[k - 1, 0], traj.positions[k, 0]
        ax.scatter([goal[0]], [goal[1]], s=80, marker="*", c="#fbc02d", edgecolors="k", linewidths=0.4, zorder=3)
        ax.scatter([a[0]], [a[1]], s=60, c="#2e7d32", zorder=4)
        if np.any(a != b):
            ax.annotate("", xy=b, xytext=a, arrowprops={"arrowstyle": "->", "color": "#1b5e20", "lw": 1.4}, zorder=5)
        mode = traj.mode_names[traj.modes[k - 1, 0]] if traj.modes is not None else "?"
        tag = letters[k - 1] if k - 1 < len(letters) else str(k)
        ax.set_title(f"({tag}) step {k}: {mode}", fontsize=8)
    ax = fig.add_subplot(nrows, ncols, n + 1)
    _draw_grid(ax, world)
    p = traj.positions[:, 0]
    ax.plot(p[:, 0], p[:, 1], "-o", color="#2e7d32", markersize=3, linewidth=1.5)
    ax.scatter([goal[0]], [goal[1]], s=80, marker="*", c="#fbc02d", edgecolors="k", linewidths=0.4, zorder=3)
    ax.set_title(f"planned path: {n} steps", fontsize=8)
    fig.suptitle(f"karim2014, seed {traj.seed}: green robot, red obstacles (redrawn every step)", fontsize=9)
    fig.tight_layout()
    return style.save_figure(fig, path)


def figure_lengths(table2: dict[str, dict[int, BatchStats]], path: Path) -> Path:
    """Mean path length (with min-max band) against the number of obstacles, the paper's
    values as markers."""
    from swarmpath.viz import style

    fig = style.new_figure(6.4, 4.2)
    ax = fig.add_subplot(1, 1, 1)
    colours = {"paper": "#1f77b4", "prey only": "#2ca02c", "distance field": "#ff7f0e"}
    for label, rows in table2.items():
        ns = sorted(rows)
        mean = [rows[n].stat("mean") for n in ns]
        ax.plot(ns, mean, "-o", color=colours.get(label, "k"), label=f"ours, {label} (mean)", markersize=4)
        if label == "paper":
            lo = [rows[n].stat("min") for n in ns]
            hi = [rows[n].stat("max") for n in ns]
            ax.fill_between(ns, lo, hi, color=colours["paper"], alpha=0.15, label="ours, paper (min-max)")
    ax.plot(list(PAPER_TABLE2), list(PAPER_TABLE2.values()), "kD", label="Karim 2014, Table 2", markersize=6)
    ax.axhspan(*PAPER_RANGE, color="#9e9e9e", alpha=0.12, label="paper's range 10-15")
    ax.axhline(OPTIMAL_STEPS, color="#616161", linestyle=":", linewidth=1, label="shortest possible (9)")
    ax.set_xlabel("number of moving obstacles")
    ax.set_ylabel("path length (steps)")
    ax.legend(fontsize=7, loc="upper left")
    style.style_axes(ax, equal=False, grid=True)
    fig.tight_layout()
    return style.save_figure(fig, path)


def figure_modes(rows: dict[int, BatchStats], path: Path) -> Path:
    """Share of each behaviour among all steps, per number of obstacles."""
    from swarmpath.viz import style

    names = ["prey", "follow", "swarm", "wait"]
    ns = sorted(rows)
    shares = np.array([[rows[n].mode_shares().get(m, 0.0) for m in names] for n in ns])
    fig = style.new_figure(6.4, 3.6)
    ax = fig.add_subplot(1, 1, 1)
    bottom = np.zeros(len(ns))
    for k, (name, colour) in enumerate(zip(names, style.mode_colors(names))):
        ax.bar(ns, shares[:, k], bottom=bottom, width=3.5, color=colour, label=name)
        bottom += shares[:, k]
    ax.set_xlabel("number of moving obstacles")
    ax.set_ylabel("share of steps")
    ax.legend(fontsize=7, ncol=4, loc="upper center", bbox_to_anchor=(0.5, 1.15))
    style.style_axes(ax, equal=False)
    fig.tight_layout()
    return style.save_figure(fig, path)


def figure_histogram(stats: BatchStats, path: Path) -> Path:
    """Distribution of path lengths with 10 obstacles, the paper's four runs marked."""
    from swarmpath.viz import style

    fig = style.new_figure(5.6, 3.4)
    ax = fig.add_subplot(1, 1, 1)
    r = stats.reached.astype(int)
    bins = np.arange(r.min() - 0.5, r.max() + 1.5) if len(r) else 10
    ax.hist(r, bins=bins, color="#1f77b4", alpha=0.8, label=f"ours, {stats.n_runs} runs")
    for k, v in enumerate(PAPER_TABLE1):
        ax.axvline(v + 0.06 * (k - 1.5), color="k", linestyle="--", linewidth=1,
                   label="paper, Table 1 runs" if k == 0 else None)
    ax.set_xlabel("path length (steps)")
    ax.set_ylabel("runs")
    ax.legend(fontsize=7)
    style.style_axes(ax, equal=False)
    fig.tight_layout()
    return style.save_figure(fig, path)


# ---------------------------------------------------------------------------------- report
def _modes_cell(s: BatchStats) -> str:
    sh = s.mode_shares()
    return " / ".join(f"{100 * sh.get(m, 0.0):.0f}" for m in ("prey", "follow", "swarm", "wait"))


def _table1(t1: BatchStats) -> tuple[list[str], list[str]]:
    runs = table(["run", "paper", "ours (seed)"], [
        [k + 1, v, f"{fmt(t1.steps[k] if k < t1.n_runs else np.nan, 0)} ({t1.seeds[k] if k < t1.n_runs else '-'})"]
        for k, v in enumerate(PAPER_TABLE1)])
    summary = table(["", "paper (4 runs)", "ours"], [
        ["runs", 4, t1.n_runs],
        ["success rate", "4/4", pct(t1.success_rate)],
        ["mean path length", f"{np.mean(PAPER_TABLE1):.2f}", f"{fmt(t1.stat('mean'))} (std {fmt(t1.stat('std'))})"],
        ["median", f"{np.median(PAPER_TABLE1):.1f}", fmt(t1.stat("median"), 1)],
        ["min / max", f"{min(PAPER_TABLE1)} / {max(PAPER_TABLE1)}",
         f"{fmt(t1.stat('min'), 0)} / {fmt(t1.stat('max'), 0)}"],
        ["runs with 9-11 steps", "4/4", pct(t1.share_within(9, 11))],
        ["contacts (all runs)", "-", int(t1.contacts.sum())],
        ["waits (all runs)", "-", int(t1.waits.sum())],
        ["behaviour shares prey / follow / swarm / wait (%)", "-", _modes_cell(t1)]])
    return runs, summary


def _table2(table2: dict[str, dict[int, BatchStats]]) -> list[str]:
    rows = []
    for n in OBSTACLE_COUNTS:
        s, p = table2["paper"][n], table2["prey only"][n]
        d = table2["distance field"].get(n)
        rows.append([n, PAPER_TABLE2[n], f"{fmt(s.stat('mean'))} ({fmt(s.stat('std'))})", fmt(s.stat("median"), 1),
                     f"{fmt(s.stat('min'), 0)}-{fmt(s.stat('max'), 0)}", pct(s.success_rate),
                     pct(s.share_within(*PAPER_RANGE)), int(s.contacts.sum()), _modes_cell(s),
                     fmt(p.stat("mean")), fmt(d.stat("mean")) if d is not None else ""])
    return table(["obstacles", "paper", "ours mean (std)", "median", "min-max", "success", "in 10-15", "contacts",
                  "prey/follow/swarm/wait %", "prey only", "distance field"], rows)


def _redraw_tables(r: Results) -> tuple[list[str], list[str]]:
    def cells(s: BatchStats) -> list[str]:
        return [pct(s.safe_success_rate), pct(s.success_rate), pct(float(np.mean(s.contacts > 0))),
                fmt(float(np.mean(s.contacts))), fmt(s.stat("mean"))]

    names = ["success (on the goal, no contact)", "on the goal at the end", "runs with a contact",
             "contacts per run", "mean steps (arrived runs)"]
    side = table(["", "paper's redraw", "ours"],
                 [[name, a, b] for name, a, b in zip(names, cells(r.paper_table1), cells(r.table1))])
    rows = [[n, *cells(r.paper_table2[n]), *cells(r.table2["paper"][n])] for n in OBSTACLE_COUNTS]
    counts = table(["obstacles", *[f"paper's redraw: {x}" for x in names], *[f"ours: {x}" for x in names]], rows)
    return side, counts


def render_report(r: Results, files: dict[str, Path], animation_note: str) -> str:
    """The report's Markdown from the runs' statistics (template ``karim2014.md``)."""
    table2 = r.table2
    means = {n: table2["paper"][n].stat("mean") for n in OBSTACLE_COUNTS}
    outside = [n for n, m in means.items() if not (PAPER_RANGE[0] <= m <= PAPER_RANGE[1])]
    within = [n for n in OBSTACLE_COUNTS
              if table2["paper"][n].stat("min") <= PAPER_TABLE2[n] <= table2["paper"][n].stat("max")]
    runs1, summary1 = _table1(r.table1)
    walks = table(["obstacles", "success", "mean steps", "runs with a contact", "contacts per run"], [
        [n, pct(s.success_rate), fmt(s.stat("mean")), pct(float(np.mean(s.contacts > 0))),
         fmt(float(np.mean(s.contacts)))] for n, s in r.walks.items()])
    side, counts = _redraw_tables(r)
    anim = f"Animation of the same run: [{files['anim'].name}]({files['anim'].name})" if "anim" in files \
        else animation_note
    cpu_tables = sum(s.cpu_s for rows in table2.values() for s in rows.values()) + r.table1.cpu_s
    return render("karim2014", optimal=OPTIMAL_STEPS, seed=r.seed, n1=r.table1.n_runs, n2=r.n2,
                  table1_runs=runs1, table1_summary=summary1, hist=files["hist"].name, table2=_table2(table2),
                  lengths=files["lengths"].name, modes=files["modes"].name,
                  outside=", ".join(f"{n} obstacles ({means[n]:.2f})" for n in outside) if outside else "none",
                  within=len(within), n_counts=len(OBSTACLE_COUNTS),
                  prey_max=f"{max(table2['prey only'][n].stat('mean') for n in OBSTACLE_COUNTS):.2f}",
                  walks=walks, redraw_side=side, redraw_table=counts, ladder=r.ladder,
                  example_seed=files["example_seed"], steps=files["steps"].name, anim=anim,
                  cpu_tables=f"{cpu_tables:.1f}", cpu_walks=f"{sum(s.cpu_s for s in r.walks.values()):.1f}",
                  cpu_paper=f"{r.paper_table1.cpu_s + sum(s.cpu_s for s in r.paper_table2.values()):.1f}")


def write_figures(r: Results, out: Path) -> tuple[dict, str]:
    """The report's figures; Figure 1 shows the first run with at least two behaviours (the
    paper's shows prey and follow)."""
    example = next((t for t in r.kept if t.status == ALL_REACHED and t.modes is not None
                    and len(set(t.modes[:, 0].tolist())) >= 2), r.kept[0])
    files: dict = {
        "steps": figure_steps(example, karim_world(10), out / "karim2014-figure1-steps.png"),
        "lengths": figure_lengths(r.table2, out / "karim2014-path-length-vs-obstacles.png"),
        "modes": figure_modes(r.table2["paper"], out / "karim2014-behaviours.png"),
        "hist": figure_histogram(r.table1, out / "karim2014-table1-histogram.png"),
        "example_seed": example.seed,
    }
    note = ""
    try:
        from swarmpath.viz.animation import save_animation

        files["anim"] = save_animation(example, out / "karim2014-run.gif", fps=2)
    except ImportError:  # pragma: no cover - the viz module ships with swarmpath
        note = "(no animation: swarmpath.viz.animation is not available)"
    return files, note


@register_reproduction("karim2014")
def reproduce(out: Path, *, runs: int | None = None, seed: int = 0,
              progress: Callable[[int, int], None] | None = None) -> Path:
    """Run the experiments and write ``out``/report.md with the figures; returns its path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    n1, n2 = runs or TABLE1_RUNS, runs or TABLE2_RUNS
    total = (2 * n1 + n2 * (2 * len(OBSTACLE_COUNTS) + len(DISTANCE_FIELD_COUNTS) + len(RANDOM_WALK_COUNTS))
             + n1 + n2 * len(OBSTACLE_COUNTS) + n1)
    bar = Progress("karim2014", total, progress)
    results = run_experiments(n1, n2, seed, bar)
    bar.stage("figures and report")
    files, note = write_figures(results, out)
    report = out / "report.md"
    report.write_text(render_report(results, files, note), encoding="utf-8")
    bar.finish()
    return report
