"""Moving obstacles: a footprint, a start, a velocity and a motion model, and the state of all
of them during a run.

A moving obstacle has a footprint (a disc, or an axis-aligned box centred on its position),
an initial position and velocity, and a motion model from :mod:`swarmpath.world.motions`
(``bounce``, ``bounce8``, ``turn-every``, ``random-walk``, ``redraw``, ``waypoints``, or any
registered model). Obstacles never react to robots (as in the papers); they only respect
the workspace and the static obstacles.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Union

import numpy as np
from numpy.typing import NDArray

from swarmpath.world.motions import Bounce, Bounce8, Motion, RandomWalk, Redraw, StepContext, TurnEvery, Waypoints
from swarmpath.world.motions.base import Terrain
from swarmpath.world.shapes import Circle, Rect

FloatArray = NDArray[np.float64]

__all__ = ["MovingObstacle", "ObstacleState", "initial_obstacle_state", "advance_obstacles", "Motion",
           "Bounce", "Bounce8", "TurnEvery", "RandomWalk", "Redraw", "Waypoints"]


@dataclass(frozen=True)
class MovingObstacle:
    """A moving obstacle: ``shape`` is a disc (its ``center`` ignored) or a box given by its
    ``min``/``max`` corners relative to the obstacle's position."""

    id: str
    shape: Union[Circle, Rect]
    start: tuple[float, float]
    velocity: tuple[float, float] = (0.0, 0.0)
    motion: Motion = field(default_factory=Bounce)

    @property
    def speed(self) -> float:
        return float(np.hypot(*self.velocity))

    @cached_property
    def extent(self) -> float:
        """Radius of the smallest disc around the position that covers the footprint."""
        if isinstance(self.shape, Circle):
            return self.shape.radius
        return float(np.max(np.linalg.norm([self.shape.min, self.shape.max], axis=1)))

    def max_step(self, dt: float, resolution: float) -> float:
        """The farthest the position can move in one step (``inf`` when it teleports)."""
        return self.motion.max_step(self, dt, resolution)

    def placed(self, position: tuple[float, float] | FloatArray) -> Union[Circle, Rect]:
        """The footprint at ``position``."""
        x, y = float(position[0]), float(position[1])
        if isinstance(self.shape, Circle):
            return Circle((x, y), self.shape.radius)
        return Rect((x + self.shape.min[0], y + self.shape.min[1]), (x + self.shape.max[0], y + self.shape.max[1]))

    def to_dict(self) -> dict:
        if isinstance(self.shape, Circle):
            shape = {"type": "circle", "radius": self.shape.radius}
        else:  # scenario files describe a centred box by its width and height
            shape = {"type": "rectangle", "width": self.shape.max[0] - self.shape.min[0],
                     "height": self.shape.max[1] - self.shape.min[1]}
        return {"id": self.id, "shape": shape, "start": list(self.start), "velocity": list(self.velocity),
                **self.motion.to_dict()}


@dataclass(frozen=True)
class ObstacleState:
    """Positions and velocities of all moving obstacles at one step (arrays of shape (m, 2))
    and one integer of motion state each (``counters``, e.g. a waypoint index)."""

    positions: FloatArray
    velocities: FloatArray
    step: int
    counters: NDArray[np.int64]


def initial_obstacle_state(world) -> ObstacleState:
    """The obstacles' state at step 0, as the scenario gives it."""
    obs = world.moving_obstacles
    return ObstacleState(
        positions=np.array([o.start for o in obs], float).reshape(-1, 2),
        velocities=np.array([o.velocity for o in obs], float).reshape(-1, 2),
        step=0,
        counters=np.zeros(len(obs), dtype=np.int64),
    )


def advance_obstacles(world: Terrain, state: ObstacleState, rng: np.random.Generator,
                      keep_clear: FloatArray | None = None) -> ObstacleState:
    """Move every obstacle one step of ``world.dt`` by its motion model, in order.

    ``keep_clear`` (points, shape (k, 2)): robots' positions and goals, which models that
    avoid robots (``redraw`` by default) keep off. Other models ignore robots entirely.
    """
    pos = state.positions.copy()
    vel = state.velocities.copy()
    counters = state.counters.copy()
    ctx = StepContext(world, rng, state.step + 1, keep_clear)
    for i, ob in enumerate(world.moving_obstacles):
        pos[i], vel[i], counters[i] = ob.motion.advance(ob, pos[i], vel[i], int(counters[i]), ctx)
    return ObstacleState(pos, vel, ctx.step, counters)
