"""Moving obstacles and their motion models.

A moving obstacle has a footprint (a disc or an axis-aligned box centred on its position), an
initial position and velocity, and a motion model. Obstacles never react to robots (as in the
papers); they only respect the workspace and the static obstacles.

Motion models (``motion:`` in scenario files):

- ``bounce``: constant velocity; on hitting the boundary or a static obstacle the velocity
  component(s) that caused it are reflected.
- ``bounce8``: one of 8 compass directions at constant speed; on a hit a new free direction is
  drawn at random (Jaleel & Hassan 2016, section III.2.A).
- ``turn-every``: straight lines, a new random heading every ``period`` steps, bouncing in
  between (PSO-prediction paper, section 6).
- ``random-walk``: each step one of the 8 directions at random (a free one).
- ``redraw``: each step the obstacle reappears at a random free cell (Karim 2014), never on a
  robot's cell or goal cell.
- ``waypoints``: moves toward the next of ``points`` at its speed, looping if ``loop``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.world.shapes import Circle, Rect

if TYPE_CHECKING:  # pragma: no cover
    from swarmpath.world.world import World

FloatArray = NDArray[np.float64]

EIGHT_DIRECTIONS = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float)
EIGHT_DIRECTIONS /= np.linalg.norm(EIGHT_DIRECTIONS, axis=1, keepdims=True)


@dataclass(frozen=True)
class Bounce:
    kind: str = field(default="bounce", init=False)


@dataclass(frozen=True)
class Bounce8:
    kind: str = field(default="bounce8", init=False)


@dataclass(frozen=True)
class TurnEvery:
    period: int = 10
    kind: str = field(default="turn-every", init=False)


@dataclass(frozen=True)
class RandomWalk:
    kind: str = field(default="random-walk", init=False)


@dataclass(frozen=True)
class Redraw:
    kind: str = field(default="redraw", init=False)


@dataclass(frozen=True)
class Waypoints:
    points: tuple[tuple[float, float], ...] = ()
    loop: bool = True
    kind: str = field(default="waypoints", init=False)


Motion = Union[Bounce, Bounce8, TurnEvery, RandomWalk, Redraw, Waypoints]


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
        motion: dict = {"motion": self.motion.kind}
        if isinstance(self.motion, TurnEvery):
            motion["period"] = self.motion.period
        if isinstance(self.motion, Waypoints):
            motion["points"] = [list(p) for p in self.motion.points]
            motion["loop"] = self.motion.loop
        return {"id": self.id, "shape": shape, "start": list(self.start), "velocity": list(self.velocity), **motion}


@dataclass(frozen=True)
class ObstacleState:
    """Positions and velocities of all moving obstacles at one step: arrays of shape (m, 2)."""

    positions: FloatArray
    velocities: FloatArray
    step: int
    waypoint_index: NDArray[np.int64]


def initial_obstacle_state(world: "World") -> ObstacleState:
    """The obstacles' state at step 0, as the scenario gives it."""
    obs = world.moving_obstacles
    return ObstacleState(
        positions=np.array([o.start for o in obs], float).reshape(-1, 2),
        velocities=np.array([o.velocity for o in obs], float).reshape(-1, 2),
        step=0,
        waypoint_index=np.zeros(len(obs), dtype=np.int64),
    )


def advance_obstacles(world: "World", state: ObstacleState, rng: np.random.Generator,
                      keep_clear: FloatArray | None = None) -> ObstacleState:
    """Move every obstacle one step of ``world.dt`` by its motion model.

    ``keep_clear`` (points, shape (k, 2)) are cells a ``redraw`` obstacle must not appear on
    (robots' positions and goals). Other models ignore robots entirely.
    """
    dt = world.dt
    pos = state.positions.copy()
    vel = state.velocities.copy()
    wp = state.waypoint_index.copy()
    step = state.step + 1
    available: NDArray[np.bool_] | None = None   # cells a redraw obstacle may appear on
    fits: dict = {}                               # footprint -> which cell centres it fits
    for i, ob in enumerate(world.moving_obstacles):
        m = ob.motion
        if isinstance(m, Redraw):
            if available is None:
                available = _redraw_available(world, keep_clear)
            pos[i] = _redraw_position(world, ob, rng, available, fits)
            _mark_taken(world, available, pos[i])
            continue
        if isinstance(m, Waypoints):
            pos[i], vel[i], wp[i] = _waypoint_step(ob, m, pos[i], int(wp[i]), dt)
            continue
        if isinstance(m, RandomWalk):
            speed = ob.speed or world.resolution
            dirs = rng.permutation(_grid_directions())
            for d in dirs:
                cand = pos[i] + d * speed * dt
                if world.obstacle_fits(ob, cand[None])[0]:
                    pos[i], vel[i] = cand, d * speed
                    break
            continue
        if isinstance(m, TurnEvery) and step % max(1, m.period) == 0:
            angle = rng.uniform(0.0, 2 * np.pi)
            vel[i] = ob.speed * np.array([np.cos(angle), np.sin(angle)])
        pos[i], vel[i] = _bounce_step(world, ob, pos[i], vel[i], dt, rng, eight=isinstance(m, Bounce8))
    return ObstacleState(pos, vel, step, wp)


