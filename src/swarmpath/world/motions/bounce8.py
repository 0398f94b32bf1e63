"""``bounce8``: one of 8 compass directions at constant speed; on a hit a new free direction
is drawn at random (Jaleel & Hassan 2016, section III.2.A)."""
from __future__ import annotations

from dataclasses import dataclass

from swarmpath.registry import register_motion
from swarmpath.world.motions.bounce import Bounce


@register_motion("bounce8")
@dataclass(frozen=True)
class Bounce8(Bounce):
    """Straight on until blocked, then a random other compass direction that is free."""

    kind = "bounce8"
    forecast = "bounce8"
    stays_clear = True
    new_direction_on_hit = True
