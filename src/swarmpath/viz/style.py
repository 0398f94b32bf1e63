"""The look shared by every swarmpath picture: colours, titles, figure creation.

One colour per robot (the same in figures, animations and the HTML replay), fixed colours for
world elements, equal aspect, and a title that says what was run: scenario, planner,
controller and seed.

Library code never touches pyplot's global state: :func:`new_figure` returns a
:class:`matplotlib.figure.Figure` bound to an Agg canvas, which is saved and dropped.
"""
from __future__ import annotations

import colorsys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_hex
from matplotlib.figure import Figure
from numpy.typing import NDArray

# World elements (hex strings so that the HTML replay uses exactly the same ones).
BACKGROUND = "#ffffff"
OUTSIDE = "#eceff1"            # area outside a circular workspace
BOUNDARY = "#37474f"
OBSTACLE = "#607d8b"
OBSTACLE_EDGE = "#455a64"
MAP_BLOCKED = "#546e7a"
DANGER = "#e53935"
MOVING = "#8e24aa"
CONTACT = "#d50000"
START_EDGE = "#212121"
TEXT = "#212121"

# Categorical palette for few robots (Okabe-Ito-like, then matplotlib's tab20).
_FEW = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf",
        "#bcbd22", "#7f7f7f", "#393b79", "#e6550d", "#31a354", "#756bb1", "#843c39", "#3182bd",
        "#de9ed6", "#636363", "#ad494a", "#6baed6")

# Colours of controller modes (HTML replay "colour by mode"; legend of mode plots).
_MODE_COLOURS = {"seek": "#e6550d", "trace": "#3182bd", "wait": "#9e9e9e", "prey": "#31a354",
                 "follow": "#756bb1", "swarm": "#d6616b", "move": "#3182bd", "done": "#bdbdbd",
                 "arrived": "#bdbdbd", "goal": "#bdbdbd", "yield": "#fdae6b", "avoid": "#e7298a"}


def _many_palette(size: int = 60) -> tuple[str, ...]:
    """``size`` colours whose hues advance by the golden angle, lightness and saturation
    alternating, so that neighbours in index order are easy to tell apart."""
    golden = 0.618033988749895
    out = []
    for i in range(size):
        h = (0.11 + i * golden) % 1.0
        lightness = (0.42, 0.55, 0.34)[i % 3]
        saturation = (0.75, 0.65, 0.85)[(i // 3) % 3]
        out.append(to_hex(colorsys.hls_to_rgb(h, lightness, saturation)))
    return tuple(out)


_MANY = _many_palette()


def robot_colors(n_robots: int) -> list[str]:
    """One colour per robot, as hex strings; robot i always gets the same colour.

    Up to 20 robots get distinct categorical colours, up to 60 distinct golden-angle hues;
    beyond 60 the hues repeat (nobody tells 1000 colours apart, and the HTML replay draws one
    batch per colour, which keeps 1000 robots fast).
    """
    if n_robots <= len(_FEW):
        return list(_FEW[:n_robots])
    return [_MANY[i % len(_MANY)] for i in range(n_robots)]


def robot_rgba(n_robots: int) -> NDArray[np.float64]:
    """:func:`robot_colors` as an array of shape (n_robots, 4) of RGBA in [0, 1]."""
    from matplotlib.colors import to_rgba_array

    if n_robots == 0:
        return np.zeros((0, 4))
    return to_rgba_array(robot_colors(n_robots))


def mode_colors(mode_names: Sequence[str]) -> list[str]:
    """A colour per controller mode name (known names get fixed colours)."""
    spare = iter(("#66a61e", "#e6ab02", "#a6761d", "#1b9e77", "#7570b3", "#d95f02", "#666666"))
    return [_MODE_COLOURS.get(name.lower()) or next(spare, "#000000") for name in mode_names]


def run_title(scenario: str | None = None, planner: str | None = None, controller: str | None = None,
              seed: int | None = None, extra: str | None = None) -> str:
    """``"jaleel2016 - planner hybrid-apf, controller cat-swarm, seed 0"`` (parts left out when None)."""
    parts = []
    if planner is not None:
        parts.append(f"planner {planner}")
    if controller is not None:
        parts.append(f"controller {controller}")
    if seed is not None:
        parts.append(f"seed {seed}")
    head = scenario or "run"
    title = f"{head} - {', '.join(parts)}" if parts else head
    return f"{title}\n{extra}" if extra else title


def trajectory_title(traj: Any, extra: str | None = None) -> str:
    """The :func:`run_title` of a :class:`~swarmpath.sim.trajectory.Trajectory`."""
    meta = getattr(traj, "meta", {}) or {}
    return run_title(traj.scenario, meta.get("planner") or "none", meta.get("controller"), traj.seed, extra)


def new_figure(width_in: float = 6.4, height_in: float = 6.4, dpi: int = 100) -> Figure:
    """A figure on an Agg canvas, outside pyplot (no global state, nothing to close)."""
    fig = Figure(figsize=(width_in, height_in), dpi=dpi, facecolor=BACKGROUND)
    FigureCanvasAgg(fig)
    return fig


def style_axes(ax: Axes, *, equal: bool = True, grid: bool = False) -> None:
    """Clean axes: equal aspect for world plots, light spines, small ticks."""
    if equal:
        ax.set_aspect("equal", adjustable="box")
    for spine in ax.spines.values():
        spine.set_color("#b0bec5")
        spine.set_linewidth(0.8)
    ax.tick_params(labelsize=8, colors="#455a64", length=3)
    if grid:
        ax.grid(True, color="#eceff1", linewidth=0.8)
        ax.set_axisbelow(True)


def save_figure(fig: Figure, path: str | Path, *, dpi: int | None = None) -> Path:
    """Write ``fig`` as PNG (or any format matplotlib knows from the suffix)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi or fig.dpi, facecolor=fig.get_facecolor(), bbox_inches="tight", pad_inches=0.1)
    return path


def show_robot_legend(n_robots: int) -> bool:
    """Whether a per-robot legend stays readable (few robots)."""
    return 0 < n_robots <= 16
