"""Optimisers side by side with peer libraries: wall time per run and median best value.

Run on demand (not a test):

    . .venv/bin/activate && pip install pyswarms pymoo      # the [bench] extra has both
    python benchmarks/bench_optim.py --setup-mealpy           # once: mealpy in .venv-mealpy
    python benchmarks/bench_optim.py [--seeds 10] [--quick] [--only spso,apso,pyswarms]

Same functions (30-D sphere, Rastrigin, Ackley, Griewank on the paper's boxes), same budgets
(8 particles x 120 iterations and 30 x 1000), same vectorised function code for every library,
10 seeds, CPU time per run (the code is single-threaded; CPU time is the wall time of an idle
machine and stays fair on a shared one; wall time is in the --json output). Every algorithm gets particles x iterations evaluations: PSO-type peers by their
iteration count, the cat swarms (ours and mealpy's) by an evaluation cap.

Ours: ``pso`` (constriction coefficients), ``spso`` (the paper's SPSO), ``apso`` (Zhan et al.'s
adaptive PSO, capped at the same evaluations: its elitist learning costs one extra evaluation
in the convergence state), ``amopso1-4`` and ``cso``. Speed ratios are against ``spso``, the
configuration pyswarms runs.

Peers: pyswarms GlobalBestPSO (w 0.9 -> 0.4 linearly, c1 = c2 = 2, the same velocity clamp and
clip-to-box walls as ours, i.e. the paper's SPSO), pymoo's PSO (its defaults: adaptive w/c1/c2
after Zhan et al. plus a perturbed global best), mealpy OriginalPSO and OriginalCSO (their
defaults, c1 = c2 = 2.05 and w = 0.4 for PSO). mealpy pins numpy <= 1.26, so it runs in its own
virtual environment (.venv-mealpy) as a worker process of this script.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from swarmpath.optim.functions import ackley, griewank, rastrigin, sphere  # noqa: E402

_IN_FUNCTION = [0.0]  # CPU seconds spent inside objective functions (reset per run)


def _timed(f):
    def g(X):
        c = time.process_time()
        out = f(X)
        _IN_FUNCTION[0] += time.process_time() - c
        return out

    g.__name__ = f.__name__
    return g


FUNCTIONS = {"sphere": (_timed(sphere), 100.0), "rastrigin": (_timed(rastrigin), 5.12),
             "ackley": (_timed(ackley), 32.0), "griewank": (_timed(griewank), 600.0)}
BUDGETS = [(8, 120), (30, 1000)]
DIM = 30
MEALPY_VENV = ROOT / ".venv-mealpy"


# ---- the algorithms: each returns (best value, evaluations) for one seeded run -----------------


def run_ours(name):
    from swarmpath.optim import minimize
    from swarmpath.optim.problem import Problem

    def run(fname, particles, iterations, seed):
        f, b = FUNCTIONS[fname]
        p = Problem(f, -b, b, dim=DIM)
        cap = particles * iterations if name in ("cso", "afsa", "apso") else None
        res = minimize(p, name, iterations=iterations if cap is None else 10**9, particles=particles,
                       seed=seed, max_evaluations=cap)
        return res.f, res.n_evaluations

    return run


def run_pyswarms(fname, particles, iterations, seed):
    import logging

    import pyswarms as ps

    logging.getLogger("pyswarms").setLevel(logging.ERROR)
    f, b = FUNCTIONS[fname]
    np.random.seed(seed)  # pyswarms draws from numpy's global state
    vmax = 0.2 * 2 * b
    opt = ps.single.GlobalBestPSO(
        n_particles=particles, dimensions=DIM, options={"c1": 2.0, "c2": 2.0, "w": 0.9},
        bounds=(np.full(DIM, -b), np.full(DIM, b)), oh_strategy={"w": "lin_variation"},
        bh_strategy="nearest", velocity_clamp=(-vmax, vmax),
    )
    cost, _ = opt.optimize(f, iters=iterations, verbose=False)
    return float(cost), particles * iterations


def run_pymoo(fname, particles, iterations, seed):
    from pymoo.algorithms.soo.nonconvex.pso import PSO
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    f, b = FUNCTIONS[fname]

    class P(Problem):
        def __init__(self):
            super().__init__(n_var=DIM, n_obj=1, xl=-b, xu=b)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = f(x)

    res = minimize(P(), PSO(pop_size=particles), termination=("n_gen", iterations), seed=seed, verbose=False)
    return float(res.F[0]), int(res.algorithm.evaluator.n_eval)


def run_mealpy(name):
    def run(fname, particles, iterations, seed):
        from mealpy import CSO, PSO, FloatVar, Termination

        f, b = FUNCTIONS[fname]
        problem = {"obj_func": lambda s: float(f(s)), "bounds": FloatVar(lb=(-b,) * DIM, ub=(b,) * DIM),
                   "minmax": "min", "log_to": None}
        budget = particles * iterations
        if name == "PSO":
            model = PSO.OriginalPSO(epoch=iterations - 1, pop_size=particles)  # initial swarm + T-1 epochs
            term = None
        else:
            model = CSO.OriginalCSO(epoch=100_000, pop_size=particles)  # stopped by max_fe
            term = Termination(max_fe=budget)
        best = model.solve(problem, termination=term, seed=seed)
        return float(best.target.fitness), int(model.nfe_counter)

    return run


# ---- measuring ----------------------------------------------------------------------------------


def measure(run, seeds, budgets, functions):
    """{budget: {function: {"time", "wall", "overhead", "best", "evals"}}}: medians over the seeds.

    "overhead" is "time" minus the CPU time spent inside the objective function (the same
    function code for every library), i.e. what the optimiser itself costs.

    "time" is the CPU time of the run (time.process_time: the code is single-threaded, so on an
    idle machine it equals the wall time, and it stays honest on a busy shared one), "wall" the
    wall-clock time.
    """
    out = {}
    run(next(iter(functions)), *budgets[0], 10**6)  # warm-up: lazy imports, caches
    for particles, iterations in budgets:
        key = f"{particles}x{iterations}"
        out[key] = {}
        for fname in functions:
            times, walls, overheads, bests, evals = [], [], [], [], []
            for seed in seeds:
                _IN_FUNCTION[0] = 0.0
                t0, c0 = time.perf_counter(), time.process_time()
                best, n = run(fname, particles, iterations, seed)
                times.append(time.process_time() - c0)
                walls.append(time.perf_counter() - t0)
                overheads.append(times[-1] - _IN_FUNCTION[0])
                bests.append(best)
                evals.append(n)
            out[key][fname] = {"time": statistics.median(times), "wall": statistics.median(walls),
                               "overhead": statistics.median(overheads),
                               "best": statistics.median(bests), "evals": int(statistics.median(evals))}
    return out


def worker(args) -> None:
    """Inside .venv-mealpy: measure mealpy's PSO and CSO and print JSON."""
    import logging

    logging.disable(logging.CRITICAL)
    seeds = range(args.seeds)
    res = {f"mealpy {n}": measure(run_mealpy(n), seeds, args.budget_list, FUNCTIONS) for n in ("PSO", "CSO")}
    print(json.dumps(res))


