"""Figures of a world and of paths in it.

``plot_world`` draws the workspace (rectangle or circle), static obstacles (circles,
rectangles, polygons, and the raster of a static map), danger zones, moving obstacles at one
step, starts and goals. ``plot_paths`` adds planned paths (dashed) and executed paths (solid),
one colour per robot; ``plot_trajectory`` does both for a saved run. Everything takes a
:class:`~swarmpath.world.World`, its scenario dict, or a
:class:`~swarmpath.sim.trajectory.Trajectory` (which carries its world), through
:class:`WorldView`.

Coordinates: x to the right; y up, except for worlds with a static map, where y grows
downward like the map's rows (MovingAI convention), so maps look as they do in their files.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle as CirclePatch
from matplotlib.patches import Patch
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.patches import Rectangle as RectPatch
from numpy.typing import NDArray

from swarmpath.viz import style

FloatArray = NDArray[np.float64]


# ---------------------------------------------------------------------------------- the view
@dataclass(frozen=True)
class WorldView:
    """What the pictures need of a world, in plain data.

    bounds : the scenario dict of the workspace ({"type": "rectangle", "width", "height"} or
        {"type": "circle", "center", "radius"})
    obstacles : scenario dicts of the static obstacles
    static_map : blocked[y, x] raster (cells of ``resolution`` units) or None
    moving : scenario dicts of the moving obstacles (shape relative to the position)
    starts, goals : (n_robots, 2); radii : (n_robots,)
    """

    name: str
    bounds: dict
    resolution: float
    obstacles: list[dict] = field(default_factory=list)
    danger_zones: list[dict] = field(default_factory=list)
    moving: list[dict] = field(default_factory=list)
    robot_ids: list[str] = field(default_factory=list)
    starts: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    goals: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    radii: FloatArray = field(default_factory=lambda: np.zeros(0))
    static_map: NDArray[np.bool_] | None = None
    y_down_override: bool | None = None

    @property
    def n_robots(self) -> int:
        return len(self.robot_ids)

    @property
    def y_down(self) -> bool:
        """Whether y grows downward on screen: by default for worlds built on a map raster."""
        if self.y_down_override is not None:
            return self.y_down_override
        return self.static_map is not None

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the workspace (and the map raster)."""
        b = self.bounds
        if b.get("type") == "circle":
            (cx, cy), r = b["center"], b["radius"]
            x0, x1, y0, y1 = cx - r, cx + r, cy - r, cy + r
        else:
            x0, x1, y0, y1 = 0.0, float(b["width"]), 0.0, float(b["height"])
        if self.static_map is not None:
            h, w = self.static_map.shape
            x1, y1 = max(x1, w * self.resolution), max(y1, h * self.resolution)
        return float(x0), float(x1), float(y0), float(y1)


def world_view(source: Any, *, y_down: bool | None = None) -> WorldView:
    """A :class:`WorldView` of a World, a Trajectory, or a scenario dict (schema 1).

    y_down : draw y growing downward (True), upward (False), or decide by the world (None:
        downward for worlds with a static map raster)."""
    if isinstance(source, WorldView):
        return source if y_down is None else replace(source, y_down_override=y_down)
    static_map = None
    if hasattr(source, "positions") and hasattr(source, "world"):        # a Trajectory
        doc, static_map = source.world, source.static_map
    elif hasattr(source, "to_dict") and hasattr(source, "robots"):        # a World
        doc = source.to_dict()
        sm = getattr(source, "static_map", None)
        static_map = None if sm is None else np.asarray(sm.blocked)
    elif isinstance(source, dict):
        doc = source
    else:
        raise TypeError(f"cannot draw a {type(source).__name__}; give a World, a Trajectory or a scenario dict")
    robots = doc.get("robots", [])
    res = float(doc.get("resolution", 1.0))
    bounds = doc.get("bounds")
    if bounds is None:
        if static_map is None:
            raise ValueError("world has neither bounds nor a static map")
        bounds = {"type": "rectangle", "width": static_map.shape[1] * res, "height": static_map.shape[0] * res}
    return WorldView(
        name=str(doc.get("name", "")), bounds=dict(bounds), resolution=res,
        obstacles=list(doc.get("obstacles", [])), danger_zones=list(doc.get("danger_zones", [])),
        moving=list(doc.get("moving_obstacles", [])), robot_ids=[str(r["id"]) for r in robots],
        starts=np.array([r["start"] for r in robots], float).reshape(-1, 2),
        goals=np.array([r["goal"] for r in robots], float).reshape(-1, 2),
        radii=np.array([r.get("radius", 0.0) for r in robots], float),
        static_map=None if static_map is None else np.asarray(static_map, bool), y_down_override=y_down)


