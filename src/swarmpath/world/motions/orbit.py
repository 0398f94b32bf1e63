"""``orbit``: the obstacle circles ``center`` on the circle through its start, at its speed,
counter-clockwise (or clockwise with ``clockwise: true``): a patrol around a fixed point."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np
from pydantic import Field

from swarmpath.errors import ScenarioError
from swarmpath.registry import register_motion
from swarmpath.world.fields import StrictBool, Vec2
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext, Terrain


@register_motion("orbit")
@dataclass(frozen=True)
class Orbit(Motion):
    """Uniform circular motion around ``center``: each step the angle grows by
    speed * dt / radius (the arc travelled equals one step of travel; the chord is shorter)."""

    center: tuple[float, float] = (0.0, 0.0)
    clockwise: bool = False
    kind = "orbit"
    parameters = {
        "center": (Optional[Vec2], Field(None, description="orbit: the point circled")),
        "clockwise": (Optional[StrictBool], Field(None, description="orbit: turn clockwise (default false)")),
    }

    @classmethod
    def example(cls) -> "Orbit":
        return cls((5.0, 5.0))

    @classmethod
    def from_parameters(cls, values: Mapping[str, Any]) -> "Orbit":
        if values.get("center") is None:
            raise ScenarioError("orbit motion needs a center", field="center")
        return cls(tuple(float(v) for v in values["center"]), bool(values.get("clockwise") or False))

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        c = np.asarray(self.center, float)
        radius = math.dist(ob.start, self.center)
        if radius == 0.0:
            return position, np.zeros(2), counter
        angle = math.atan2(position[1] - c[1], position[0] - c[0])
        turn = (ob.speed * ctx.terrain.dt / radius) % (2 * math.pi)
        angle += -turn if self.clockwise else turn
        new = c + radius * np.array([math.cos(angle), math.sin(angle)])
        return new, (new - position) / ctx.terrain.dt, counter

    def to_dict(self) -> dict[str, Any]:
        return {"motion": self.kind, "center": list(self.center), "clockwise": self.clockwise}

    def check(self, ob: Any, terrain: Terrain, where: str) -> None:
        """The whole circle must be free for the footprint (sampled every quarter cell)."""
        radius = math.dist(ob.start, self.center)
        n = max(8, int(math.ceil(2 * math.pi * radius / (terrain.resolution / 4))))
        angles = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        ring = np.asarray(self.center, float) + radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        bad = ~terrain.obstacle_fits(ob, ring)
        if bad.any():
            x, y = ring[np.argmax(bad)]
            raise ScenarioError(f"the orbit passes ({x:g}, {y:g}), which overlaps a static obstacle or leaves "
                                "the workspace", field=f"{where}.center")
