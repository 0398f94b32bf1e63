"""Pareto dominance (eq. 14), non-dominated filtering, crowding distance, archive truncation and
the exact two-objective hypervolume.

All functions minimise every objective and work on objective matrices F of shape
(n_points, n_objectives).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]


def dominates(u: ArrayLike, v: ArrayLike) -> bool | NDArray[np.bool_]:
    """Eq. 14: u dominates v iff u_i <= v_i for every objective and u_j < v_j for at least one.

    Parameters
    ----------
    u, v : array_like of shape (..., n_objectives)
        Broadcast against each other, so one vector can be compared with many.

    Returns
    -------
    bool, or ndarray of bools of the broadcast shape without the last axis.
    """
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    result = np.all(u <= v, axis=-1) & np.any(u < v, axis=-1)
    return bool(result) if np.ndim(result) == 0 else result


def dominance_matrix(F: ArrayLike) -> NDArray[np.bool_]:
    """D[i, j] = True when point i dominates point j (eq. 14); F (n, m) -> D (n, n)."""
    F = np.asarray(F, dtype=float)
    le = np.all(F[:, None, :] <= F[None, :, :], axis=-1)
    lt = np.any(F[:, None, :] < F[None, :, :], axis=-1)
    return le & lt


def non_dominated(F: ArrayLike) -> NDArray[np.bool_]:
    """Mask of the points no other point dominates (the first Pareto front); F (n, m) -> (n,).

    Identical points do not dominate each other, so duplicates are all kept (see
    :func:`unique_rows` to drop them).
    """
    F = np.asarray(F, dtype=float)
    if F.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    return ~dominance_matrix(F).any(axis=0)


def unique_rows(F: ArrayLike) -> NDArray[np.intp]:
    """Indices of the first occurrence of each distinct row of F (n, m), in ascending order."""
    F = np.asarray(F, dtype=float)
    if F.shape[0] == 0:
        return np.zeros(0, dtype=np.intp)
    _, first = np.unique(F, axis=0, return_index=True)
    return np.sort(first)


def crowding_distance(F: ArrayLike) -> Array:
    """NSGA-II crowding distance of each point within the set F (n, m) -> (n,).

    For every objective the points are sorted; the two extremes get +inf, every other point
    adds (next - previous) / (max - min) (nothing when max = min). Larger means less crowded.
    With two points or fewer all distances are +inf.
    """
    F = np.asarray(F, dtype=float)
    n, m = F.shape
    if n <= 2:
        return np.full(n, np.inf)
    dist = np.zeros(n)
    order = np.argsort(F, axis=0, kind="stable")
    Fs = np.take_along_axis(F, order, axis=0)
    span = Fs[-1] - Fs[0]
    gaps = np.zeros((n, m))
    with np.errstate(divide="ignore", invalid="ignore"):
        gaps[1:-1] = np.where(span > 0, (Fs[2:] - Fs[:-2]) / span, 0.0)
    gaps[0] = np.inf
    gaps[-1] = np.inf
    for j in range(m):
        dist[order[:, j]] += gaps[:, j]
    return dist


def truncate_by_crowding(F: ArrayLike, size: int) -> NDArray[np.intp]:
    """Indices of ``size`` points of F (n, m) kept when the archive is over its limit.

    Repeatedly removes the point with the smallest crowding distance, recomputing the
    distances after each removal (more even spread than one cut, Coello-style archive
    pruning); ties go to the lowest index. Returns ascending indices; all of them when
    n <= size.
    """
    F = np.asarray(F, dtype=float)
    keep = np.arange(F.shape[0])
    while keep.shape[0] > size:
        surplus = keep.shape[0] - size
        cd = crowding_distance(F[keep])
        # Several removals at once when the surplus is large: they are spread over the set,
        # so removing the most crowded few together changes little; the last ones go singly.
        k = max(1, surplus // 4)
        drop = np.argsort(cd, kind="stable")[:k]
        keep = np.delete(keep, drop)
    return keep


def hypervolume_2d(F: ArrayLike, reference: ArrayLike) -> float:
    """Exact hypervolume (area) dominated by the points F (n, 2) and bounded by ``reference``.

    Points that do not strictly dominate the reference point contribute nothing. The sweep:
    sort the non-dominated points by f1 ascending (f2 is then descending) and add the
    rectangles (f1_{k+1} - f1_k) * (r2 - f2_k), with f1_{n+1} = r1.
    """
    F = np.asarray(F, dtype=float).reshape(-1, 2)
    r = np.asarray(reference, dtype=float)
    F = F[np.all(F < r, axis=1)]
    if F.shape[0] == 0:
        return 0.0
    F = F[np.lexsort((F[:, 1], F[:, 0]))]
    # keep the staircase: points whose f2 is below every f2 seen so far (sorted by f1)
    best_f2 = np.minimum.accumulate(F[:, 1])
    keep = np.ones(F.shape[0], dtype=bool)
    keep[1:] = F[1:, 1] < best_f2[:-1]
    F = F[keep]
    widths = np.append(F[1:, 0], r[0]) - F[:, 0]
    return float(np.sum(widths * (r[1] - F[:, 1])))
