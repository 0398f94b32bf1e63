"""Figures of the artificial potential field, in the manner of Jaleel & Hassan 2016,
Figures 2-4: the field as a heatmap with arrows along the negative gradient, the obstacles,
the robots' starts and goals, and paths.

Only reads results (fields and plans); the planners never plot. Figures are
:class:`matplotlib.figure.Figure` objects on an Agg canvas (no pyplot state).
"""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Circle as CirclePatch
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.patches import Rectangle as RectPatch
from numpy.typing import ArrayLike, NDArray

from swarmpath.world.bounds import CircleBounds
from swarmpath.world.shapes import Circle, Polygon, Rect

FloatArray = NDArray[np.float64]

_OBSTACLE = "#607d8b"
_EDGE = "#37474f"
_PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
            "#bcbd22", "#7f7f7f", "#393b79", "#e6550d")


def _colour(i: int) -> str:
    return _PALETTE[i % len(_PALETTE)]


def display_values(total: ArrayLike, clip_quantile: float = 0.98) -> NDArray[np.float64]:
    """The field as shown: ``log(1 + U - min U)`` clipped at a quantile of the finite values
    (the repulsive term grows without bound at obstacles and would flatten the picture);
    blocked cells (``inf``) become NaN. Shape as ``total``."""
    u = np.asarray(total, float)
    finite = np.isfinite(u)
    out = np.full(u.shape, np.nan)
    if not finite.any():
        return out
    v = np.log1p(u[finite] - u[finite].min())
    out[finite] = np.minimum(v, np.quantile(v, clip_quantile))
    return out


def _draw_world(ax: Axes, world) -> None:
    b = world.bounds
    if isinstance(b, CircleBounds):
        ax.add_patch(CirclePatch(tuple(b.center), b.radius, fill=False, edgecolor=_EDGE, linewidth=1.4, zorder=3))
    else:
        ax.add_patch(RectPatch((0, 0), b.width, b.height, fill=False, edgecolor=_EDGE, linewidth=1.4, zorder=3))
    for ob in world.obstacles:
        kw = dict(facecolor=_OBSTACLE, edgecolor=_EDGE, linewidth=0.8, zorder=3)
        if isinstance(ob, Circle):
            ax.add_patch(CirclePatch(tuple(ob.center), ob.radius, **kw))
        elif isinstance(ob, Rect):
            ax.add_patch(RectPatch(tuple(ob.min), ob.max[0] - ob.min[0], ob.max[1] - ob.min[1], **kw))
        elif isinstance(ob, Polygon):
            ax.add_patch(PolygonPatch(ob.vertices, closed=True, **kw))
    if world.static_map is not None:
        sm = world.static_map
        ax.imshow(sm.blocked.astype(np.uint8), cmap=ListedColormap([(0, 0, 0, 0), _OBSTACLE]), vmin=0, vmax=1,
                  origin="lower", interpolation="nearest", zorder=3,
                  extent=(0, sm.width * sm.cell_size, 0, sm.height * sm.cell_size))


def plot_potential_field(world, field, paths: Sequence[ArrayLike | None] | None = None, ax: Axes | None = None, *,
                         arrows: int = 24, title: str | None = None) -> Figure:
    """Heatmap of the field with arrows along ``-grad U``, the obstacles, every robot's start
    (circle) and goal (star), and ``paths`` (one polyline (n, 2) or None per robot, drawn in
    the robot's colour; a path list shorter than the robot list is allowed).

    ``field`` is a :class:`~swarmpath.planning.potential_field.PotentialField` or a plain
    array (height, width) of potential values on ``world.grid()`` (arrows then come from its
    finite differences). ``arrows``: about that many arrows across the wider side. Returns
    the figure (a new one unless ``ax`` is given)."""
    if ax is None:
        fig = Figure(figsize=(6.4, 6.4))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    if hasattr(field, "total"):
        total, res = np.asarray(field.total), field.grid.resolution
        gradient = np.asarray(field.gradient)
    else:
        total = np.asarray(field, float)
        res = world.resolution
        filled = np.where(np.isfinite(total), total, np.nan)
        gy, gx = np.gradient(filled, res)
        gradient = np.nan_to_num(np.stack([gx, gy], axis=-1))
    h, w = total.shape
    extent = (0, w * res, 0, h * res)
    image = ax.imshow(display_values(total), origin="lower", extent=extent, cmap="viridis", interpolation="nearest",
                      zorder=1)
    fig.colorbar(image, ax=ax, fraction=0.046, pad=0.04, label="log(1 + U - min U), clipped")
    step = max(1, int(np.ceil(max(h, w) / arrows)))
    ys, xs = np.mgrid[step // 2:h:step, step // 2:w:step]
    g = -gradient[ys, xs]
    norm = np.linalg.norm(g, axis=-1)
    ok = np.isfinite(total[ys, xs]) & (norm > 0)
    unit = g[ok] / norm[ok][:, None]
    ax.quiver((xs[ok] + 0.5) * res, (ys[ok] + 0.5) * res, unit[:, 0], unit[:, 1], color="white", alpha=0.8,
              scale=arrows * 1.6, width=0.003, zorder=2)
    _draw_world(ax, world)
    if paths is not None:
        for i, p in enumerate(paths):
            if p is not None and len(p):
                p = np.asarray(p, float)
                ax.plot(p[:, 0], p[:, 1], color=_colour(i), linewidth=1.6, zorder=4)
    starts, goals = world.starts, world.goals
    for i in range(world.n_robots):
        ax.plot(*starts[i], marker="o", color=_colour(i), markeredgecolor="black", markersize=6, zorder=5)
        ax.plot(*goals[i], marker="*", color=_colour(i), markeredgecolor="black", markersize=10, zorder=5)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    if title:
        ax.set_title(title)
    return fig


def write_offline_figures(world, out_dir: str | Path, *, robot: int = 0, params=None, dpi: int = 110) -> list[Path]:
    """The three offline pictures of the paper for ``world``, written as PNGs to ``out_dir``:
    ``apf-field.png`` (Figure 2: the field of robot ``robot``), ``apf-paths.png`` (Figure 3:
    plain APF paths, partial where a local minimum stopped them) and ``hybrid-paths.png``
    (Figure 4: the hybrid planner's paths). Returns the written paths."""
    from swarmpath.planning.apf import APFPlanner
    from swarmpath.planning.hybrid_apf import HybridAPFPlanner
    from swarmpath.planning.potential_field import FieldParameters, potential_field

    p = params or FieldParameters()
    kw = dict(attractive_gain=p.attractive_gain, quadratic_range=p.quadratic_range,
              repulsive_gain=p.repulsive_gain, influence_range=p.influence_range)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    r = world.robots[robot]
    field = potential_field(world, r.goal, radius=r.radius, params=p)
    apf = APFPlanner(**kw).plan(world)
    hybrid = HybridAPFPlanner(**kw).plan(world)
    apf_paths = [rp.path if rp else rp.diagnostics.get("partial_path") for rp in apf.robots]
    written = []
    for name, paths, title in (("apf-field.png", None, f"{world.name}: potential field of {r.id}"),
                               ("apf-paths.png", apf_paths, f"{world.name}: APF paths "
                                                            f"(local minima: {apf.diagnostics['local_minima']})"),
                               ("hybrid-paths.png", hybrid.paths, f"{world.name}: hybrid APF + A* + B-spline")):
        fig = plot_potential_field(world, field, paths, title=title)
        path = out / name
        fig.savefig(path, dpi=dpi)
        written.append(path)
    return written
