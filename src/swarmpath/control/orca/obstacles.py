"""What a robot must keep clear of a moving obstacle during its next step.

The simulator moves obstacles first and robots second in every step (see
:mod:`swarmpath.sim.collisions`). A controller acting at step t sees each obstacle at ``now``
(after its move of step t) and one step earlier; the robot's move then has two dangers:

- *phase 2 of this step*: the robot's swept disc must avoid the footprint standing at ``now``;
- *phase 1 of the next step*: the robot's end disc must avoid every position the obstacle can
  take on its next move: the segment ``now -> next`` grown by ``reach`` (``reach = 0`` for a
  predictable move; the whole one-step reach disc, ``next = now``, when the motion model may
  turn). A ``redraw`` obstacle jumps to a random free cell that holds no robot and no robot's
  goal: :class:`RedrawGuard` tells which end positions such a jump could hit.

:func:`forecast_obstacles` gives this forecast for every obstacle. The worst case per motion
model lives in one private function, :func:`_worst_case_next`, which reads the motion-model
registry's own declarations (``max_step``, ``teleports``, ``forecast``), so a new model is
handled safely (its whole reach disc) without code here. Rectangular footprints are treated
exactly for phase 2 and as their bounding disc (radius ``extent``) for phase 1.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmpath.world.shapes import Circle

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Motion models (``obstacle.motion.kind``) that keep their heading between known events
#: (a bounce, a turning step, a route corner): their next move may be predicted as straight on.
STRAIGHT = ("bounce", "bounce8", "turn-every", "waypoints")


def teleports(ob) -> bool:
    """Whether obstacle ``ob``'s motion model jumps instead of travelling (``redraw``)."""
    return bool(getattr(ob.motion, "teleports", False))


@dataclass(frozen=True)
class ObstacleForecast:
    """The moving obstacles at one step, arrays over obstacles (m,).

    now : (m, 2) positions after their move of this step
    next : (m, 2) end of the next move's sweep (= now when unknown)
    reach : (m,) radius around the sweep ``now -> next`` the next move may also cover
    velocity : (m, 2) predicted velocity (0 for unpredictable and jumping obstacles)
    extent : (m,) radius of the disc that covers each footprint
    jumping : (m,) redraw obstacles (their next position is anywhere; see RedrawGuard)
    next2, reach2 : (m, 2), (m,) the same for the move after next, which starts anywhere the
        next one may end (its sweep ``next -> next2`` grown by ``reach2``)
    """

    now: FloatArray
    next: FloatArray
    reach: FloatArray
    velocity: FloatArray
    extent: FloatArray
    jumping: BoolArray
    next2: FloatArray | None = None
    reach2: FloatArray | None = None


def _worst_case_next(ob, world, now: FloatArray, prev: FloatArray, step: int, dt: float
                     ) -> tuple[FloatArray, float]:
    """(end of the next sweep, extra reach) of obstacle ``ob`` seen at ``now`` after moving
    from ``prev`` at observation ``step``.

    The reach is the motion model's own worst case (``ob.max_step``: ``speed * dt`` for the
    travelling models, ``sqrt(2)`` times the step length for ``random-walk``). A straight
    move continues only for the models known to keep their heading (``bounce``,
    ``bounce8``, ``turn-every`` between turning steps, ``waypoints`` on a straight leg), when
    the obstacle moved exactly one step last time and the continued footprint fits (no
    bounce); otherwise, and for every other model (``forecast`` "random-walk" or
    "any-heading", e.g. ``orbit``), the whole disc of one step's reach around ``now`` is
    kept clear. Teleporting models are not handled here (see :class:`RedrawGuard`).
    """
    kind = getattr(ob.motion, "kind", "")
    reach = float(ob.max_step(dt, float(world.resolution)))
    if kind not in STRAIGHT or getattr(ob.motion, "forecast", "any-heading") == "random-walk":
        return now.copy(), reach
    speed = float(ob.speed)
    if speed == 0.0:
        return now.copy(), 0.0
    if kind == "turn-every" and ob.motion.steady_steps(step) == 0:   # step + 1 turns
        return now.copy(), reach
    moved = now - prev
    one = speed * dt
    if abs(float(np.hypot(*moved)) - one) > 1e-9 * max(1.0, one):
        return now.copy(), reach                     # stopped or turned last step: heading unknown
    cand = now + moved
    if kind == "waypoints" and not _on_straight_leg(ob, now, moved):
        return now.copy(), reach
    if not bool(world.obstacle_fits(ob, cand[None])[0]):
        return now.copy(), reach                     # it bounces next step
    return cand, 0.0


def _on_straight_leg(ob, now: FloatArray, moved: FloatArray) -> bool:
    """Whether a waypoint route continues straight for one more step from ``now``: some
    route point lies ahead on the ray of ``moved`` at least one step away."""
    length = float(np.hypot(*moved))
    unit = moved / length
    for q in ob.motion.points:
        rel = np.asarray(q, float) - now
        ahead = float(rel @ unit)
        off = abs(float(rel[0] * unit[1] - rel[1] * unit[0]))
        if ahead >= length - 1e-9 and off <= 1e-9 * max(1.0, ahead):
            return True
    return False


