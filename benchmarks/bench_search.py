"""Grid search speed: swarmpath's A* and distance field next to the tools people use.

Run on demand (not a test):  python benchmarks/bench_search.py [--queries 20]

Peers (install with `pip install ".[bench]"`):
- pyastar2d (C++ A*; charges 1 per diagonal and cuts corners, so compare time, not cost),
- pathfinding (pure Python; octile, diagonal only when no obstacle: the same semantics as ours),
- scipy.sparse.csgraph.dijkstra (a full distance field, plus building the graph).
Maps: 1024x1024 with 20% random obstacles, and a 1024x1024 room map (16x16 rooms, doors).
Targets (issue 2): A* <= 2x pyastar2d time, >= 20x faster than pathfinding; distance field within
1.5x of scipy (graph build included); `swarmpath path` cold command on a 1024^2 map < 2 s;
`import swarmpath` < 0.5 s.
"""
from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from swarmpath.search import astar, distance_field
from swarmpath.world import write_map


def random_map(size: int, density: float, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((size, size)) < density


def room_map(size: int, room: int, seed: int) -> np.ndarray:
    """Rooms of ``room`` cells separated by one-cell walls, each wall with a random door of 2."""
    rng = np.random.default_rng(seed)
    blocked = np.zeros((size, size), dtype=bool)
    blocked[::room, :] = True
    blocked[:, ::room] = True
    for y0 in range(0, size, room):
        for x0 in range(0, size, room):
            d = rng.integers(1, room - 2)
            if x0 + room < size:
                blocked[y0 + d:y0 + d + 2, x0 + room] = False
            if y0 + room < size:
                blocked[y0 + room, x0 + d:x0 + d + 2] = False
    return blocked


def csgraph_field(blocked: np.ndarray, goal: tuple[int, int]) -> tuple[np.ndarray, float, float]:
    """scipy's Dijkstra on the same move graph (no corner cutting); returns field, build s, solve s."""
    t0 = time.perf_counter()
    h, w = blocked.shape
    free = ~blocked
    idx = np.arange(h * w).reshape(h, w)
    rows, cols, vals = [], [], []
    for dx, dy in [(1, 0), (0, 1), (1, 1), (1, -1)]:
        ys, xs = np.nonzero(free)
        nx, ny = xs + dx, ys + dy
        ok = (nx < w) & (ny >= 0) & (ny < h)
        xs, ys, nx, ny = xs[ok], ys[ok], nx[ok], ny[ok]
        ok = free[ny, nx]
        if dx and dy:
            ok &= free[ys, nx] & free[ny, xs]
        a, b = idx[ys[ok], xs[ok]], idx[ny[ok], nx[ok]]
        cost = math.sqrt(2) if dx and dy else 1.0
        rows += [a, b]
        cols += [b, a]
        vals += [np.full(len(a), cost)] * 2
    graph = csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(h * w, h * w))
    t1 = time.perf_counter()
    field = dijkstra(graph, indices=goal[1] * w + goal[0]).reshape(h, w)
    return field, t1 - t0, time.perf_counter() - t1


def pick_queries(blocked: np.ndarray, n: int, seed: int) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    rng = np.random.default_rng(seed)
    free = np.argwhere(~blocked)
    anchor = tuple(free[rng.integers(len(free))][::-1])
    reach = np.isfinite(distance_field(blocked, anchor))
    cells = np.argwhere(reach)
    out = []
    while len(out) < n:
        a, b = cells[rng.integers(len(cells), size=2)]
        out.append((tuple(int(v) for v in a[::-1]), tuple(int(v) for v in b[::-1])))
    return out


def time_ours(blocked, queries):
    times, costs = [], []
    for s, g in queries:
        t = time.perf_counter()
        r = astar(blocked, s, g)
        times.append(time.perf_counter() - t)
        costs.append(r.cost)
    return times, costs


def time_pyastar2d(blocked, queries):
    import pyastar2d

    weights = np.where(blocked, np.inf, 1.0).astype(np.float32)
    times = []
    for s, g in queries:
        t = time.perf_counter()
        pyastar2d.astar_path(weights, (s[1], s[0]), (g[1], g[0]), allow_diagonal=True)
        times.append(time.perf_counter() - t)
    return times


