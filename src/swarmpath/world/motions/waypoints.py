"""``waypoints``: the obstacle travels toward the next of ``points`` at its speed, turning at
each point, and starts over from the first point after the last when ``loop`` is true (it
stops at the last point otherwise). A scripted route, checked to be free of static obstacles."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np
from pydantic import Field

from swarmpath.errors import ScenarioError
from swarmpath.registry import register_motion
from swarmpath.world.fields import StrictBool, Vec2
from swarmpath.world.limits import MAX_WAYPOINTS
from swarmpath.world.motions.base import FloatArray, Footprinted, Motion, StepContext, Terrain


@register_motion("waypoints")
@dataclass(frozen=True)
class Waypoints(Motion):
    """Travel along ``points`` at the obstacle's speed (``counter`` = index of the next point)."""

    points: tuple[tuple[float, float], ...] = ()
    loop: bool = True
    kind = "waypoints"
    scripted = True
    parameters = {
        "points": (Optional[list[Vec2]], Field(None, max_length=MAX_WAYPOINTS,
                                               description="waypoints: the points to visit")),
        "loop": (Optional[StrictBool], Field(None, description="waypoints: start over after the last point (default true)")),
    }

    @classmethod
    def example(cls) -> "Waypoints":
        return cls(((8.5, 1.5), (8.5, 8.5), (1.5, 8.5), (1.5, 1.5)), True)

    @classmethod
    def from_parameters(cls, values: Mapping[str, Any]) -> "Waypoints":
        points = tuple(tuple(float(v) for v in p) for p in (values.get("points") or ()))
        loop = values.get("loop")
        return cls(points, True if loop is None else bool(loop))

    def advance(self, ob: Footprinted, position: FloatArray, velocity: FloatArray, counter: int,
                ctx: StepContext) -> tuple[FloatArray, FloatArray, int]:
        dt = ctx.terrain.dt
        p, k = waypoint_travel(self.points, self.loop, position, counter, ob.speed * dt)
        return p, (p - position) / dt, k

    def to_dict(self) -> dict[str, Any]:
        return {"motion": self.kind, "points": [list(p) for p in self.points], "loop": self.loop}

    def check(self, ob: Any, terrain: Terrain, where: str) -> None:
        """Every point finite, and the whole route (with the way back to the first point when
        looping) free for the footprint, sampled every quarter cell."""
        if not self.points:
            raise ScenarioError("waypoints motion needs at least one point", field=f"{where}.points")
        route = np.asarray([ob.start, *self.points] + ([self.points[0]] if self.loop else []), float)
        if not np.all(np.isfinite(route)):
            raise ScenarioError("must be finite numbers", field=f"{where}.points")
        for k in range(len(route) - 1):
            a, b = route[k], route[k + 1]
            n = max(2, int(np.ceil(np.linalg.norm(b - a) / (terrain.resolution / 4))) + 1)
            pts = a + np.linspace(0, 1, n)[:, None] * (b - a)
            bad = ~terrain.obstacle_fits(ob, pts)
            if bad.any():
                x, y = pts[np.argmax(bad)]
                raise ScenarioError(f"the route passes ({x:g}, {y:g}), which overlaps a static obstacle "
                                    "or leaves the workspace", field=f"{where}.points")


def waypoint_travel(points: tuple[tuple[float, float], ...], loop: bool, p: FloatArray, k: int, budget: float
                    ) -> tuple[FloatArray, int]:
    """Move ``p`` up to ``budget`` along the route toward ``points[k]`` and on; returns the
    new position and the index of the next point. Bounded whatever the numbers: a budget
    longer than a whole loop is first reduced by whole loops, so one step visits each point
    at most twice."""
    if not points or k >= len(points):
        return p, k
    p = np.asarray(p, float)
    full = budget
    if loop and len(points) > 1 and np.isfinite(budget):
        ring = np.asarray(points, float)
        perimeter = float(np.linalg.norm(np.diff(np.vstack([ring, ring[:1]]), axis=0), axis=1).sum())
        first = float(np.linalg.norm(ring[k] - p))
        if perimeter > 0 and budget > 2 * perimeter + first:
            budget = first + perimeter + math.fmod(budget - first, perimeter)
    if not np.isfinite(budget):
        budget = 0.0
    for _ in range(2 * len(points) + 2):
        if not (budget > 1e-12 and k < len(points)):
            break
        target = np.asarray(points[k], float)
        gap = float(np.linalg.norm(target - p))
        if gap <= budget:
            p, budget = target, budget - gap
            k += 1
            if k >= len(points) and loop:
                k = 0
            if gap == 0 and budget == full:
                break
        else:
            p = p + (target - p) * (budget / gap)
            budget = 0.0
    return p, k
