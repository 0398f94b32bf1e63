"""Animations: a GIF with one frame per step (or a subsample), frames that change, moving
obstacles and trails drawn, a progress callback, the size budget, MP4 only with ffmpeg."""
from __future__ import annotations

import itertools

import numpy as np
import pytest
from PIL import Image, ImageSequence

from swarmpath.errors import ConfigError
from swarmpath.viz import animation, style
from swarmpath.viz.animation import FrameRenderer, frame_steps, save_animation


def gif_frames(path) -> list[np.ndarray]:
    with Image.open(path) as im:
        return [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)]


def test_frame_steps():
    np.testing.assert_array_equal(frame_steps(5, 10), np.arange(6))
    s = frame_steps(1000, 300)
    assert len(s) == 300 and s[0] == 0 and s[-1] == 1000 and np.all(np.diff(s) > 0)
    with pytest.raises(ConfigError):
        frame_steps(10, 1)


def test_gif_of_a_run(jaleel_run, tmp_path, facts):
    traj = jaleel_run.trajectory
    calls = []
    path = save_animation(traj, tmp_path / "run.gif", progress=lambda done, total: calls.append((done, total)))
    assert path.exists() and path.stat().st_size < 10_000_000
    frames = gif_frames(path)
    assert len(frames) == traj.n_steps + 1
    assert calls[-1] == (traj.n_steps + 1, traj.n_steps + 1)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    h, w, _ = frames[0].shape
    assert w == 640 and 500 < h < 800
    # consecutive frames differ (robots move), the first and the last differ a lot
    changed = [np.mean(np.any(a != b, axis=2)) for a, b in itertools.pairwise(frames[:11])]
    assert all(c > 0 for c in changed)
    assert np.mean(np.any(frames[0] != frames[-1], axis=2)) > 0.005
    f = facts(path)
    assert f["ink"] > 0.2 and f["colours"] > 10


def test_frames_show_robots_trails_and_moving_obstacles(synthetic):
    traj = synthetic(4, 30)
    with_trails = FrameRenderer(traj, trails=True).frame(20)
    without = FrameRenderer(traj, trails=False).frame(20)
    assert np.mean(np.any(with_trails != without, axis=2)) > 0.001
    moving = np.array([int(style.MOVING[i:i + 2], 16) for i in (1, 3, 5)])

    def moving_pixels(img):
        return np.argwhere(np.all(np.abs(img.astype(int) - moving) <= 25, axis=2))

    r = FrameRenderer(traj)
    a, b = moving_pixels(r.frame(0)), moving_pixels(r.frame(10))
    assert len(a) > 20 and len(b) > 20
    assert abs(a[:, 1].mean() - b[:, 1].mean()) > 5          # the obstacle moved to the right
    for c in style.robot_colors(4):                            # every robot is drawn
        rgb = np.array([int(c[i:i + 2], 16) for i in (1, 3, 5)])
        assert np.sum(np.all(np.abs(r.frame(5).astype(int) - rgb) <= 20, axis=2)) > 10, c


def test_long_runs_are_subsampled(synthetic, tmp_path):
    traj = synthetic(3, 120)
    path = save_animation(traj, tmp_path / "long.gif", max_frames=25, fps=20)
    assert len(gif_frames(path)) == 25


def test_size_budget_shrinks_the_gif(synthetic, tmp_path):
    traj = synthetic(30, 16, keep_moving=True)
    full = save_animation(traj, tmp_path / "full.gif", width_px=400)
    small = save_animation(traj, tmp_path / "small.gif", width_px=400, max_bytes=full.stat().st_size // 2)
    assert small.stat().st_size < full.stat().st_size
    assert gif_frames(small)[0].shape[1] < gif_frames(full)[0].shape[1]


def test_disc_robots_and_static_maps(synthetic, tmp_path, facts):
    traj = synthetic(5, 10, radius=0.8, static_map=True)
    path = save_animation(traj, tmp_path / "discs.gif", trails=False)
    f = facts(path)
    assert f["ink"] > 0.1


def test_formats(synthetic, tmp_path, monkeypatch):
    traj = synthetic(2, 5)
    with pytest.raises(ConfigError, match="gif or .mp4"):
        save_animation(traj, tmp_path / "x.avi")
    with pytest.raises(ConfigError):
        save_animation(traj, tmp_path / "x.gif", fps=0)
    monkeypatch.setattr(animation.shutil, "which", lambda name: None)
    with pytest.raises(ConfigError, match="ffmpeg"):
        save_animation(traj, tmp_path / "x.mp4")


@pytest.mark.skipif(not animation.ffmpeg_available(), reason="ffmpeg is not installed (MP4 is optional)")
def test_mp4(synthetic, tmp_path):
    path = save_animation(synthetic(3, 12), tmp_path / "x.mp4")
    assert path.stat().st_size > 1000


def test_mp4_frames_are_piped_to_ffmpeg(synthetic, tmp_path, monkeypatch):
    """With a stand-in ffmpeg that stores its input, the stream holds every frame, raw RGB."""
    fake = tmp_path / "ffmpeg"
    fake.write_text('#!/bin/sh\nfor last; do :; done\ncat > "$last"\n')
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{tmp_path}:{__import__('os').environ['PATH']}")
    traj = synthetic(3, 12)
    path = save_animation(traj, tmp_path / "x.mp4")
    w, h = FrameRenderer(traj).size
    assert path.stat().st_size == (traj.n_steps + 1) * w * h * 3
