"""``bounce8``: one of 8 compass directions at constant speed; on a hit a new free direction
is drawn at random (Jaleel & Hassan 2016, section III.2.A)."""
from __future__ import annotations

from dataclasses import dataclass

from swarmpath.registry import register_motion
from swarmpath.world.motions._straight import straight_step
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext


@register_motion("bounce8")
@dataclass(frozen=True)
class Bounce8(Motion):
    """Straight on until blocked, then a random other compass direction that is free."""

    kind = "bounce8"
    forecast = "bounce8"

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        p, v = straight_step(ctx.terrain, ob, position, velocity, ctx.terrain.dt, ctx.rng, eight=True)
        return p, v, counter