def setup_mealpy() -> None:
    subprocess.run([sys.executable, "-m", "venv", str(MEALPY_VENV)], check=True)
    subprocess.run([str(MEALPY_VENV / "bin" / "pip"), "install", "-q", "mealpy"], check=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--quick", action="store_true", help="3 seeds, small budget only")
    ap.add_argument("--setup-mealpy", action="store_true", help="create .venv-mealpy with mealpy and exit")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--budgets", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--json", type=Path, default=None, help="also write the raw numbers here")
    ap.add_argument("--only", default=None,
                    help="comma-separated subset, e.g. spso,apso,pyswarms (peers: pyswarms, pymoo, mealpy)")
    args = ap.parse_args()
    if args.quick:
        args.seeds = 3
    args.budget_list = [tuple(map(int, b.split("x"))) for b in args.budgets.split(",")] if args.budgets else (
        [BUDGETS[0]] if args.quick else BUDGETS)
    if args.setup_mealpy:
        setup_mealpy()
        return
    if args.worker:
        worker(args)
        return

    seeds = range(args.seeds)
    results = {}
    only = set(args.only.split(",")) | {"spso"} if args.only else None  # spso: the speed baseline
    wanted = (lambda name: only is None or name in only)
    ours = [n for n in ["pso", "spso", "apso", "amopso1", "amopso2", "amopso3", "amopso4", "cso"] if wanted(n)]
    for name in ours:
        results[name] = measure(run_ours(name), seeds, args.budget_list, FUNCTIONS)
        print(f"measured {name}", file=sys.stderr)
    for label, run in [("pyswarms GlobalBestPSO", run_pyswarms), ("pymoo PSO", run_pymoo)]:
        if not wanted(label.split()[0]):
            continue
        try:
            results[label] = measure(run, seeds, args.budget_list, FUNCTIONS)
            print(f"measured {label}", file=sys.stderr)
        except ImportError as exc:
            print(f"skipping {label}: {exc}", file=sys.stderr)
    if wanted("mealpy"):
        results.update(measure_mealpy(args))
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    report(results, args.budget_list, args.seeds)


