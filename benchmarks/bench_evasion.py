"""The walker-evasion value on a large map: time per step and memory of the risk queries when
many robots stand near random walkers spread over the whole map.

Run on demand (not a test):  nice python benchmarks/bench_evasion.py [--size 512] [--robots 1000]
                                 [--walkers 200] [--steps 20] [--cap-mib 1024] [--seed 0]

World: size x size, 20 % of the cells blocked at random; `walkers` 1 x 1 random walkers on free
cells; each robot within 3 cells (Chebyshev) of a walker picked at random, so every robot is
queried every step and the queries cover the whole map. Each step the walkers and the robots
move by a random offset of -1, 0 or 1 cells on each axis (blocked cells are not avoided: only
the cost of the queries is measured, not a run) and the controllers' query
(``EvasionRisk.move_risk``, 8 steps ahead) runs for every robot. Printed: the first step (the tiles computed for the first time), the median and
largest later step, and the memory the tiles hold. ``--cap-mib`` sets the memory cap
(``swarmpath.control.evasion.walker.MAX_BYTES``): below the tiles a step needs, tiles are dropped
and computed again every step.
Target: later steps under 0.1 s at 512 x 512 with 1,000 robots and 200 walkers, under 1 GiB.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from swarmpath.control.evasion import EvasionRisk, walker
from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.pibt.core import static_moves
from swarmpath.world import Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.moving import MovingObstacle, RandomWalk


def measure(size: int, n_robots: int, n_walkers: int, steps: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < 0.2
    free = np.argwhere(~blocked)[:, ::-1]
    starts = free[rng.choice(len(free), n_walkers, replace=False)]
    box = Rect((-0.5, -0.5), (0.5, 0.5))
    moving = tuple(MovingObstacle(f"w{k}", box, tuple(c + 0.5), (1.0, 0.0), RandomWalk())
                   for k, c in enumerate(starts))
    robot = (Robot("r", tuple(free[0] + 0.5), tuple(free[0] + 0.5), 0.0, 1.5),)
    world = World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), moving_obstacles=moving, robots=robot)
    grid = world.grid()
    risk = EvasionRisk(world, grid, static_moves(blocked, 8), ObstacleForecast(world, grid, 0.0), 0.0, 8)
    walkers = starts + 0.5
    cells = np.clip(starts[rng.integers(n_walkers, size=n_robots)] + rng.integers(-3, 4, size=(n_robots, 2)),
                    0, size - 1)
    times = []
    for _ in range(steps):
        t = time.perf_counter()
        risk.move_risk(cells, walkers)
        times.append(time.perf_counter() - t)
        walkers = np.clip(walkers + rng.integers(-1, 2, size=walkers.shape), 0.5, size - 0.5)
        cells = np.clip(cells + rng.integers(-1, 2, size=cells.shape), 0, size - 1)
    table = risk.groups[0][0]
    later = times[1:] or [float("nan")]
    return {"first": times[0], "median": float(np.median(later)), "max": float(np.max(later)),
            "mib": table.bytes_ / 2 ** 20}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--robots", type=int, default=1000)
    ap.add_argument("--walkers", type=int, default=200)
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--cap-mib", type=float, default=walker.MAX_BYTES / 2 ** 20)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    walker.MAX_BYTES = int(args.cap_mib * 2 ** 20)
    r = measure(args.size, args.robots, args.walkers, max(args.steps, 1), args.seed)
    print(f"{args.size} x {args.size}, {args.robots} robots near {args.walkers} walkers, cap {args.cap_mib:.0f} MiB: "
          f"first step {r['first']:.2f} s, later steps median {r['median']:.3f} s (max {r['max']:.3f} s), "
          f"tiles held {r['mib']:.0f} MiB")


if __name__ == "__main__":
    main()