def moving_outline(shape: dict) -> FloatArray:
    """Outline of a moving obstacle's footprint relative to its position: (k, 2) vertices.

    Accepts {"type": "circle", "radius"} and rectangles as {"min", "max"} corners or
    {"width", "height"} (centred)."""
    if shape.get("type") == "circle":
        t = np.linspace(0, 2 * np.pi, 33)[:-1]
        return float(shape["radius"]) * np.stack([np.cos(t), np.sin(t)], axis=1)
    if "min" in shape:
        (x0, y0), (x1, y1) = shape["min"], shape["max"]
    else:
        w, h = float(shape["width"]) / 2, float(shape["height"]) / 2
        x0, y0, x1, y1 = -w, -h, w, h
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


# ---------------------------------------------------------------------------------- drawing
def _shape_patch(d: dict, **kw) -> Any:
    kind = d.get("type")
    if kind == "circle":
        return CirclePatch(tuple(d["center"]), float(d["radius"]), **kw)
    if kind == "rectangle":
        (x0, y0), (x1, y1) = d["min"], d["max"]
        return RectPatch((x0, y0), x1 - x0, y1 - y0, **kw)
    if kind == "polygon":
        return PolygonPatch(np.asarray(d["points"], float), closed=True, **kw)
    raise ValueError(f"unknown obstacle type {kind!r}")


def setup_world_axes(ax: Axes, view: WorldView, margin: float = 0.02) -> None:
    """Limits, equal aspect and y direction for ``view``."""
    x0, x1, y0, y1 = view.extent
    pad = margin * max(x1 - x0, y1 - y0)
    ax.set_xlim(x0 - pad, x1 + pad)
    if view.y_down:
        ax.set_ylim(y1 + pad, y0 - pad)
    else:
        ax.set_ylim(y0 - pad, y1 + pad)
    style.style_axes(ax, equal=True)


def draw_static(ax: Axes, view: WorldView) -> None:
    """Workspace, static obstacles, static map raster and danger zones."""
    b = view.bounds
    if b.get("type") == "circle":
        x0, x1, y0, y1 = view.extent
        ax.add_patch(RectPatch((x0, y0), x1 - x0, y1 - y0, facecolor=style.OUTSIDE, edgecolor="none", zorder=0))
        ax.add_patch(CirclePatch(tuple(b["center"]), float(b["radius"]), facecolor=style.BACKGROUND,
                                 edgecolor=style.BOUNDARY, linewidth=1.4, zorder=0.5))
    else:
        ax.add_patch(RectPatch((0, 0), float(b["width"]), float(b["height"]), facecolor=style.BACKGROUND,
                               edgecolor=style.BOUNDARY, linewidth=1.4, zorder=0.5))
    if view.static_map is not None and view.static_map.any():
        h, w = view.static_map.shape
        cmap = ListedColormap([(0, 0, 0, 0), style.MAP_BLOCKED])
        ax.imshow(view.static_map.astype(np.uint8), cmap=cmap, vmin=0, vmax=1, interpolation="nearest",
                  origin="lower", extent=(0, w * view.resolution, 0, h * view.resolution), zorder=1)
        ax.set_aspect("equal", adjustable="box")
    if view.obstacles:
        patches = [_shape_patch(o) for o in view.obstacles]
        ax.add_collection(PatchCollection(patches, facecolor=style.OBSTACLE, edgecolor=style.OBSTACLE_EDGE,
                                          linewidth=0.8, zorder=1.2))
    for dz in view.danger_zones:
        c, r = tuple(dz["center"]), float(dz.get("radius", 0.0))
        if r > 0:
            ax.add_patch(CirclePatch(c, r, facecolor=style.DANGER, alpha=0.18, edgecolor=style.DANGER,
                                     linewidth=1.0, linestyle="--", zorder=1.1))
        ax.plot(*c, marker="X", color=style.DANGER, markersize=8, markeredgecolor="white", zorder=4)


