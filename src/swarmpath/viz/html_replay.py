"""A self-contained interactive HTML replay of a :class:`~swarmpath.sim.trajectory.Trajectory`.

One file, no network access: the page (``replay_template.html``, plain JavaScript on a
``<canvas>``) and the data are inlined. Controls: play/pause, step, scrub, speed, toggles for
trails / planned paths / sensing ranges / labels / colour by controller mode / collisions,
hover a robot for its id, mode, remaining length and distance to goal, wheel zoom, drag pan,
double-click to fit.

Data encoding (compact, exact to a quantum of 1/65535 of the world's extent):

- positions (T + 1, n, 2) are quantised to int16 over the bounding box, differenced along time
  (robots move little per step, and not at all once arrived), split into low and high byte
  planes and gzip-compressed, then base64 (the page inflates with the browser's
  ``DecompressionStream``); moving obstacles and planned paths the same way;
- the static map raster is bit-packed and gzip-compressed;
- modes are int8 (T, n), gzip-compressed.

A 1000-robot x 300-step replay is a few megabytes at most and renders a frame in a few
milliseconds (see benchmarks/bench_replay.py).
"""
from __future__ import annotations

import base64
import gzip
import json
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmpath.viz import style
from swarmpath.viz.world_plot import moving_outline, world_view

DATA_MARKER = "/*__SWARMPATH_REPLAY_DATA__*/null"
FORMAT_VERSION = 1


def _b64(raw: bytes, compress: bool = True) -> str:
    if compress:
        raw = gzip.compress(raw, compresslevel=6, mtime=0)
    return base64.b64encode(raw).decode("ascii")


def _quantise(points: NDArray[np.float64], lo: NDArray[np.float64], scale: NDArray[np.float64]) -> NDArray[np.int32]:
    """int values in [-32768, 32767] of points (..., 2) on the grid lo + (q + 32768) * scale."""
    q = np.round((np.asarray(points, float) - lo) / scale) - 32768
    return np.clip(q, -32768, 32767).astype(np.int32)


def _shuffled_int16(values: NDArray[np.integer]) -> bytes:
    """int16 values (wrapping) as a low-byte plane followed by a high-byte plane."""
    u = (np.asarray(values, np.int64) % 65536).astype(np.uint16).ravel()
    return (u & 0xFF).astype(np.uint8).tobytes() + (u >> 8).astype(np.uint8).tobytes()


def encode_track(points: NDArray[np.float64], lo: NDArray[np.float64], scale: NDArray[np.float64]) -> str:
    """Positions (T, k, 2) as base64 gzip of time-differenced, byte-shuffled int16."""
    q = _quantise(points, lo, scale)
    if len(q) > 1:
        q = np.concatenate([q[:1], np.diff(q, axis=0)], axis=0)
    return _b64(_shuffled_int16(q))


def decode_track(text: str, shape: tuple[int, int, int], lo: NDArray[np.float64],
                 scale: NDArray[np.float64]) -> NDArray[np.float64]:
    """Inverse of :func:`encode_track` (what the page's JavaScript does), for tests."""
    raw = np.frombuffer(gzip.decompress(base64.b64decode(text)), np.uint8)
    half = raw.size // 2
    u = raw[:half].astype(np.uint16) | (raw[half:].astype(np.uint16) << 8)
    d = u.view(np.int16).astype(np.int64).reshape(shape)
    q = (np.cumsum(d, axis=0) + 32768) % 65536 - 32768
    return lo + (q + 32768) * scale


def _padded_modes(traj: Any) -> NDArray[np.int8] | None:
    """Modes (n_steps, n_robots), front-padded with -1 if the controller reported modes only
    from some step on."""
    if traj.modes is None:
        return None
    m = np.asarray(traj.modes, np.int8).reshape(-1, traj.n_robots)
    if len(m) < traj.n_steps:
        m = np.concatenate([np.full((traj.n_steps - len(m), traj.n_robots), -1, np.int8), m])
    return m[:traj.n_steps]


