"""``bounce``: constant velocity; on hitting the boundary or a static obstacle the velocity
component(s) that caused it are reflected."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from swarmpath.registry import register_motion
from swarmpath.world.motions._straight import straight_step
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext


@register_motion("bounce")
@dataclass(frozen=True)
class Bounce(Motion):
    """Straight lines at the obstacle's velocity, reflected off walls (a billiard ball)."""

    kind = "bounce"
    forecast = "bounce"
    stays_clear = True
    #: On a hit: a random free compass direction (True) instead of a reflection.
    new_direction_on_hit: ClassVar[bool] = False

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        p, v = straight_step(ctx.terrain, ob, position, velocity, ctx.terrain.dt, ctx.rng,
                             eight=self.new_direction_on_hit)
        return p, v, counter