def draw_moving(ax: Axes, view: WorldView, positions: FloatArray | None = None,
                history: FloatArray | None = None) -> None:
    """Moving obstacles at ``positions`` (m, 2) (default: their starts); ``history``
    (T, m, 2) adds each obstacle's track as a thin dotted line."""
    if not view.moving:
        return
    if positions is None:
        positions = np.array([m["start"] for m in view.moving], float)
    if history is not None and len(history) > 1:
        for k in range(history.shape[1]):
            if k < len(view.moving) and view.moving[k].get("motion") == "redraw":
                continue                                  # it jumps: a track would be noise
            ax.plot(history[:, k, 0], history[:, k, 1], color=style.MOVING, linewidth=0.7, linestyle=":",
                    alpha=0.45, zorder=2)
    for m, p in zip(view.moving, positions):
        ax.add_patch(PolygonPatch(moving_outline(m["shape"]) + p, closed=True, facecolor=style.MOVING,
                                  edgecolor="white", linewidth=0.6, alpha=0.9, zorder=3))


def draw_starts_goals(ax: Axes, view: WorldView, colors: Sequence[str] | None = None, *,
                      label_ids: bool | None = None) -> None:
    """Starts as open circles, goals as stars, in each robot's colour."""
    n = view.n_robots
    if n == 0:
        return
    colors = list(colors or style.robot_colors(n))
    size = 36 if n <= 50 else max(4.0, 36 * (50 / n) ** 0.5)
    ax.scatter(view.starts[:, 0], view.starts[:, 1], s=size, facecolors="white", edgecolors=colors,
               linewidths=1.4, zorder=5)
    ax.scatter(view.goals[:, 0], view.goals[:, 1], s=size * 2.2, marker="*", c=colors,
               edgecolors=style.START_EDGE, linewidths=0.4, zorder=5)
    if label_ids is None:
        label_ids = n <= 16
    if label_ids:
        for rid, s, c in zip(view.robot_ids, view.starts, colors):
            ax.annotate(rid, s, xytext=(3, 3), textcoords="offset points", fontsize=7, color=c,
                        fontweight="bold", zorder=6)


def draw_paths(ax: Axes, paths: Sequence[FloatArray | None], colors: Sequence[str], *, linestyle: str = "-",
               linewidth: float = 1.6, alpha: float = 0.95, zorder: float = 4) -> None:
    """Polylines (one (n_points, 2) array per robot; None skipped) in one LineCollection."""
    segs, cols = [], []
    for p, c in zip(paths, colors):
        if p is None or len(p) < 2:
            continue
        segs.append(np.asarray(p, float))
        cols.append(c)
    if segs:
        ax.add_collection(LineCollection(segs, colors=cols, linestyles=linestyle, linewidths=linewidth,
                                         alpha=alpha, zorder=zorder, capstyle="round", joinstyle="round"))