def measure_mealpy(args) -> dict:
    """mealpy's results from a worker process in .venv-mealpy (empty if it is not set up)."""
    py = MEALPY_VENV / "bin" / "python"
    if not py.exists():
        print("skipping mealpy: run `python benchmarks/bench_optim.py --setup-mealpy` first", file=sys.stderr)
        return {}
    budgets = ",".join(f"{p}x{i}" for p, i in args.budget_list)
    proc = subprocess.run([str(py), __file__, "--worker", "--seeds", str(args.seeds), "--budgets", budgets], check=False,
                          capture_output=True, text=True, env={**os.environ, "PYTHONWARNINGS": "ignore"})
    if proc.returncode != 0:
        print(f"mealpy worker failed: {proc.stderr.strip()[-500:]}", file=sys.stderr)
        return {}
    print("measured mealpy", file=sys.stderr)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def report(results, budgets, n_seeds) -> None:
    names = list(results)
    print(f"# {DIM}-D, median over {n_seeds} seeds; time = median CPU time per run (single-threaded)")
    for particles, iterations in budgets:
        key = f"{particles}x{iterations}"
        print(f"\n## {particles} particles x {iterations} iterations ({particles * iterations} evaluations)\n")
        print("| algorithm | " + " | ".join(f"{f} best" for f in FUNCTIONS)
              + " | ms/run | / ours spso | ms/run outside f | / ours spso |")
        print("|---|" + "---|" * (len(FUNCTIONS) + 4))
        base = statistics.mean(results["spso"][key][f]["time"] for f in FUNCTIONS)
        base_o = statistics.mean(results["spso"][key][f]["overhead"] for f in FUNCTIONS)
        for n in names:
            cells = results[n][key]
            t = statistics.mean(cells[f]["time"] for f in FUNCTIONS)
            o = statistics.mean(cells[f]["overhead"] for f in FUNCTIONS)
            bests = " | ".join(f"{cells[f]['best']:.3g}" for f in FUNCTIONS)
            print(f"| {n} | {bests} | {1000 * t:.1f} | {t / base:.2f} | {1000 * o:.1f} | {o / base_o:.2f} |")
        print("\nms/run: CPU time per run, mean over the 4 functions of the median over seeds; "
              "outside f: the same minus the time inside the objective function")
        evals = {n: sorted({results[n][key][f]["evals"] for f in FUNCTIONS}) for n in names}
        print("\nevaluations per run: " + ", ".join(f"{n} {'/'.join(map(str, e))}" for n, e in evals.items()))
        if "pymoo PSO" in results and "amopso1" in results:
            for group in (["amopso1", "amopso2", "amopso3", "amopso4"], ["apso", "amopso1", "amopso2", "amopso3", "amopso4"]):
                print(f"best of {', '.join(group)} vs pymoo PSO: " + _versus(results, key, group, "pymoo PSO"))


def _versus(results, key, group, peer) -> str:
    """Per function: the best median of ``group`` against ``peer``'s, and the tally of ok's."""
    cells, ok_count = [], 0
    for f in FUNCTIONS:
        best = min(group, key=lambda a: results[a][key][f]["best"])
        ok = results[best][key][f]["best"] <= results[peer][key][f]["best"]
        ok_count += ok
        cells.append(f"{f}: {best} {results[best][key][f]['best']:.3g} vs {results[peer][key][f]['best']:.3g} "
                     f"({'ok' if ok else 'worse'})")
    return "; ".join(cells) + f" -> at least as good on {ok_count} of {len(FUNCTIONS)}"


if __name__ == "__main__":
    main()