def time_pathfinding(blocked, queries):
    from pathfinding.core.diagonal_movement import DiagonalMovement
    from pathfinding.core.grid import Grid
    from pathfinding.finder.a_star import AStarFinder

    matrix = (~blocked).astype(int).tolist()
    builds, times = [], []
    for s, g in queries:
        t = time.perf_counter()
        grid = Grid(matrix=matrix)
        t1 = time.perf_counter()
        finder = AStarFinder(diagonal_movement=DiagonalMovement.only_when_no_obstacle)
        finder.find_path(grid.node(*s), grid.node(*g), grid)
        times.append(time.perf_counter() - t1)
        builds.append(t1 - t)
    return builds, times


def cold_command_seconds(blocked: np.ndarray, query) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.map"
        write_map(path, blocked)
        (s, g) = query
        best = math.inf
        for _ in range(3):
            t = time.perf_counter()
            subprocess.run(["swarmpath", "path", "--map", str(path), "--start", str(s[0]), str(s[1]), "--goal",
                            str(g[0]), str(g[1]), "--json"], check=True, capture_output=True)
            best = min(best, time.perf_counter() - t)
    return best


def import_seconds() -> float:
    best = math.inf
    for _ in range(5):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import swarmpath"], check=True)
        total = time.perf_counter() - t
        t = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], check=True)
        best = min(best, total - (time.perf_counter() - t))
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=20)
    ap.add_argument("--pathfinding-queries", type=int, default=3)
    args = ap.parse_args()
    maps = {"random 1024^2 20%": random_map(1024, 0.2, 1), "rooms 1024^2 (16x16)": room_map(1024, 16, 2)}
    for name, blocked in maps.items():
        queries = pick_queries(blocked, args.queries, 3)
        ours, costs = time_ours(blocked, queries)
        ours = time_ours(blocked, queries)[0]  # warm
        line = [f"\n== {name}: {args.queries} random reachable queries"]
        ours_mean = statistics.mean(ours)
        line.append(f"swarmpath A*          mean {ours_mean * 1e3:8.2f} ms   median {statistics.median(ours) * 1e3:8.2f} ms")
        try:
            py = time_pyastar2d(blocked, queries)
            line.append(f"pyastar2d (C++)       mean {statistics.mean(py) * 1e3:8.2f} ms   "
                        f"ratio ours/pyastar2d {ours_mean / statistics.mean(py):.2f} (target <= 2)")
        except ImportError:
            line.append("pyastar2d not installed (pip install '.[bench]')")
        try:
            k = args.pathfinding_queries
            builds, pf = time_pathfinding(blocked, queries[:k])
            line.append(f"pathfinding (Python)  mean {statistics.mean(pf):8.3f} s + grid build {statistics.mean(builds):.3f} s"
                        f"   ratio pathfinding/ours {statistics.mean(pf) / statistics.mean(ours[:k]):.0f}x (target >= 20x)")
        except ImportError:
            line.append("pathfinding not installed (pip install '.[bench]')")
        goal = queries[0][1]
        t = time.perf_counter()
        field = distance_field(blocked, goal)
        ours_field = time.perf_counter() - t
        ref, build, solve = csgraph_field(blocked, goal)
        same = np.allclose(np.where(np.isfinite(ref), ref, -1), np.where(np.isfinite(field), field, -1))
        line.append(f"distance field        ours {ours_field:.3f} s; scipy csgraph {solve:.3f} s + build {build:.3f} s"
                    f" = {solve + build:.3f} s; ratio ours/scipy {ours_field / (solve + build):.2f} (target <= 1.5);"
                    f" identical values: {same}")
        line.append(f"cold `swarmpath path` on this map: {cold_command_seconds(blocked, queries[0]):.2f} s (target < 2 s)")
        print("\n".join(line))
    print(f"\n`import swarmpath`: {import_seconds() * 1e3:.0f} ms beyond bare Python startup (target < 500 ms)")


if __name__ == "__main__":
    main()
