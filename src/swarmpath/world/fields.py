"""Field types of scenario files, shared by the scenario models and the motion models'
parameters: numbers are strict (``true`` or ``"10"`` is not a number), finite and within the
coordinate limit of :mod:`swarmpath.world.limits`; names are strings of bounded length."""
from __future__ import annotations

from typing import Annotated

from pydantic import Field, Strict

from swarmpath.world.limits import MAX_COORDINATE

Coordinate = Annotated[float, Strict(), Field(allow_inf_nan=False, ge=-MAX_COORDINATE, le=MAX_COORDINATE)]
Vec2 = tuple[Coordinate, Coordinate]
PositiveFloat = Annotated[float, Strict(), Field(gt=0, allow_inf_nan=False, le=MAX_COORDINATE)]
NonNegativeFloat = Annotated[float, Strict(), Field(ge=0, allow_inf_nan=False, le=MAX_COORDINATE)]
Name = Annotated[str, Strict(), Field(max_length=200)]
StrictBool = Annotated[bool, Strict()]
Count = Annotated[int, Strict(), Field(ge=1, le=10**9)]
