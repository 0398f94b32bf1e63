"""Speed of the learning environment: env steps per second with random actions, next to POGEMA
on the same map with the same robots.

Run on demand (not a test):
    python benchmarks/bench_env.py [--agents 64] [--steps 3000] [--pogema-python PATH]

Task: the MovingAI map random-32-32-10 (32 x 32, 10% blocked), the first 64 rows of
random-32-32-10-random-1.scen as robots, random actions (drawn outside the timed calls),
episodes of 256 steps; every robot stays an agent for the whole episode (swarmpath
``stay_arrived=True``, POGEMA ``on_target="nothing"``), so 64 agents act at every step.

- swarmpath: ``swarmpath.env.parallel_env`` (PettingZoo Parallel API). One env step moves
  the robots through the simulator's pieces (move validation, the independent collision
  checker ``step_contacts``: same cell, swaps, crossing diagonals, corner cutting), computes
  rewards and infos (contacts by kind, action masks) and builds every agent's observation
  (5 x 11 x 11 patch and goal vector); the episode is recorded as a Trajectory. Measured with
  8 moves (the default) and with 4 (POGEMA's action set), and once with random actions drawn
  among those the info's ``action_mask`` allows (fewer contacts for the checker to report).
- POGEMA: the same map, starts and goals, ``obs_radius=5`` (11 x 11, 3 channels), 5 actions;
  its native list API (``pogema_v0``) and its PettingZoo integration. POGEMA checks moves
  against each other by its own rules (``collision_system="priority"``): a move into an
  occupied or contested cell is not made.

Both are timed around ``step()`` only (resets apart), in wall time and in CPU time of this
process, in blocks: the best block is reported with the median beside it (on a shared machine
other work slows some blocks down). POGEMA needs gymnasium 0.28 and
pydantic 1, which swarmpath's own dependencies exclude: install it in a separate virtual
environment (``python -m venv .venv-pogema && .venv-pogema/bin/pip install pogema``) and pass
``--pogema-python .venv-pogema/bin/python``; the script then runs the POGEMA part there.
Target: at least 1,000 swarmpath env steps per second with 64 robots.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

MAP, SCEN = "random-32-32-10.map", "random-32-32-10-random-1.scen"


def task(agents: int) -> tuple[object, dict]:
    """The swarmpath World and the same task in POGEMA's terms (map rows of '.' and '#',
    positions as (row, column))."""
    from swarmpath.world import world_from_movingai

    world = world_from_movingai(MAP, SCEN, agents)
    blocked = world.static_map.blocked
    rows = ["".join("#" if b else "." for b in row) for row in blocked]
    starts = np.floor(world.starts).astype(int)
    goals = np.floor(world.goals).astype(int)
    return world, {"map": "\n".join(rows), "agents_xy": [[int(y), int(x)] for x, y in starts],
                   "targets_xy": [[int(y), int(x)] for x, y in goals]}


def timed_steps(env_step, make_actions, reset, steps: int, repeats: int = 1) -> dict:
    """Call ``env_step(make_actions())`` ``steps`` times (``reset()`` when an episode ends,
    untimed) in ``repeats`` blocks; steps per second of the step calls in the best block and
    the median block, by wall time and by this process's CPU time (on a shared machine other
    work slows some blocks down; the best block is the closest to the code's own speed)."""
    blocks = []
    per_block = max(1, steps // repeats)
    for _ in range(repeats):
        wall = cpu = 0.0
        for _ in range(per_block):
            actions = make_actions()
            if actions is None:
                reset()
                actions = make_actions()
            w0, c0 = time.perf_counter(), time.process_time()
            env_step(actions)
            wall += time.perf_counter() - w0
            cpu += time.process_time() - c0
        blocks.append((per_block / wall, per_block / cpu if cpu > 0 else float("inf")))
    walls = sorted(b[0] for b in blocks)
    cpus = sorted(b[1] for b in blocks)
    return {"steps": per_block * repeats, "steps_per_s": walls[-1], "median_steps_per_s": walls[len(walls) // 2],
            "steps_per_cpu_s": cpus[-1], "median_steps_per_cpu_s": cpus[len(cpus) // 2]}


def bench_swarmpath(world, steps: int, episode: int, connectivity: int, seed: int, repeats: int,
                    masked: bool = False) -> dict:
    """swarmpath's side; ``masked``: random among the actions the info's action_mask allows."""
    from swarmpath.env import parallel_env
    from swarmpath.sim.collisions import step_contacts

    env = parallel_env(world, max_steps=episode, stay_arrived=True, connectivity=connectivity)
    rng = np.random.default_rng(seed)
    last = {"infos": env.reset(seed=seed)[1]}
    n_actions = env.action_space(env.possible_agents[0]).n

    def actions():
        if not env.agents:
            return None
        if not masked:
            return dict(zip(env.agents, rng.integers(0, n_actions, len(env.agents)).tolist()))
        infos = last["infos"]
        return {a: int(rng.choice(np.flatnonzero(infos[a]["action_mask"]))) for a in env.agents}

    def step(a):
        last["infos"] = env.step(a)[4]

    def reset():
        last["infos"] = env.reset()[1]

    timed_steps(step, actions, reset, 30)                                 # warm-up
    out = timed_steps(step, actions, reset, steps, repeats)
    # the share of the independent checker: the last episode's steps, checked again
    traj = env.trajectory()
    pos, obs = traj.positions, traj.obstacle_positions
    t0 = time.perf_counter()
    for t in range(1, len(pos)):
        step_contacts(world, t, pos[t - 1], pos[t], obs[t - 1], obs[t])
    out["checker_us_per_step"] = 1e6 * (time.perf_counter() - t0) / max(1, len(pos) - 1)
    out["contacts_per_step"] = len(traj.contacts) / max(1, traj.n_steps)
    return out


def bench_pogema(spec: dict, steps: int, episode: int, seed: int, pettingzoo: bool, repeats: int) -> dict:
    """POGEMA's side (imports nothing of swarmpath, so that it runs in POGEMA's own venv)."""
    from pogema import GridConfig, pogema_v0

    cfg = GridConfig(map=spec["map"], agents_xy=spec["agents_xy"], targets_xy=spec["targets_xy"], obs_radius=5,
                     max_episode_steps=episode, on_target="nothing", seed=seed,
                     integration="PettingZoo" if pettingzoo else None)
    env = pogema_v0(cfg)
    rng = np.random.default_rng(seed)
    n = len(spec["agents_xy"])
    state = {"done": False}
    env.reset(seed=seed)

    if pettingzoo:
        def actions():
            if not env.agents:
                return None
            return dict(zip(env.agents, rng.integers(0, 5, len(env.agents)).tolist()))

        def step(a):
            env.step(a)

        reset = lambda: env.reset(seed=seed)  # noqa: E731
    else:
        def actions():
            if state["done"]:
                return None
            return rng.integers(0, 5, n).tolist()

        def step(a):
            _, _, terminated, truncated, _ = env.step(a)
            state["done"] = all(terminated) or all(truncated)

        def reset():
            env.reset(seed=seed)
            state["done"] = False

    timed_steps(step, actions, reset, 30)
    return timed_steps(step, actions, reset, steps, repeats)


def pogema_results(spec: dict, args) -> dict | None:
    """POGEMA's figures: here if it imports, else with ``--pogema-python``; None without."""
    try:
        import pogema  # noqa: F401
    except ImportError:
        if not args.pogema_python:
            return None
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "task.json"
            path.write_text(json.dumps(spec), encoding="utf-8")
            cmd = [args.pogema_python, __file__, "--pogema-only", str(path), "--steps", str(args.steps),
                   "--episode", str(args.episode), "--seed", str(args.seed), "--repeats", str(args.repeats)]
            out = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
        if out.returncode != 0:
            print(f"POGEMA run failed: {out.stderr.strip().splitlines()[-1:]}")
            return None
        return json.loads(out.stdout.strip().splitlines()[-1])
    return pogema_figures(spec, args)


def pogema_figures(spec: dict, args) -> dict:
    import pogema

    return {"native": bench_pogema(spec, args.steps, args.episode, args.seed, False, args.repeats),
            "pettingzoo": bench_pogema(spec, args.steps, args.episode, args.seed, True, args.repeats),
            "version": pogema.__version__}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--agents", type=int, default=64)
    ap.add_argument("--steps", type=int, default=3000, help="timed env steps per configuration")
    ap.add_argument("--episode", type=int, default=256, help="steps per episode")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=5, help="timed blocks per configuration (best and median)")
    ap.add_argument("--pogema-python", default=None, help="a Python interpreter with pogema installed")
    ap.add_argument("--pogema-only", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.pogema_only:            # the POGEMA half, run by the other interpreter
        spec = json.loads(Path(args.pogema_only).read_text(encoding="utf-8"))
        print(json.dumps(pogema_figures(spec, args)))
        return

    world, spec = task(args.agents)
    print(f"{world.name}: {args.agents} robots, random actions, episodes of {args.episode} steps, "
          f"{args.steps} timed steps per line")
    rows = {}
    for connectivity in (8, 4):
        rows[f"swarmpath PettingZoo, {connectivity}-connected"] = bench_swarmpath(world, args.steps, args.episode,
                                                                                 connectivity, args.seed, args.repeats)
    rows["swarmpath PettingZoo, 8-conn., masked"] = bench_swarmpath(world, args.steps, args.episode, 8, args.seed,
                                                                    args.repeats, masked=True)
    pogema = pogema_results(spec, args)
    if pogema is not None:
        rows[f"POGEMA {pogema['version']} native"] = pogema["native"]
        rows[f"POGEMA {pogema['version']} PettingZoo"] = pogema["pettingzoo"]
    print(f"steps per second in the best of {args.repeats} blocks (median block in brackets)")
    print(f"{'environment':40s} {'wall':>14s} {'CPU':>14s} {'us/step':>8s}")
    for name, r in rows.items():
        print(f"{name:40s} {r['steps_per_s']:6.0f} ({r['median_steps_per_s']:5.0f}) "
              f"{r['steps_per_cpu_s']:6.0f} ({r['median_steps_per_cpu_s']:5.0f}) {1e6 / r['steps_per_s']:8.0f}")
    for name, r in rows.items():
        if "checker_us_per_step" in r:
            print(f"{name}: the independent checker takes {r['checker_us_per_step']:.0f} us of a step "
                  f"({r['contacts_per_step']:.1f} contacts per step with random actions)")
    ours = rows["swarmpath PettingZoo, 8-connected"]["steps_per_s"]
    print(f"target >= 1000 steps/s: {'met' if ours >= 1000 else 'NOT met'} ({ours:.0f})")
    if pogema is None:
        print("POGEMA: not measured (pip install pogema in another venv; --pogema-python PATH)")
        return
    for ours_name in ("swarmpath PettingZoo, 8-connected", "swarmpath PettingZoo, 4-connected"):
        for theirs in ("native", "PettingZoo"):
            key = f"POGEMA {pogema['version']} {theirs}"
            ratio = rows[ours_name]["steps_per_cpu_s"] / rows[key]["steps_per_cpu_s"]
            print(f"ratio {ours_name} / {key}: {ratio:.2f} (CPU time)")


if __name__ == "__main__":
    main()
