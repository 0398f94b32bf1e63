"""``turn-every``: straight lines, a new random heading every ``period`` steps, bouncing in
between (PSO-prediction paper, 2013, section 6: the obstacle "changes its direction at
regular intervals")."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydantic import Field

from swarmpath.registry import register_motion
from swarmpath.world.fields import Count
from swarmpath.world.motions._straight import straight_step
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext


@register_motion("turn-every")
@dataclass(frozen=True)
class TurnEvery(Motion):
    """A uniformly random new heading (same speed) at every multiple of ``period`` steps."""

    period: int = 10
    kind = "turn-every"
    stays_clear = True
    parameters = {"period": (Optional[Count],
                             Field(None, description="turn-every: steps between turns (default 10)"))}

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        if ctx.step % max(1, self.period) == 0:
            angle = ctx.rng.uniform(0.0, 2 * np.pi)
            velocity = ob.speed * np.array([np.cos(angle), np.sin(angle)])
        p, v = straight_step(ctx.terrain, ob, position, velocity, ctx.terrain.dt, ctx.rng, eight=False)
        return p, v, counter

    def steady_steps(self, step: int) -> int:
        """Straight on (reflected where blocked, as ``bounce``) on every step up to the next
        multiple of ``period``, where it draws a new heading."""
        period = max(1, self.period)
        return (step // period + 1) * period - step - 1

    def to_dict(self) -> dict:
        return {"motion": self.kind, "period": self.period}
