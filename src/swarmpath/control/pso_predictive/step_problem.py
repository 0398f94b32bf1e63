"""One step's optimisation problem of k robots (eq. 3-7 of the PSO-prediction paper, 2013):
the data (:class:`StepProblem`), the weights of its terms, the hard safety constraints and
the objective a per-robot swarm minimises."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.pso_predictive.kernels import (goal_distance, inverse_obstacle_distance, kin_penalty,
                                                      path_buffer_penalty, static_clearance_penalty)
from swarmpath.world.geometry import origin_segment_distance, planar_norm
from swarmpath.world.move_rules import swept_gap

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Violation counted for a move whose swept disc touches a static obstacle or leaves the
#: workspace: more than any sum of robot and moving-obstacle depths (each at most a few contact
#: distances), so a swarm never trades a wall for room from an obstacle. Standing still never
#: hits (a robot starts in free space), so some candidate is always free of it.
STATIC_HIT = 1e6


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
    obstacle_jumps : (m,) obstacles that teleport (redraw): where one stands now says nothing
        of where it will be, so only the hard constraint of this step (it stands during the
        robot's move) applies to it, not eq. 7 (None: none teleports)
    static_margin : (k,) each robot's static clearance margin (world units) when it must be
        smaller than :attr:`Weights.static_margin` (None: that margin for all)
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
    obstacle_jumps: BoolArray | None = None
    static_margin: FloatArray | None = None

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
                       obstacle_mask=self.obstacle_mask[idx], static_near=self.static_near[idx],
                       static_margin=None if self.static_margin is None else self.static_margin[idx])

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
    """Total depth (world units) by which each candidate breaks the hard constraints, plus
    :data:`STATIC_HIT` for a static hit; 0 = acceptable. x_next (k, p, 2) -> (k, p).

    ``world`` is anything with ``static_hits(a, b, radius)`` (a :class:`~swarmpath.world.World`
    or :class:`StaticGeometry`)."""
    k, p, _ = x_next.shape
    start = problem.start
    total = np.zeros((k, p))
    # robots: relative motion of the two discs over the step
    e = problem.pair_row
    if len(e):
        d = swept_gap(start[e][:, None, :], x_next[e], problem.pair_from[:, None, :],
                      problem.pair_to[:, None, :])                                # (e, p)
        np.add.at(total, e, np.maximum(0.0, problem.pair_separation[:, None] - d))
    # moving obstacles
    for j in range(problem.obstacle_now.shape[0]):
        rows = np.flatnonzero(problem.obstacle_mask[:, j])
        if not len(rows):
            continue
        need = problem.obstacle_clear[rows, j][:, None]
        o, q = problem.obstacle_now[j], problem.obstacle_next[j]
        xs = x_next[rows]
        sweep = origin_segment_distance(start[rows][:, None, :] - o, xs - o)       # phase 2: o stands
        ahead = origin_segment_distance(o - xs, q - xs)                             # next phase 1
        near = planar_norm(xs - o)
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
        total[near] += STATIC_HIT * hits.reshape(len(near), p)
    return total


def objective(problem: StepProblem, world, x_next: FloatArray, weights: Weights) -> tuple[FloatArray, FloatArray]:
    """Eq. 3-7 for candidates x_next (k, p, 2): (cost, violation), both (k, p)."""
    k, p, _ = x_next.shape
    cost = goal_distance(x_next, problem.goal)
    if len(problem.pair_row):
        cost = cost + weights.kin * kin_penalty(x_next, problem.pair_row, problem.pair_announced,
                                                problem.pair_room)
    sensed = problem.obstacle_mask if problem.obstacle_jumps is None else \
        problem.obstacle_mask & ~problem.obstacle_jumps[None, :]
    if sensed.any():
        cost = cost + weights.moving * inverse_obstacle_distance(x_next, problem.obstacle_target, sensed)
    if weights.buffer > 0:
        for j in np.flatnonzero(problem.buffer > 0):
            rows = np.flatnonzero(problem.obstacle_mask[:, j])
            if len(rows):
                cost[rows] += weights.buffer * path_buffer_penalty(
                    x_next[rows], problem.obstacle_now[j], problem.path_end[j], problem.obstacle_clear[rows, j],
                    problem.buffer[j])
    near = np.flatnonzero(problem.static_near)
    if len(near) and (weights.static > 0 or weights.line_of_sight > 0):
        flat = x_next[near].reshape(-1, 2)
        radius = np.repeat(problem.radius[near], p)
        if weights.static > 0:
            clear = world.static_clearance(flat, radius).reshape(len(near), p)
            margin = weights.static_margin if problem.static_margin is None else problem.static_margin[near][:, None]
            cost[near] += weights.static * static_clearance_penalty(clear, margin, weights.static_margin)
        if weights.line_of_sight > 0:
            blocked = world.static_hits(flat, np.repeat(problem.goal[near], p, axis=0), radius)
            cost[near] += weights.line_of_sight * blocked.reshape(len(near), p)
    violation = hard_violation(problem, world, x_next)
    cost = cost + weights.hard * (violation + (violation > 0))
    return cost, violation


def paper_objective(problem: StepProblem, world, x_next: FloatArray,
                    weights: Weights) -> tuple[FloatArray, FloatArray]:
    """Eq. 3-7 as printed, for candidates x_next (k, p, 2): (cost, zeros), both (k, p).

    F_i = ||x_i' - g_i|| + f_dp sum_j min(0, d'_ij - (r_i + r_j + eps))^2
          + f_st ([x_i -> x_i' touches a static obstacle] + [x_i' -> g_i touches one])
          + f_dy sum_m [m sensed] / ||x_i' - p_m'||

    ``weights.kin``, ``weights.static`` and ``weights.moving`` are f_dp, f_st and f_dy (the
    paper: positive constants, values not given). The paper's "local trajectory" is the two
    segments; each that touches a static obstacle or the workspace's edge adds f_st (with one
    constant for both, a robot whose goal is hidden would walk into the obstacle: every
    candidate pays it). No clearance ramp, no hard constraints.
    ``problem.pair_room`` is r_i + r_j + eps and ``problem.obstacle_target`` p_m', the
    predicted (or, without prediction, current) position of obstacle m.
    """
    k, p, _ = x_next.shape
    cost = goal_distance(x_next, problem.goal)
    if len(problem.pair_row):
        cost = cost + weights.kin * kin_penalty(x_next, problem.pair_row, problem.pair_announced, problem.pair_room)
    if problem.obstacle_mask.any():
        cost = cost + weights.moving * inverse_obstacle_distance(x_next, problem.obstacle_target,
                                                                 problem.obstacle_mask)
    flat = x_next.reshape(-1, 2)
    radius = np.repeat(problem.radius, p)
    start = np.repeat(problem.start, p, axis=0)
    moved = np.any(flat != start, axis=1)
    on_step = np.zeros(len(flat), bool)
    if moved.any():
        on_step[moved] = world.static_hits(start[moved], flat[moved], radius[moved])
    on_line = world.static_hits(flat, np.repeat(problem.goal, p, axis=0), radius)
    cost = cost + weights.static * (on_step.astype(float) + on_line).reshape(k, p)
    return cost, np.zeros((k, p))
