"""Straight-line travel with reflections, shared by the bounce, bounce8 and turn-every models."""
from __future__ import annotations

import numpy as np

from swarmpath.world.motions.base import FloatArray, Footprinted, Terrain

#: The 8 compass directions as unit vectors (E, NE, N, NW, W, SW, S, SE).
EIGHT_DIRECTIONS = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float)
EIGHT_DIRECTIONS /= np.linalg.norm(EIGHT_DIRECTIONS, axis=1, keepdims=True)
#: Velocity flips tried, in order, when a straight move is blocked: x, y, both.
FLIPS = np.array([[-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]])


def straight_step(terrain: Terrain, ob: Footprinted, p: FloatArray, v: FloatArray, dt: float,
                  rng: np.random.Generator, eight: bool) -> tuple[FloatArray, FloatArray]:
    """Move ``p`` by ``v * dt`` when the footprint fits there. When it does not: with
    ``eight``, a random other compass direction at the same speed that fits (Jaleel & Hassan
    2016, III.2.A); else the first of the reflections (flip x, flip y, flip both) that fits.
    With nothing free the obstacle stays and reverses. Returns (position, velocity)."""
    if not np.any(v):
        return p, v
    cand = p + v * dt
    if terrain.obstacle_fits(ob, cand[None])[0]:
        return cand, v
    if eight:
        steps = EIGHT_DIRECTIONS * float(np.hypot(*v))
        cands = p + steps * dt
        ok = terrain.obstacle_fits(ob, cands)
        current = np.all(np.isclose(steps, v), axis=1)
        choices = np.flatnonzero(ok & ~current)
        if len(choices) == 0:
            return p, -v
        k = int(rng.choice(choices))
        return cands[k], steps[k]
    options = v * FLIPS
    cands = p + options * dt
    ok = terrain.obstacle_fits(ob, cands)
    if ok.any():
        k = int(np.argmax(ok))
        return cands[k], options[k]
    return p, -v
