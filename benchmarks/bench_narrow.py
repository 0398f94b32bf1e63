"""Grid robots in narrow worlds among moving obstacles of every kind: do all robots get through?

Run on demand (not a test):
    python benchmarks/bench_narrow.py [--seeds 200:230] [--families warehouse rooms corridors maze]
                                      [--controllers pibt cat-swarm] [--workers 2]

Test: worlds of four families, each seed its own map, robots and obstacles, drawn at random so
that no choice in the controllers was tuned on them (the issue's "scenarios you do not have"):

- ``warehouse``: rows of shelves 4-8 cells long with 1- or 2-wide aisles between them;
- ``rooms``: a grid of square rooms (6-10 cells) behind 1-cell walls, with a 1- or 2-wide door
  to each neighbour;
- ``corridors``: two rooms joined by one to three 2-wide corridors 4-11 cells long, with
  dead-end niches cut into the wall;
- ``maze``: a maze of 2-wide passages (random depth-first carving), with a few walls knocked
  out.

On the largest connected area: 6-39 point robots (at most one per 6 free cells) on distinct
cells with distinct goals, and 5-40 obstacles (at most one per 30 free cells), each a 1 x 1
box or a disc of radius 0.4, bounce, bounce8, turn-every (3-8 steps), random-walk or redraw
at random, heading along an axis or a diagonal, starting at least 3 cells from every start, 2
from every goal and off cells with a single way in. The step budget is 1,000.

Obstacles never react, so some worlds cannot be won: a bouncer heading across a 2-wide
passage shuttles between its two cells for ever and seals it. Printed per family and
controller: runs in which every robot arrived, runs that succeeded (every robot home at the
end and no contact), runs with a robot-robot or robot-static contact (the controllers' rule
forbids both), runs with a robot-moving contact on a step the robot was not cornered (every
move it had led into an obstacle's reach), runs ending with a robot whose goal the obstacles
had sealed off (`swarmpath.metrics.sealed`: cells no two steps in a row of the last 200 left
clear), and the wall time a run.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.ndimage import binary_dilation, label

sys.path.insert(0, str(Path(__file__).parent))
from bench_moving import checked_seeds, fail, run_all  # noqa: E402

from swarmpath.metrics.sealed import sealed_goals  # noqa: E402
from swarmpath.registry import CONTROLLERS  # noqa: E402
from swarmpath.runner import simulate  # noqa: E402
from swarmpath.world import Circle, Rect, RectBounds, Robot, StaticMap, World  # noqa: E402
from swarmpath.world.moving import Bounce, Bounce8, MovingObstacle, RandomWalk, Redraw, TurnEvery  # noqa: E402

MAX_STEPS = 1000
MOTIONS = ("bounce", "bounce8", "turn-every", "random-walk", "redraw")
HEADINGS = ((1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1))


def warehouse(rng: np.random.Generator) -> np.ndarray:
    """Rows of shelves with 1- or 2-wide aisles; a 3-cell margin all round."""
    width, height = int(rng.integers(30, 50)), int(rng.integers(24, 40))
    blocked = np.zeros((height, width), bool)
    aisle, length = int(rng.integers(1, 3)), int(rng.integers(4, 9))
    for y in range(3, height - 3, 1 + aisle):
        for x in range(3, width - 3 - length, length + 2):
            blocked[y, x:x + length] = True
    return blocked


def rooms(rng: np.random.Generator) -> np.ndarray:
    """Square rooms behind 1-cell walls, a 1- or 2-wide door to the east and north neighbours."""
    side, nx, ny = int(rng.integers(6, 11)), int(rng.integers(3, 5)), int(rng.integers(2, 4))
    blocked = np.zeros((ny * (side + 1) + 1, nx * (side + 1) + 1), bool)
    blocked[::side + 1, :] = True
    blocked[:, ::side + 1] = True
    for i in range(nx):
        for j in range(ny):
            x0, y0, door = i * (side + 1), j * (side + 1), int(rng.integers(1, 3))
            if i + 1 < nx:
                d = y0 + 1 + int(rng.integers(0, side - door + 1))
                blocked[d:d + door, x0 + side + 1] = False
            if j + 1 < ny:
                d = x0 + 1 + int(rng.integers(0, side - door + 1))
                blocked[y0 + side + 1, d:d + door] = False
    return blocked


def corridors(rng: np.random.Generator) -> np.ndarray:
    """Two rooms joined by 2-wide corridors through a thick wall, with dead-end niches in it."""
    room, length, height = int(rng.integers(8, 14)), int(rng.integers(4, 12)), int(rng.integers(14, 26))
    blocked = np.zeros((height, 2 * room + length), bool)
    blocked[:, room:room + length] = True
    for _ in range(int(rng.integers(1, 4))):
        y = int(rng.integers(1, height - 3))
        blocked[y:y + 2, room:room + length] = False
    for _ in range(int(rng.integers(0, 4))):
        y, x = int(rng.integers(1, height - 2)), room + int(rng.integers(0, length))
        blocked[y, room:x + 1] = False
    return blocked


def maze(rng: np.random.Generator) -> np.ndarray:
    """A depth-first maze of 2-wide passages (cells 3 apart), some walls knocked out."""
    cw, ch = int(rng.integers(6, 12)), int(rng.integers(5, 9))
    blocked = np.ones((ch * 3 + 1, cw * 3 + 1), bool)
    seen = np.zeros((ch, cw), bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    blocked[1:3, 1:3] = False
    while stack:
        i, j = stack[-1]
        nexts = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                 if 0 <= i + di < cw and 0 <= j + dj < ch and not seen[j + dj, i + di]]
        if not nexts:
            stack.pop()
            continue
        ni, nj = nexts[int(rng.integers(len(nexts)))]
        seen[nj, ni] = True
        x0, x1 = sorted((3 * i + 1, 3 * ni + 1))
        y0, y1 = sorted((3 * j + 1, 3 * nj + 1))
        blocked[y0:y1 + 2, x0:x1 + 2] = False
        stack.append((ni, nj))
    h, w = blocked.shape
    for _ in range(int(rng.integers(0, cw * ch // 4))):
        blocked[int(rng.integers(1, h - 1)), int(rng.integers(1, w - 1))] = False
    return blocked


FAMILIES = {"warehouse": warehouse, "rooms": rooms, "corridors": corridors, "maze": maze}


def narrow_world(family: str, seed: int) -> World:
    """The world of ``family`` and ``seed`` (see the module's docstring)."""
    rng = np.random.default_rng(seed)
    blocked = FAMILIES[family](rng)
    area, _ = label(~blocked)
    sizes = np.bincount(area.ravel())
    sizes[0] = 0
    free = np.argwhere(area == int(np.argmax(sizes)))[:, ::-1]                    # (x, y)
    n_robots = int(min(rng.integers(6, 40), len(free) // 6))
    n_moving = int(min(rng.integers(5, 41), len(free) // 30))
    pick = free[rng.choice(len(free), size=2 * n_robots, replace=False)]
    starts, goals = pick[:n_robots], pick[n_robots:]
    near = np.zeros_like(blocked)
    near[starts[:, 1], starts[:, 0]] = True
    near = binary_dilation(near, np.ones((5, 5), bool))                          # within 2 of a start
    at_goal = np.zeros_like(blocked)
    at_goal[goals[:, 1], goals[:, 0]] = True
    near |= binary_dilation(at_goal, np.ones((3, 3), bool))                      # within 1 of a goal
    walled = np.pad(blocked, 1, constant_values=True)
    ways = (~walled[:-2, 1:-1]).astype(int) + ~walled[2:, 1:-1] + ~walled[1:-1, :-2] + ~walled[1:-1, 2:]
    near |= ways <= 1
    spare = free[~near[free[:, 1], free[:, 0]]]
    places = spare[rng.permutation(len(spare))[:n_moving]]
    robots = tuple(Robot(f"r{i}", tuple(starts[i] + 0.5), tuple(goals[i] + 0.5), 0.0, float(np.sqrt(2)))
                   for i in range(n_robots))
    moving = []
    for k, cell in enumerate(places):
        kind = MOTIONS[int(rng.integers(len(MOTIONS)))]
        heading = HEADINGS[int(rng.integers(4 if kind == "bounce" else 8))]
        motion = {"bounce": Bounce, "bounce8": Bounce8, "random-walk": RandomWalk, "redraw": Redraw}.get(kind)
        motion = TurnEvery(int(rng.integers(3, 9))) if motion is None else motion()
        shape = Rect((-0.5, -0.5), (0.5, 0.5)) if rng.random() < 0.5 else Circle((0.0, 0.0), 0.4)
        moving.append(MovingObstacle(f"m{k}", shape, tuple(cell + 0.5), (float(heading[0]), float(heading[1])), motion))
    h, w = blocked.shape
    return World(RectBounds(w, h), static_map=StaticMap(blocked, 1.0), moving_obstacles=tuple(moving), robots=robots,
                 name=f"{family}-{seed}")


def one(job: tuple[str, str, int]) -> dict:
    """One run: its outcome as plain numbers."""
    family, controller, seed = job
    world = narrow_world(family, seed)
    t0 = time.perf_counter()
    traj = simulate(world, controller, seed=seed, max_steps=MAX_STEPS)
    wall = time.perf_counter() - t0
    home = int(np.sum(np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9))
    cornered = {(e["step"], e["robot"]) for e in traj.events if e.get("kind") == "no_escape"}
    kinds = [c.kind for c in traj.contacts]
    loose = sum(c.kind == "robot_moving" and not {(c.step, c.robot), (c.step - 1, c.robot)} & cornered
                for c in traj.contacts)
    return dict(family=family, controller=controller, seed=seed, n=len(world.robots), home=home,
                arrived=home == len(world.robots), ok=home == len(world.robots) and not kinds,
                forbidden=kinds.count("robot_robot") + kinds.count("robot_static"), loose=int(loose),
                sealed=len(sealed_goals(world, traj)), wall=wall)


def report(family: str, controller: str, rows: list[dict]) -> None:
    n = len(rows)
    print(f"{family:10s} {controller:10s} all arrived {sum(r['arrived'] for r in rows):3d} of {n}, "
          f"success {sum(r['ok'] for r in rows):3d}; runs with a robot-robot or robot-static contact "
          f"{sum(r['forbidden'] > 0 for r in rows)}, with a robot-moving contact not cornered "
          f"{sum(r['loose'] > 0 for r in rows)}; short of all home with a goal cut off "
          f"{sum(r['sealed'] > 0 for r in rows)}; robots home {sum(r['home'] for r in rows)} of "
          f"{sum(r['n'] for r in rows)}; {np.mean([r['wall'] for r in rows]):.1f} s a run")
    failed = [r["seed"] for r in rows if not r["arrived"]]
    print(f"{'':10s} {'':10s} seeds not all arrived: {' '.join(map(str, failed)) or 'none'}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="200:230", help="'a:b' (a to b - 1) or a comma list (default 200:230)")
    ap.add_argument("--families", nargs="+", default=list(FAMILIES), help=f"of {', '.join(FAMILIES)}")
    ap.add_argument("--controllers", nargs="+", default=["pibt", "cat-swarm"], help="grid controllers")
    ap.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    args = ap.parse_args()
    seeds = checked_seeds(args.seeds)
    if args.workers < 1:
        fail(f"--workers must be >= 1, got {args.workers}")
    for family in args.families:
        if family not in FAMILIES:
            fail(f"--families: {family!r} is not one of {', '.join(FAMILIES)}")
    for controller in args.controllers:
        if controller not in CONTROLLERS:
            fail(f"--controllers: {controller!r} is not a controller (controllers: {', '.join(CONTROLLERS.names())})")
    jobs = [(f, c, s) for f in args.families for c in args.controllers for s in seeds]
    print(f"{len(seeds)} seeds x {len(args.families)} families x {len(args.controllers)} controllers, "
          f"{MAX_STEPS} steps at most a run")
    t0 = time.perf_counter()
    results = run_all(one, jobs, args.workers)
    for family in args.families:
        for controller in args.controllers:
            rows = sorted((r for r in results if r["family"] == family and r["controller"] == controller),
                          key=lambda r: r["seed"])
            report(family, controller, rows)
    print(f"wall time {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
