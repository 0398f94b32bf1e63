"""Animations of a :class:`~swarmpath.sim.trajectory.Trajectory`: GIF (Pillow) or MP4 (ffmpeg).

The world (workspace, obstacles, map raster, danger zones, goals, planned paths) is drawn once;
each frame restores that background and draws only what moves (robots, trails, moving
obstacles, collisions so far, the step counter) on the Agg canvas — matplotlib's blitting,
without a GUI. Frames share one palette, so the GIF stores little more than the pixels that
change between frames.

Long runs are subsampled to at most ``max_frames`` frames (the counter shows the true step);
if a GIF still exceeds ``max_bytes`` it is rendered again smaller.
"""
from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.collections import LineCollection, PolyCollection
from numpy.typing import NDArray

from swarmpath.errors import ConfigError
from swarmpath.viz import style
from swarmpath.viz.world_plot import (
    draw_paths,
    draw_static,
    moving_outline,
    setup_world_axes,
    world_view,
)

Progress = Callable[[int, int], None]
MAX_GIF_BYTES = 10_000_000


def frame_steps(n_steps: int, max_frames: int) -> NDArray[np.int64]:
    """Steps shown by the frames: all of 0..n_steps, or ``max_frames`` of them evenly spread
    (always the first and the last)."""
    if max_frames < 2:
        raise ConfigError(f"max_frames must be at least 2, got {max_frames}")
    if n_steps + 1 <= max_frames:
        return np.arange(n_steps + 1)
    return np.unique(np.round(np.linspace(0, n_steps, max_frames)).astype(np.int64))


