"""Statistics of the reproductions: one paired test, nan-aware summaries, paired counts.

Every comparison of two configurations in a report runs on the same seeds, so samples are
*paired* (run r of both used seed r). :func:`wilcoxon_vs` is the one test of the package.
"""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import ArrayLike

#: Significance level of every verdict.
ALPHA = 0.05


def wilcoxon_vs(variant: ArrayLike, baseline: ArrayLike) -> tuple[float, str]:
    """Two-sided paired Wilcoxon signed-rank test of ``variant`` against ``baseline`` (lower is
    better), two samples over the same seeds.

    NaN and ties, decided once for every report:

    - a pair with a NaN (or an infinity) on either side is dropped (a run without a result
      has nothing to compare);
    - fewer than two pairs left, or every paired difference zero: p = 1, "no difference";
    - zero differences among others are dropped by the test (scipy's ``zero_method="wilcox"``,
      Wilcoxon's own rule); the p-value is exact for up to 50 pairs without ties, else the
      normal approximation (scipy's ``method="auto"``);
    - a p-value that is not finite counts as "no difference".

    Returns
    -------
    (p, verdict) with verdict "better" / "worse" (the median paired difference variant -
    baseline is below / above 0, at the 5 % level) or "no difference".
    """
    from scipy.stats import wilcoxon

    v = np.asarray(variant, float)
    b = np.asarray(baseline, float)
    ok = np.isfinite(v) & np.isfinite(b)
    diff = v[ok] - b[ok]
    if diff.shape[0] < 2 or np.all(diff == 0):
        return 1.0, "no difference"
    p = float(wilcoxon(v[ok], b[ok]).pvalue)
    if not np.isfinite(p) or p >= ALPHA:
        return p, "no difference"
    return p, "better" if np.median(diff) < 0 else "worse"


def finite(values: ArrayLike) -> np.ndarray:
    """The finite entries of ``values`` as a float array (1-D)."""
    v = np.asarray(values, float).ravel()
    return v[np.isfinite(v)]


def mean(values: Iterable[float] | ArrayLike) -> float:
    """Mean of the values (NaN when there are none; NaN entries propagate)."""
    v = np.asarray(list(values) if not isinstance(values, np.ndarray) else values, float)
    return float(v.mean()) if v.size else float("nan")


def describe(values: ArrayLike, name: str) -> float:
    """``name`` in mean / median / std (population) / min / max of the finite values; NaN
    when there are none."""
    v = finite(values)
    if len(v) == 0:
        return float("nan")
    return float({"mean": np.mean, "median": np.median, "std": np.std, "min": np.min, "max": np.max}[name](v))


def share_within(values: ArrayLike, lo: float, hi: float) -> float:
    """Fraction of the finite values in [lo, hi] (NaN when there are none)."""
    v = finite(values)
    return float(np.mean((v >= lo) & (v <= hi))) if len(v) else float("nan")


def paired_counts(a: ArrayLike, b: ArrayLike) -> tuple[int, int, int]:
    """Pairs where ``a`` is below / equal to / above ``b`` (pairs with a NaN skipped)."""
    x, y = np.asarray(a, float), np.asarray(b, float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    return int(np.sum(x < y)), int(np.sum(x == y)), int(np.sum(x > y))
