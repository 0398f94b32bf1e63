"""``redraw``: each step the obstacle reappears at a uniformly random free cell centre where
its footprint fits (Karim 2014, "the obstacles are redrawn randomly at each step"), by
default never on a robot's cell or goal cell; ``avoid_robots: false`` is the paper's plain
uniform redraw.

Avoiding robots is our addition: with the plain redraw a robot can be hit where it stands
with no way to avoid it, and a goal can be covered for good. Redrawn obstacles of one step
never land on each other's cells."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import Field

from swarmpath.registry import register_motion
from swarmpath.world.fields import StrictBool
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext, Terrain
from swarmpath.world.shapes import Circle, Rect


@register_motion("redraw")
@dataclass(frozen=True)
class Redraw(Motion):
    """A teleport to a random free cell centre every step (the velocity is kept as given)."""

    avoid_robots: bool = True
    kind = "redraw"
    teleports = True
    forecast = "teleport"
    parameters = {"avoid_robots": (Optional[StrictBool], Field(None, description=(
        "redraw: never reappear on a robot's cell or goal cell (default true); false is the "
        "paper's uniform redraw")))}

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        terrain = ctx.terrain
        taken = ctx.scratch.get("redraw-taken")
        if taken is None:  # cells taken this step by redrawn obstacles (and, for most, by robots)
            taken = ctx.scratch["redraw-taken"] = terrain.grid().blocked.copy()
            robots = np.zeros_like(taken)
            if ctx.keep_clear is not None:
                mark_taken(terrain, robots, ctx.keep_clear)
            ctx.scratch["redraw-robots"] = robots
        robots = ctx.scratch["redraw-robots"]
        available = ~(taken | robots) if self.avoid_robots else ~taken
        fits = ctx.scratch.setdefault("redraw-fits", {})
        new = redraw_position(terrain, ob, ctx.rng, available, fits)
        mark_taken(terrain, taken, new)
        return new, velocity, counter

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"motion": self.kind}
        if not self.avoid_robots:
            out["avoid_robots"] = False
        return out

    def max_step(self, ob: Footprinted, dt: float, resolution: float) -> float:
        return math.inf


def mark_taken(terrain: Terrain, cells: NDArray[np.bool_], points: ArrayLike) -> None:
    """Mark the grid cells of ``points`` (shape (k, 2)) in ``cells`` (height, width)."""
    res = terrain.grid().resolution
    h, w = cells.shape
    for x, y in np.asarray(points, float).reshape(-1, 2):
        cx, cy = math.floor(x / res + 1e-9), math.floor(y / res + 1e-9)   # OccupancyGrid.cell_of
        if 0 <= cx < w and 0 <= cy < h:
            cells[cy, cx] = True


def redraw_position(terrain: Terrain, ob: Any, rng: np.random.Generator, available: NDArray[np.bool_],
                    fits: dict) -> FloatArray:
    """A uniformly random available cell centre where the footprint fits (``ob.start`` if
    none). ``fits`` caches, per footprint, whether it fits at every cell centre."""
    grid = terrain.grid()
    ys, xs = np.nonzero(available)
    if len(xs) == 0:
        return np.asarray(ob.start, float)
    order = rng.permutation(len(xs))
    key = ob.shape if isinstance(ob.shape, Rect) else Circle((0.0, 0.0), ob.shape.radius)
    fit = fits.get(key)
    if fit is None:
        h, w = available.shape
        every = grid.centers(np.stack(np.meshgrid(np.arange(w), np.arange(h), indexing="xy"), axis=-1).reshape(-1, 2))
        fit = fits[key] = terrain.obstacle_fits(ob, every).reshape(h, w)
    ok = fit[ys[order], xs[order]]
    if ok.any():
        k = int(order[int(np.argmax(ok))])
        return grid.centers(np.array([xs[k], ys[k]]))
    return np.asarray(ob.start, float)