def replay_payload(traj: Any, *, sensing_range: float | None = None, title: str | None = None,
                   y_down: bool | None = None) -> dict:
    """The JSON document the page reads (arrays encoded as described in the module docstring)."""
    view = world_view(traj, y_down=y_down)
    n, n_steps = traj.n_robots, traj.n_steps
    pos = np.asarray(traj.positions, float).reshape(n_steps + 1, n, 2)
    obs = np.asarray(traj.obstacle_positions, float).reshape(n_steps + 1, -1, 2)
    x0, x1, y0, y1 = view.extent
    pts = [np.array([[x0, y0], [x1, y1]]), pos.reshape(-1, 2), obs.reshape(-1, 2), traj.goals.reshape(-1, 2)]
    planned = [None if p is None else np.asarray(p, float).reshape(-1, 2) for p in (traj.planned_paths or [])]
    pts += [p for p in planned if p is not None]
    allp = np.concatenate([p for p in pts if len(p)])
    allp = allp[np.all(np.isfinite(allp), axis=1)]
    lo = allp.min(axis=0) - 1e-9
    hi = allp.max(axis=0) + 1e-9
    scale = np.maximum((hi - lo) / 65535.0, 1e-12)
    meta = traj.meta or {}
    if sensing_range is None:
        sensing_range = meta.get("sensing_range")
    if sensing_range is None:
        from swarmpath.control.observation import SensingConfig

        sensing_range = SensingConfig().range * traj.resolution
    modes = _padded_modes(traj)
    doc: dict[str, Any] = {
        "format": "swarmpath-replay", "version": FORMAT_VERSION,
        "title": title or style.trajectory_title(traj).replace("\n", " - "),
        "scenario": traj.scenario, "planner": meta.get("planner") or "none", "controller": meta.get("controller"),
        "seed": traj.seed, "status": traj.status, "dt": traj.dt, "resolution": traj.resolution,
        "n_robots": n, "n_steps": n_steps, "n_obstacles": int(obs.shape[1]),
        "robot_ids": list(traj.robot_ids), "colors": style.robot_colors(n),
        "radii": np.round(np.asarray(traj.radii, float), 6).tolist(),
        "goals": _b64(np.asarray(traj.goals, np.float32).tobytes(), compress=False),
        "quant": {"lo": lo.tolist(), "scale": scale.tolist()},
        "positions": encode_track(pos, lo, scale),
        "obstacles": encode_track(obs, lo, scale) if obs.shape[1] else None,
        "obstacle_ids": list(traj.obstacle_ids),
        "obstacle_outlines": [np.round(moving_outline(m["shape"]), 6).tolist() for m in view.moving],
        "modes": None if modes is None else _b64(modes.tobytes()),
        "mode_names": [m or "-" for m in traj.mode_names],
        "mode_colors": style.mode_colors([m or "-" for m in traj.mode_names]),
        "sensing_range": float(sensing_range),
        "world": {
            "bounds": view.bounds, "extent": [x0, x1, y0, y1], "y_down": view.y_down,
            "obstacles": view.obstacles, "danger_zones": view.danger_zones,
        },
        "static_map": None,
        "planned": None,
        "contacts": None,
        "n_contacts": len(traj.contacts),
        "events": _event_counts(traj.events),
        "style": {"background": style.BACKGROUND, "outside": style.OUTSIDE, "boundary": style.BOUNDARY,
                  "obstacle": style.OBSTACLE, "obstacle_edge": style.OBSTACLE_EDGE, "map": style.MAP_BLOCKED,
                  "danger": style.DANGER, "moving": style.MOVING, "contact": style.CONTACT},
    }
    if view.static_map is not None:
        sm = np.asarray(view.static_map, bool)
        doc["static_map"] = {"width": int(sm.shape[1]), "height": int(sm.shape[0]),
                             "bits": _b64(np.packbits(sm.ravel()).tobytes())}
    if planned and any(p is not None for p in planned):
        lengths = np.array([0 if p is None else len(p) for p in planned], np.int32)
        cat = np.concatenate([p for p in planned if p is not None]) if lengths.sum() else np.zeros((0, 2))
        doc["planned"] = {"lengths": _b64(lengths.tobytes(), compress=False),
                          "points": _b64(_shuffled_int16(_quantise(cat, lo, scale)))}
    if traj.contacts:
        kinds = sorted({c.kind for c in traj.contacts})
        rows = np.array(sorted([c.step, c.robot, c.other, kinds.index(c.kind)] for c in traj.contacts), np.int32)
        doc["contacts"] = {"rows": _b64(rows.tobytes()), "kinds": kinds}
    return doc


def _event_counts(events: list[dict]) -> dict[str, int]:
    counts: dict[str, int] = {}
    for ev in events:
        kind = str(ev.get("kind", "event"))
        counts[kind] = counts.get(kind, 0) + 1
    return counts


def template() -> str:
    """The HTML page with the data marker (``DATA_MARKER``) still in it."""
    return resources.files("swarmpath.viz").joinpath("replay_template.html").read_text(encoding="utf-8")


def replay_html(traj: Any, *, sensing_range: float | None = None, title: str | None = None,
                y_down: bool | None = None) -> str:
    """The whole HTML document for ``traj``."""
    payload = replay_payload(traj, sensing_range=sensing_range, title=title, y_down=y_down)
    # "<" escaped so that no "</script>" can end the script element early
    data = json.dumps(payload, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")
    page = template()
    if DATA_MARKER not in page:  # pragma: no cover - packaging error
        raise RuntimeError("replay template lacks its data marker")
    title_text = payload["title"].replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    page = page.replace("<title>swarmpath replay</title>", f"<title>{title_text} - swarmpath replay</title>", 1)
    return page.replace(DATA_MARKER, data, 1)


def write_replay_html(traj: Any, path: str | Path, *, sensing_range: float | None = None,
                      title: str | None = None, y_down: bool | None = None) -> Path:
    """Write the self-contained replay of ``traj`` (a Trajectory) to ``path``; returns it.

    sensing_range : radius drawn by the "sensing ranges" toggle, in world units (default:
        ``traj.meta["sensing_range"]``, else the simulator's default sensing range)
    y_down : screen direction of y (None: downward for worlds on a map raster, else upward)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(replay_html(traj, sensing_range=sensing_range, title=title, y_down=y_down), encoding="utf-8")
    return path