def _grid_directions() -> FloatArray:
    return np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float)


def _bounce_step(world: "World", ob: MovingObstacle, p: FloatArray, v: FloatArray, dt: float,
                 rng: np.random.Generator, eight: bool) -> tuple[FloatArray, FloatArray]:
    if not np.any(v):
        return p, v
    cand = p + v * dt
    if world.obstacle_fits(ob, cand[None])[0]:
        return cand, v
    if eight:
        steps = EIGHT_DIRECTIONS * float(np.hypot(*v))
        cands = p + steps * dt
        ok = world.obstacle_fits(ob, cands)
        current = np.all(np.isclose(steps, v), axis=1)
        choices = np.flatnonzero(ok & ~current)
        if len(choices) == 0:
            return p, -v
        k = int(rng.choice(choices))
        return cands[k], steps[k]
    flips = np.array([[-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]])
    options = v * flips
    cands = p + options * dt
    ok = world.obstacle_fits(ob, cands)
    if ok.any():
        k = int(np.argmax(ok))
        return cands[k], options[k]
    return p, -v


def _waypoint_step(ob: MovingObstacle, m: Waypoints, p: FloatArray, k: int, dt: float
                   ) -> tuple[FloatArray, FloatArray, int]:
    if not m.points or k >= len(m.points):
        return p, np.zeros(2), k
    budget = ob.speed * dt
    start = p.copy()
    while budget > 1e-12 and k < len(m.points):
        target = np.asarray(m.points[k], float)
        gap = float(np.linalg.norm(target - p))
        if gap <= budget:
            p, budget = target, budget - gap
            k += 1
            if k >= len(m.points) and m.loop:
                k = 0
            if gap == 0 and budget == ob.speed * dt:
                break
        else:
            p = p + (target - p) * (budget / gap)
            budget = 0.0
    return p, (p - start) / dt, k


def _redraw_available(world: "World", keep_clear: FloatArray | None) -> NDArray[np.bool_]:
    """Free cells of the world's grid minus the cells of ``keep_clear`` points (robots and
    their goals), shape (height, width); redrawn obstacles then take cells out one by one."""
    grid = world.grid()
    free = ~grid.blocked.copy()
    if keep_clear is not None:
        _mark_taken(world, free, keep_clear)
    return free


def _mark_taken(world: "World", available: NDArray[np.bool_], points: ArrayLike) -> None:
    """Take the cells of ``points`` (shape (k, 2)) out of ``available``."""
    res = world.grid().resolution
    h, w = available.shape
    for x, y in np.asarray(points, float).reshape(-1, 2):
        cx, cy = math.floor(x / res + 1e-9), math.floor(y / res + 1e-9)   # OccupancyGrid.cell_of
        if 0 <= cx < w and 0 <= cy < h:
            available[cy, cx] = False


def _redraw_position(world: "World", ob: MovingObstacle, rng: np.random.Generator,
                     available: NDArray[np.bool_], fits: dict) -> FloatArray:
    """A uniformly random available cell centre where the footprint fits (``ob.start`` if
    none). ``fits`` caches, per footprint, whether it fits at every cell centre."""
    grid = world.grid()
    ys, xs = np.nonzero(available)
    if len(xs) == 0:
        return np.asarray(ob.start, float)
    order = rng.permutation(len(xs))
    key = ob.shape if isinstance(ob.shape, Rect) else Circle((0.0, 0.0), ob.shape.radius)
    fit = fits.get(key)
    if fit is None:
        h, w = available.shape
        every = grid.centers(np.stack(np.meshgrid(np.arange(w), np.arange(h), indexing="xy"), axis=-1).reshape(-1, 2))
        fit = fits[key] = world.obstacle_fits(ob, every).reshape(h, w)
    ok = fit[ys[order], xs[order]]
    if ok.any():
        k = int(order[int(np.argmax(ok))])
        return grid.centers(np.array([xs[k], ys[k]]))
    return np.asarray(ob.start, float)