class FrameRenderer:
    """Renders frames of one trajectory as RGB arrays of shape (height, width, 3).

    Use :meth:`frame` for one step; the figure and background are built once."""

    def __init__(self, traj: Any, *, trails: bool = True, trail_length: int | None = None,
                 planned: bool = True, width_px: int = 640, dpi: int = 100, y_down: bool | None = None):
        self.traj = traj
        self.trails, self.trail_length = trails, trail_length
        view = world_view(traj, y_down=y_down)
        self.view = view
        x0, x1, y0, y1 = view.extent
        aspect = float(np.clip((y1 - y0) / max(x1 - x0, 1e-9), 0.3, 2.0))
        w_in = width_px / dpi
        pad, title_in = 0.08, 0.4
        ax_w = w_in - 2 * pad
        h_in = ax_w * aspect + pad + title_in
        fig = style.new_figure(w_in, h_in, dpi)
        self.fig = fig
        ax = fig.add_axes((pad / w_in, pad / h_in, ax_w / w_in, ax_w * aspect / h_in))
        self.ax = ax
        n = traj.n_robots
        self.colors = style.robot_colors(n)
        draw_static(ax, view)
        if planned and traj.planned_paths and any(p is not None for p in traj.planned_paths):
            draw_paths(ax, traj.planned_paths, self.colors, linestyle=(0, (3, 2)), linewidth=0.9, alpha=0.45,
                       zorder=3)
        gsize = 50 if n <= 50 else max(6.0, 50 * (50 / n) ** 0.5)
        ax.scatter(traj.goals[:, 0], traj.goals[:, 1], s=gsize, marker="*", c=self.colors,
                   edgecolors=style.START_EDGE, linewidths=0.3, zorder=3.5)
        setup_world_axes(ax, view)
        ax.set_xticks([])
        ax.set_yticks([])
        for spine in ax.spines.values():
            spine.set_visible(False)
        fig.suptitle(style.trajectory_title(traj), fontsize=9, color=style.TEXT, y=1 - 0.08 / h_in,
                     va="top")
        # moving artists
        self.trail_lines = LineCollection([], colors=self.colors, linewidths=1.2 if n <= 100 else 0.5,
                                          alpha=0.75, zorder=4, capstyle="round", animated=True)
        ax.add_collection(self.trail_lines)
        self.outlines = [moving_outline(m["shape"]) for m in view.moving]
        self.obstacles = PolyCollection([], facecolors=style.MOVING, edgecolors="white", linewidths=0.5,
                                        alpha=0.9, zorder=5, animated=True)
        ax.add_collection(self.obstacles)
        self.robots = ax.scatter(traj.positions[0, :, 0], traj.positions[0, :, 1], s=self._robot_sizes(),
                                 c=self.colors, edgecolors=style.START_EDGE, linewidths=0.5 if n <= 200 else 0,
                                 zorder=6, animated=True)
        self.contact_steps = np.array([c.step for c in traj.contacts], int)
        self.contact_xy = np.array([traj.positions[min(c.step, traj.n_steps), c.robot] for c in traj.contacts],
                                   float).reshape(-1, 2)
        self.contacts = ax.scatter([], [], marker="x", s=28, c=style.CONTACT, linewidths=1.3, zorder=7,
                                   animated=True)
        fig.canvas.draw()
        self.background = fig.canvas.copy_from_bbox(fig.bbox)
        # the step counter is drawn with Pillow on the finished frame: matplotlib's text
        # layout would cost more than the rest of the frame
        from matplotlib import font_manager
        from PIL import ImageFont

        font_px = max(9, round(12 * width_px / 640))
        self.font = ImageFont.truetype(font_manager.findfont("DejaVu Sans Mono"), font_px)
        box = ax.get_window_extent()
        self.counter_xy = (int(box.x0) + 6, int(fig.canvas.get_width_height()[1] - box.y1) + 6)

    def _robot_sizes(self) -> NDArray[np.float64]:
        """Marker areas (points^2): a disc robot's true size, at least a visible dot."""
        x0, x1, _, _ = self.ax.get_xlim() + self.ax.get_ylim()
        self.fig.canvas.draw()
        width_pt = self.ax.get_window_extent().width * 72.0 / self.fig.dpi
        pt_per_unit = width_pt / abs(x1 - x0)
        n = self.traj.n_robots
        floor = 30.0 if n <= 50 else max(3.0, 30.0 * (50 / n) ** 0.5)
        return np.maximum((2 * self.traj.radii * pt_per_unit) ** 2, floor)

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of a frame in pixels."""
        w, h = self.fig.canvas.get_width_height()
        return int(w), int(h)

    def frame(self, step: int) -> NDArray[np.uint8]:
        """RGB pixels (height, width, 3) of the world at ``step``."""
        traj, ax, canvas = self.traj, self.ax, self.fig.canvas
        canvas.restore_region(self.background)
        pos = traj.positions[step]
        if self.trails and step > 0:
            t0 = 0 if self.trail_length is None else max(0, step - self.trail_length)
            self.trail_lines.set_segments([traj.positions[t0:step + 1, i] for i in range(traj.n_robots)])
            ax.draw_artist(self.trail_lines)
        if self.outlines:
            obs = traj.obstacle_positions[step]
            self.obstacles.set_verts([o + p for o, p in zip(self.outlines, obs)])
            ax.draw_artist(self.obstacles)
        self.robots.set_offsets(pos)
        ax.draw_artist(self.robots)
        if len(self.contact_steps):
            self.contacts.set_offsets(self.contact_xy[self.contact_steps <= step])
            ax.draw_artist(self.contacts)
        rgb = np.ascontiguousarray(np.asarray(canvas.buffer_rgba())[..., :3])
        return self._draw_counter(rgb, step, pos)

    def _draw_counter(self, rgb: NDArray[np.uint8], step: int, pos: NDArray[np.float64]) -> NDArray[np.uint8]:
        from PIL import Image, ImageDraw

        traj = self.traj
        arrived = int(np.sum(np.linalg.norm(pos - traj.goals, axis=1) <= 1e-6))
        text = f"step {step:>{len(str(traj.n_steps))}d}/{traj.n_steps}  at goal {arrived}/{traj.n_robots}"
        img = Image.fromarray(rgb)
        draw = ImageDraw.Draw(img)
        x, y = self.counter_xy
        left, top, right, bottom = draw.textbbox((x, y), text, font=self.font)
        draw.rounded_rectangle((left - 4, top - 3, right + 4, bottom + 3), radius=4, fill="white", outline="#b0bec5")
        draw.text((x, y), text, font=self.font, fill=style.TEXT)
        return np.asarray(img)


def iter_frames(traj: Any, steps: NDArray[np.int64], **renderer_options: Any) -> Iterator[NDArray[np.uint8]]:
    """RGB frames (height, width, 3) of ``traj`` at ``steps``."""
    renderer = FrameRenderer(traj, **renderer_options)
    for s in steps:
        yield renderer.frame(int(s))


def ffmpeg_available() -> bool:
    return shutil.which("ffmpeg") is not None


def save_animation(traj: Any, path: str | Path, *, fps: int = 10, trails: bool = True,
                   progress: Progress | None = None, trail_length: int | None = None, max_frames: int = 300,
                   width_px: int = 640, max_bytes: int = MAX_GIF_BYTES, y_down: bool | None = None) -> Path:
    """Write an animation of ``traj``: a GIF (Pillow) for ``.gif``, an MP4 for ``.mp4`` (needs
    ffmpeg on PATH). Returns the path written.

    fps : frames per second; trails : draw each robot's path so far (the last
    ``trail_length`` steps, or all); progress : called as ``progress(done, total)`` after each
    frame; max_frames : longer runs are subsampled; max_bytes : a GIF above this is rendered
    again at a smaller size and with fewer frames (until it fits); y_down : screen direction
    of y (None: downward for worlds on a map raster, else upward)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ConfigError(f"{path}: animation format must be .gif or .mp4")
    if fps < 1:
        raise ConfigError(f"fps must be at least 1, got {fps}")
    if suffix == ".mp4" and not ffmpeg_available():
        raise ConfigError(f"{path}: writing MP4 needs ffmpeg on PATH; write a .gif instead")
    path.parent.mkdir(parents=True, exist_ok=True)
    options = {"trails": trails, "trail_length": trail_length, "width_px": width_px, "y_down": y_down}
    if suffix == ".mp4":
        _write_mp4(traj, path, frame_steps(traj.n_steps, max_frames), fps, options, progress)
        return path
    for _attempt in range(4):
        _write_gif(traj, path, frame_steps(traj.n_steps, max_frames), fps, options, progress)
        if path.stat().st_size <= max_bytes:
            break
        options["width_px"] = int(options["width_px"] * 0.75)
        max_frames = max(2, int(max_frames * 0.7))
    return path


