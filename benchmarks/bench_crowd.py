"""CrowdNav-style crossings with ``orca`` and ``pso-predictive``: success rate, contact rate and
time to goal over many seeded episodes.

Run on demand (not a test):  nice python benchmarks/bench_crowd.py [--episodes 500] [--controllers orca]

Episode (swarmpath.world.generators.crowd_crossing): a walled 12 x 12 room, dt 0.5; one
robot (radius 0.3, max speed 1) crosses from (1, 6) to (11, 6) among 5, 10 or 20 discs of
radius 0.3 that ignore it: "bounce" (constant velocity 0.5, bouncing off the walls),
"random-walk" (a new one of 8 directions every step, at most 0.5) or "mixed" (half each).
Obstacles are slower than the robot, so no single one can catch it; several can still corner
it against a wall.

Success: the robot stands on its goal within 200 steps (100 time units). Contact rate: share
of episodes with any contact (swarmpath's checker). "Cornered": episodes in which the robot at
some step had no move clear of the obstacles' next moves (the controller's ``exposed``
event, from orca itself or from the safety layer after the PSO); contacts outside cornered episodes are reported separately. Time to goal: mean over
successful episodes, in time units; the straight line takes 10.
Target: success >= 0.95 and contacts in <= 1% of the episodes where the obstacles cannot
corner the robot.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from swarmpath.registry import CONTROLLERS
from swarmpath.sim import Simulator
from swarmpath.world.generators import crowd_crossing


def measure(controller: str, n_obstacles: int, motion: str, episodes: int, max_steps: int = 200) -> dict:
    success = contact = cornered = contact_uncornered = 0
    times = []
    t0 = time.perf_counter()
    for seed in range(episodes):
        world = crowd_crossing(n_obstacles, seed, motion)
        traj = Simulator(world, CONTROLLERS.get(controller)(), None, seed=seed, max_steps=max_steps).run()
        ok = str(traj.status) == "all_reached"
        success += ok
        hit = bool(traj.contacts)
        contact += hit
        was_cornered = any(e["kind"] == "exposed" for e in traj.events)
        cornered += was_cornered
        contact_uncornered += hit and not was_cornered
        if ok:
            times.append(traj.n_steps * world.dt)
    return {"success": success / episodes, "contact": contact / episodes, "cornered": cornered / episodes,
            "contact_uncornered": contact_uncornered / max(1, episodes - cornered),
            "time": float(np.mean(times)) if times else float("nan"), "wall_s": time.perf_counter() - t0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=int, default=500)
    ap.add_argument("--obstacles", type=int, nargs="+", default=[5, 10, 20])
    ap.add_argument("--motions", nargs="+", default=["bounce", "random-walk"])
    ap.add_argument("--controllers", nargs="+", default=["orca", "pso-predictive"], choices=sorted(CONTROLLERS.names()))
    args = ap.parse_args()
    print(f"crowd crossing, {args.episodes} episodes per setting")
    settings = [(c, n, motion) for c in args.controllers for n in args.obstacles for motion in args.motions]
    for controller, n, motion in settings:
        m = measure(controller, n, motion, args.episodes)
        met = m["success"] >= 0.95 and m["contact_uncornered"] <= 0.01
        print(f"{controller:15s} {n:3d} {motion:12s}: success {m['success']:.3f}, contact {m['contact']:.3f} "
              f"(cornered episodes {m['cornered']:.3f}; contact when not cornered {m['contact_uncornered']:.3f}), "
              f"time to goal {m['time']:.2f} (straight 10.0), target {'met' if met else 'NOT met'}, "
              f"{m['wall_s']:.0f} s", flush=True)


if __name__ == "__main__":
    main()
