"""Batched ORCA linear programs: every robot's lines packed into one padded array, solved in
one call of the C loop (``_orcalp.c``), with the pure-Python reference of
:mod:`swarmpath.control.orca.lp` as the fallback and the test oracle.

The other per-step loops of :class:`~swarmpath.control.orca.core.ORCASolver` that cost far
more in numpy call overhead than in arithmetic at a few hundred robots run in the same
extension: the nearest neighbours (:func:`nearest`), the robot-robot half-planes
(:func:`robot_halfplanes`), the packing (:func:`pack_lines`), the pairwise move check
(:func:`robot_pairs`) and the tidying of the moves (:func:`tidy_moves`). Each gives exactly
the bits of its numpy reference (tests/control/test_orca_kernels.py), which remains the
fallback without the extension, so trajectories do not depend on whether it was built.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.orca import lp

try:  # the compiled loop; absent only in a source tree that was never built
    from swarmpath.control.orca import _orcalp  # type: ignore[attr-defined]
except ImportError:  # pragma: no cover - exercised only without the extension
    _orcalp = None

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


def pack_lines(owner: IntArray, points: FloatArray, directions: FloatArray, tier: IntArray,
               n_robots: int, use_c: bool = True) -> tuple[FloatArray, IntArray, IntArray, IntArray]:
    """Pack lines given as flat arrays into a padded per-robot array.

    owner (e,) robot of each line; points, directions (e, 2); tier (e,) 0 hard, 1 firm,
    2 soft (see :func:`swarmpath.control.orca.lp.solve_orca_lp`). Within a robot the lines
    keep their given order inside each tier (a stable sort), hard first. The C loop places
    each line by a running slot per robot and tier (the same order as the numpy lexsort
    below, the reference).

    Returns lines (n, k, 4), n_lines, n_hard, n_firm (n,) with k the largest count.
    """
    owner = np.asarray(owner, np.int64)
    tier = np.asarray(tier, np.int64)
    if use_c and _orcalp is not None:
        owner = np.ascontiguousarray(owner)
        tier = np.ascontiguousarray(tier)
        n_lines = np.empty(n_robots, np.int64)
        n_hard = np.empty(n_robots, np.int64)
        n_firm = np.empty(n_robots, np.int64)
        _orcalp.count_lines(owner, tier, n_lines, n_hard, n_firm)
        lines = np.zeros((n_robots, max(int(n_lines.max(initial=0)), 1), 4))
        _orcalp.pack_lines(owner, tier, np.ascontiguousarray(points, np.float64).reshape(-1, 2),
                           np.ascontiguousarray(directions, np.float64).reshape(-1, 2), n_hard, n_firm, lines)
        return lines, n_lines, n_hard, n_firm
    order = np.lexsort((np.arange(len(owner)), tier, owner))
    owner_s, tier_s = owner[order], tier[order]
    n_lines = np.bincount(owner_s, minlength=n_robots).astype(np.int64)
    n_hard = np.bincount(owner_s[tier_s == 0], minlength=n_robots).astype(np.int64)
    n_firm = n_hard + np.bincount(owner_s[tier_s == 1], minlength=n_robots).astype(np.int64)
    k = int(n_lines.max(initial=0))
    lines = np.zeros((n_robots, max(k, 1), 4))
    if len(owner_s):
        start = np.concatenate([[0], np.cumsum(n_lines)[:-1]])
        slot = np.arange(len(owner_s)) - start[owner_s]
        lines[owner_s, slot, 0:2] = points[order]
        lines[owner_s, slot, 2:4] = directions[order]
    return lines, n_lines, n_hard, n_firm


def solve_lines(lines: FloatArray, n_lines: IntArray, n_hard: IntArray, n_firm: IntArray, preferred: FloatArray,
                radius: FloatArray, use_c: bool = True) -> tuple[FloatArray, IntArray]:
    """New velocities (n, 2) and LP statuses (n,) of all robots (see ``lp.solve_orca_lp``):
    lines (n, k, 4), counts (n,), preferred velocities (n, 2), speed limits (n,)."""
    n = len(radius)
    lines = np.ascontiguousarray(lines, dtype=np.float64)
    preferred = np.ascontiguousarray(preferred, dtype=np.float64).reshape(n, 2)
    radius = np.ascontiguousarray(radius, dtype=np.float64)
    counts = [np.ascontiguousarray(c, dtype=np.int64) for c in (n_lines, n_hard, n_firm)]
    out = np.zeros((n, 2))
    status = np.zeros(n, dtype=np.int64)
    if use_c and _orcalp is not None:
        _orcalp.solve(lines, counts[0], counts[1], counts[2], preferred, radius, out, status)
        return out, status
    for i in range(n):
        m = int(counts[0][i])
        v, st = lp.solve_orca_lp(lines[i, :m, 0:2], lines[i, :m, 2:4], int(counts[1][i]), float(radius[i]),
                                 preferred[i], int(counts[2][i]))
        out[i], status[i] = v, st
    return out, status


def nearest(pos: FloatArray, k: int, upper: float) -> tuple[IntArray, BoolArray] | None:
    """Each robot's ``k`` nearest robots (itself included) closer than ``upper``, nearest
    first: (n, k) indices, -1 where fewer, as ``cKDTree(pos).query(pos, k,
    distance_upper_bound=upper)`` finds them (squared distances dx * dx + dy * dy below
    upper * upper); and (n,) which robots have two of those, or the k-th and the next, at
    exactly the same distance, where cKDTree's order (its tree's) must be asked of cKDTree.
    None without the extension."""
    if _orcalp is None:
        return None
    pos = np.ascontiguousarray(pos, np.float64).reshape(-1, 2)
    idx = np.empty((len(pos), k), np.int64)
    tied = np.empty(len(pos), bool)
    _orcalp.knn(pos, int(k), float(upper), idx, tied)
    return idx, tied


def robot_halfplanes(pos: FloatArray, vel: FloatArray, radii: FloatArray, responsibility: FloatArray,
                     i: IntArray, j: IntArray, diagonal: float, margin: float, time_horizon: float,
                     dt: float) -> tuple[FloatArray, FloatArray] | None:
    """ORCA's lines of robots ``i`` (e,) for neighbours ``j`` (e,): the bits of
    ``orca_halfplanes_robots(pos[j] - pos[i], vel[i] - vel[j], vel[i], R, time_horizon, dt,
    responsibility[j])`` with the combined radius R = radii[i] + radii[j] + margin, or
    ``diagonal`` + margin for two point robots (radius 0), as
    :meth:`~swarmpath.control.orca.core.ORCASolver.combined_radius`. pos, vel (n, 2); radii,
    responsibility (n,). Returns points, directions (e, 2); None without the extension."""
    if _orcalp is None:
        return None
    e = len(i)
    points = np.empty((e, 2))
    directions = np.empty((e, 2))
    _orcalp.robot_halfplanes(np.ascontiguousarray(pos, np.float64), np.ascontiguousarray(vel, np.float64),
                             np.ascontiguousarray(radii, np.float64),
                             np.ascontiguousarray(responsibility, np.float64),
                             np.ascontiguousarray(i, np.int64), np.ascontiguousarray(j, np.int64),
                             float(diagonal), float(margin), float(time_horizon), float(dt), points, directions)
    return points, directions


def robot_pairs(p0: FloatArray, d: FloatArray, check_radii: FloatArray, threatened: BoolArray, level: IntArray,
                scales: FloatArray, resolution: float, extra: float) -> IntArray | None:
    """The C loop of :meth:`~swarmpath.control.orca.core.ORCASolver._robot_pairs`: the
    levels (n,) (indices into ``scales``) after every pair of robots starting within twice
    the longest move of ``d`` (n, 2) plus ``extra`` (no pair farther apart can conflict)
    passed the simulator's move rules (:func:`swarmpath.world.move_rules.move_conflicts`,
    radii ``check_radii`` (n,)) for the moves p0 -> p0 + scales[level] * d, lowered round by
    round as the numpy loop does. None without the extension."""
    if _orcalp is None:
        return None
    out = np.array(level, dtype=np.int64, copy=True)
    _orcalp.robot_pairs(np.ascontiguousarray(p0, np.float64), np.ascontiguousarray(d, np.float64),
                        np.ascontiguousarray(check_radii, np.float64), np.ascontiguousarray(threatened, bool),
                        out, np.ascontiguousarray(scales, np.float64), float(resolution), float(extra))
    return out


def tidy_moves(pos: FloatArray, p1: FloatArray, goals: FloatArray, step_len: FloatArray,
               snap: float) -> FloatArray | None:
    """The C loop of :func:`swarmpath.control.orca.core.tidy_moves` (the same bits); None
    without the extension."""
    if _orcalp is None:
        return None
    n = len(pos)
    out = np.empty((n, 2))
    _orcalp.tidy(np.ascontiguousarray(pos, np.float64), np.ascontiguousarray(p1, np.float64),
                 np.ascontiguousarray(np.broadcast_to(np.asarray(goals, np.float64), (n, 2))),
                 np.ascontiguousarray(np.broadcast_to(np.asarray(step_len, np.float64), (n,))), float(snap), out)
    return out