def _write_gif(traj: Any, path: Path, steps: NDArray[np.int64], fps: int, options: dict,
               progress: Progress | None) -> None:
    from PIL import Image

    renderer = FrameRenderer(traj, **options)
    total = len(steps)
    rgb = [renderer.frame(int(s)) for s in steps[:1]]
    if progress is not None:
        progress(1, total)
    # one palette for all frames: from the first and the last frame side by side
    last = renderer.frame(int(steps[-1]))
    palette = Image.fromarray(np.concatenate([rgb[0], last], axis=1)).quantize(
        colors=255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    frames = [Image.fromarray(rgb[0]).quantize(palette=palette, dither=Image.Dither.NONE)]
    for k, s in enumerate(steps[1:], start=2):
        img = last if s == steps[-1] else renderer.frame(int(s))
        frames.append(Image.fromarray(img).quantize(palette=palette, dither=Image.Dither.NONE))
        if progress is not None:
            progress(k, total)
    frame_ms = max(20, round(1000 / fps))
    durations = [frame_ms] * len(frames)
    durations[-1] = max(frame_ms, 1500)          # hold the final state
    frames[0].save(path, format="GIF", save_all=True, append_images=frames[1:], duration=durations, loop=0,
                   optimize=False, disposal=1)


def _write_mp4(traj: Any, path: Path, steps: NDArray[np.int64], fps: int, options: dict,
               progress: Progress | None) -> None:
    renderer = FrameRenderer(traj, **options)
    w, h = renderer.size
    cmd = [shutil.which("ffmpeg") or "ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
           "-s", f"{w}x{h}", "-r", str(fps), "-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
           "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", str(path)]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdin is not None
    try:
        for k, s in enumerate(steps, start=1):
            proc.stdin.write(renderer.frame(int(s)).tobytes())
            if progress is not None:
                progress(k, len(steps))
        proc.stdin.close()
    except BrokenPipeError:
        pass
    err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
    if proc.wait() != 0:
        raise ConfigError(f"{path}: ffmpeg failed: {err.strip().splitlines()[-1] if err.strip() else proc.returncode}")
