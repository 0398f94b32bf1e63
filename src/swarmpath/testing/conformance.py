"""Conformance checks for planners and controllers, including users' plug-ins.

Each check runs the algorithm on small worlds and returns a list of problems (empty = it
conforms): same seed gives the same result, outputs pass the validators, and impossible
problems are reported as outcomes instead of crashing or hanging.
"""
from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from swarmpath.testing.validators import validate_paths, validate_trajectory
from swarmpath.world import Circle, CircleBounds, Rect, RectBounds, Robot, World
from swarmpath.world.moving import Bounce8, MovingObstacle


def conformance_worlds() -> list[World]:
    """Small worlds that exercise the usual cases (open space, obstacles, a moving obstacle)."""
    s2 = float(np.sqrt(2))
    crossing = World(RectBounds(10, 10), obstacles=(Circle((5, 5), 1.2),), robots=(
        Robot("a", (1.5, 1.5), (8.5, 8.5), 0.0, s2), Robot("b", (8.5, 1.5), (1.5, 8.5), 0.0, s2),
        Robot("c", (1.5, 8.5), (8.5, 1.5), 0.0, s2), Robot("d", (8.5, 8.5), (1.5, 1.5), 0.0, s2)), name="crossing")
    walls = World(RectBounds(12, 8), obstacles=(Rect((5, 0), (6, 5)), Rect((8, 3), (9, 8))), robots=(
        Robot("a", (1.5, 1.5), (10.5, 6.5), 0.0, s2), Robot("b", (10.5, 1.5), (1.5, 6.5), 0.0, s2)), name="walls")
    moving = World(CircleBounds((6, 6), 6), robots=(Robot("a", (2.5, 6.5), (9.5, 6.5), 0.0, s2),),
                   moving_obstacles=(MovingObstacle("m", Rect((-0.5, -0.5), (0.5, 0.5)), (6.5, 3.5), (0.0, 1.0),
                                                    Bounce8()),), name="moving")
    return [crossing, walls, moving]


def unreachable_world() -> World:
    """One robot whose goal is walled in: planners must report it, not crash or hang.

    The walls reach past the workspace's edge: walls ending exactly on the edge would leave a
    gap of zero width along it, and since touching is not a collision a point robot could
    slide through it (a continuous planner finds that path)."""
    return World(RectBounds(10, 10), obstacles=(Rect((6, 6), (11, 6.8)), Rect((6, 6), (6.8, 11))),
                 robots=(Robot("a", (1.5, 1.5), (8.5, 8.5), 0.0, float(np.sqrt(2))),), name="walled-in")


def check_planner(make_planner: Callable[[], object], worlds: Sequence[World] | None = None,
                  seeds: Sequence[int] = (0, 1)) -> list[str]:
    """Determinism, valid paths, and an unreachable goal reported as a falsy robot plan."""
    problems: list[str] = []
    for world in worlds or conformance_worlds():
        for seed in seeds:
            first = make_planner().plan(world, rng=seed)
            again = make_planner().plan(world, rng=seed)
            for a, b in zip(first.paths, again.paths):
                if (a is None) != (b is None) or (a is not None and not np.array_equal(a, b)):
                    problems.append(f"{world.name}, seed {seed}: same seed gave different paths")
                    break
            good = [r.path if r else None for r in first.robots]
            for v in validate_paths(world, good, require_all=False):
                problems.append(f"{world.name}, seed {seed}: {v}")
    blocked = make_planner().plan(unreachable_world(), rng=0)
    if bool(blocked.robots[0]):
        problems.append("walled-in goal: the plan claims a path")
    return problems


def collision_free_expected(capabilities, world: World) -> bool:
    """Whether a controller with ``capabilities`` promises zero contacts in ``world``: it must
    promise them at all (``contact_free``), avoid other robots when there are several, and
    moving obstacles when there are any."""
    if not getattr(capabilities, "contact_free", True):
        return False
    if world.n_robots > 1 and not capabilities.multi_robot:
        return False
    return not (world.moving_obstacles and not capabilities.moving_obstacles)


def check_controller(make_controller: Callable[[], object], planner: str | None = "astar",
                     worlds: Sequence[World] | None = None, seeds: Sequence[int] = (0, 1),
                     require_collision_free: bool | str = "auto", max_steps: int = 400) -> list[str]:
    """Determinism (bit for bit), no invalid moves, and no contacts where promised.

    ``require_collision_free="auto"`` asks for zero contacts in the worlds the controller's
    capabilities cover (see :func:`collision_free_expected`); True or False force it."""
    from swarmpath.registry import PLANNERS
    from swarmpath.sim.simulator import Simulator

    problems: list[str] = []
    capabilities = getattr(make_controller(), "capabilities", None)
    for world in worlds or conformance_worlds():
        strict = require_collision_free
        if strict == "auto":
            strict = capabilities is None or collision_free_expected(capabilities, world)
        plan = PLANNERS.get(planner)().plan(world, rng=0) if planner and planner != "none" else None
        for seed in seeds:
            t1 = Simulator(world, make_controller(), plan, seed=seed, max_steps=max_steps).run()
            t2 = Simulator(world, make_controller(), plan, seed=seed, max_steps=max_steps).run()
            if t1.positions.shape != t2.positions.shape or not np.array_equal(t1.positions, t2.positions):
                problems.append(f"{world.name}, seed {seed}: same seed gave different trajectories")
            invalid = [e for e in t1.events if e.get("kind") == "invalid_move"]
            if invalid:
                problems.append(f"{world.name}, seed {seed}: {len(invalid)} invalid moves, first {invalid[0]}")
            if strict:
                for v in validate_trajectory(world, t1)[:3]:
                    problems.append(f"{world.name}, seed {seed}: {v}")
    return problems
