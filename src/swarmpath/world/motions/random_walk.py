"""``random-walk``: each step one of the 8 grid directions, drawn at random among the free
ones, at the obstacle's speed per axis (one cell per step by default)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swarmpath.registry import register_motion
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext

GRID_DIRECTIONS = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float)


@register_motion("random-walk")
@dataclass(frozen=True)
class RandomWalk(Motion):
    """A random free grid step (dx, dy in {-1, 0, 1}, not both 0) times the step length
    ``speed * dt`` (``resolution * dt`` for an obstacle without speed); it stays when boxed in."""

    kind = "random-walk"
    forecast = "random-walk"
    stays_clear = True

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        speed = ob.speed or ctx.terrain.resolution
        for d in ctx.rng.permutation(GRID_DIRECTIONS):
            cand = position + d * speed * ctx.terrain.dt
            if ctx.terrain.obstacle_fits(ob, cand[None])[0]:
                return cand, d * speed, counter
        return position, velocity, counter

    def max_step(self, ob: Footprinted, dt: float, resolution: float) -> float:
        """A diagonal grid step: sqrt(2) times the step length."""
        return math.sqrt(2.0) * (ob.speed or resolution) * dt