def _legend(ax: Axes, view: WorldView, colors: Sequence[str], *, planned: bool, executed: bool,
            contacts: bool) -> None:
    handles: list[Any] = []
    if view.obstacles or (view.static_map is not None and view.static_map.any()):
        handles.append(Patch(facecolor=style.OBSTACLE, edgecolor=style.OBSTACLE_EDGE, label="obstacle"))
    if view.danger_zones:
        handles.append(Patch(facecolor=style.DANGER, alpha=0.3, edgecolor=style.DANGER, label="danger zone"))
    if view.moving:
        handles.append(Patch(facecolor=style.MOVING, label="moving obstacle"))
    if view.n_robots:
        handles.append(Line2D([], [], marker="o", color="none", markerfacecolor="white",
                              markeredgecolor=style.START_EDGE, label="start"))
        handles.append(Line2D([], [], marker="*", color="none", markerfacecolor=style.START_EDGE,
                              markersize=10, label="goal"))
    if planned:
        handles.append(Line2D([], [], color=style.START_EDGE, linestyle="--", linewidth=1.2, label="planned"))
    if executed:
        handles.append(Line2D([], [], color=style.START_EDGE, linewidth=1.8, label="executed"))
    if contacts:
        handles.append(Line2D([], [], marker="x", color="none", markeredgecolor=style.CONTACT, label="collision"))
    if style.show_robot_legend(view.n_robots):
        handles += [Line2D([], [], color=c, linewidth=3, label=rid) for rid, c in zip(view.robot_ids, colors)]
    if handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False,
                  borderaxespad=0.0, handlelength=1.8)


# ---------------------------------------------------------------------------------- figures
def plot_world(world: Any, *, title: str | None = None, ax: Axes | None = None,
               obstacle_positions: FloatArray | None = None, legend: bool = True,
               y_down: bool | None = None) -> Figure:
    """The world alone: workspace, obstacles, danger zones, moving obstacles, starts, goals.
    ``y_down`` as in :func:`world_view`."""
    view = world_view(world, y_down=y_down)
    fig, ax = _fig_ax(ax)
    colors = style.robot_colors(view.n_robots)
    draw_static(ax, view)
    draw_moving(ax, view, obstacle_positions)
    draw_starts_goals(ax, view, colors)
    setup_world_axes(ax, view)
    ax.set_title(title if title is not None else (view.name or "world"), fontsize=10, color=style.TEXT)
    if legend:
        _legend(ax, view, colors, planned=False, executed=False, contacts=False)
    return fig


def plot_paths(world: Any, *, planned: Sequence[FloatArray | None] | None = None,
               executed: Sequence[FloatArray | None] | None = None, title: str | None = None,
               ax: Axes | None = None, obstacle_history: FloatArray | None = None,
               contacts: FloatArray | None = None, legend: bool = True, y_down: bool | None = None) -> Figure:
    """World plus planned paths (dashed) and executed paths (solid), one colour per robot.

    planned, executed : one (n_points, 2) array (or None) per robot
    obstacle_history : (T, m, 2) positions of the moving obstacles (tracks are drawn, and the
        obstacles at their last position)
    contacts : (k, 2) places where the simulator found collisions (red crosses)
    y_down : as in :func:`world_view`
    """
    view = world_view(world, y_down=y_down)
    fig, ax = _fig_ax(ax)
    colors = style.robot_colors(view.n_robots)
    draw_static(ax, view)
    last = None if obstacle_history is None or len(obstacle_history) == 0 else obstacle_history[-1]
    draw_moving(ax, view, last, obstacle_history)
    many = view.n_robots > 50
    if planned:
        draw_paths(ax, planned, colors, linestyle=(0, (3, 2)), linewidth=0.6 if many else 1.1,
                   alpha=0.55 if executed else 0.9, zorder=3.5)
    if executed:
        draw_paths(ax, executed, colors, linewidth=0.7 if many else 1.8, alpha=0.9, zorder=4)
    draw_starts_goals(ax, view, colors)
    has_contacts = contacts is not None and len(contacts) > 0
    if has_contacts:
        ax.scatter(contacts[:, 0], contacts[:, 1], marker="x", s=30, c=style.CONTACT, linewidths=1.3, zorder=7)
    setup_world_axes(ax, view)
    ax.set_title(title if title is not None else (view.name or "paths"), fontsize=10, color=style.TEXT)
    if legend:
        _legend(ax, view, colors, planned=bool(planned), executed=bool(executed), contacts=has_contacts)
    return fig


