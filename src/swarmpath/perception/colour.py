"""Colour recognition by RGB vector distance (PSO-prediction paper 2013, section 6, eq. 9).

A pixel of colour (R, G, B) is accepted as the reference colour t = (t_R, t_G, t_B) when

    D = sqrt((R - t_R)^2 + (G - t_G)^2 + (B - t_B)^2) < tolerance                 (eq. 9)

(the paper's pseudo-code: "compute the distance between that pixel and the reference color;
if D < Threshold the current pixel is accepted"). Accepted pixels are grouped into connected
regions (``scipy.ndimage.label``, 8-connectivity); each region's centroid is an object's
position, in pixels and, through a :class:`PixelFrame`, in world units.

Pixel conventions: an image is an array of shape (height, width, 3) (rows, columns, RGB);
pixel (row r, column c) covers the square [c, c + 1) x [r, r + 1) in pixel units, so its
centre is (c + 0.5, r + 0.5). Pixel x = column, y = row, like world coordinates (y grows
with the row index).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from swarmpath.errors import ConfigError

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PixelFrame:
    """How pixels map to the world: ``pixels_per_unit`` pixels per world unit, the world
    origin at pixel coordinates ``origin_px`` (x, y); no rotation, y grows with the row."""

    pixels_per_unit: float = 20.0
    origin_px: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if not self.pixels_per_unit > 0:
            raise ConfigError(f"pixels_per_unit must be > 0, got {self.pixels_per_unit}")

    def to_world(self, pixels: ArrayLike) -> FloatArray:
        """Pixel coordinates (..., 2) -> world coordinates (..., 2)."""
        return (np.asarray(pixels, float) - np.asarray(self.origin_px, float)) / self.pixels_per_unit

    def to_pixels(self, points: ArrayLike) -> FloatArray:
        """World coordinates (..., 2) -> pixel coordinates (..., 2)."""
        return np.asarray(points, float) * self.pixels_per_unit + np.asarray(self.origin_px, float)


@dataclass(frozen=True)
class Region:
    """One connected region of accepted pixels: its size, its centroid in pixel coordinates
    (x = column, y = row, pixel centres at +0.5) and in world coordinates."""

    n_pixels: int
    centroid_px: tuple[float, float]
    centroid: tuple[float, float]


def as_rgb(image: ArrayLike) -> FloatArray:
    """An image as float RGB of shape (height, width, 3); an alpha channel is dropped."""
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] not in (3, 4):
        raise ConfigError(f"an RGB image has shape (height, width, 3), got {a.shape}")
    return a[..., :3].astype(float)


def rgb_distance(image: ArrayLike, reference: ArrayLike) -> FloatArray:
    """Eq. 9: the Euclidean distance of every pixel's (R, G, B) to ``reference`` (3,).
    Returns (height, width)."""
    ref = np.asarray(reference, float).reshape(3)
    return np.sqrt(np.sum((as_rgb(image) - ref) ** 2, axis=2))


def colour_mask(image: ArrayLike, reference: ArrayLike, tolerance: float) -> NDArray[np.bool_]:
    """Pixels accepted as the reference colour: D < tolerance (eq. 9). (height, width)."""
    if not tolerance > 0:
        raise ConfigError(f"tolerance must be > 0, got {tolerance}")
    return rgb_distance(image, reference) < tolerance


def find_regions(image: ArrayLike, reference: ArrayLike, tolerance: float, *, frame: PixelFrame | None = None,
                 min_pixels: int = 1) -> list[Region]:
    """Connected regions (8-connected) of pixels within ``tolerance`` of ``reference``, with
    at least ``min_pixels`` pixels (smaller ones are noise), sorted by centroid (y, then x)."""
    frame = frame or PixelFrame()
    mask = colour_mask(image, reference, tolerance)
    labels, n = ndimage.label(mask, structure=np.ones((3, 3), bool))
    if n == 0:
        return []
    index = np.arange(1, n + 1)
    sizes = ndimage.sum_labels(np.ones_like(labels), labels, index)
    rows, cols = np.indices(labels.shape, dtype=float)
    cy = ndimage.mean(rows + 0.5, labels, index)
    cx = ndimage.mean(cols + 0.5, labels, index)
    regions = []
    for size, x, y in zip(sizes, cx, cy):
        if size < min_pixels:
            continue
        world = frame.to_world([x, y])
        regions.append(Region(int(size), (float(x), float(y)), (float(world[0]), float(world[1]))))
    return sorted(regions, key=lambda r: (r.centroid_px[1], r.centroid_px[0]))


def centroids(regions: list[Region]) -> FloatArray:
    """World-coordinate centroids of regions as an array (k, 2)."""
    return np.array([r.centroid for r in regions], float).reshape(-1, 2)


def load_image(path: str | Path) -> NDArray[np.uint8]:
    """An image file (PNG, BMP, ...) as a uint8 RGB array (height, width, 3) (Pillow)."""
    from PIL import Image

    try:
        with Image.open(path) as im:
            return np.asarray(im.convert("RGB"), dtype=np.uint8).copy()
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such image file") from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the image: {exc}") from None
