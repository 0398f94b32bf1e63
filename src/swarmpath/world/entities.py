"""Robots and danger zones: the plain records a World holds."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Robot:
    """A robot: a disc of ``radius`` (0 = a point robot that occupies its grid cell) that must
    travel from ``start`` to ``goal`` moving at most ``max_speed`` world units per time unit."""

    id: str
    start: tuple[float, float]
    goal: tuple[float, float]
    radius: float = 0.0
    max_speed: float = 1.5

    def to_dict(self) -> dict:
        return {"id": self.id, "start": list(self.start), "goal": list(self.goal),
                "radius": self.radius, "max_speed": self.max_speed}


@dataclass(frozen=True)
class DangerZone:
    """A region to keep away from (Abbas & Abdulsahab, section 2.1): a centre, a radius inside
    which a path counts as exposed, and a weight for weighted objectives."""

    center: tuple[float, float]
    radius: float = 0.0
    weight: float = 1.0
    id: str = ""

    def to_dict(self) -> dict:
        return {"center": list(self.center), "radius": self.radius, "weight": self.weight}
