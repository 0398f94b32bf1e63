"""Fixtures for the visualisation tests: a real run of jaleel2016 and synthetic trajectories
of any size (the pictures only read trajectories, so synthetic ones exercise them fully)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.sim.collisions import Contact
from swarmpath.sim.trajectory import ALL_REACHED, TRUNCATED, Trajectory


def make_trajectory(n_robots: int = 6, n_steps: int = 40, *, seed: int = 0, size: float = 20.0,
                    radius: float = 0.0, static_map: bool = False, moving: int = 1, keep_moving: bool = False,
                    robot_ids: list[str] | None = None) -> Trajectory:
    """A trajectory in a ``size`` x ``size`` world: robots go straight to their goals at speed
    <= 1 (or, with ``keep_moving``, wander for the whole run), a moving obstacle bounces,
    modes cycle through seek/trace/wait, planned paths are the straight lines."""
    rng = np.random.default_rng(seed)
    starts = rng.uniform(1, size - 1, (n_robots, 2))
    goals = rng.uniform(1, size - 1, (n_robots, 2))
    t = np.arange(n_steps + 1)[:, None, None]
    if keep_moving:
        phase = rng.uniform(0, 2 * np.pi, (1, n_robots, 1))
        amp = rng.uniform(0.5, 3.0, (1, n_robots, 1))
        frac = t / n_steps
        pos = starts + (goals - starts) * frac + amp * np.sin(0.15 * t + phase) * np.array([1.0, -1.0]) * frac * (1 - frac) * 4
        pos = np.clip(pos, 0.5, size - 0.5)
    else:
        dist = np.linalg.norm(goals - starts, axis=1)[None, :, None]
        frac = np.minimum(1.0, t * 1.0 / np.maximum(dist, 1e-9))
        pos = starts + (goals - starts) * frac
    obs_pos = np.zeros((n_steps + 1, moving, 2))
    for k in range(moving):
        x = (2 + 0.5 * np.arange(n_steps + 1) + 3 * k) % (2 * (size - 4))
        obs_pos[:, k, 0] = 2 + np.where(x > size - 4, 2 * (size - 4) - x, x)
        obs_pos[:, k, 1] = size / 2 + k
    names = ["seek", "trace", "wait"]
    modes = ((np.arange(n_steps)[:, None] + np.arange(n_robots)[None, :]) % 3).astype(np.int8)
    ids = robot_ids or [f"R{i + 1}" for i in range(n_robots)]
    world = {"schema_version": 1, "name": "synthetic", "resolution": 1.0, "dt": 1.0,
             "bounds": {"type": "rectangle", "width": size, "height": size},
             "obstacles": [{"type": "circle", "center": [size / 2, size / 4], "radius": size / 12},
                           {"type": "rectangle", "min": [size * 0.7, size * 0.7], "max": [size * 0.8, size * 0.9]},
                           {"type": "polygon", "points": [[1, size - 1], [3, size - 1], [2, size - 3]]}],
             "danger_zones": [{"center": [size * 0.25, size * 0.75], "radius": size / 15, "weight": 1.0}],
             "moving_obstacles": [{"id": f"m{k + 1}", "shape": {"type": "rectangle", "min": [-0.5, -0.5], "max": [0.5, 0.5]},
                                   "start": obs_pos[0, k].tolist(), "velocity": [0.5, 0.0], "motion": "bounce"}
                                  for k in range(moving)],
             "robots": [{"id": ids[i], "start": starts[i].tolist(), "goal": goals[i].tolist(), "radius": radius,
                         "max_speed": 1.0} for i in range(n_robots)]}
    raster = None
    if static_map:
        cells = int(size)
        raster = np.zeros((cells, cells), bool)
        raster[2:4, 2:cells // 2] = True
        raster[cells // 2:, cells - 3] = True
    return Trajectory(
        scenario="synthetic", seed=seed, dt=1.0, resolution=1.0, robot_ids=ids,
        radii=np.full(n_robots, radius), goals=goals, positions=pos, obstacle_ids=[f"m{k + 1}" for k in range(moving)],
        obstacle_positions=obs_pos, contacts=[Contact(step=min(3, n_steps), kind="robot_robot", robot=0, other=1, detail="test")],
        events=[{"step": 1, "kind": "invalid_move", "robot": 0}], modes=modes, mode_names=names,
        planned_paths=[np.stack([s, g]) for s, g in zip(starts, goals)],
        status=TRUNCATED if keep_moving else ALL_REACHED, world=world, static_map=raster,
        meta={"planner": "straight", "controller": "synthetic"})


@pytest.fixture
def synthetic():
    """The factory :func:`make_trajectory`."""
    return make_trajectory


@pytest.fixture(scope="session")
def jaleel_run():
    """One real run of the README's scenario (A* plans, plain path following: always available)."""
    from swarmpath.runner import run_world
    from swarmpath.world import load_scenario

    return run_world(load_scenario("jaleel2016"), planner="astar", controller="follow", seed=0)


def image_facts(path) -> dict:
    """Size, share of pixels that differ from the most common (background) colour, and number
    of distinct colours of an image file (its first frame)."""
    from PIL import Image

    with Image.open(path) as im:
        rgb = np.asarray(im.convert("RGB"))
    packed = (rgb[..., 0].astype(np.int32) << 16 | rgb[..., 1].astype(np.int32) << 8 | rgb[..., 2]).ravel()
    colours, counts = np.unique(packed, return_counts=True)
    background = colours[np.argmax(counts)]
    return {"width": rgb.shape[1], "height": rgb.shape[0], "colours": len(colours),
            "ink": float(np.mean(packed != background)), "pixels": rgb}


@pytest.fixture
def facts():
    """The function :func:`image_facts`."""
    return image_facts


def has_colour(pixels: np.ndarray, hex_colour: str, tolerance: int = 8, min_pixels: int = 5) -> bool:
    """Whether at least ``min_pixels`` pixels are within ``tolerance`` of ``hex_colour``."""
    target = np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)])
    close = np.all(np.abs(pixels.reshape(-1, 3).astype(int) - target) <= tolerance, axis=1)
    return int(close.sum()) >= min_pixels


@pytest.fixture
def colour_present():
    """The function :func:`has_colour`."""
    return has_colour
