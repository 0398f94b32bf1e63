"""Generic curve figures for reports: UTD curves, optimiser convergence, Pareto fronts, grouped
bars. They take plain arrays (what the metrics and optimisers return) and return a
:class:`matplotlib.figure.Figure` (Agg, outside pyplot); reproductions save them with
:func:`swarmpath.viz.style.save_figure`.

Series are given as a mapping ``label -> array``. A 1-D array is one curve; a 2-D array of
shape (n_runs, n_points) is several runs of the same configuration, drawn as their centre
(mean or median) with a shaded band (std, min-max or interquartile range). Runs of different
lengths can be given as a list of 1-D arrays: shorter runs are held at their last value (a
finished run stays finished), which is what UTD after arrival and best-so-far values mean.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from numpy.typing import ArrayLike, NDArray

from swarmpath.viz import style

FloatArray = NDArray[np.float64]
Series = Mapping[str, "ArrayLike | Sequence[ArrayLike]"]


def stack_runs(runs: ArrayLike | Sequence[ArrayLike]) -> FloatArray:
    """Runs as an array of shape (n_runs, n_points): a 1-D input becomes one run; runs of
    different lengths are padded with their last value."""
    if isinstance(runs, np.ndarray) and runs.dtype != object:
        arr = np.asarray(runs, float)
        return arr[None, :] if arr.ndim == 1 else arr.reshape(arr.shape[0], -1)
    items = list(runs)  # type: ignore[arg-type]
    if all(np.ndim(r) == 0 for r in items):          # a plain list of numbers: one run
        return np.asarray(items, float).reshape(1, -1)
    seq = [np.asarray(r, float).ravel() for r in items]
    length = max((len(r) for r in seq), default=0)
    out = np.full((len(seq), length), np.nan)
    for k, r in enumerate(seq):
        if len(r):
            out[k, :len(r)] = r
            out[k, len(r):] = r[-1]
    return out


def band(runs: FloatArray, center: str = "mean", spread: str | None = "std") -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
    """Centre line and band edges of runs (n_runs, n_points).

    center : "mean" or "median"; spread : "std" (centre +- one standard deviation), "minmax",
    "iqr" (25th-75th percentile) or None."""
    if center == "median":
        mid = np.nanmedian(runs, axis=0)
    elif center == "mean":
        mid = np.nanmean(runs, axis=0)
    else:
        raise ValueError(f"center must be 'mean' or 'median', not {center!r}")
    if spread is None or runs.shape[0] < 2:
        return mid, None, None
    if spread == "std":
        sd = np.nanstd(runs, axis=0, ddof=1)
        return mid, mid - sd, mid + sd
    if spread == "minmax":
        return mid, np.nanmin(runs, axis=0), np.nanmax(runs, axis=0)
    if spread == "iqr":
        return mid, np.nanpercentile(runs, 25, axis=0), np.nanpercentile(runs, 75, axis=0)
    raise ValueError(f"spread must be 'std', 'minmax', 'iqr' or None, not {spread!r}")


def plot_curves(series: Series, *, xlabel: str = "step", ylabel: str = "", title: str | None = None,
                x: ArrayLike | None = None, center: str = "mean", spread: str | None = "std",
                log_y: bool = False, ax: Axes | None = None, colors: Sequence[str] | None = None,
                legend_title: str | None = None) -> Figure:
    """Curves of several labelled series, each a run or a set of runs (see module docstring)."""
    fig, ax = _fig_ax(ax)
    colors = list(colors) if colors is not None else style.robot_colors(len(series))
    for (label, runs), color in zip(series.items(), colors):
        arr = stack_runs(runs)
        if arr.size == 0:
            continue
        xs = np.arange(arr.shape[1]) if x is None else np.asarray(x, float)[:arr.shape[1]]
        mid, lo, hi = band(arr, center, spread)
        n_label = f"{label} (n={arr.shape[0]})" if arr.shape[0] > 1 else str(label)
        ax.plot(xs, mid, color=color, linewidth=1.6, label=n_label)
        if lo is not None:
            if log_y:
                lo = np.where(lo > 0, lo, np.nan)
            ax.fill_between(xs, lo, hi, color=color, alpha=0.18, linewidth=0)
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_ylabel(ylabel, fontsize=9)
    style.style_axes(ax, equal=False, grid=True)
    if title:
        ax.set_title(title, fontsize=10, color=style.TEXT)
    if len(series):
        ax.legend(fontsize=8, frameon=False, title=legend_title, title_fontsize=8)
    return fig


def plot_utd_curves(series: Series, *, title: str | None = None, dt: float = 1.0, spread: str | None = "std",
                    ax: Axes | None = None, legend_title: str | None = None) -> Figure:
    """UTD(t) = sum_i ||G_i - C_i(t)|| against steps (PSO-prediction paper, section 7).

    series : label -> UTD curve (n_steps + 1,) or runs (n_runs, n_steps + 1) / list of curves;
    several runs are drawn as their mean (the paper's AUTD) with a +-1 std band."""
    longest = max((stack_runs(v).shape[1] for v in series.values()), default=0)
    return plot_curves(series, xlabel="step" if dt == 1.0 else "time", ylabel="UTD (sum of distances to goals)",
                       title=title, x=np.arange(longest) * dt, center="mean", spread=spread, ax=ax,
                       legend_title=legend_title)


def plot_convergence(series: Series, *, title: str | None = None, log_y: bool = True, center: str = "median",
                     spread: str | None = "iqr", xlabel: str = "iteration", ylabel: str = "best value",
                     ax: Axes | None = None) -> Figure:
    """Optimiser convergence: best-so-far value against iterations, per algorithm.

    series : algorithm -> history (n_iterations,) or runs (n_runs, n_iterations); several runs
    are drawn as their median with the interquartile band (log y by default)."""
    if log_y:
        mins = [np.nanmin(stack_runs(v)) for v in series.values() if stack_runs(v).size]
        log_y = bool(mins) and min(mins) > 0
    return plot_curves(series, xlabel=xlabel, ylabel=ylabel, title=title, center=center, spread=spread,
                       log_y=log_y, ax=ax)


def pareto_mask(points: ArrayLike) -> NDArray[np.bool_]:
    """Which rows of ``points`` (n, k), all objectives minimised, no other row dominates."""
    p = np.asarray(points, float).reshape(len(points), -1) if len(points) else np.zeros((0, 2))
    le = np.all(p[:, None, :] <= p[None, :, :], axis=-1)
    lt = np.any(p[:, None, :] < p[None, :, :], axis=-1)
    dominated = np.any(le & lt, axis=0)
    return ~dominated


def plot_pareto_fronts(fronts: Mapping[str, ArrayLike], *, objectives: tuple[str, str] = ("f1", "f2"),
                       title: str | None = None, others: Mapping[str, ArrayLike] | None = None,
                       highlight: Mapping[str, ArrayLike] | None = None, ax: Axes | None = None) -> Figure:
    """Two-objective Pareto fronts (both minimised), one per label.

    fronts : label -> points (n, 2); the non-dominated ones are joined by a staircase
    others : label -> points (n, 2) drawn faintly (e.g. dominated archive members)
    highlight : label -> one point (2,) marked with a large symbol (e.g. the weighted-sum
        choice or the paper's solution)"""
    fig, ax = _fig_ax(ax)
    colors = style.robot_colors(len(fronts) + len(others or {}) + len(highlight or {}))
    k = 0
    for label, pts in (others or {}).items():
        p = np.asarray(pts, float).reshape(-1, 2)
        ax.scatter(p[:, 0], p[:, 1], s=10, color=colors[k], alpha=0.3, linewidths=0, label=label)
        k += 1
    for label, pts in fronts.items():
        p = np.asarray(pts, float).reshape(-1, 2)
        mask = pareto_mask(p)
        front = p[mask]
        front = front[np.argsort(front[:, 0])]
        if (~mask).any():
            ax.scatter(p[~mask, 0], p[~mask, 1], s=10, color=colors[k], alpha=0.3, linewidths=0, zorder=2)
        ax.scatter(front[:, 0], front[:, 1], s=22, color=colors[k], zorder=3,
                   label=f"{label} ({len(front)} non-dominated of {len(p)})")
        if len(front) > 1:
            ax.step(front[:, 0], front[:, 1], where="post", color=colors[k], linewidth=1.2, alpha=0.8, zorder=2)
        k += 1
    markers = iter("DsP^vX")
    for label, pt in (highlight or {}).items():
        q = np.asarray(pt, float).ravel()
        ax.scatter([q[0]], [q[1]], s=80, marker=next(markers, "D"), color=colors[k], edgecolors="black",
                   linewidths=0.8, zorder=4, label=label)
        k += 1
    ax.set_xlabel(objectives[0], fontsize=9)
    ax.set_ylabel(objectives[1], fontsize=9)
    style.style_axes(ax, equal=False, grid=True)
    if title:
        ax.set_title(title, fontsize=10, color=style.TEXT)
    ax.legend(fontsize=8, frameon=False)
    return fig


def plot_grouped_bars(categories: Sequence[str], series: Mapping[str, ArrayLike], *,
                      errors: Mapping[str, ArrayLike] | None = None, ylabel: str = "", xlabel: str = "",
                      title: str | None = None, ax: Axes | None = None) -> Figure:
    """Grouped bars: for each category (x), one bar per series (e.g. steps with and without
    prediction per number of robots). series : label -> values (n_categories,); errors :
    label -> error bar half-heights (n_categories,)."""
    fig, ax = _fig_ax(ax)
    n = max(len(series), 1)
    width = 0.8 / n
    xs = np.arange(len(categories))
    colors = style.robot_colors(len(series))
    for k, (label, values) in enumerate(series.items()):
        v = np.asarray(values, float)
        err = None if errors is None or label not in errors else np.asarray(errors[label], float)
        ax.bar(xs + (k - (n - 1) / 2) * width, v, width * 0.92, yerr=err, color=colors[k], label=label,
               capsize=2, error_kw={"linewidth": 0.8})
    ax.set_xticks(xs, [str(c) for c in categories])
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_ylabel(ylabel, fontsize=9)
    style.style_axes(ax, equal=False, grid=True)
    ax.grid(False, axis="x")
    if title:
        ax.set_title(title, fontsize=10, color=style.TEXT)
    if len(series):
        ax.legend(fontsize=8, frameon=False)
    return fig


def _fig_ax(ax: Axes | None) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.figure, ax
    fig = style.new_figure(6.4, 4.2)
    return fig, fig.add_subplot(1, 1, 1)
