"""World generators for tests, benchmarks and sweeps: the antipodal circle, rooms with doors,
MovingAI maps with disc robots, moving obstacles of every motion model added to a world, the
CrowdNav-style crossing (one robot among obstacles that ignore it) and the crowded random grid
among obstacles that never stop (the grid controllers' acceptance world)."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
from scipy.ndimage import binary_dilation, label

from swarmpath.errors import ScenarioError
from swarmpath.world import (
    Bounce,
    Bounce8,
    Circle,
    RandomWalk,
    Rect,
    RectBounds,
    Redraw,
    Robot,
    StaticMap,
    TurnEvery,
    Waypoints,
    World,
    world_from_movingai,
)
from swarmpath.world.moving import MovingObstacle



def antipodal(n: int, radius: float = 0.3, speed: float = 0.5, spacing: float = 1.0) -> World:
    """n robots on a circle (arc spacing ``spacing``, circle radius at least 5), each to the
    diametrically opposite point."""
    big = max(5.0, n * spacing / (2 * np.pi))
    c = big + 2.0
    a = 2 * np.pi * np.arange(n) / n
    st = np.stack([c + big * np.cos(a), c + big * np.sin(a)], axis=1)
    robots = tuple(Robot(f"r{i}", tuple(st[i]), tuple(2 * c - st[i]), radius, speed) for i in range(n))
    return World(RectBounds(2 * c, 2 * c), robots=robots, name=f"antipodal-{n}")


def rooms_with_doors(radius: float = 0.3) -> World:
    """Four rooms (20 x 20, walls 1 thick with 1.6-wide doors) and six robots that cross them."""
    walls = (Rect((9.5, 0), (10.5, 4)), Rect((9.5, 5.6), (10.5, 14)), Rect((9.5, 15.6), (10.5, 20)),
             Rect((0, 9.5), (3, 10.5)), Rect((4.6, 9.5), (15, 10.5)), Rect((16.6, 9.5), (20, 10.5)))
    pairs = [((2, 2), (18, 18)), ((18, 2), (2, 18)), ((2, 18), (18, 3)), ((18, 18), (3, 2)),
             ((6, 6), (14, 15)), ((14, 6), (6, 15))]
    robots = tuple(Robot(f"r{k}", s, g, radius, 1.0) for k, (s, g) in enumerate(pairs))
    return World(RectBounds(20, 20), obstacles=walls, robots=robots, name="rooms")


def movingai(name: str, n: int, radius: float = 0.4, speed: float = 1.0, data: Path | None = None) -> World:
    """A MovingAI map (``data``/name.map with name-even-10.scen; default: the built-in files) with
    the first ``n`` agents as discs of ``radius``."""
    if data is None:
        world = world_from_movingai(f"{name}.map", f"{name}-even-10.scen", n)
    else:
        world = world_from_movingai(data / f"{name}.map", data / f"{name}-even-10.scen", n)
    return world.replace(robots=tuple(dataclasses.replace(r, radius=radius, max_speed=speed) for r in world.robots))


MOTIONS = {
    "redraw": lambda: Redraw(),
    "turn-every": lambda: TurnEvery(period=5),
    "random-walk": lambda: RandomWalk(),
    "waypoints": None,
    "bounce": lambda: Bounce(),
}


def with_obstacles(world: World, kind: str, count: int, seed: int, speed: float = 0.5, radius: float = 0.35
                   ) -> World:
    """``world`` plus ``count`` disc obstacles of motion ``kind`` on free cells away from the
    robots' starts and goals (chosen by ``seed``)."""
    rng = np.random.default_rng(seed)
    grid = world.grid(radius=radius)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    centres = grid.centers(free)
    keep = np.ones(len(centres), bool)
    for p in np.concatenate([world.starts, world.goals]):
        keep &= np.linalg.norm(centres - p, axis=1) > 2.5
    centres = centres[keep]
    pick = rng.choice(len(centres), size=count, replace=False)
    obstacles = []
    for k, j in enumerate(pick):
        start = tuple(float(v) for v in centres[j])
        ang = rng.uniform(0, 2 * np.pi)
        vel = (speed * float(np.cos(ang)), speed * float(np.sin(ang)))
        if kind == "waypoints":
            # a back-and-forth route along a free straight line through the start
            for d in ((1, 0), (0, 1), (-1, 0), (0, -1)):
                end = centres[j] + 3 * np.array(d, float)
                ob = MovingObstacle(f"m{k}", Circle((0, 0), radius), start, vel, Waypoints(((end[0], end[1]), start)))
                pts = centres[j] + np.linspace(0, 3, 13)[:, None] * np.array(d, float)
                if world.obstacle_fits(ob, pts).all():
                    break
            else:
                ob = MovingObstacle(f"m{k}", Circle((0, 0), radius), start, (0.0, 0.0), Bounce())
        else:
            ob = MovingObstacle(f"m{k}", Circle((0, 0), radius), start, vel, MOTIONS[kind]())
        obstacles.append(ob)
    return world.replace(moving_obstacles=tuple(obstacles), name=f"{world.name}-{kind}-{seed}")


