"""Scale: thousands of robots with the ``pibt`` controller through the real simulator.

Run on demand (not a test):  nice python benchmarks/bench_scale.py [--robots 1000 10000] [--size 512]
[--rescue-after 0]

Test: a size x size map with 20% of the cells blocked at random (seed 0); starts and goals
are distinct random cells of the largest 4-connected free component (no corner cutting, so
every goal is reachable). Point robots, max speed sqrt 2 cells per step (8-connected moves).
The run is ``swarmpath.runner.run_world(world, planner="none", controller="pibt")``: the
simulator senses, asks the controller, validates and checks every move (its own checker) and
records the trajectory. Any search of the controller's stall rescue (LaCAM from where the robots
stand, ``control/pibt/rescue.py``) is printed with the step it started on.

Printed per robot count: the time to build the World (its robot validation is O(n^2)), the
controller's reset, the whole run (reset included), where the run's time goes (controller's
act vs the rest of the simulator), steps, robots arrived, contacts, the lazy distance tables'
cells expanded and memory, and the peak resident memory while building and while running
(sampled from /proc/self/status every 50 ms). On a shared machine the run's CPU time is the
steadier figure.
Targets: 10,000 robots all arrive, whole run under 120 s, peak memory under 4 GB; 1,000
robots: reset under 1 s.
"""
from __future__ import annotations

import argparse
import threading
import time

import numpy as np
from scipy import ndimage

from swarmpath.control.pibt import PIBTController
from swarmpath.sim.simulator import Simulator
from swarmpath.world import RectBounds, Robot, World
from swarmpath.world.static_map import StaticMap


class PeakRSS:
    """Peak resident memory (bytes) of this process while the block runs."""

    def __enter__(self):
        self.peak = self._rss()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._watch, daemon=True)
        self._thread.start()
        return self

    def _rss(self) -> int:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
        return 0

    def _watch(self) -> None:
        while not self._stop.wait(0.05):
            self.peak = max(self.peak, self._rss())

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, self._rss())


def make_map(size: int, density: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(blocked (size, size), free cells of the largest 4-connected component (k, 2) as x, y)."""
    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < density
    labels, _ = ndimage.label(~blocked)
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    ys, xs = np.nonzero(labels == sizes.argmax())
    return blocked, np.stack([xs, ys], axis=1)


def make_world(blocked: np.ndarray, cells: np.ndarray, n: int, seed: int) -> World:
    rng = np.random.default_rng(seed)
    starts = cells[rng.choice(len(cells), n, replace=False)] + 0.5
    goals = cells[rng.choice(len(cells), n, replace=False)] + 0.5
    robots = tuple(Robot(f"r{i}", tuple(s), tuple(g), 0.0, float(np.sqrt(2)))
                   for i, (s, g) in enumerate(zip(starts.tolist(), goals.tolist())))
    h, w = blocked.shape
    return World(RectBounds(w, h), static_map=StaticMap(blocked), robots=robots, name=f"random-{w}-{n}")


def run(n: int, size: int, density: float, rescue_after: int | None = None) -> None:
    blocked, cells = make_map(size, density, 0)
    with PeakRSS() as build_mem:
        t = time.perf_counter()
        world = make_world(blocked, cells, n, 1)
        build = time.perf_counter() - t
    controller = PIBTController() if rescue_after is None else PIBTController(rescue_after=rescue_after)
    with PeakRSS() as run_mem:
        t, cpu = time.perf_counter(), time.process_time()
        traj = Simulator(world, controller, None, seed=0).run()
        total, cpu = time.perf_counter() - t, time.process_time() - cpu
    arrived = int(np.sum(np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9))
    meta = traj.meta
    tables = controller.tables_
    print(f"{n:>6} robots on {size}x{size}: world built in {build:.2f} s (peak RSS {build_mem.peak / 2**30:.2f} GiB)")
    print(f"       reset {meta['controller_reset_s']:.3f} s; whole run {total:.1f} s = controller "
          f"{meta['controller_time_s']:.1f} s + simulator {total - meta['controller_time_s']:.1f} s "
          f"(CPU time of the run {cpu:.1f} s); "
          f"{len(traj.positions) - 1} steps, status {traj.status.value}")
    print(f"       arrived {arrived}/{n}; contacts {len(traj.contacts)}; pushes {int(controller.pushes_.sum())}; "
          f"tables live at the end {tables.live}, memory {tables.memory_bytes() / 2**20:.1f} MiB; "
          f"peak RSS during the run {run_mem.peak / 2**30:.2f} GiB")
    for e in traj.events:
        if e["kind"].startswith("rescue"):
            print(f"       step {e['step']}: {e['kind']}: {e['detail']}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[1000, 10000])
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--density", type=float, default=0.2)
    ap.add_argument("--rescue-after", type=int, default=None,
                    help="the controller's rescue_after (default: its own; 0: no LaCAM rescue)")
    args = ap.parse_args()
    for n in args.robots:
        run(n, args.size, args.density, args.rescue_after)


if __name__ == "__main__":
    main()
