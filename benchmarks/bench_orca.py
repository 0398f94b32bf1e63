"""ORCA in swarmpath's simulator next to RVO2 (C++, through pyrvo) on the antipodal circle.

Run on demand (not a test):  nice python benchmarks/bench_orca.py [--robots 100 1000 5000]

Test: n disc robots (radius 0.3, max speed 0.5, time step 1) on a circle with 1.0 of arc
between neighbours (radius n / 2 pi, at least 5), each going to the diametrically opposite
point. Both are run one simulator step at a time and BOTH trajectories are judged by
swarmpath's own checker (swarmpath.sim.collisions.step_contacts: straight moves between
recorded positions, any overlap during the step counts):

- ours: the registered ``orca`` controller in swarmpath.sim.Simulator; steps per second of
  the whole simulator step (obstacles, sensing, controller, move validation, the checker,
  recording), and the controller's share;
- pyrvo: RVO2 with the same parameters (neighbour distance 8, 10 neighbours, time horizon 4,
  obstacle horizon 2), preferred velocity straight at the goal; one RVO2 step of 1 time unit
  per simulator step ("dt 1"), and 4 sub-steps of 0.25 per simulator step ("dt 1/4", RVO2's
  usual small step). Its step time is the whole loop (preferred velocities, do_step, reading
  positions, the same checker) and do_step alone.

Colliding pairs: distinct robot pairs that ever came into contact; "arrived": within 1e-6 of
the goal (ours lands exactly). Peer install: pip install ".[bench]". Targets: 1,000 robots at
>= 20 steps/s with zero contacts; our step time within 3x of pyrvo's.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from swarmpath.control.orca import ORCAController
from swarmpath.sim import Simulator
from swarmpath.sim.collisions import step_contacts
from swarmpath.world.generators import antipodal


def default_steps(world) -> int:
    diameter = float(np.max(np.linalg.norm(world.goals - world.starts, axis=1)))
    return int(3 * diameter / 0.5) + 300


def run_ours(n: int, max_steps: int | None) -> dict:
    world = antipodal(n)
    steps = max_steps or default_steps(world)
    t0 = time.perf_counter()
    traj = Simulator(world, ORCAController(), None, seed=0, max_steps=steps).run()
    wall = time.perf_counter() - t0
    pairs = {(c.robot, c.other) for c in traj.contacts if c.kind == "robot_robot"}
    arrived = int(np.sum(np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-6))
    return {"steps": traj.n_steps, "status": str(traj.status), "ms_per_step": 1000 * wall / traj.n_steps,
            "controller_ms": 1000 * traj.meta["controller_time_s"] / traj.n_steps, "contacts": len(traj.contacts),
            "pairs": len(pairs), "arrived": arrived}


def run_pyrvo(n: int, max_steps: int | None, substeps: int) -> dict:
    import pyrvo

    world = antipodal(n)
    steps = max_steps or default_steps(world)
    starts, goals = world.starts, world.goals
    speed, radius = 0.5, 0.3
    dt = world.dt / substeps
    sim = pyrvo.RVOSimulator(dt, 8.0, 10, 4.0, 2.0, radius, speed)
    for p in starts:
        sim.add_agent((float(p[0]), float(p[1])))
    empty = np.zeros((0, 2))
    pos = starts.copy()
    pairs: set[tuple[int, int]] = set()
    contacts = 0
    loop_time = step_time = 0.0
    done = 0
    for done in range(1, steps + 1):
        t_loop = time.perf_counter()
        before = pos
        for _ in range(substeps):
            d = goals - pos
            dist = np.linalg.norm(d, axis=1)
            pref = d / np.maximum(dist, 1e-12)[:, None] * np.minimum(speed, dist / dt)[:, None]
            for i in range(n):
                sim.set_agent_pref_velocity(i, (float(pref[i, 0]), float(pref[i, 1])))
            t0 = time.perf_counter()
            sim.do_step()
            step_time += time.perf_counter() - t0
            pos = np.array([sim.get_agent_position(i).to_tuple() for i in range(n)])
        found = step_contacts(world, done, before, pos, empty, empty)
        loop_time += time.perf_counter() - t_loop
        contacts += len(found)
        pairs.update((c.robot, c.other) for c in found if c.kind == "robot_robot")
        if np.all(np.linalg.norm(goals - pos, axis=1) <= 1e-6):
            break
    arrived = int(np.sum(np.linalg.norm(goals - pos, axis=1) <= 1e-6))
    return {"steps": done, "ms_per_step": 1000 * loop_time / done, "do_step_ms": 1000 * step_time / done,
            "contacts": contacts, "pairs": len(pairs), "arrived": arrived}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[100, 1000, 5000])
    ap.add_argument("--max-steps", type=int, default=None, help="default: 3 crossings' time + 300")
    ap.add_argument("--no-pyrvo", action="store_true")
    args = ap.parse_args()
    print("antipodal circle: radius 0.3, speed 0.5, dt 1, arc spacing 1.0; contacts by swarmpath's checker")
    for n in args.robots:
        ours = run_ours(n, args.max_steps)
        print(f"ours        n={n:5d}: {1000 / ours['ms_per_step']:7.1f} steps/s ({ours['ms_per_step']:.2f} ms/step, "
              f"controller {ours['controller_ms']:.2f} ms), {ours['steps']} steps, {ours['status']}, "
              f"arrived {ours['arrived']}/{n}, contacts {ours['contacts']}, colliding pairs {ours['pairs']}", flush=True)
        if n >= 1000:
            ok = 1000 / ours["ms_per_step"] >= 20 and ours["contacts"] == 0
            print(f"  target n={n}: >= 20 steps/s and 0 contacts: {'met' if ok else 'NOT met'}", flush=True)
        if args.no_pyrvo:
            continue
        try:
            for sub in (1, 4):
                rvo = run_pyrvo(n, args.max_steps, sub)
                print(f"pyrvo dt 1/{sub} n={n:5d}: {1000 / rvo['ms_per_step']:7.1f} steps/s ({rvo['ms_per_step']:.2f} ms/step, "
                      f"do_step {rvo['do_step_ms']:.2f} ms), {rvo['steps']} steps, arrived {rvo['arrived']}/{n}, "
                      f"contacts {rvo['contacts']}, colliding pairs {rvo['pairs']}", flush=True)
                print(f"  ours / pyrvo dt 1/{sub} time per step: {ours['ms_per_step'] / rvo['ms_per_step']:.2f} "
                      f"(target <= 3), per do_step: {ours['ms_per_step'] / rvo['do_step_ms']:.2f}", flush=True)
        except ImportError:
            print("pyrvo not installed: pip install '.[bench]'")


if __name__ == "__main__":
    main()