def executed_paths(positions: FloatArray) -> list[FloatArray]:
    """Per robot, the executed polyline (n_points, 2) with repeated positions (waits) removed.

    positions : (T + 1, n_robots, 2)"""
    out = []
    for i in range(positions.shape[1]):
        p = positions[:, i]
        keep = np.ones(len(p), bool)
        keep[1:] = np.any(np.abs(np.diff(p, axis=0)) > 1e-12, axis=1)
        out.append(p[keep])
    return out


def contact_points(traj: Any) -> FloatArray:
    """(k, 2) positions of the robots involved in the trajectory's contacts, at their step."""
    pts = [traj.positions[min(c.step, traj.n_steps), c.robot] for c in traj.contacts
           if 0 <= c.robot < traj.n_robots]
    return np.asarray(pts, float).reshape(-1, 2)


def plot_trajectory(traj: Any, *, planned: bool = True, executed: bool = True, title: str | None = None,
                    ax: Axes | None = None, legend: bool = True, y_down: bool | None = None) -> Figure:
    """Planned and executed paths of a :class:`~swarmpath.sim.trajectory.Trajectory`, with the
    tracks of the moving obstacles and the collisions found by the simulator."""
    plans = [p for p in traj.planned_paths] if planned and traj.planned_paths else None
    if plans is not None and all(p is None for p in plans):
        plans = None
    extra = f"{traj.n_robots} robots, {traj.n_steps} steps, {traj.status.replace('_', ' ')}"
    return plot_paths(traj, planned=plans, executed=executed_paths(traj.positions) if executed else None,
                      title=title if title is not None else style.trajectory_title(traj, extra), ax=ax,
                      obstacle_history=traj.obstacle_positions if traj.obstacle_positions.size else None,
                      contacts=contact_points(traj), legend=legend, y_down=y_down)


def plot_snapshots(traj: Any, steps: Sequence[int] | None = None, *, n_panels: int = 4, ncols: int = 4,
                   title: str | None = None, panel_size: float = 3.0, y_down: bool | None = None) -> Figure:
    """Small multiples: the world at several steps (default: ``n_panels`` evenly spread),
    each with the moving obstacles where they are then and every robot's path so far."""
    view = world_view(traj, y_down=y_down)
    if steps is None:
        steps = sorted({round(x) for x in np.linspace(0, traj.n_steps, n_panels)})
    steps = [min(max(int(s), 0), traj.n_steps) for s in steps]
    ncols = min(ncols, len(steps))
    nrows = -(-len(steps) // ncols)
    fig = style.new_figure(panel_size * ncols + 0.3, panel_size * nrows + 0.6)
    colors = style.robot_colors(view.n_robots)
    for k, step in enumerate(steps):
        ax = fig.add_subplot(nrows, ncols, k + 1)
        draw_static(ax, view)
        if traj.obstacle_positions.size:
            draw_moving(ax, view, traj.obstacle_positions[step])
        if step > 0:
            draw_paths(ax, executed_paths(traj.positions[:step + 1]), colors, linewidth=1.4)
        pos = traj.positions[step]
        ax.scatter(view.goals[:, 0], view.goals[:, 1], s=40, marker="*", c=colors, edgecolors=style.START_EDGE,
                   linewidths=0.4, zorder=5)
        ax.scatter(pos[:, 0], pos[:, 1], s=30, c=colors, edgecolors=style.START_EDGE, linewidths=0.5, zorder=6)
        setup_world_axes(ax, view)
        ax.set_title(f"step {step}", fontsize=9, color=style.TEXT)
    fig.suptitle(title if title is not None else style.trajectory_title(traj), fontsize=10, color=style.TEXT)
    fig.tight_layout()
    return fig


def _fig_ax(ax: Axes | None) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.figure, ax
    fig = style.new_figure(7.6, 6.0)
    return fig, fig.add_subplot(1, 1, 1)
