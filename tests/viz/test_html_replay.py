"""The HTML replay file: self-contained, data embedded compactly and exactly enough, safe
against robot names that look like markup. (The browser tests drive the page itself.)"""
from __future__ import annotations

import base64
import dataclasses
import gzip
import json
import re

import numpy as np

from swarmpath.viz.html_replay import (
    DATA_MARKER,
    decode_track,
    encode_track,
    replay_html,
    replay_payload,
    write_replay_html,
)


def payload_of(html: str) -> dict:
    m = re.search(r'<script id="replay-data" type="application/json">(.*?)</script>', html, re.DOTALL)
    assert m, "no data element"
    return json.loads(m.group(1))


def external_references(html: str) -> list[str]:
    """src/href attributes or CSS url()s that point to the network."""
    refs = re.findall(r'(?:src|href)\s*=\s*["\']?\s*((?:https?:)?//[^"\'\s>]*)', html, re.IGNORECASE)
    refs += re.findall(r'url\(\s*["\']?((?:https?:)?//[^)"\']*)', html, re.IGNORECASE)
    refs += re.findall(r'@import', html)
    return refs


def test_replay_is_self_contained(jaleel_run, tmp_path):
    path = write_replay_html(jaleel_run.trajectory, tmp_path / "replay.html")
    html = path.read_text(encoding="utf-8")
    assert html.startswith("<!DOCTYPE html>")
    assert external_references(html) == []
    assert not re.search(r"https?://", html)                    # no network address at all
    assert "<link" not in html and not re.search(r"<script[^>]+src=", html)
    assert DATA_MARKER not in html
    assert "jaleel2016" in html and "<canvas" in html
    for control in ("play", "step-fwd", "step-back", "scrub", "speed", "opt-trails", "opt-planned",
                    "opt-sensing", "step-counter"):
        assert f'id="{control}"' in html, control


def test_external_reference_check_can_fail():
    assert external_references('<img src="https://example.org/x.png">')
    assert external_references("<a href='//cdn.example/x.js'>")
    assert external_references('<style>a{background:url("http://x/y.png")}</style>')


def test_track_encoding_round_trip(synthetic):
    traj = synthetic(25, 60, keep_moving=True)
    doc = replay_payload(traj)
    lo, scale = np.array(doc["quant"]["lo"]), np.array(doc["quant"]["scale"])
    back = decode_track(doc["positions"], traj.positions.shape, lo, scale)
    assert np.max(np.abs(back - traj.positions)) <= scale.max() * 0.5 + 1e-9
    assert scale.max() < 1e-3                                    # 20-unit world: sub-millimetre quantum
    obs = decode_track(doc["obstacles"], traj.obstacle_positions.shape, lo, scale)
    np.testing.assert_allclose(obs, traj.obstacle_positions, atol=scale.max())


def test_encoding_survives_large_jumps():
    """Differences beyond the int16 range wrap and still decode exactly (the page's Int16Array
    accumulates the same way)."""
    pts = np.array([[[0.0, 0.0]], [[1000.0, 1000.0]], [[0.0, 1000.0]], [[1000.0, 0.0]]])
    lo, scale = np.zeros(2), np.full(2, 1000.0 / 65535)
    back = decode_track(encode_track(pts, lo, scale), pts.shape, lo, scale)
    np.testing.assert_allclose(back, pts, atol=scale[0])


def test_payload_carries_modes_plans_contacts_and_map(synthetic):
    traj = synthetic(4, 12, static_map=True)
    doc = replay_payload(traj)
    assert doc["n_robots"] == 4 and doc["n_steps"] == 12
    assert doc["mode_names"] == ["seek", "trace", "wait"] and len(doc["mode_colors"]) == 3
    modes = np.frombuffer(gzip.decompress(base64.b64decode(doc["modes"])), np.int8).reshape(12, 4)
    np.testing.assert_array_equal(modes, traj.modes)
    bits = np.frombuffer(gzip.decompress(base64.b64decode(doc["static_map"]["bits"])), np.uint8)
    raster = np.unpackbits(bits)[:traj.static_map.size].reshape(traj.static_map.shape).astype(bool)
    np.testing.assert_array_equal(raster, traj.static_map)
    assert doc["world"]["y_down"] is True
    rows = np.frombuffer(gzip.decompress(base64.b64decode(doc["contacts"]["rows"])), np.int32).reshape(-1, 4)
    assert rows.tolist() == [[3, 0, 1, 0]] and doc["contacts"]["kinds"] == ["robot_robot"]
    lengths = np.frombuffer(base64.b64decode(doc["planned"]["lengths"]), np.int32)
    assert lengths.tolist() == [2, 2, 2, 2]
    assert doc["events"] == {"invalid_move": 1}
    assert doc["sensing_range"] > 0
    assert doc["colors"][0] == "#1f77b4"


def test_modes_reported_from_a_later_step_are_aligned(synthetic):
    traj = synthetic(3, 10)
    traj = dataclasses.replace(traj, modes=traj.modes[4:])    # the controller began reporting at step 5
    doc = replay_payload(traj)
    modes = np.frombuffer(gzip.decompress(base64.b64decode(doc["modes"])), np.int8).reshape(10, 3)
    assert np.all(modes[:4] == -1) and np.array_equal(modes[4:], traj.modes)


def test_markup_in_names_cannot_break_out(synthetic):
    traj = synthetic(2, 4, robot_ids=["</script><script>alert(1)</script>", "a&b"])
    html = replay_html(traj)
    assert html.count("</script>") == 2                       # the data block's and the code's
    doc = payload_of(html)
    assert doc["robot_ids"][0] == "</script><script>alert(1)</script>"


def test_thousand_robots_replay_is_compact(synthetic, tmp_path):
    traj = synthetic(1000, 300, size=150.0, keep_moving=True)
    path = write_replay_html(traj, tmp_path / "big.html")
    size = path.stat().st_size
    print(f"\n1000 robots x 300 steps (all moving every step): replay.html {size / 1e6:.2f} MB")
    raw_float32 = traj.positions.size * 4
    assert size < 0.6 * raw_float32                           # smaller than the bare float32 positions
    assert size < 5_000_000
