"""MAPF: swarmpath's lacam planner and pibt controller beside pymapf's LaCAM and PIBT.

Run on demand (not a test):  nice python benchmarks/bench_mapf.py [--agents 100 200 300 400]
Peer install: pip install pymapf (the ``[bench]`` extra).

Instances: random-32-32-10 (src/swarmpath/data/movingai/random-32-32-10-random-1.scen, 461 rows) and
room-32-32-4 (src/swarmpath/data/movingai/room-32-32-4-even-10.scen has 130 rows; beyond that, distinct random
starts and goals in the map's free component, seed 0, flagged "rand"). Both solvers get the
same start/goal cells. pymapf's grid is 4-connected with unit costs when
``allow_diagonals=False`` (cells are (row, column)); its sum of costs counts, per agent, the
steps until it last arrives (waits included), the makespan the longest such count. We run
ours 4-connected to compare like with like, and 8-connected (octile moves without corner
cutting) beside it.

Printed per instance: success; sum of costs (SOC); SOC / lower bound, the lower bound being
the sum of the agents' shortest path lengths in steps (BFS on the same graph); makespan;
wall time. Then the ratios ours / pymapf for LaCAM: SOC and wall time. PIBT runs: pymapf's
PIBT solver; ours is the ``pibt`` controller through swarmpath's simulator (its controller
time is the PIBT time; the simulator's checking and recording come on top and are shown).
Targets: success wherever pymapf succeeds, SOC within 1.1x of pymapf's LaCAM, wall time at
most 1/10 of it. Both LaCAMs run ``--repeats`` times (3) with the same seed and the least wall
time counts: ours takes 15-80 ms on these instances, where one pause of a shared machine
would otherwise decide the ratio.

``--sweep`` instead runs the acceptance sweep on every MovingAI scen in src/swarmpath/data/movingai: agent
counts from 25 to 400 (or the file's maximum) in steps of 25, ``lacam`` (8-connected, 10 s)
and the grid controllers named by ``--controllers`` (default ``pibt cat-swarm``) through the
simulator without a plan (success = every robot at its goal at the end with zero contacts),
for ``--seeds`` seeds; per map the slowest plan, each controller's failures, the median
and worst wall time of a controller's run, and in how many runs the controller's stall rescue
(LaCAM from where the robots stand, ``control/pibt/rescue.py``) took over. ``--scen-dir
DIR`` sweeps the scens in DIR instead (each with its map beside it), e.g. MovingAI maps not
shipped here.

``--ladder`` runs the rungs of the cat swarm's ablation ladder that use the core
(``swarmpath.bench.jaleel2016.ladder_rungs``, rung 2 on) on crowded MovingAI instances without
moving obstacles, where the core's guarantees matter (the paper's scenario is too sparse to
tell them apart): per rung, successes (every robot at its goal at the end, zero contacts) and
the median number of steps.
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import shortest_path

from swarmpath.control.pibt import PIBTController
from swarmpath.control.pibt.core import static_moves
from swarmpath.data.movingai import MOVINGAI
from swarmpath.planning.lacam import LaCAMPlanner
from swarmpath.sim.simulator import Simulator
from swarmpath.world import RectBounds, Robot, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.movingai import read_map, read_scen
from swarmpath.world.static_map import StaticMap

DATA = MOVINGAI
INSTANCES = [("random-32-32-10", "random-32-32-10-random-1"), ("room-32-32-4", "room-32-32-4-even-10")]


def instance(name: str, scen: str, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """(blocked, starts (n, 2) x/y cells, goals, source) from the scen file, or random."""
    m = read_map(DATA / f"{name}.map")
    rows = read_scen(DATA / f"{scen}.scen", m)
    if n <= len(rows):
        rows = rows[:n]
        return m.blocked, np.array([e.start for e in rows]), np.array([e.goal for e in rows]), "scen"
    labels, _ = ndimage.label(~m.blocked)
    comp = np.argwhere(labels == np.bincount(labels.ravel())[1:].argmax() + 1)[:, ::-1]
    rng = np.random.default_rng(0)
    return (m.blocked, comp[rng.choice(len(comp), n, replace=False)], comp[rng.choice(len(comp), n, replace=False)],
            "rand")


def step_lower_bound(blocked: np.ndarray, starts: np.ndarray, goals: np.ndarray, connectivity: int) -> int:
    """Sum of shortest path lengths in steps (unit-cost BFS, no corner cutting)."""
    h, w = blocked.shape
    moves = static_moves(blocked, connectivity)
    ys, xs, a = np.nonzero(moves[:, :, 1:])
    d = GRID_MOVES[1:][a]
    src = ys * w + xs
    dst = (ys + d[:, 1]) * w + xs + d[:, 0]
    graph = coo_matrix((np.ones(len(src)), (src, dst)), shape=(h * w, h * w)).tocsr()
    dist = shortest_path(graph, unweighted=True, indices=goals[:, 1] * w + goals[:, 0])
    return int(dist[np.arange(len(goals)), starts[:, 1] * w + starts[:, 0]].sum())


def soc_makespan(cells: np.ndarray, goals: np.ndarray) -> tuple[int, int]:
    """cells (T + 1, n, 2): per agent the step after which it stays on its goal."""
    at = np.all(cells == goals[None], axis=2)
    last_off = np.where(~at.all(axis=0), cells.shape[0] - 1, 0)
    for i in range(cells.shape[1]):
        off = np.flatnonzero(~at[:, i])
        last_off[i] = off[-1] + 1 if len(off) else 0
    return int(last_off.sum()), int(last_off.max(initial=0))


def world_of(blocked, starts, goals) -> World:
    h, w = blocked.shape
    robots = tuple(Robot(f"a{i}", (s[0] + 0.5, s[1] + 0.5), (g[0] + 0.5, g[1] + 0.5), 0.0, float(np.sqrt(2)))
                   for i, (s, g) in enumerate(zip(starts.tolist(), goals.tolist())))
    return World(RectBounds(w, h), static_map=StaticMap(blocked), robots=robots)


def run_pymapf(kind: str, blocked, starts, goals, time_limit: float):
    from pymapf.algorithms.lacam import LaCAM
    from pymapf.algorithms.pibt import PIBT
    from pymapf.core.grid import GridMap
    from pymapf.core.solver import Agent, MAPFProblem

    agents = [Agent(f"a{i}", (int(s[1]), int(s[0])), (int(g[1]), int(g[0]))) for i, (s, g) in enumerate(zip(starts, goals))]
    problem = MAPFProblem(GridMap(blocked.astype(int).tolist()), agents, allow_diagonals=False)
    solver = LaCAM(time_limit=time_limit, seed=0) if kind == "lacam" else PIBT(seed=0, time_limit=time_limit)
    t = time.perf_counter()
    sol = solver.solve(problem)
    wall = time.perf_counter() - t
    if sol is None:
        return None, wall
    if sol.first_conflict() is not None:
        return "conflict", wall
    return (sol.sum_of_costs, sol.makespan), wall


def best_of(repeats: int, run, *args):
    """``run(*args)`` ``repeats`` times (a seeded solver gives the same result each time): its
    result and the least wall time."""
    results = [run(*args) for _ in range(max(1, repeats))]
    return results[0][0], min(wall for _, wall in results)


def run_ours_lacam(world, goals, connectivity: int, time_limit: float):
    t = time.perf_counter()
    plan = LaCAMPlanner(connectivity=connectivity, time_limit=time_limit).plan(world, rng=0)
    wall = time.perf_counter() - t
    if not plan:
        return None, wall
    cells = np.floor(np.stack([r.path for r in plan.robots], axis=1)).astype(int)
    return soc_makespan(cells, goals), wall


def run_ours_pibt(world, goals, connectivity: int):
    ctl = PIBTController(connectivity=connectivity)
    t = time.perf_counter()
    traj = Simulator(world, ctl, seed=0).run()
    wall = time.perf_counter() - t
    if traj.status.value != "all_reached" or traj.contacts:
        return None, traj.meta["controller_time_s"], wall
    cells = np.floor(traj.positions).astype(int)
    return soc_makespan(cells, goals), traj.meta["controller_time_s"], wall


def fmt(result, lb) -> str:
    if result is None:
        return "fail".ljust(28)
    if result == "conflict":
        return "INVALID (conflict)".ljust(28)
    soc, mk = result
    return f"SOC {soc:>6} ({soc / lb:5.3f}x) mk {mk:>4}"


SWEEP = [("random-32-32-10", "random-32-32-10-random-1"), ("room-32-32-4", "room-32-32-4-even-10"),
         ("maze-32-32-2", "maze-32-32-2-even-10"), ("den312d", "den312d-even-10"), ("empty-8-8", "empty-8-8-even-10")]


def scens_in(folder: Path) -> list[tuple[str, str]]:
    """(map, scen) names of every MovingAI scen in ``folder`` whose map (named in its first
    row) lies beside it, sorted."""
    out = []
    for path in sorted(folder.glob("*.scen")):
        lines = path.read_text().splitlines()
        fields = lines[1].split("\t") if len(lines) > 1 else []
        name = Path(fields[1]).stem if len(fields) > 1 else ""
        if name and (folder / f"{name}.map").exists():
            out.append((name, path.stem))
    return out


def sweep(seeds: int, controllers: list[str], folder: Path | None = None) -> None:
    from swarmpath.registry import CONTROLLERS
    from swarmpath.world import world_from_movingai

    data = folder if folder is not None else DATA
    for name, scen in (scens_in(folder) if folder is not None else SWEEP):
        rows = len(read_scen(data / f"{scen}.scen", read_map(data / f"{name}.map")))
        counts = list(range(25, min(400, rows) + 1, 25)) or [rows]
        if name == "empty-8-8":
            counts = [8, 16, 24, 32]
        fails: list[str] = []
        worst_lacam = 0.0
        walls: dict[str, list[float]] = {c: [] for c in controllers}
        runs = 0
        rescued: dict[str, int] = {c: 0 for c in controllers}
        for n in counts:
            world = world_from_movingai(data / f"{name}.map", data / f"{scen}.scen", n)
            for seed in range(seeds):
                t = time.perf_counter()
                plan = LaCAMPlanner(time_limit=10.0).plan(world, rng=seed)
                worst_lacam = max(worst_lacam, time.perf_counter() - t)
                if not plan:
                    fails.append(f"n={n} seed={seed}: lacam FAIL")
                runs += 1
                for c in controllers:
                    t = time.perf_counter()
                    traj = Simulator(world, CONTROLLERS.get(c)(), seed=seed).run()
                    walls[c].append(time.perf_counter() - t)
                    rescued[c] += any(e["kind"] == "rescue" for e in traj.events)
                    if traj.status.value != "all_reached" or traj.contacts:
                        at = np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9
                        fails.append(f"n={n} seed={seed}: {c} FAIL ({traj.status.value}, {int(at.sum())}/{n} at "
                                     f"goal, {len(traj.contacts)} contacts)")
        times = "; ".join(f"{c} run median {np.median(w):.2f} s, worst {max(w):.2f} s, LaCAM rescue in "
                          f"{rescued[c]} runs" for c, w in walls.items())
        print(f"{scen}: counts {counts[0]}..{counts[-1]}, {seeds} seeds ({runs} instances): slowest lacam "
              f"{worst_lacam:.3f} s; {times}; " + ("every instance solved by all" if not fails else "; ".join(fails)),
              flush=True)


LADDER = [("random-32-32-10", "random-32-32-10-random-1", 300), ("room-32-32-4", "room-32-32-4-even-10", 125),
          ("maze-32-32-2", "maze-32-32-2-even-10", 150), ("den312d", "den312d-even-10", 200)]


def ladder(seeds: int) -> None:
    from swarmpath.bench.jaleel2016 import ladder_rungs
    from swarmpath.world import world_from_movingai

    rungs = ladder_rungs()
    worlds = [(f"{name} {n}", world_from_movingai(DATA / f"{name}.map", DATA / f"{scen}.scen", n))
              for name, scen, n in LADDER]
    print("rung | addition | " + " | ".join(label for label, _ in worlds))
    for k, rung in enumerate(rungs[2:], start=2):
        cells = []
        for _, world in worlds:
            ok, steps = 0, []
            for seed in range(seeds):
                traj = Simulator(world, rung.controller(), seed=seed).run()
                ok += traj.status.value == "all_reached" and not traj.contacts
                steps.append(traj.n_steps)
            cells.append(f"{ok}/{seeds}, {int(np.median(steps))} steps")
        print(f"{k} | {rung.addition.split(' (')[0]} | " + " | ".join(cells), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--agents", type=int, nargs="+", default=[100, 200, 300, 400])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--repeats", type=int, default=3, help="runs of each LaCAM; the least wall time counts")
    ap.add_argument("--sweep", action="store_true")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--controllers", nargs="+", default=["pibt", "cat-swarm"])
    ap.add_argument("--ladder", action="store_true")
    ap.add_argument("--scen-dir", type=Path, default=None,
                    help="with --sweep: every MovingAI scen in this folder whose map lies beside it "
                         "(default: the scens shipped in src/swarmpath/data/movingai)")
    args = ap.parse_args()
    if args.ladder:
        ladder(args.seeds)
        return
    if args.sweep:
        sweep(args.seeds, args.controllers, args.scen_dir)
        return
    lacam_soc, lacam_time = [], []
    for name, scen in INSTANCES:
        for n in args.agents:
            blocked, starts, goals, source = instance(name, scen, n)
            world = world_of(blocked, starts, goals)
            lb4 = step_lower_bound(blocked, starts, goals, 4)
            lb8 = step_lower_bound(blocked, starts, goals, 8)
            print(f"\n{name} ({source}) {n} agents; lower bound {lb4} steps (4-conn), {lb8} (8-conn)")
            py_l, py_lt = best_of(args.repeats, run_pymapf, "lacam", blocked, starts, goals, args.time_limit)
            ours4, o4t = best_of(args.repeats, run_ours_lacam, world, goals, 4, args.time_limit)
            ours8, o8t = best_of(args.repeats, run_ours_lacam, world, goals, 8, args.time_limit)
            py_p, py_pt = run_pymapf("pibt", blocked, starts, goals, args.time_limit)
            pibt4, p4c, p4w = run_ours_pibt(world, goals, 4)
            pibt8, p8c, p8w = run_ours_pibt(world, goals, 8)
            print(f"  LaCAM  pymapf      {fmt(py_l, lb4)}  {py_lt:8.3f} s")
            print(f"  LaCAM  ours 4-conn {fmt(ours4, lb4)}  {o4t:8.3f} s")
            print(f"  LaCAM  ours 8-conn {fmt(ours8, lb8)}  {o8t:8.3f} s")
            print(f"  PIBT   pymapf      {fmt(py_p, lb4)}  {py_pt:8.3f} s")
            print(f"  PIBT   ours 4-conn {fmt(pibt4, lb4)}  {p4c:8.3f} s controller ({p4w:.2f} s with the simulator)")
            print(f"  PIBT   ours 8-conn {fmt(pibt8, lb8)}  {p8c:8.3f} s controller ({p8w:.2f} s with the simulator)")
            if isinstance(py_l, tuple) and isinstance(ours4, tuple):
                lacam_soc.append(ours4[0] / py_l[0])
                lacam_time.append(o4t / py_lt)
                print(f"  ours/pymapf LaCAM (4-conn): SOC {lacam_soc[-1]:.3f}x, wall time {lacam_time[-1]:.4f}x")
            elif isinstance(py_l, tuple):
                print("  ours/pymapf LaCAM: ours FAILED where pymapf succeeded")
    if lacam_soc:
        print(f"\nLaCAM ours/pymapf over {len(lacam_soc)} instances: SOC max {max(lacam_soc):.3f}x "
              f"(mean {np.mean(lacam_soc):.3f}x); wall time max {max(lacam_time):.4f}x (mean {np.mean(lacam_time):.4f}x)")


if __name__ == "__main__":
    main()
