"""MovingAI .map/.scen reading exactly as the benchmark defines it, and one-line errors."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from swarmpath.errors import MapFormatError
from swarmpath.world import parse_map, parse_scen, read_map, read_scen, world_from_movingai, write_map

GOOD = "type octile\nheight 2\nwidth 3\nmap\n.@T\nGSW\n"


def test_terrain_letters() -> None:
    m = parse_map(GOOD)
    assert m.width == 3 and m.height == 2
    assert m.blocked.tolist() == [[False, True, True], [False, False, True]]


@pytest.mark.parametrize("text, words", [
    ("type grid\nheight 1\nwidth 1\nmap\n.\n", "type must be 'octile'"),
    ("type octile\nheight x\nwidth 1\nmap\n.\n", "height must be a whole number"),
    ("type octile\nwidth 1\nmap\n.\n", "lacks 'height'"),
    ("type octile\nheight 1\nwidth 2\nmap\n.\n", "line 5: row 0 has 1 letters, header says width 2"),
    ("type octile\nheight 2\nwidth 1\nmap\n.\n", "height 2 but 1 map rows"),
    ("type octile\nheight 1\nwidth 2\nmap\n.X\n", "line 5, column 2: unknown terrain letter 'X'"),
    ("type octile\nheight 1\nwidth 1\n.\n", "unexpected header line"),
])
def test_bad_maps(text: str, words: str) -> None:
    with pytest.raises(MapFormatError) as err:
        parse_map(text, "bad.map")
    assert str(err.value).startswith("bad.map: ") and words in str(err.value)


def test_bad_scen_rows() -> None:
    m = parse_map(GOOD)
    with pytest.raises(MapFormatError, match=r"s.scen: line 2: start \(5, 0\) is outside the map"):
        parse_scen("version 1\n0\tm.map\t3\t2\t5\t0\t0\t1\t1.0\n", "s.scen", m)
    with pytest.raises(MapFormatError, match="line 2: goal \\(1, 0\\) is a blocked cell"):
        parse_scen("version 1\n0\tm.map\t3\t2\t0\t0\t1\t0\t1.0\n", "s.scen", m)
    with pytest.raises(MapFormatError, match="line 2: expected 9 tab-separated fields"):
        parse_scen("version 1\n0\tm.map\t3\n", "s.scen")
    with pytest.raises(MapFormatError, match="line 1: expected 'version 1'"):
        parse_scen("0\tm.map\t3\t2\t0\t0\t1\t0\t1.0\n", "s.scen")
    with pytest.raises(MapFormatError, match="map size 4x2 differs"):
        parse_scen("version 1\n0\tm.map\t4\t2\t0\t0\t0\t1\t1.0\n", "s.scen", m)


def test_write_then_read(tmp_path: Path) -> None:
    blocked = np.random.default_rng(0).random((7, 11)) < 0.3
    write_map(tmp_path / "x.map", blocked)
    assert np.array_equal(read_map(tmp_path / "x.map").blocked, blocked)


def test_world_from_movingai_places_robots_at_cell_centres(data_dir: Path) -> None:
    w = world_from_movingai(data_dir / "random-32-32-10.map", data_dir / "random-32-32-10-random-1.scen", 20)
    rows = read_scen(data_dir / "random-32-32-10-random-1.scen")[:20]
    assert w.n_robots == 20
    assert np.allclose(w.starts, [(r.start[0] + 0.5, r.start[1] + 0.5) for r in rows])
    assert np.array_equal(w.grid().blocked, read_map(data_dir / "random-32-32-10.map").blocked)


def test_too_many_agents_is_reported(data_dir: Path) -> None:
    from swarmpath.errors import ScenarioError

    with pytest.raises(ScenarioError, match="asks for 9999 agents"):
        world_from_movingai(data_dir / "empty-8-8.map", data_dir / "empty-8-8-even-10.scen", 9999)


def test_missing_file() -> None:
    with pytest.raises(MapFormatError, match="no such map file"):
        read_map("/nonexistent/x.map")