def crowd_crossing(n_obstacles: int, seed: int, motion: str = "mixed", size: float = 12.0, dt: float = 0.5,
                   robot_speed: float = 1.0, obstacle_speed: float = 0.5, radius: float = 0.3) -> World:
    """The CrowdNav-style episode: one robot (disc ``radius``, ``robot_speed``) crosses a
    walled ``size`` x ``size`` room from the middle of its left side to the middle of its
    right side among ``n_obstacles`` discs of the same radius that ignore it.

    ``motion``: "bounce" (constant velocity, bouncing off the walls), "random-walk" (one of 8
    directions each step, at most ``obstacle_speed``) or "mixed" (alternating). Obstacles
    start at random non-overlapping places at least 1.5 away from the robot's start and goal,
    with random headings (all drawn from ``seed``). Obstacles are slower than the robot, so
    a single one can never catch it."""
    rng = np.random.default_rng(seed)
    start, goal = (1.0, size / 2), (size - 1.0, size / 2)
    placed: list[np.ndarray] = []
    obstacles = []
    for k in range(n_obstacles):
        for _ in range(1000):   # rejection sampling, bounded
            p = rng.uniform(radius + 0.05, size - radius - 0.05, 2)
            if min(np.linalg.norm(p - start), np.linalg.norm(p - goal)) < 1.5:
                continue
            if placed and np.min(np.linalg.norm(np.array(placed) - p, axis=1)) < 2 * radius + 0.2:
                continue
            break
        placed.append(p)
        kind = motion if motion != "mixed" else ("bounce" if k % 2 == 0 else "random-walk")
        ang = rng.uniform(0, 2 * np.pi)
        if kind == "random-walk":
            speed = obstacle_speed / np.sqrt(2)        # diagonal steps are sqrt(2) longer
            model = RandomWalk()
        else:
            speed = obstacle_speed
            model = Bounce()
        vel = (speed * float(np.cos(ang)), speed * float(np.sin(ang)))
        obstacles.append(MovingObstacle(f"h{k}", Circle((0, 0), radius), (float(p[0]), float(p[1])), vel, model))
    robot = Robot("robot", start, goal, radius, robot_speed)
    return World(RectBounds(size, size), moving_obstacles=tuple(obstacles), robots=(robot,), dt=dt,
                 name=f"crowd-{n_obstacles}-{motion}-{seed}")