def forecast_obstacles(world, now: FloatArray, prev: FloatArray, step: int, dt: float) -> ObstacleForecast:
    """The :class:`ObstacleForecast` of all moving obstacles of ``world`` from their positions
    ``now`` and ``prev`` (both (m, 2)) at observation ``step``."""
    now = np.asarray(now, float).reshape(-1, 2)
    prev = np.asarray(prev, float).reshape(-1, 2)
    m = len(now)
    nxt = now.copy()
    reach = np.zeros(m)
    jumping = np.zeros(m, bool)
    extent = np.array([ob.extent for ob in world.moving_obstacles], float).reshape(m)
    for j, ob in enumerate(world.moving_obstacles):
        if teleports(ob):
            jumping[j] = True
            continue
        nxt[j], reach[j] = _worst_case_next(ob, world, now[j], prev[j], step, dt)
    velocity = np.where((reach == 0)[:, None] & ~jumping[:, None], (nxt - now) / dt, 0.0)
    # the move after next: a predictable move continues the model from `next`; after an
    # unpredictable one the obstacle may be anywhere in the reach disc, and then moves again
    nxt2 = nxt.copy()
    reach2 = 2 * reach
    for j, ob in enumerate(world.moving_obstacles):
        if not jumping[j] and reach[j] == 0 and np.any(nxt[j] != now[j]):
            nxt2[j], extra = _worst_case_next(ob, world, nxt[j], now[j], step + 1, dt)
            if extra > 0:
                nxt2[j], reach2[j] = nxt[j], extra
    return ObstacleForecast(now, nxt, reach, velocity, extent, jumping, nxt2, reach2)


def footprint_offsets(world, now: FloatArray, positions: FloatArray, owner: NDArray[np.int64],
                      obstacle: NDArray[np.int64]) -> FloatArray:
    """Vector from each robot ``positions[owner]`` to the closest point of obstacle
    ``obstacle``'s footprint standing at ``now`` (exact for discs and boxes), (e, 2)."""
    out = np.zeros((len(owner), 2))
    for j in np.unique(obstacle):
        rows = np.flatnonzero(obstacle == j)
        ob = world.moving_obstacles[j]
        p = positions[owner[rows]]
        if isinstance(ob.shape, Circle):
            rel = now[j] - p
            d = np.linalg.norm(rel, axis=1)
            scale = np.where(d > 1e-12, (d - ob.shape.radius) / np.maximum(d, 1e-12), 0.0)
            out[rows] = rel * scale[:, None]
        else:
            lo = now[j] + np.asarray(ob.shape.min, float)
            hi = now[j] + np.asarray(ob.shape.max, float)
            out[rows] = np.clip(p, lo, hi) - p
    return out


class RedrawGuard:
    """Where a ``redraw`` obstacle may appear next: the centres of free cells of the world's
    grid where its footprint fits, except cells holding a robot (after this step's moves) or
    a robot's goal, as the simulator draws them (:mod:`swarmpath.world.moving`).

    :meth:`danger` says which robot end positions such an appearance would touch. A
    teleporting obstacle that may land on robots (``redraw`` with ``avoid_robots: false``,
    the paper's uniform redraw) can hit a robot wherever it stands: no end position is safer
    than another, so it is left out (its hits are counted, not avoided)."""

    def __init__(self, world):
        self.world = world
        grid = world.grid()
        self.grid = grid
        self.res = float(grid.resolution)
        h, w = grid.blocked.shape
        cells = np.stack(np.meshgrid(np.arange(w), np.arange(h), indexing="xy"), axis=-1).reshape(-1, 2)
        centres = grid.centers(cells)
        self.fits: dict[int, NDArray[np.bool_]] = {}
        for j, ob in enumerate(world.moving_obstacles):
            if teleports(ob) and getattr(ob.motion, "avoid_robots", True):
                self.fits[j] = (~grid.blocked) & world.obstacle_fits(ob, centres).reshape(h, w)
        self.goal_cells = grid.cell_of(world.goals) if world.n_robots else np.zeros((0, 2), np.int64)

    def danger(self, ends: FloatArray, radii: FloatArray) -> BoolArray:
        """Whether a redraw obstacle appearing next on some cell it may take would overlap a
        robot's disc at ``ends`` (k, 2) with ``radii`` (k,). The robot's own end cell and
        every goal cell are excluded (the simulator never draws them); other robots' cells
        are not (conservative: they may leave)."""
        ends = np.asarray(ends, float).reshape(-1, 2)
        radii = np.asarray(radii, float).reshape(-1)
        out = np.zeros(len(ends), bool)
        if not self.fits or not len(ends):
            return out
        h, w = self.grid.blocked.shape
        taken = np.zeros((h, w), bool)
        ok = self.grid.contains_cells(self.goal_cells)
        taken[self.goal_cells[ok, 1], self.goal_cells[ok, 0]] = True
        base = self.grid.cell_of(ends)
        for j, fit in self.fits.items():
            ob = self.world.moving_obstacles[j]
            avail = fit & ~taken
            span = int(np.ceil((ob.extent + float(radii.max(initial=0.0))) / self.res)) + 1
            off = np.arange(-span, span + 1)
            ox, oy = np.meshgrid(off, off, indexing="xy")
            ox, oy = ox.ravel(), oy.ravel()
            cx = base[:, None, 0] + ox[None]
            cy = base[:, None, 1] + oy[None]
            inside = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
            cand = np.zeros(cx.shape, bool)
            cand[inside] = avail[cy[inside], cx[inside]]
            cand[:, (ox == 0) & (oy == 0)] = False          # the robot's own cell
            centre = (np.stack([cx, cy], axis=-1) + 0.5) * self.res
            p = ends[:, None, :]
            r = radii[:, None]
            if isinstance(ob.shape, Circle):
                gap = np.linalg.norm(centre - p, axis=-1) - ob.shape.radius
            else:
                lo = centre + np.asarray(ob.shape.min, float)
                hi = centre + np.asarray(ob.shape.max, float)
                gap = np.linalg.norm(np.maximum(np.maximum(lo - p, p - hi), 0.0), axis=-1)
            out |= np.any(cand & (gap < np.maximum(r, 1e-9)), axis=1)
        return out
