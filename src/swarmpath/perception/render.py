"""Draw a world state as an RGB image with known colours (the simulated overhead camera).

Static obstacles are dark gray and the dynamic obstacle orange, as in the paper's simulation
(section 5); robots are black, like the Khepera robots its kin recognition looks for
(section 6); the floor is white. A pixel is painted when its centre lies inside a shape (no
anti-aliasing), so the centroid of a disc's pixels lies within a fraction of a pixel of the
disc's centre. Later layers cover earlier ones: static obstacles, moving obstacles, robots.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.perception.colour import PixelFrame
from swarmpath.world.shapes import Circle

RGB = tuple[int, int, int]


@dataclass(frozen=True)
class Palette:
    """Colours of the rendered classes (8-bit RGB)."""

    floor: RGB = (255, 255, 255)
    static: RGB = (64, 64, 64)
    moving: RGB = (255, 140, 0)
    robot: RGB = (0, 0, 0)


def _paint(image: NDArray[np.uint8], shape, colour: RGB, frame: PixelFrame) -> None:
    """Paint the pixels whose centres lie inside ``shape`` (only its bounding box is visited)."""
    lo, hi = shape.bbox
    (c0, r0), (c1, r1) = frame.to_pixels(lo), frame.to_pixels(hi)
    h, w = image.shape[:2]
    c0, r0 = max(int(np.floor(c0)), 0), max(int(np.floor(r0)), 0)
    c1, r1 = min(int(np.ceil(c1)) + 1, w), min(int(np.ceil(r1)) + 1, h)
    if c0 >= c1 or r0 >= r1:
        return
    cols, rows = np.meshgrid(np.arange(c0, c1) + 0.5, np.arange(r0, r1) + 0.5)
    centres = frame.to_world(np.stack([cols, rows], axis=-1))
    inside = shape.signed_distance(centres.reshape(-1, 2)).reshape(centres.shape[:2]) <= 0
    image[r0:r1, c0:c1][inside] = colour


def render_state(world, robot_positions: ArrayLike, obstacle_positions: ArrayLike | None = None, *,
                 frame: PixelFrame | None = None, palette: Palette | None = None,
                 min_radius_px: float = 2.0) -> NDArray[np.uint8]:
    """An image (height, width, 3) uint8 of ``world`` with robots at ``robot_positions``
    (n, 2) and moving obstacles at ``obstacle_positions`` (m, 2; default: their starts).

    The image covers the workspace's bounding box at ``frame.pixels_per_unit``; point robots
    (radius 0) are drawn as discs of ``min_radius_px`` pixels.
    """
    frame = frame or PixelFrame()
    palette = palette or Palette()
    size = np.ceil(frame.to_pixels(world.bounds.extent)).astype(int)
    image = np.empty((size[1], size[0], 3), np.uint8)
    image[:] = palette.floor
    for ob in world.obstacles:
        _paint(image, ob, palette.static, frame)
    if world.static_map is not None:
        cols, rows = np.meshgrid(np.arange(size[0]) + 0.5, np.arange(size[1]) + 0.5)
        cells = np.floor(frame.to_world(np.stack([cols, rows], axis=-1)) / world.static_map.cell_size).astype(int)
        blocked = world.static_map.blocked
        ok = ((cells[..., 0] >= 0) & (cells[..., 1] >= 0) & (cells[..., 0] < blocked.shape[1])
              & (cells[..., 1] < blocked.shape[0]))
        hit = np.zeros(ok.shape, bool)
        hit[ok] = blocked[cells[..., 1][ok], cells[..., 0][ok]]
        image[hit] = palette.static
    obstacles = (np.array([o.start for o in world.moving_obstacles], float).reshape(-1, 2)
                 if obstacle_positions is None else np.asarray(obstacle_positions, float).reshape(-1, 2))
    for ob, p in zip(world.moving_obstacles, obstacles):
        _paint(image, ob.placed(p), palette.moving, frame)
    min_r = min_radius_px / frame.pixels_per_unit
    for robot, p in zip(world.robots, np.asarray(robot_positions, float).reshape(-1, 2)):
        _paint(image, Circle((float(p[0]), float(p[1])), max(robot.radius, min_r)), palette.robot, frame)
    return image


def add_noise(image: ArrayLike, sigma: float, rng: np.random.Generator) -> NDArray[np.uint8]:
    """The image with Gaussian noise of standard deviation ``sigma`` (8-bit levels) added to
    every channel, clipped to [0, 255]."""
    noisy = np.asarray(image, float) + rng.normal(0.0, sigma, np.shape(image))
    return np.clip(np.rint(noisy), 0, 255).astype(np.uint8)


def save_png(image: ArrayLike, path: str | Path) -> Path:
    """Write an RGB image (height, width, 3) as PNG (Pillow); returns the path."""
    from PIL import Image

    path = Path(path)
    Image.fromarray(np.ascontiguousarray(image, np.uint8)).save(path, format="PNG")
    return path
