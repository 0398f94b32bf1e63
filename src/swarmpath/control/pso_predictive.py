"""Multi-robot PSO with linear prediction of moving obstacles, in continuous space
(controllers ``pso-predictive`` and ``pso-reactive``; PSO-prediction paper 2013, eq. 1-8).

Each step every robot i chooses its next position with a 10-particle PSO over its heading
theta and a speed fraction sigma in [0, 1] (eq. 1-2, speed up to ``max_speed``):

    x_i' = x_i + sigma v_i dt cos(theta),   y_i' = y_i + sigma v_i dt sin(theta)

minimising the objective of eq. 3-7 (the text's equations are garbled; the reading used is
written out in docs/papers/pso-prediction-2013.md):

    F_i = ||x_i' - g_i||                                             goal term (eq. 3)
        + f_dp sum_j min(0, ||x_i' - a_j|| - (r_i + r_j + eps))^2    kin term (eq. 5), a_j the
                                                                     announced/predicted next
                                                                     position of robot j
        + f_st [static clearance penalty on the local trajectory]    (eq. 6)
        + f_dy sum_m 1 / ||x_i' - p_m'||                             (eq. 7), p_m' the predicted
                                                                     next obstacle position
        + f_buf sum_m buffer(x_i', predicted path over 2 steps)      our addition (see below)
        + H (violation + [violation > 0])                            hard safety constraints

The hard constraints make a candidate unacceptable (H = 1000 dominates every soft term):
the swept disc of the move enters a static obstacle or leaves the workspace; the move comes
closer than r_i + r_j + eps to another robot (others stand still, or move along their
already decided segment: robots are resolved sequentially by index, the paper's "i-th
algorithm for the i-th robot"); the move passes through the obstacle's current footprint
(phase 2 of the simulator's step); and the end position lies where the obstacle will sweep
in the next step (phase 1 of the next step). Only the last one differs between the two
controllers:

- ``pso-predictive``: the obstacle's next sweep is the segment from its current position to
  its linear prediction (:mod:`swarmpath.control.prediction`); when the obstacle may turn at
  the next step (its turning period is not yet known, or the next step is a turning step) or
  the prediction is impossible (it would bounce off a wall), the whole disc it can reach in
  one step is kept clear instead (the "turn guard", our addition).
  The predictive controller also keeps, softly, one obstacle step of extra room around the
  obstacle's predicted path over the next ``buffer_steps`` steps (:func:`path_buffer_penalty`,
  our addition: without it robots crowd the obstacle's path and get cornered).
- ``pso-reactive``: the paper's "classical non-prediction approach": the obstacle is taken to
  stand where it is now (all terms use its current position; no guard, no buffer).

All robots' swarms run in one vectorised PSO (n_robots x 10 particles); a robot whose result
conflicts with the segment of a robot decided before it is solved again alone. The pure
kernels below carry the equations; the controller classes wire them to the simulator.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from swarmpath.control import prediction as pred
from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.errors import ConfigError
from swarmpath.capabilities import Capabilities
from swarmpath.registry import register_controller
from swarmpath.world import geometry as g
from swarmpath.planning.base import Plan
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

TWO_PI = 2.0 * np.pi


# ------------------------------------------------------------------------------ kernels
def wrap_angle(theta: FloatArray) -> FloatArray:
    """Angles wrapped to [-pi, pi)."""
    return (np.asarray(theta, float) + np.pi) % TWO_PI - np.pi


def next_position(position: FloatArray, theta: FloatArray, sigma: FloatArray, reach: FloatArray) -> FloatArray:
    """Eq. 1-2: x' = x + sigma v dt cos(theta), y' = y + sigma v dt sin(theta).

    position : (k, 2); theta, sigma : (k, p); reach : (k,) = v dt. Returns (k, p, 2).
    """
    step = (np.asarray(sigma, float) * np.asarray(reach, float)[:, None])[..., None]
    return position[:, None, :] + step * np.stack([np.cos(theta), np.sin(theta)], axis=-1)


def goal_distance(x_next: FloatArray, goal: FloatArray) -> FloatArray:
    """Eq. 3 (one robot's term): ||x' - g||; x_next (k, p, 2), goal (k, 2) -> (k, p)."""
    return _norm(x_next - goal[:, None, :])


def kin_penalty(x_next: FloatArray, pair_row: NDArray[np.int64], announced: FloatArray,
                separation: FloatArray) -> FloatArray:
    """Eq. 5, second term: sum_j min(0, d'_ij - (r_i + r_j + eps))^2 over sensed robots j.

    x_next (k, p, 2); one entry per sensed pair (i, j): pair_row (e,) the row i, announced
    (e, 2) robot j's announced/predicted next position, separation (e,) = r_i + r_j + eps.
    Returns (k, p).
    """
    out = np.zeros(x_next.shape[:2])
    if len(pair_row):
        diff = x_next[pair_row] - announced[:, None, :]
        d = np.sqrt(diff[..., 0] ** 2 + diff[..., 1] ** 2)
        short = np.minimum(0.0, d - separation[:, None])
        np.add.at(out, pair_row, short * short)
    return out


def inverse_obstacle_distance(x_next: FloatArray, target: FloatArray, mask: BoolArray,
                              floor: float = 1e-6) -> FloatArray:
    """Eq. 7, last term: sum_m 1 / ||x' - p_m'|| over sensed obstacles (the paper maximises
    the distance to the predicted position by minimising its inverse).

    x_next (k, p, 2); target (m, 2) predicted (or current) obstacle positions; mask (k, m).
    Returns (k, p).
    """
    if target.shape[0] == 0:
        return np.zeros(x_next.shape[:2])
    d = _norm(x_next[:, :, None, :] - target[None, None, :, :])
    return np.sum(np.where(mask[:, None, :], 1.0 / np.maximum(d, floor), 0.0), axis=-1)


def _origin_segment_distance(a: FloatArray, b: FloatArray) -> FloatArray:
    """Distance from the origin to segments a-b (broadcast over leading axes, last axis 2)."""
    ax, ay = a[..., 0], a[..., 1]
    dx, dy = b[..., 0] - ax, b[..., 1] - ay
    denom = dx * dx + dy * dy
    safe = np.where(denom > 0, denom, 1.0)
    t = np.clip(-(ax * dx + ay * dy) / safe, 0.0, 1.0)
    cx, cy = ax + t * dx, ay + t * dy
    return np.sqrt(cx * cx + cy * cy)


def _norm(v: FloatArray) -> FloatArray:
    """Euclidean norm over the last axis (of size 2)."""
    return np.sqrt(v[..., 0] * v[..., 0] + v[..., 1] * v[..., 1])


def point_segment_distance(p: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Distance from points p to segments a-b (broadcast, last axis 2)."""
    return _origin_segment_distance(a - p, b - p)


def path_buffer_penalty(x_next: FloatArray, start: FloatArray, end: FloatArray, need: FloatArray,
                        buffer: FloatArray) -> FloatArray:
    """Soft keep-away from a moving obstacle's predicted path over the next few steps (our
    addition to eq. 7): ((need + b - d) / b)^2 when the distance d from x' to the segment
    start-end is below need + b, else 0.

    x_next (k, p, 2); start, end (2,) the predicted path; need (k,) the contact distance
    R + r + margin; buffer b (scalar > 0). Returns (k, p).
    """
    d = _origin_segment_distance(start - x_next, end - x_next)
    short = np.maximum(0.0, need[:, None] + buffer - d) / buffer
    return short * short


def static_clearance_penalty(clearance: FloatArray, margin: float) -> FloatArray:
    """Eq. 6, static term as implemented: (margin - c)/margin for a disc whose clearance c to
    the nearest static obstacle is below ``margin`` (0 when clear, 1 when touching, more
    when penetrating); the paper's constant "f_st when a static obstacle is on the local
    trajectory" becomes a clearance-based ramp so that PSO has a slope to follow."""
    return np.maximum(0.0, margin - clearance) / margin


def pso_velocity_update_wrapped(v: FloatArray, x: FloatArray, pbest: FloatArray, gbest: FloatArray, w: float,
                                c1: float, c2: float, r1: FloatArray, r2: FloatArray) -> FloatArray:
    """Eq. 8: V(t+1) = w V(t) + C1 phi1 (P - X) + C2 phi2 (g - X), for particles (theta,
    sigma) whose heading is periodic: the heading differences are wrapped to [-pi, pi).

    v, x, pbest, r1, r2 : (k, p, 2); gbest : (k, 1, 2). Returns (k, p, 2).
    """
    dp = pbest - x
    dg = gbest - x
    dp[..., 0] = wrap_angle(dp[..., 0])
    dg[..., 0] = wrap_angle(dg[..., 0])
    return w * v + c1 * r1 * dp + c2 * r2 * dg


# ------------------------------------------------------------------------------ one step's problem
class StaticGeometry:
    """Fast static-obstacle queries for worlds made of circles and rectangles (no raster map,
    no polygons), with the same two methods as :class:`~swarmpath.world.World` that the
    objective needs. Slightly conservative: a move that only touches an obstacle counts as a
    hit. Use :func:`static_geometry` to get this or the world itself."""

    def __init__(self, world):
        from swarmpath.world.shapes import Circle

        circles = [o for o in world.obstacles if isinstance(o, Circle)]
        rects = [o for o in world.obstacles if not isinstance(o, Circle)]
        self.bounds = world.bounds
        self.centers = np.array([c.center for c in circles], float).reshape(-1, 2)
        self.rho = np.array([c.radius for c in circles], float)
        self.lo = np.array([r.min for r in rects], float).reshape(-1, 2)
        self.hi = np.array([r.max for r in rects], float).reshape(-1, 2)

    def near(self, points: FloatArray, distance: FloatArray) -> "StaticGeometry":
        """The same geometry keeping only the shapes closer than ``distance`` (k,) to some
        point of ``points`` (k, 2)."""
        out = object.__new__(StaticGeometry)
        out.bounds = self.bounds
        keep = np.any(_norm(points[:, None, :] - self.centers[None]) - self.rho < distance[:, None], axis=0)
        out.centers, out.rho = self.centers[keep], self.rho[keep]
        gap = g.point_box_distance(points[:, None, :], self.lo, self.hi)
        keep = np.any(gap < distance[:, None], axis=0)
        out.lo, out.hi = self.lo[keep], self.hi[keep]
        return out

    def static_clearance(self, points: FloatArray, radius: FloatArray) -> FloatArray:
        """Free distance between discs at points (N, 2) of radius (N,) and the nearest
        obstacle or the boundary."""
        best = self.bounds.clearance(points)
        if len(self.rho):
            d = _norm(points[:, None, :] - self.centers[None]) - self.rho
            best = np.minimum(best, d.min(axis=1))
        if len(self.lo):
            best = np.minimum(best, g.point_box_signed_distance(points[:, None, :], self.lo, self.hi).min(axis=1))
        return best - radius

    def static_hits(self, a: FloatArray, b: FloatArray, radius: FloatArray) -> BoolArray:
        """Whether discs moving a -> b (N, 2) touch an obstacle or leave the workspace."""
        hit = ~(self.bounds.contains(a, radius) & self.bounds.contains(b, radius))
        if len(self.rho):
            c = self.centers[None]
            d = _origin_segment_distance(a[:, None, :] - c, b[:, None, :] - c) - self.rho
            hit |= np.any(d < radius[:, None] + 1e-9, axis=1)
        if len(self.lo):
            d = g.segment_box_distance(a[:, None, :], b[:, None, :], self.lo, self.hi)
            hit |= np.any(d < radius[:, None] + 1e-9, axis=1)
        return hit


def static_geometry(world):
    """:class:`StaticGeometry` for worlds of circles and rectangles, else the world itself."""
    from swarmpath.world.shapes import Circle, Rect

    if world.static_map is None and all(isinstance(o, (Circle, Rect)) for o in world.obstacles):
        return StaticGeometry(world)
    return world


@dataclass(frozen=True)
class StepProblem:
    """The eq. 3-7 problem of k robots at one step (arrays indexed by those robots).

    start, goal : (k, 2); radius, reach : (k,) (reach = max_speed * dt)
    robot : (k,) index of each row's robot in the world
    Sensed robot pairs, one entry per pair (i, j), e pairs:
        pair_row (e,) the row of robot i; pair_other (e,) the index of robot j;
        pair_from, pair_to (e, 2) robot j's move this step (equal while j stands still);
        pair_announced (e, 2) robot j's announced or predicted next position (kin term);
        pair_separation (e,) r_i + r_j + eps (hard constraint); pair_room (e,) the distance
        the kin term asks for (larger than pair_separation when robot j needs room)
    obstacle_now : (m, 2) obstacles' current positions; obstacle_next : (m, 2) end of the
        sweep to keep clear (their predicted next positions; = now for the reactive rule)
    obstacle_target : (m, 2) position used by the inverse-distance term
    guard : (m,) extra keep-out radius around obstacle_now (the turn guard; 0 when off)
    path_end : (m, 2) end of the predicted path over the buffer horizon; buffer (m,) the soft
        clearance kept from that path (0: no buffer term)
    obstacle_clear : (k, m) required centre distance R_m + r_i + margin; obstacle_mask (k, m)
    static_near : (k,) False when no move within reach can come near a static obstacle or the
        boundary (then the static terms are 0 and are not computed)
    """

    start: FloatArray
    goal: FloatArray
    radius: FloatArray
    reach: FloatArray
    robot: NDArray[np.int64]
    pair_row: NDArray[np.int64]
    pair_other: NDArray[np.int64]
    pair_from: FloatArray
    pair_to: FloatArray
    pair_announced: FloatArray
    pair_separation: FloatArray
    pair_room: FloatArray
    obstacle_now: FloatArray
    obstacle_next: FloatArray
    obstacle_target: FloatArray
    guard: FloatArray
    path_end: FloatArray
    buffer: FloatArray
    obstacle_clear: FloatArray
    obstacle_mask: BoolArray
    static_near: BoolArray

    def rows(self, idx) -> "StepProblem":
        """The problem of a subset of the rows (obstacle arrays are shared)."""
        idx = np.asarray(idx, dtype=np.int64)
        new_row = np.full(len(self.start), -1, dtype=np.int64)
        new_row[idx] = np.arange(len(idx))
        keep = new_row[self.pair_row] >= 0
        return replace(self, start=self.start[idx], goal=self.goal[idx], radius=self.radius[idx],
                       reach=self.reach[idx], robot=self.robot[idx], pair_row=new_row[self.pair_row[keep]],
                       pair_other=self.pair_other[keep], pair_from=self.pair_from[keep],
                       pair_to=self.pair_to[keep], pair_announced=self.pair_announced[keep],
                       pair_separation=self.pair_separation[keep], pair_room=self.pair_room[keep],
                       obstacle_clear=self.obstacle_clear[idx],
                       obstacle_mask=self.obstacle_mask[idx], static_near=self.static_near[idx])

    def after(self, decided: FloatArray) -> "StepProblem":
        """The problem in which every robot j with a smaller index than the row's robot moves
        to its decided position ``decided[j]`` (positions of all robots, (n, 2)) and announces
        it: the sequential, priority-ordered form."""
        earlier = self.pair_other < self.robot[self.pair_row]
        to = np.where(earlier[:, None], decided[self.pair_other], self.pair_to)
        told = np.where(earlier[:, None], decided[self.pair_other], self.pair_announced)
        return replace(self, pair_to=to, pair_announced=told)


@dataclass(frozen=True)
class Weights:
    """Scale factors of eq. 5-7 (f_dp, f_st, f_dy), the line-of-sight constant of eq. 6, the
    weight of the predicted-path buffer (our addition), the hard-constraint weight H and the
    static clearance margin (world units)."""

    kin: float = 10.0
    static: float = 2.0
    line_of_sight: float = 0.0
    moving: float = 2.0
    buffer: float = 5.0
    hard: float = 1000.0
    static_margin: float = 0.25


def hard_violation(problem: StepProblem, world, x_next: FloatArray) -> FloatArray:
    """Total depth (world units) by which each candidate breaks the hard constraints, plus 1
    for a static hit; 0 = acceptable. x_next (k, p, 2) -> (k, p).

    ``world`` is anything with ``static_hits(a, b, radius)`` (a :class:`~swarmpath.world.World`
    or :class:`StaticGeometry`)."""
    k, p, _ = x_next.shape
    start = problem.start
    total = np.zeros((k, p))
    # robots: relative motion of the two discs over the step
    e = problem.pair_row
    if len(e):
        rel0 = (start[e] - problem.pair_from)[:, None, :]                      # (e, 1, 2)
        rel1 = x_next[e] - problem.pair_to[:, None, :]                         # (e, p, 2)
        d = _origin_segment_distance(rel0, rel1)
        np.add.at(total, e, np.maximum(0.0, problem.pair_separation[:, None] - d))
    # moving obstacles
    for j in range(problem.obstacle_now.shape[0]):
        rows = np.flatnonzero(problem.obstacle_mask[:, j])
        if not len(rows):
            continue
        need = problem.obstacle_clear[rows, j][:, None]
        o, q = problem.obstacle_now[j], problem.obstacle_next[j]
        xs = x_next[rows]
        sweep = _origin_segment_distance(start[rows][:, None, :] - o, xs - o)       # phase 2: o stands
        ahead = _origin_segment_distance(o - xs, q - xs)                             # next phase 1
        near = _norm(xs - o)
        total[rows] += (np.maximum(0.0, need - sweep) + np.maximum(0.0, need - ahead)
                        + np.maximum(0.0, need + problem.guard[j] - near))
    # static obstacles and the workspace, exact geometry (only robots near them)
    near = np.flatnonzero(problem.static_near)
    if len(near):
        xs = x_next[near]
        a = np.broadcast_to(start[near][:, None, :], xs.shape).reshape(-1, 2)
        b = xs.reshape(-1, 2)
        r = np.repeat(problem.radius[near], p)
        moved = np.any(a != b, axis=1)
        hits = np.zeros(len(a), bool)
        if moved.any():
            hits[moved] = world.static_hits(a[moved], b[moved], r[moved] + 1e-6)
        total[near] += hits.reshape(len(near), p)
    return total


def objective(problem: StepProblem, world, x_next: FloatArray, weights: Weights) -> tuple[FloatArray, FloatArray]:
    """Eq. 3-7 for candidates x_next (k, p, 2): (cost, violation), both (k, p)."""
    k, p, _ = x_next.shape
    cost = goal_distance(x_next, problem.goal)
    if len(problem.pair_row):
        cost = cost + weights.kin * kin_penalty(x_next, problem.pair_row, problem.pair_announced,
                                                problem.pair_room)
    if problem.obstacle_mask.any():
        cost = cost + weights.moving * inverse_obstacle_distance(x_next, problem.obstacle_target,
                                                                 problem.obstacle_mask)
    if weights.buffer > 0:
        for j in np.flatnonzero(problem.buffer > 0):
            rows = np.flatnonzero(problem.obstacle_mask[:, j])
            if len(rows):
                cost[rows] += weights.buffer * path_buffer_penalty(
                    x_next[rows], problem.obstacle_now[j], problem.path_end[j], problem.obstacle_clear[rows, j],
                    problem.buffer[j])
    near = np.flatnonzero(problem.static_near)
    if len(near):
        flat = x_next[near].reshape(-1, 2)
        radius = np.repeat(problem.radius[near], p)
        clear = world.static_clearance(flat, radius).reshape(len(near), p)
        cost[near] += weights.static * static_clearance_penalty(clear, weights.static_margin)
        if weights.line_of_sight > 0:
            blocked = world.static_hits(flat, np.repeat(problem.goal[near], p, axis=0), radius)
            cost[near] += weights.line_of_sight * blocked.reshape(len(near), p)
    violation = hard_violation(problem, world, x_next)
    cost = cost + weights.hard * (violation + (violation > 0))
    return cost, violation


@dataclass(frozen=True)
class SwarmSettings:
    """PSO hyperparameters of the per-step search (eq. 8): particles, iterations, inertia w,
    confidences C1 and C2, and the velocity limits of heading (rad) and speed fraction."""

    n_particles: int = 10
    n_iterations: int = 20
    w: float = 0.7298
    c1: float = 1.49618
    c2: float = 1.49618
    v_max_heading: float = np.pi / 2
    v_max_speed: float = 0.5


@dataclass(frozen=True)
class StepChoice:
    """Chosen next positions of k robots with their cost and hard-constraint violation."""

    positions: FloatArray
    cost: FloatArray
    violation: FloatArray


def solve_step(problem: StepProblem, world, weights: Weights, settings: SwarmSettings,
               rng: np.random.Generator) -> StepChoice:
    """One batched PSO (k robots x n_particles) over (heading, speed fraction), then the best
    of the swarm's result, standing still and (within reach) stepping exactly onto the goal."""
    k = problem.start.shape[0]
    p = settings.n_particles
    to_goal = problem.goal - problem.start
    goal_heading = np.arctan2(to_goal[:, 1], to_goal[:, 0])
    theta = rng.uniform(-np.pi, np.pi, (k, p))
    sigma = rng.uniform(0.0, 1.0, (k, p))
    theta[:, 0], sigma[:, 0] = goal_heading, 1.0       # one informed particle: straight to the goal
    x = np.stack([theta, sigma], axis=-1)
    vmax = np.array([settings.v_max_heading, settings.v_max_speed])
    v = rng.uniform(-1.0, 1.0, (k, p, 2)) * vmax * 0.5
    cost, viol = objective(problem, world, next_position(problem.start, x[..., 0], x[..., 1], problem.reach),
                           weights)
    pbest, pbest_f, pbest_v = x.copy(), cost.copy(), viol.copy()
    rows = np.arange(k)
    for _ in range(settings.n_iterations - 1):
        g = np.argmin(pbest_f, axis=1)
        gbest = pbest[rows, g][:, None, :]
        r = rng.random((2, k, p, 2))
        v = pso_velocity_update_wrapped(v, x, pbest, gbest, settings.w, settings.c1, settings.c2, r[0], r[1])
        v = np.clip(v, -vmax, vmax)
        x = x + v
        x[..., 0] = wrap_angle(x[..., 0])
        x[..., 1] = np.clip(x[..., 1], 0.0, 1.0)
        cost, viol = objective(problem, world, next_position(problem.start, x[..., 0], x[..., 1], problem.reach),
                               weights)
        better = cost < pbest_f
        pbest[better], pbest_f[better], pbest_v[better] = x[better], cost[better], viol[better]
    g = np.argmin(pbest_f, axis=1)
    best = next_position(problem.start, pbest[rows, g][:, None, 0], pbest[rows, g][:, None, 1], problem.reach)[:, 0]
    # exact extra candidates: stand still, and the goal itself when it is within reach
    gap = np.linalg.norm(to_goal, axis=1)
    snap = np.where((gap <= problem.reach)[:, None], problem.goal, problem.start)
    cands = np.stack([best, problem.start, snap], axis=1)                     # (k, 3, 2)
    c_cost, c_viol = objective(problem, world, cands, weights)
    pick = np.argmin(c_cost, axis=1)
    return StepChoice(cands[rows, pick].copy(), c_cost[rows, pick], c_viol[rows, pick])


# ------------------------------------------------------------------------------ the controllers
@register_controller("pso-predictive")
class PredictivePSOController(Controller):
    """Per-step multi-robot PSO with linear prediction of moving obstacles (PSO-prediction
    paper 2013). Needs no offline plan; robots are discs (radius >= 0) in continuous space.

    Parameters (hyperparameters only; state is created in ``reset``):
    sensing_factor : n in the sensing radius n (R + r), n > 1 (pseudo-code of section 4)
    eps : the paper's robot-robot threshold epsilon (world units)
    obstacle_margin : extra clearance kept from moving obstacles (world units)
    buffer_steps : horizon (steps) of the predicted path kept clear softly, with a buffer of
        one obstacle step (0 = off; the paper has no such term)
    yield_reach : robots pressed by the moving obstacle (no safe move, or inside the buffer of
        its predicted path) ask their neighbours, through the kin term, for this many steps of
        travel of extra room (our addition; 0 = off)
    stuck_steps : a robot whose distance to its goal has not shrunk for this many steps takes
        a detour: for up to ``stuck_steps`` steps its goal term aims at a waypoint
        ``detour_reach`` steps of travel to one side (random) of its goal direction (our
        addition: eq. 3 alone leaves robots in local minima, e.g. two robots crossing on top
        of an obstacle); 0 = off
    turn_guard : "learned" (keep the obstacle's whole one-step reach clear when it may turn:
        period not yet learnt, turning step, or impossible prediction), "always", or "never"
        (the paper's pure linear prediction)
    weights, swarm : :class:`Weights` and :class:`SwarmSettings`
    """

    capabilities = Capabilities(continuous=True, moving_obstacles=True, multi_robot=True, randomized=True)
    predictive: ClassVar[bool] = True

    def __init__(self, *, sensing_factor: float = 3.0, eps: float = 0.05, obstacle_margin: float = 0.05,
                 turn_guard: str = "learned", buffer_steps: int = 2, stuck_steps: int = 10,
                 detour_reach: float = 6.0, yield_reach: float = 2.0, weights: Weights | None = None,
                 swarm: SwarmSettings | None = None):
        if not sensing_factor > 1:
            raise ConfigError(f"sensing_factor must be > 1 (the paper's n), got {sensing_factor}")
        if eps <= 0 or obstacle_margin < 0:
            raise ConfigError(f"eps must be > 0 and obstacle_margin >= 0, got {eps}, {obstacle_margin}")
        if turn_guard not in ("learned", "always", "never"):
            raise ConfigError(f"turn_guard must be 'learned', 'always' or 'never', got {turn_guard!r}")
        self.sensing_factor = sensing_factor
        self.eps = eps
        self.obstacle_margin = obstacle_margin
        self.turn_guard = turn_guard
        if buffer_steps < 0:
            raise ConfigError(f"buffer_steps must be >= 0, got {buffer_steps}")
        self.buffer_steps = buffer_steps
        if stuck_steps < 0 or not detour_reach > 0:
            raise ConfigError(f"need stuck_steps >= 0 and detour_reach > 0, got {stuck_steps}, {detour_reach}")
        self.stuck_steps = stuck_steps
        if yield_reach < 0:
            raise ConfigError(f"yield_reach must be >= 0, got {yield_reach}")
        self.yield_reach = yield_reach
        self.detour_reach = detour_reach
        self.weights = weights or Weights()
        self.swarm = swarm or SwarmSettings()
        if self.swarm.n_particles < 1 or self.swarm.n_iterations < 1:
            raise ConfigError("swarm needs n_particles >= 1 and n_iterations >= 1")

    # -------------------------------------------------------------- run state
    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        self.world_ = world
        self.static_ = static_geometry(world)
        self.rng_ = rng
        n = world.n_robots
        self.radii_ = world.radii
        self.reach_ = world.max_speeds * world.dt
        self.goals_ = world.goals
        # robot-robot contact distance; point robots occupy grid cells, so two of them must stay
        # more than a cell diagonal apart (then they never share or swap cells)
        rsum = self.radii_[:, None] + self.radii_[None, :]
        both_points = (self.radii_[:, None] == 0) & (self.radii_[None, :] == 0)
        contact = np.where(both_points, np.sqrt(2.0) * world.resolution, rsum)
        self.separation_ = contact + self.eps
        reach_pair = self.reach_[:, None] + self.reach_[None, :]
        self.kin_range_ = np.maximum(self.sensing_factor * rsum, self.separation_ + reach_pair + self.eps)
        self.extent_ = np.array([ob.extent for ob in world.moving_obstacles], float)
        self.previous_positions_ = world.starts.copy()
        self.best_gap_ = np.linalg.norm(world.starts - self.goals_, axis=1)
        self.stalled_ = np.zeros(n, dtype=np.int64)
        self.detour_ = np.full((n, 2), np.nan)
        self.detour_left_ = np.zeros(n, dtype=np.int64)
        self.pressed_ = np.zeros(n, dtype=bool)
        self.track_ = pred.ObstacleTrack()
        self.eye_ = np.eye(n, dtype=bool)

    def _obstacle_terms(self, obs) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """(sweep end, inverse-distance target, guard radius, buffered path end, buffer) of
        every moving obstacle."""
        now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        if not self.predictive:
            zero = np.zeros(len(now))
            return now, now, zero, now, zero
        prev = np.asarray(obs.obstacle_previous, float).reshape(-1, 2)
        self.track_ = pred.update_track(self.track_, obs.step, prev, now, obs.dt)
        dt_s = self.track_.sampling_times(obs.dt)
        predicted = np.stack([pred.predict_linear(prev[j:j + 1], now[j:j + 1], obs.dt, dt_s[j])[0]
                              for j in range(len(now))]) if len(now) else now
        possible = np.array([bool(self.world_.obstacle_fits(ob, predicted[j:j + 1])[0])
                             for j, ob in enumerate(self.world_.moving_obstacles)], bool)
        self.track_ = pred.with_linear_possible(self.track_, possible)
        speed = np.linalg.norm(predicted - now, axis=1)
        if self.turn_guard == "never":
            guard = np.zeros(len(now))
        elif self.turn_guard == "always":
            guard = speed
        else:
            periods = self.track_.periods()
            uncertain = np.array([not possible[j] or pred.turn_expected(obs.step + 1, self.track_.turn_steps[j],
                                                                        periods[j]) for j in range(len(now))], bool)
            guard = np.where(uncertain, speed, 0.0)
        # a turning or bouncing obstacle keeps its speed: it stays within `speed` of `now`
        sweep_end = np.where((guard > 0)[:, None], now, predicted)
        path_end = now + self.buffer_steps * (predicted - now)
        buffer = speed if self.buffer_steps > 0 else np.zeros(len(now))
        return sweep_end, predicted, guard * (1 + 1e-6), path_end, buffer

    def _near_path(self, x: FloatArray, problem: StepProblem) -> BoolArray:
        """Robots whose position ``x`` (n, 2) lies within the buffer of an obstacle's
        predicted path (pressed by it); none without a buffer."""
        out = np.zeros(len(x), bool)
        for j in np.flatnonzero(problem.buffer > 0):
            d = point_segment_distance(x, problem.obstacle_now[j], problem.path_end[j])
            out |= problem.obstacle_mask[:, j] & (d < problem.obstacle_clear[:, j] + problem.buffer[j])
        return out

    def _targets(self, pos: FloatArray, events: list) -> FloatArray:
        """Each robot's goal, or its detour waypoint while it is taking a detour (updates the
        stall counters; appends "detour" events)."""
        gap = np.linalg.norm(pos - self.goals_, axis=1)
        improved = gap < self.best_gap_ - 0.25 * self.reach_
        self.best_gap_ = np.where(improved, gap, self.best_gap_)
        self.stalled_ = np.where(improved | (gap <= 1e-9), 0, self.stalled_ + 1)
        if self.stuck_steps == 0:
            return self.goals_
        active = ~np.isnan(self.detour_[:, 0])
        self.detour_left_ = np.where(active, self.detour_left_ - 1, 0)
        done = active & ((self.detour_left_ <= 0) | (np.linalg.norm(pos - self.detour_, axis=1) <= self.reach_))
        self.detour_[done] = np.nan
        self.best_gap_ = np.where(done, gap, self.best_gap_)
        self.stalled_[done] = 0
        for i in np.flatnonzero(np.isnan(self.detour_[:, 0]) & (self.stalled_ >= self.stuck_steps)):
            self.detour_[i] = self._waypoint(pos[i], i)
            self.detour_left_[i] = self.stuck_steps
            self.stalled_[i] = 0
            events.append({"robot": int(i), "kind": "detour", "detail": f"to {np.round(self.detour_[i], 3).tolist()}"})
        return np.where(np.isnan(self.detour_), self.goals_, self.detour_)

    def _waypoint(self, p: FloatArray, i: int) -> FloatArray:
        """A point ``detour_reach`` steps of travel to a random side of robot i's goal
        direction (the other side, or straight back, when that one is not free)."""
        d = self.goals_[i] - p
        d = d / max(float(np.linalg.norm(d)), 1e-12)
        side = 1.0 if self.rng_.random() < 0.5 else -1.0
        length = self.detour_reach * self.reach_[i]
        options = [p + length * side * np.array([-d[1], d[0]]), p - length * side * np.array([-d[1], d[0]]),
                   p - length * d]
        for w in options:
            if self.static_.static_clearance(w[None], self.radii_[i:i + 1])[0] > 0:
                return w
        return p.copy()

    def _problem(self, obs, targets: FloatArray) -> StepProblem:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        sweep_end, target, guard, path_end, buffer = self._obstacle_terms(obs)
        now = np.asarray(obs.obstacle_positions, float).reshape(-1, 2)
        dist = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
        pair_row, pair_other = np.nonzero((dist <= self.kin_range_) & ~self.eye_)
        # kin prediction: every other robot continues its last displacement
        announced = pos + (pos - self.previous_positions_)
        # robots pressed by the moving obstacle ask their neighbours for room (our addition)
        extra = np.where(self.pressed_, self.yield_reach * self.reach_, 0.0)
        clear = self.extent_[None, :] + self.radii_[:, None] + self.obstacle_margin
        if len(now):
            d_obs = np.linalg.norm(pos[:, None] - now[None], axis=-1)
            speed = np.maximum(np.linalg.norm(path_end - now, axis=1), guard) + buffer
            sense = np.maximum(self.sensing_factor * (self.extent_[None, :] + self.radii_[:, None]),
                               clear + self.reach_[:, None] + 2 * speed[None, :] + self.obstacle_margin)
            obstacle_mask = d_obs <= sense
        else:
            obstacle_mask = np.zeros((n, 0), bool)
        if self.weights.line_of_sight > 0:
            static_near = np.ones(n, bool)
        else:
            free = self.static_.static_clearance(pos, self.radii_) - self.reach_
            static_near = free < self.weights.static_margin + 1e-6
        return StepProblem(start=pos, goal=targets, radius=self.radii_, reach=self.reach_,
                           robot=np.arange(n), pair_row=pair_row, pair_other=pair_other,
                           pair_from=pos[pair_other], pair_to=pos[pair_other],
                           pair_announced=announced[pair_other],
                           pair_separation=self.separation_[pair_row, pair_other],
                           pair_room=self.separation_[pair_row, pair_other] + extra[pair_other], obstacle_now=now,
                           obstacle_next=sweep_end, obstacle_target=target, guard=guard,
                           path_end=path_end, buffer=buffer,
                           obstacle_clear=clear, obstacle_mask=obstacle_mask, static_near=static_near)

    def act(self, obs: Observation) -> Decision:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        if n == 0:
            return Decision(pos.copy(), [])
        events: list[dict] = []
        targets = self._targets(pos, events)
        problem = self._problem(obs, targets)
        static = self.static_
        if isinstance(static, StaticGeometry):
            static = static.near(pos, self.reach_ + self.radii_ + self.weights.static_margin + 1e-6)
        choice = solve_step(problem, static, self.weights, self.swarm, self.rng_)
        final = choice.positions.copy()
        violation = choice.violation.copy()
        # sequential resolution by index: robot i must respect the segments of robots j < i.
        # All robots are checked at once against the decisions before them; the first one with
        # a new conflict is solved again alone, and the check resumes after it.
        first = 1
        while first < n:
            checked = problem.after(final)
            idx = np.arange(first, n)
            _, v = objective(checked.rows(idx), static, final[idx][:, None, :], self.weights)
            worse = np.flatnonzero(v[:, 0] > violation[idx] + 1e-12)
            if len(worse) == 0:
                break
            i = int(idx[worse[0]])
            again = solve_step(checked.rows([i]), static, self.weights, self.swarm, self.rng_)
            final[i], violation[i] = again.positions[0], again.violation[0]
            first = i + 1
        self.pressed_ = (violation > 0) | self._near_path(final, problem)
        for i in np.flatnonzero(violation > 0):
            events.append({"robot": int(i), "kind": "no_safe_move", "detail": f"violation {violation[i]:.3g}"})
        self.previous_positions_ = pos.copy()
        at_goal = np.linalg.norm(final - self.goals_, axis=1) <= 1e-9
        moved = np.any(final != pos, axis=1)
        avoiding = problem.obstacle_mask.any(axis=1)
        detour = ~np.isnan(self.detour_[:, 0])
        modes = ["arrived" if at_goal[i] else ("wait" if not moved[i] else
                                               ("avoid" if avoiding[i] else ("detour" if detour[i] else "seek")))
                 for i in range(n)]
        return Decision(final, modes, tuple(events))


@register_controller("pso-reactive")
class ReactivePSOController(PredictivePSOController):
    """The same PSO without prediction (the paper's "classical non-prediction approach"): the
    moving obstacle is taken to stay at its current position.

    It keeps clear of where a moving obstacle *is*, not of where it goes, so it does not
    promise to avoid moving obstacles (``capabilities.moving_obstacles`` is False): an
    obstacle can run it over, which is the effect the paper measures."""

    capabilities = Capabilities(continuous=True, moving_obstacles=False, multi_robot=True, randomized=True)
    predictive = False
