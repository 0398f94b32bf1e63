"""Batched ORCA linear programs: every robot's lines packed into one padded array, solved in
one call of the C loop (``_orcalp.c``), with the pure-Python reference of
:mod:`swarmpath.control.orca.lp` as the fallback and the test oracle.
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


def pack_lines(owner: IntArray, points: FloatArray, directions: FloatArray, tier: IntArray,
               n_robots: int) -> tuple[FloatArray, IntArray, IntArray, IntArray]:
    """Pack lines given as flat arrays into a padded per-robot array.

    owner (e,) robot of each line; points, directions (e, 2); tier (e,) 0 hard, 1 firm,
    2 soft (see :func:`swarmpath.control.orca.lp.solve_orca_lp`). Within a robot the lines
    keep their given order inside each tier (a stable sort), hard first.

    Returns lines (n, k, 4), n_lines, n_hard, n_firm (n,) with k the largest count.
    """
    owner = np.asarray(owner, np.int64)
    tier = np.asarray(tier, np.int64)
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