def random_grid_with_movers(seed: int, n_robots: int = 100, n_moving: int = 20, size: int = 64,
                            density: float = 0.1, motions: tuple | None = None, radius: float = 0.0,
                            goal_offset: float = 0.0) -> World:
    """The crowded random grid among obstacles that never stop: a ``size`` x ``size`` map of
    1 x 1 cells with ``density`` of them blocked at random, ``n_robots`` robots (points, or
    discs of ``radius``; speed sqrt 2, one 8-neighbour cell a step) on distinct free cells of
    one connected area (that of a random free cell, or the largest when that one is too
    small) with distinct goals there, and ``n_moving`` 1-cell obstacles starting
    at least 3 cells (Chebyshev) from every robot, heading east, north, west and south in turn
    at one cell a step. Their motions are bounce8 and random-walk in turn, or the ``motions``
    (motion model instances) in turn. Each goal is its cell's centre moved by up to
    ``goal_offset`` along each axis, drawn from its own stream, so the map, robots and
    obstacles are those of ``goal_offset=0``. Everything is drawn from ``seed``.

    This is the acceptance world of the grid controllers among moving obstacles (100 robots,
    64 x 64, 20 obstacles; tests/sim/test_acceptance_online.py,
    benchmarks/bench_moving.py). The connected area is the 4-connected component of a random
    free cell: with 8-neighbour moves that cut no corner, exactly the cells a robot there can
    reach. Raises ScenarioError naming the parameter when the numbers cannot make a world.
    """
    for name, value, low in (("n_robots", n_robots, 1), ("n_moving", n_moving, 0), ("size", size, 2)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise ScenarioError(f"random_grid_with_movers: {name} must be a whole number >= {low}, got {value!r}")
    if size > 4096:
        raise ScenarioError(f"random_grid_with_movers: size must be at most 4096, got {size}")
    for name, value, high in (("density", density, 0.9), ("radius", radius, 0.5), ("goal_offset", goal_offset, 0.5)):
        if not isinstance(value, (int, float)) or not 0 <= float(value) <= high:
            raise ScenarioError(f"random_grid_with_movers: {name} must be a number from 0 to {high}, got {value!r}")
    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < density
    free = np.argwhere(~blocked)
    if not len(free):
        raise ScenarioError(f"random_grid_with_movers: density {density} left no free cell on seed {seed}")
    y, x = free[rng.integers(len(free))]
    area, _ = label(~blocked)
    connected = np.argwhere(area == area[y, x])[:, ::-1]                            # (x, y)
    need = 2 * n_robots + 4 * n_moving
    if need > len(connected):
        # the random cell lies in a small pocket: the largest area instead (seeds whose own
        # area is large enough keep their worlds)
        sizes = np.bincount(area.ravel())
        sizes[0] = 0
        connected = np.argwhere(area == int(np.argmax(sizes)))[:, ::-1]
    if need > len(connected):
        raise ScenarioError(f"random_grid_with_movers: n_robots and n_moving need {need} free cells "
                            f"(2 per robot, 4 per obstacle); the connected area of seed {seed} has {len(connected)}")
    pick = connected[rng.choice(len(connected), size=need, replace=False)]
    starts, goals, rest = pick[:n_robots], pick[n_robots:2 * n_robots], pick[2 * n_robots:]
    offset = np.random.default_rng([seed, 1]).uniform(-goal_offset, goal_offset, (n_robots, 2))
    robots = tuple(Robot(f"r{i}", tuple(starts[i] + 0.5), tuple(goals[i] + 0.5 + offset[i]), radius, float(np.sqrt(2)))
                   for i in range(n_robots))
    # obstacles on the drawn cells at least 3 cells from every start; when too few of those are,
    # on the area's other such cells in a random order (worlds with enough keep their obstacles)
    places = [c for c in rest if np.min(np.max(np.abs(starts - c), axis=1)) >= 3][:n_moving]
    if len(places) < n_moving:
        near = np.zeros((size, size), bool)
        near[starts[:, 1], starts[:, 0]] = True
        near = binary_dilation(near, np.ones((5, 5), bool))               # within 2 cells of a start
        near[pick[:, 1], pick[:, 0]] = True                               # and the cells drawn already
        spare = connected[~near[connected[:, 1], connected[:, 0]]]
        places += list(spare[rng.permutation(len(spare))[:n_moving - len(places)]])
    if len(places) < n_moving:
        raise ScenarioError(f"random_grid_with_movers: n_moving {n_moving} obstacles do not fit at least 3 cells "
                            f"from every robot's start on seed {seed} (room for {len(places)})")
    moving = []
    headings = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)]
    for k, c in enumerate(places):
        motion = (RandomWalk() if k % 2 else Bounce8()) if motions is None else motions[k % len(motions)]
        moving.append(MovingObstacle(f"m{k}", Rect((-0.5, -0.5), (0.5, 0.5)), tuple(c + 0.5), headings[k % 4], motion))
    return World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), moving_obstacles=tuple(moving),
                 robots=robots, name=f"random{size}-{seed}")
