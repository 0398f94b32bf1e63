"""Reproduction of Table 3 of Abbas & Abdulsahab: SPSO vs AMOPSO1-4 on f1-f6 (30-D).

``swarmpath reproduce amopso-benchmarks --out DIR [--runs N]`` runs every algorithm on every
function of Table 2 for ``runs`` seeded runs (100 by default, as the paper) at the paper's
budget (8 particles x 120 iterations = 960 evaluations) and at a larger one (30 x 1000), and
writes DIR/report.md with min / mean / std per cell, the paper's numbers beside ours, a
Wilcoxon signed-rank test of each variant against SPSO on the same seeds (run r of every
algorithm starts from the same swarm and sees the same noise), and convergence plots (templates ``templates/amopso-benchmarks*.md``).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from swarmpath.bench.formatting import render, sig, table
from swarmpath.bench.progress import Progress
from swarmpath.bench.stats import wilcoxon_vs
from swarmpath.errors import ConfigError
from swarmpath.optim.benchmark import benchmark_results
from swarmpath.optim.functions import PAPER_FUNCTIONS, get_function
from swarmpath.registry import register_reproduction

ALGORITHMS: tuple[str, ...] = ("spso", "amopso1", "amopso2", "amopso3", "amopso4")
LABELS = {"spso": "SPSO", "amopso1": "AMOPSO1", "amopso2": "AMOPSO2", "amopso3": "AMOPSO3", "amopso4": "AMOPSO4"}
#: (particles, iterations): the paper's budget and a larger one.
BUDGETS: tuple[tuple[int, int], ...] = ((8, 120), (30, 1000))
DIM = 30
PAPER_RUNS = 100

#: Table 3 of the paper: function label -> algorithm -> (min, average) over 100 runs.
PAPER_TABLE3: dict[str, dict[str, tuple[float, float]]] = {
    "f1": {"spso": (0.16239, 0.26797), "amopso1": (0.020316, 0.020322), "amopso2": (0.022755, 0.02276),
           "amopso3": (0.020315, 0.020318), "amopso4": (0.021744, 0.021748)},
    "f2": {"spso": (0.61426, 0.71556), "amopso1": (0.063806, 0.063186), "amopso2": (0.066616, 0.066639),
           "amopso3": (0.060719, 0.060745), "amopso4": (0.06022, 0.060259)},
    "f3": {"spso": (0.20384, 8.4377), "amopso1": (0.07885, 0.087416), "amopso2": (0.065096, 0.070362),
           "amopso3": (0.072637, 0.081607), "amopso4": (0.031205, 0.048147)},
    "f4": {"spso": (0.16376, 2.1796), "amopso1": (0.044989, 0.080379), "amopso2": (0.078139, 0.09372),
           "amopso3": (0.020808, 0.02131), "amopso4": (0.019634, 0.021526)},
    "f5": {"spso": (0.21717, 0.30033), "amopso1": (0.018962, 0.019161), "amopso2": (0.020767, 0.020981),
           "amopso3": (0.021648, 0.02187), "amopso4": (0.021819, 0.022042)},
    "f6": {"spso": (0.20413, 0.36459), "amopso1": (0.027966, 0.028254), "amopso2": (0.027475, 0.0281),
           "amopso3": (0.028591, 0.028887), "amopso4": (0.028807, 0.029154)},
}


@dataclass(frozen=True)
class Cell:
    """The runs of one algorithm on one function at one budget."""

    best: np.ndarray  # (runs,) best value of each run
    history: np.ndarray  # (runs, iterations) best-so-far per iteration
    cpu_time_s: float


def _plot(cells: dict[tuple[str, str], Cell], functions: Sequence[str], title: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cols = 3
    rows = math.ceil(len(functions) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.3 * rows), squeeze=False)
    for ax, fname in zip(axes.flat, functions):
        for algo in ALGORITHMS:
            h = cells[(fname, algo)].history
            med = np.median(h, axis=0)
            lo, hi = np.percentile(h, [25, 75], axis=0)
            it = np.arange(1, h.shape[1] + 1)
            ax.plot(it, med, label=LABELS[algo], lw=1.4)
            ax.fill_between(it, lo, hi, alpha=0.15)
        bench = get_function(fname)
        ax.set_title(f"{bench.paper_label} {fname}")
        ax.set_xlabel("iteration")
        ax.set_ylabel("best value (median, IQR)")
        if np.all(np.concatenate([cells[(fname, a)].history.ravel() for a in ALGORITHMS]) > 0):
            ax.set_yscale("log")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(functions):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_cells(budgets: Sequence[tuple[int, int]], functions: Sequence[str], dim: int, runs: int, seed: int,
              progress: Progress) -> dict[tuple[int, int], dict[tuple[str, str], Cell]]:
    """Every (budget, function, algorithm) cell: ``runs`` seeded runs each."""
    results: dict[tuple[int, int], dict[tuple[str, str], Cell]] = {}
    for particles, iterations in budgets:
        progress.stage(f"{particles} particles x {iterations} iterations", len(functions) * len(ALGORITHMS) * runs)
        cells: dict[tuple[str, str], Cell] = {}
        for fname in functions:
            for algo in ALGORITHMS:
                t0 = time.process_time()
                res = benchmark_results(algo, fname, dim, particles, iterations, runs, seed, progress=progress.ticker())
                cells[(fname, algo)] = Cell(
                    best=np.array([r.f for r in res]),
                    history=np.stack([r.history for r in res]),
                    cpu_time_s=time.process_time() - t0,
                )
        results[(particles, iterations)] = cells
    return results


@register_reproduction("amopso-benchmarks")
def reproduce(
    out: Path,
    *,
    runs: int | None = None,
    seed: int = 0,
    progress: Callable[..., None] | None = None,
    budgets: Sequence[tuple[int, int]] = BUDGETS,
    functions: Sequence[str] = PAPER_FUNCTIONS,
    dim: int = DIM,
) -> Path:
    """Run the Table 3 experiment and write ``out``/report.md plus convergence PNGs.

    Parameters
    ----------
    out : Path
        Directory for the report (created if missing).
    runs : int, optional
        Runs per (algorithm, function, budget); default 100 as in the paper.
    seed : int
        Seed of the experiment; run r of every algorithm uses the streams of (seed, r).
    progress : callable, optional
        ``progress(done, total)`` after every run.
    budgets, functions, dim
        Smaller settings for quick checks; the defaults are the paper's.

    Returns
    -------
    Path of report.md.
    """
    runs = PAPER_RUNS if runs is None else runs
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise ConfigError(f"amopso-benchmarks: runs must be an integer >= 1, got {runs!r}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    bar = Progress("amopso-benchmarks", len(budgets) * len(functions) * len(ALGORITHMS) * runs, progress)
    started, cpu_started = time.perf_counter(), time.process_time()
    results = run_cells(budgets, functions, dim, runs, seed, bar)
    elapsed = (time.perf_counter() - started, time.process_time() - cpu_started)
    bar.stage("figures and report")
    images = []
    for (particles, iterations), cells in results.items():
        name = f"convergence-{particles}x{iterations}.png"
        _plot(cells, functions, f"{dim}-D, {particles} particles x {iterations} iterations, {runs} runs", out / name)
        images.append(name)
    report = out / "report.md"
    report.write_text(_report(results, functions, runs, seed, dim, elapsed, images), encoding="utf-8")
    bar.finish()
    return report


def _budget_section(particles: int, iterations: int, cells: dict[tuple[str, str], Cell], functions: Sequence[str],
                    runs: int) -> str:
    values = []
    for fname in functions:
        label = get_function(fname).paper_label or fname
        values.append([f"{label} {fname}", *(f"{sig(b.min())} / {sig(b.mean())} +- {sig(b.std())}"
                                             for b in (cells[(fname, a)].best for a in ALGORITHMS))])
    tally = {a: {"better": 0, "worse": 0, "no difference": 0} for a in ALGORITHMS[1:]}
    tests = []
    for fname in functions:
        base = cells[(fname, "spso")].best
        row = [get_function(fname).paper_label or fname]
        for algo in ALGORITHMS[1:]:
            p, verdict = wilcoxon_vs(cells[(fname, algo)].best, base)
            tally[algo][verdict] += 1
            row.append(f"{verdict} (p = {p:.2g})")
        tests.append(row)
    return render("amopso-benchmarks-budget", particles=particles, iterations=iterations,
                  evaluations=particles * iterations,
                  values=table(["f", *(LABELS[a] for a in ALGORITHMS)], values),
                  tests=table(["f", *(LABELS[a] for a in ALGORITHMS[1:])], tests),
                  tally="; ".join(f"{LABELS[a]} better on {t['better']}, worse on {t['worse']}, no difference on "
                                  f"{t['no difference']}" for a, t in tally.items()),
                  cpu=", ".join(f"{LABELS[a]} {1000 * np.mean([cells[(f, a)].cpu_time_s for f in functions]) / runs:.1f}"
                                for a in ALGORITHMS))


def _report(
    results: dict[tuple[int, int], dict[tuple[str, str], Cell]],
    functions: Sequence[str],
    runs: int,
    seed: int,
    dim: int,
    elapsed: tuple[float, float],
    images: list[str],
) -> str:
    """The report's Markdown (templates ``amopso-benchmarks*.md``)."""
    budgets = "".join(_budget_section(p, i, cells, functions, runs) for (p, i), cells in results.items())
    paper = table(["f", *(LABELS[a] for a in ALGORITHMS)],
                  [[label, *(f"{row[a][0]:g} & {row[a][1]:g}" for a in ALGORITHMS)]
                   for label, row in PAPER_TABLE3.items()])
    return render("amopso-benchmarks", dim=dim, runs=runs, seed=seed, wall=f"{elapsed[0]:.0f}",
                  cpu=f"{elapsed[1]:.0f}", budgets=budgets, paper_table=paper,
                  images=[f"![{img}]({img})" for img in images])
