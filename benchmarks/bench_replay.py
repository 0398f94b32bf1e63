"""HTML replay at scale: 1000 robots x 300 steps in headless Chromium.

Run on demand (not a test):  python benchmarks/bench_replay.py [--robots 1000] [--steps 300]

Two trajectories of the same size:
1. "run": a real simulation: ``--robots`` point robots with A* plans and plain path following
   on a 150 x 150 world with two static obstacles and a moving obstacle (speed 0.5, so most
   robots travel for most of the ``--steps`` steps);
2. "worst case": synthetic, every robot moves every step (nothing compresses by standing still).

For each: the file size, the time to write it (Python), the time from opening the file to the
first frame (Chromium, parse + inflate + decode), the render time of one frame (mean, median,
p95 over 200 frames along the run, trails on), and the frame rate while playing (requestAnimationFrame
for 3 s, playback at 4x). Also the frame time with the sensing ranges drawn and with trails off.
Needs Debian's chromium on PATH and Python Playwright (pip install ".[test]").
"""
from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from swarmpath.sim.collisions import Contact
from swarmpath.sim.trajectory import TRUNCATED, Trajectory
from swarmpath.viz.html_replay import write_replay_html

CHROMIUM_ARGS = ["--no-sandbox", "--headless", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]


def real_run(n_robots: int, n_steps: int, seed: int = 0) -> Trajectory:
    """A* + follow on a 150 x 150 world (robots at distinct cell centres)."""
    from swarmpath.runner import run_world
    from swarmpath.world import world_from_dict

    size = 150
    rng = np.random.default_rng(seed)
    cells = np.arange(size * size)
    xy = np.stack([cells % size, cells // size], axis=1) + 0.5
    free = ~(((xy[:, 0] > 19) & (xy[:, 0] < 31) & (xy[:, 1] > 19) & (xy[:, 1] < 51))
             | (np.hypot(xy[:, 0] - 60, xy[:, 1] - 60) < 11.5))
    xy = xy[free][rng.choice(int(free.sum()), 2 * n_robots, replace=False)]
    doc = {"schema_version": 1, "name": f"bench-{n_robots}", "resolution": 1.0, "dt": 1.0,
           "bounds": {"type": "rectangle", "width": size, "height": size},
           "obstacles": [{"type": "circle", "center": [60, 60], "radius": 10},
                         {"type": "rectangle", "min": [20, 20], "max": [30, 50]}],
           "moving_obstacles": [{"shape": {"type": "circle", "radius": 2}, "start": [10, 100],
                                 "velocity": [1, 0.5], "motion": "bounce"}],
           "robots": [{"id": f"r{i}", "start": xy[i].tolist(), "goal": xy[n_robots + i].tolist(), "max_speed": 0.5}
                      for i in range(n_robots)]}
    result = run_world(world_from_dict(doc), planner="astar", controller="follow", seed=seed, max_steps=n_steps,
                       clearance=False)
    return result.trajectory


def worst_case(n_robots: int, n_steps: int, seed: int = 0) -> Trajectory:
    """Every robot moves every step (wavy lines from start to goal)."""
    size = 150.0
    rng = np.random.default_rng(seed)
    starts, goals = rng.uniform(1, size - 1, (2, n_robots, 2))
    t = np.arange(n_steps + 1)[:, None, None] / n_steps
    wave = rng.uniform(0.5, 3, (1, n_robots, 1)) * np.sin(40 * t + rng.uniform(0, 6.3, (1, n_robots, 1)))
    pos = np.clip(starts + (goals - starts) * t + wave * np.array([1.0, -1.0]) * 4 * t * (1 - t), 0.5, size - 0.5)
    obs = np.stack([10 + 0.4 * np.arange(n_steps + 1), np.full(n_steps + 1, 75.0)], axis=1)[:, None, :]
    world = {"schema_version": 1, "name": "worst-case", "resolution": 1.0, "dt": 1.0,
             "bounds": {"type": "rectangle", "width": size, "height": size},
             "moving_obstacles": [{"id": "m1", "shape": {"type": "circle", "radius": 2}, "start": obs[0, 0].tolist(),
                                   "velocity": [0.4, 0], "motion": "bounce"}],
             "robots": [{"id": f"r{i}", "start": starts[i].tolist(), "goal": goals[i].tolist()} for i in range(n_robots)]}
    modes = rng.integers(0, 3, (n_steps, n_robots)).astype(np.int8)
    return Trajectory(scenario="worst-case", seed=seed, dt=1.0, resolution=1.0, robot_ids=[f"r{i}" for i in range(n_robots)],
                      radii=np.zeros(n_robots), goals=goals, positions=pos, obstacle_ids=["m1"], obstacle_positions=obs,
                      contacts=[Contact(10, "robot_robot", 0, 1, "")], modes=modes, mode_names=["seek", "trace", "wait"],
                      planned_paths=[np.stack([s, g]) for s, g in zip(starts, goals)], status=TRUNCATED, world=world,
                      meta={"planner": "straight", "controller": "synthetic"})


def measure(browser, path: Path) -> dict:
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    t0 = time.perf_counter()
    page.goto(path.resolve().as_uri())
    page.wait_for_function("window.replay && (window.replay.ready || window.replay.error)", timeout=120_000)
    load_s = time.perf_counter() - t0
    if page.evaluate("window.replay.error || null"):
        raise RuntimeError(page.evaluate("window.replay.error"))
    out = {"load_s": load_s, "frame": page.evaluate("window.replay.benchmark(200)")}
    page.click("#opt-sensing")
    out["frame_sensing"] = page.evaluate("window.replay.benchmark(100)")
    page.click("#opt-sensing")
    page.click("#opt-trails")
    out["frame_no_trails"] = page.evaluate("window.replay.benchmark(100)")
    page.click("#opt-trails")
    page.select_option("#speed", "4")
    before = page.evaluate("window.replay.stats.frames")
    page.click("#play")
    t1 = time.perf_counter()
    page.wait_for_timeout(3000)
    frames = page.evaluate("window.replay.stats.frames") - before
    out["fps"] = frames / (time.perf_counter() - t1)
    out["step_after_3s"] = page.evaluate("window.replay.step")
    page.close()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=300)
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    exe = shutil.which("chromium")
    if exe is None:
        raise SystemExit("chromium not on PATH (apt-get install -y chromium)")
    tmp = Path(tempfile.mkdtemp(prefix="bench-replay-"))
    rows = []
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)
        for name, make in (("run", real_run), ("worst case", worst_case)):
            t0 = time.perf_counter()
            traj = make(args.robots, args.steps)
            build_s = time.perf_counter() - t0
            t0 = time.perf_counter()
            path = write_replay_html(traj, tmp / f"{name.replace(' ', '-')}.html")
            write_s = time.perf_counter() - t0
            m = measure(browser, path)
            rows.append((name, traj, path.stat().st_size, build_s, write_s, m))
        browser.close()
    print(f"HTML replay, {args.robots} robots x {args.steps} steps, Chromium {exe}")
    for name, traj, size, build_s, write_s, m in rows:
        f, fs, fn = m["frame"], m["frame_sensing"], m["frame_no_trails"]
        raw = traj.positions.astype(np.float32).nbytes
        print(f"\n[{name}] {traj.n_robots} robots, {traj.n_steps} steps "
              f"(trajectory built in {build_s:.2f} s)")
        print(f"  file size           {size / 1e6:8.2f} MB  ({size / raw:.2f} x the raw float32 positions, "
              f"{raw / 1e6:.2f} MB)")
        print(f"  write (Python)      {write_s:8.2f} s")
        print(f"  load to first frame {m['load_s']:8.2f} s")
        print(f"  frame, trails       {f['mean']:8.2f} ms mean, {f['median']:.2f} median, {f['p95']:.2f} p95, "
              f"{f['max']:.2f} max")
        print(f"  frame, + sensing    {fs['mean']:8.2f} ms mean, {fs['p95']:.2f} p95")
        print(f"  frame, no trails    {fn['mean']:8.2f} ms mean, {fn['p95']:.2f} p95")
        print(f"  playing (4x)        {m['fps']:8.1f} frames/s, reached step {m['step_after_3s']:.0f} in 3 s")


if __name__ == "__main__":
    main()
