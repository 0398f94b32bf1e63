"""The linear programs of ORCA (van den Berg, Guy, Lin & Manocha, ISRR 2011, section 5.2),
as RVO2 solves them: an incremental 2-D program over half-planes inside the speed disc, and
the 3-D program that minimises the largest violation when the 2-D one is infeasible.

A *line* is a half-plane in velocity space given by a point ``p`` on its boundary and a unit
``direction`` ``d``; velocities on its left are permitted:

    det(d, p - v) <= 0    (the half-plane ORCA^tau_{A|B} of eq. (6))

``solve_lp2`` finds the permitted velocity closest to the preferred one (eq. (7): v_new =
argmin ||v - v_pref|| over the intersection of all lines and the disc ||v|| <= v_max), adding
lines one at a time (Seidel's incremental algorithm without the random shuffle, so results
depend only on the order given: deterministic). When the lines have no common point inside
the disc, ``solve_lp3`` keeps the first ``n_hard`` lines (static and obstacle constraints) as
they are and moves the others (robot-robot constraints) outwards equally, minimising the
largest violation (section 5.3, "densely packed conditions"): the 3-D program (v, d) is solved
as a sequence of 2-D programs over the lines projected on the boundary of the most violated
one, as RVO2 does.

These pure-Python functions are the reference; :mod:`swarmpath.control.orca.kernels` runs the
same algorithm for many robots at once in C (``_orcalp.c``) and is tested against them.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Lines whose directions' determinant is below this are treated as parallel.
PARALLEL_EPS = 1e-12


def _det(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def solve_lp1(points: FloatArray, directions: FloatArray, line_no: int, radius: float, opt: ArrayLike,
              direction_opt: bool) -> tuple[bool, FloatArray]:
    """The best point on the boundary of line ``line_no`` that satisfies lines ``0..line_no-1``
    and lies in the disc of ``radius``: the closest to ``opt``, or the farthest along the unit
    vector ``opt`` when ``direction_opt``. Returns (feasible, point)."""
    px, py = float(points[line_no, 0]), float(points[line_no, 1])
    dx, dy = float(directions[line_no, 0]), float(directions[line_no, 1])
    dot = px * dx + py * dy
    disc = dot * dot + radius * radius - (px * px + py * py)
    if disc < 0.0:                        # the speed disc lies wholly outside line line_no
        return False, np.zeros(2)
    root = math.sqrt(disc)
    t_left, t_right = -dot - root, -dot + root
    for i in range(line_no):
        qx, qy = float(points[i, 0]), float(points[i, 1])
        ex, ey = float(directions[i, 0]), float(directions[i, 1])
        denominator = _det(dx, dy, ex, ey)
        numerator = _det(ex, ey, px - qx, py - qy)
        if abs(denominator) <= PARALLEL_EPS:  # parallel lines
            if numerator < 0.0:
                return False, np.zeros(2)
            continue
        t = numerator / denominator
        if denominator >= 0.0:
            t_right = min(t_right, t)         # line i bounds line_no on the right
        else:
            t_left = max(t_left, t)           # ... on the left
        if t_left > t_right:
            return False, np.zeros(2)
    ox, oy = float(opt[0]), float(opt[1])
    if direction_opt:
        t = t_right if ox * dx + oy * dy > 0.0 else t_left
    else:
        t = min(max(dx * (ox - px) + dy * (oy - py), t_left), t_right)
    return True, np.array([px + t * dx, py + t * dy])


def solve_lp2(points: ArrayLike, directions: ArrayLike, radius: float, opt: ArrayLike,
              direction_opt: bool = False) -> tuple[int, FloatArray]:
    """Eq. (7): the velocity in the disc of ``radius`` that satisfies every line and is closest
    to ``opt`` (or farthest along the unit vector ``opt`` when ``direction_opt``).

    points, directions : (k, 2). Returns ``(fail, v)``: ``fail == k`` when all lines hold,
    else the index of the first line that could not be satisfied, with ``v`` the best result
    for lines ``0..fail-1``.
    """
    points = np.asarray(points, float).reshape(-1, 2)
    directions = np.asarray(directions, float).reshape(-1, 2)
    opt = np.asarray(opt, float)
    ox, oy = float(opt[0]), float(opt[1])
    if direction_opt:
        result = np.array([ox * radius, oy * radius])
    elif ox * ox + oy * oy > radius * radius:
        norm = math.sqrt(ox * ox + oy * oy)
        result = np.array([ox / norm * radius, oy / norm * radius])
    else:
        result = np.array([ox, oy])
    for i in range(len(points)):
        if _det(directions[i, 0], directions[i, 1], points[i, 0] - result[0], points[i, 1] - result[1]) > 0.0:
            ok, new = solve_lp1(points, directions, i, radius, opt, direction_opt)
            if not ok:
                return i, result
            result = new
    return len(points), result


def solve_lp3(points: ArrayLike, directions: ArrayLike, n_hard: int, begin: int, radius: float,
              result: ArrayLike) -> FloatArray:
    """Section 5.3: starting from ``result`` (the 2-D program's answer for lines before
    ``begin``), the velocity that keeps the first ``n_hard`` lines and minimises the largest
    distance by which it violates any other line. Returns the velocity (2,)."""
    points = np.asarray(points, float).reshape(-1, 2)
    directions = np.asarray(directions, float).reshape(-1, 2)
    result = np.asarray(result, float).copy()
    distance = 0.0
    for i in range(begin, len(points)):
        dx, dy = directions[i]
        if _det(dx, dy, points[i, 0] - result[0], points[i, 1] - result[1]) <= distance:
            continue
        # lines on which violating i and j equally: the hard lines as they are, and for each
        # earlier soft line j the bisector of lines i and j
        proj_p = [points[k] for k in range(n_hard)]
        proj_d = [directions[k] for k in range(n_hard)]
        for j in range(n_hard, i):
            ex, ey = directions[j]
            determinant = _det(dx, dy, ex, ey)
            if abs(determinant) <= PARALLEL_EPS:
                if dx * ex + dy * ey > 0.0:       # same direction: j is implied
                    continue
                point = 0.5 * (points[i] + points[j])
            else:
                s = _det(ex, ey, points[i, 0] - points[j, 0], points[i, 1] - points[j, 1]) / determinant
                point = points[i] + s * directions[i]
            bx, by = ex - dx, ey - dy
            norm = math.sqrt(bx * bx + by * by)
            proj_p.append(point)
            proj_d.append(np.array([bx / norm, by / norm]))
        before = result.copy()
        fail, new = solve_lp2(np.array(proj_p).reshape(-1, 2), np.array(proj_d).reshape(-1, 2), radius,
                              np.array([-dy, dx]), True)
        # failing here is floating-point error only (the old result is feasible): keep it
        result = before if fail < len(proj_p) else new
        distance = _det(dx, dy, points[i, 0] - result[0], points[i, 1] - result[1])
    return result


def solve_orca_lp(points: ArrayLike, directions: ArrayLike, n_hard: int, radius: float,
                  preferred: ArrayLike, n_firm: int | None = None) -> tuple[FloatArray, int]:
    """One robot's new velocity: the 2-D program, and the 3-D one when it fails (RVO2's
    ``computeNewVelocity``), with one tier more than RVO2.

    Lines come in three tiers: ``0..n_hard-1`` are *hard* (static geometry; velocity 0 always
    satisfies them), ``n_hard..n_firm-1`` are *firm* (this step's moving-obstacle lines) and
    the rest are *soft* (robot-robot and anticipation lines). When the 2-D program fails on a
    soft line, the 3-D program keeps hard and firm lines; when it fails on a firm line (the
    obstacles corner the robot), the 3-D program keeps the hard lines and minimises the
    largest violation of the firm lines alone (the soft ones are dropped: escaping this
    step's danger comes first). Returns (velocity (2,), status): status 0 = all lines hold, 1 = the
    soft lines were relaxed, 2 = the firm lines were relaxed too, 3 = the hard lines
    themselves conflict (the robot stands still; cannot happen when velocity 0 is permitted
    by every hard line).
    """
    points = np.asarray(points, float).reshape(-1, 2)
    directions = np.asarray(directions, float).reshape(-1, 2)
    n_firm = n_hard if n_firm is None else n_firm
    fail, v = solve_lp2(points, directions, radius, preferred, False)
    if fail >= len(points):
        return v, 0
    if fail >= n_firm:
        return solve_lp3(points, directions, n_firm, fail, radius, v), 1
    if fail >= n_hard:
        return solve_lp3(points[:n_firm], directions[:n_firm], n_hard, fail, radius, v), 2
    return np.zeros(2), 3


def violation(points: ArrayLike, directions: ArrayLike, v: ArrayLike) -> FloatArray:
    """How far velocity ``v`` lies on the forbidden side of each line (<= 0: satisfied)."""
    points = np.asarray(points, float).reshape(-1, 2)
    directions = np.asarray(directions, float).reshape(-1, 2)
    v = np.asarray(v, float)
    rel = points - v
    return directions[:, 0] * rel[:, 1] - directions[:, 1] * rel[:, 0]
