"""Conformance checks for motion models of moving obstacles, including users' own.

``check_motion(model)`` runs the model for a few hundred steps in a walled test room, for
several obstacles and footprints, and returns a list of problems (empty = it conforms).
"""
from __future__ import annotations

import numpy as np

from swarmpath.errors import SwarmpathError
from swarmpath.world import Circle, MovingObstacle, Rect, RectBounds, Robot, World, world_from_dict
from swarmpath.world.motions import FORECASTS, Motion
from swarmpath.world.moving import advance_obstacles, initial_obstacle_state

CELL = Rect((-0.5, -0.5), (0.5, 0.5))


def motion_test_world(motion: Motion, speed: float = 1.0) -> World:
    """A 10 x 10 room with a 2 x 2 block in the middle, two robots, and three obstacles
    (box and disc footprints) moving by ``motion``."""
    obstacles = (MovingObstacle("a", CELL, (1.5, 2.5), (speed, 0.0), motion),
                 MovingObstacle("b", Circle((0.0, 0.0), 0.4), (7.5, 7.5), (-0.6 * speed, -0.8 * speed), motion),
                 MovingObstacle("c", CELL, (8.5, 5.5), (0.0, -speed), motion))
    robots = (Robot("r1", (0.5, 0.5), (9.5, 9.5), 0.0, 1.5), Robot("r2", (9.5, 0.5), (0.5, 9.5), 0.0, 1.5))
    return World(RectBounds(10, 10), obstacles=(Rect((4, 4), (6, 6)),), moving_obstacles=obstacles, robots=robots,
                 name="motion-test")


def obstacle_track(world: World, steps: int, rng: np.random.Generator,
                   keep_clear: np.ndarray | None = None) -> np.ndarray:
    """The moving obstacles' positions over ``steps`` steps of their models, as the simulator
    moves them (``keep_clear``: points a redraw avoids): array (steps + 1, m, 2), the start
    first."""
    state = initial_obstacle_state(world)
    track = [state.positions]
    for _ in range(steps):
        state = advance_obstacles(world, state, rng, keep_clear=keep_clear)
        track.append(state.positions)
    return np.asarray(track)


def check_motion(motion: Motion, steps: int = 300, seeds: tuple[int, ...] = (0, 1)) -> list[str]:
    """Problems of ``motion`` (an instance): its footprint always fits the free space, the
    same seed gives the same track, no step moves farther than ``max_step`` (unless the model
    teleports), a huge speed still takes bounded time per step, the forecast class is known,
    and the scenario form (``to_dict``) reads back to the same model."""
    problems: list[str] = []
    name = getattr(type(motion), "kind", type(motion).__name__)
    if type(motion).forecast not in FORECASTS:
        problems.append(f"{name}: forecast {type(motion).forecast!r} is not one of {FORECASTS}")
    try:
        world = motion_test_world(motion)
    except SwarmpathError as exc:
        return problems + [f"{name}: the test world refuses the model: {exc}"]
    keep = np.concatenate([world.starts, world.goals])
    for seed in seeds:
        tracks = [obstacle_track(world, steps, np.random.default_rng(seed), keep) for _ in range(2)]
        if not np.array_equal(tracks[0], tracks[1]):
            problems.append(f"{name}, seed {seed}: the same seed gave different tracks")
        track = tracks[0]
        for j, ob in enumerate(world.moving_obstacles):
            bad = ~world.obstacle_fits(ob, track[:, j])
            if bad.any():
                problems.append(f"{name}, seed {seed}: obstacle {ob.id} leaves the free space at step "
                                f"{int(np.argmax(bad))}")
            if not type(motion).teleports:
                moved = np.linalg.norm(np.diff(track[:, j], axis=0), axis=1)
                limit = ob.max_step(world.dt, world.resolution) * (1 + 1e-9) + 1e-12
                if np.any(moved > limit):
                    problems.append(f"{name}, seed {seed}: obstacle {ob.id} moved {moved.max():.6g} in one step, "
                                    f"more than its max_step {limit:.6g}")
    fast = motion_test_world(motion, speed=1e17)
    state = initial_obstacle_state(fast)
    rng = np.random.default_rng(0)
    for _ in range(3):   # must return (a hang here is the failure)
        state = advance_obstacles(fast, state, rng, keep_clear=keep)
    doc = world.to_dict()
    try:
        again = world_from_dict(doc)
    except SwarmpathError as exc:
        problems.append(f"{name}: to_dict() does not read back: {exc}")
    else:
        if [ob.motion for ob in again.moving_obstacles] != [ob.motion for ob in world.moving_obstacles]:
            problems.append(f"{name}: to_dict() reads back as a different model")
    return problems
