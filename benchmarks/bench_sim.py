"""Simulation speed and safety: the cat-swarm controller in swarmpath's simulator next to ORCA
(RVO2's C++ core through pyrvo) on the antipodal-circle test.

Run on demand (not a test):  python benchmarks/bench_sim.py [--robots 100 1000] [--max-steps 800]

Test: a 256 x 256 open map; robots start on concentric rings around the centre (distinct
cells, at least 3 cells apart along a ring) and each must reach the cell diametrically
opposite its start, so everyone meets in the middle.
- swarmpath: point robots, one 8-neighbour cell per step (max speed sqrt 2 cells), the
  simulator's own checker counts every contact (same cell, swap, crossing, any overlap).
  Steps per second are the simulator's full steps (sensing, controller, move validation,
  collision checking, recording); the controller's one-off reset is reported apart (the
  distance tables are lazy: it builds the grid's structures and, with a robot per 4,096 free
  cells or more, 8 landmark fields).
- ORCA (pyrvo): discs of radius 0.4 cells (so that neighbouring starts do not touch), max
  speed 1 cell per time unit, RVO2's usual time step 0.25 (4 sub-steps per step), 10
  neighbours within 10 cells, time horizon 5, preferred velocity straight at the goal. A
  collision is a pair of discs overlapping after a sub-step; we report the distinct pairs that
  ever overlapped and the pair-sub-steps. ORCA's time is its C++ do_step only.
Peer install: pip install ".[bench]" (pyrvo). Target (issue 4): 1000 robots at >= 20 steps per
second with zero collisions.
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.spatial import cKDTree

from swarmpath.control.cat_swarm import CatSwarmController
from swarmpath.search import astar
from swarmpath.sim import Simulator
from swarmpath.sim.collisions import ROBOT_MOVING, ROBOT_ROBOT, ROBOT_STATIC
from swarmpath.world import RectBounds, Robot, StaticMap, World

SIZE = 256
S2 = math.sqrt(2)


def antipodal_cells(n: int, size: int = SIZE, per_ring: int = 200, gap: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
    """Start and goal cells (n, 2): rings of up to ``per_ring`` robots, radii 0.45 * size,
    then ``gap`` cells further in for each next ring; goals mirrored through the centre."""
    centre = size / 2
    rings = math.ceil(n / per_ring)
    pts = []
    for r in range(rings):
        k = min(per_ring, n - len(pts))
        radius = 0.45 * size - gap * r
        angle = 2 * np.pi * (np.arange(k) + 0.5 * (r % 2)) / k
        pts.append(np.stack([centre + radius * np.cos(angle), centre + radius * np.sin(angle)], axis=1))
    starts = np.floor(np.concatenate(pts)).astype(np.int64)
    goals = (size - 1) - starts  # the cell mirrored through the map's centre
    if len(np.unique(starts, axis=0)) != n:
        raise ValueError("rings too crowded: two robots share a start cell")
    return starts, goals


def antipodal_world(n: int) -> World:
    starts, goals = antipodal_cells(n)
    robots = tuple(Robot(f"r{i}", tuple(starts[i] + 0.5), tuple(goals[i] + 0.5), 0.0, S2) for i in range(n))
    return World(RectBounds(SIZE, SIZE), static_map=StaticMap(np.zeros((SIZE, SIZE), bool), 1.0), robots=robots,
                 name=f"antipodal-{n}")


def run_cat_swarm(n: int, max_steps: int) -> dict:
    world = antipodal_world(n)
    t0 = time.perf_counter()
    traj = Simulator(world, CatSwarmController(), None, seed=0, max_steps=max_steps).run()
    wall = time.perf_counter() - t0
    reset = traj.meta["controller_reset_s"]
    kinds = {ROBOT_ROBOT: 0, ROBOT_STATIC: 0, ROBOT_MOVING: 0}
    for c in traj.contacts:
        kinds[c.kind] += 1
    at = np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9
    lengths = np.linalg.norm(np.diff(traj.positions, axis=0), axis=2).sum()
    grid = world.grid()
    optimal = sum(astar(grid, grid.cell_of(r.start), grid.cell_of(r.goal)).cost for r in world.robots)
    return {"robots": n, "steps": traj.n_steps, "status": traj.status, "reset_s": reset,
            "steps_per_s": traj.n_steps / (wall - reset),
            "controller_ms": 1000 * (traj.meta["controller_time_s"] - reset) / traj.n_steps,
            "collisions": kinds, "at_goal": int(at.sum()), "length_ratio": lengths / optimal}


def run_orca(n: int, max_steps: int, radius: float = 0.4, speed: float = 1.0, substeps: int = 4) -> dict:
    import pyrvo

    starts, goals = antipodal_cells(n)
    starts = starts + 0.5
    goals = goals + 0.5
    dt = 1.0 / substeps
    sim = pyrvo.RVOSimulator(dt, 10.0, 10, 5.0, 5.0, radius, speed)
    for p in starts:
        sim.add_agent((float(p[0]), float(p[1])))
    pairs_ever: set[tuple[int, int]] = set()
    pair_steps = 0
    step_time = 0.0
    pos = starts.copy()
    steps = 0
    for steps in range(1, max_steps + 1):
        for _ in range(substeps):
            to_goal = goals - pos
            dist = np.linalg.norm(to_goal, axis=1)
            pref = to_goal / np.maximum(dist, 1e-12)[:, None] * np.minimum(dist / dt, speed)[:, None]
            for i in range(n):
                sim.set_agent_pref_velocity(i, (float(pref[i, 0]), float(pref[i, 1])))
            t0 = time.perf_counter()
            sim.do_step()
            step_time += time.perf_counter() - t0
            pos = np.array([sim.get_agent_position(i).to_tuple() for i in range(n)])
            close = cKDTree(pos).query_pairs(2 * radius - 1e-9, output_type="ndarray")
            pair_steps += len(close)
            pairs_ever.update(map(tuple, close.tolist()))
        if np.all(np.linalg.norm(goals - pos, axis=1) <= 0.5):
            break
    arrived = int(np.sum(np.linalg.norm(goals - pos, axis=1) <= 0.5))
    return {"robots": n, "steps": steps, "ms_per_step": 1000 * step_time / steps,
            "colliding_pairs": len(pairs_ever), "pair_steps": pair_steps, "arrived": arrived}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[100, 1000])
    ap.add_argument("--max-steps", type=int, default=800)
    ap.add_argument("--no-orca", action="store_true", help="skip the ORCA peer")
    args = ap.parse_args()
    print(f"antipodal circle on a {SIZE}x{SIZE} open map, max {args.max_steps} steps")
    for n in args.robots:
        cs = run_cat_swarm(n, args.max_steps)
        total = sum(cs["collisions"].values())
        print(f"cat-swarm n={n:5d}: {cs['steps_per_s']:7.1f} steps/s (controller {cs['controller_ms']:.1f} ms/step, "
              f"reset {cs['reset_s']:.1f} s), {cs['steps']} steps, {cs['status']}, at goal {cs['at_goal']}/{n}, "
              f"collisions {total} {cs['collisions']}, executed/optimal length {cs['length_ratio']:.3f}")
        if not args.no_orca:
            try:
                orca = run_orca(n, args.max_steps)
            except ImportError:
                print("ORCA (pyrvo) not installed: pip install '.[bench]'")
            else:
                print(f"ORCA      n={n:5d}: {1000 / orca['ms_per_step']:7.1f} steps/s ({orca['ms_per_step']:.2f} ms/step, "
                      f"C++ step only), {orca['steps']} steps, arrived {orca['arrived']}/{n}, "
                      f"colliding pairs {orca['colliding_pairs']} ({orca['pair_steps']} pair-sub-steps)")
        if n >= 1000:
            ok = cs["steps_per_s"] >= 20 and total == 0
            print(f"target n={n}: >= 20 steps/s and 0 collisions: {'met' if ok else 'NOT met'}")


if __name__ == "__main__":
    main()
