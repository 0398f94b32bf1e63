"""Acceptance: every row of the public MovingAI scenario files is reproduced to 1e-6 (relative)
by the Python API (A* and distance field) and by the `swarmpath path` command."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from swarmpath.cli import cli
from swarmpath.data.movingai import MOVINGAI
from swarmpath.search import astar, distance_field
from swarmpath.world import read_map, read_scen

DATA = MOVINGAI
SCENS = sorted(DATA.glob("*.scen"))


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-6 * max(1.0, abs(b))


@pytest.mark.parametrize("scen", SCENS, ids=lambda p: p.name)
def test_api_reproduces_every_row(scen: Path) -> None:
    rows = read_scen(scen)
    grid = read_map(DATA / rows[0].map_name).blocked
    fields: dict = {}
    for row in rows:
        result = astar(grid, row.start, row.goal)
        assert _close(result.cost, row.optimal_length), (row.line, result.cost, row.optimal_length)
        field = fields.setdefault(row.goal, distance_field(grid, row.goal))
        assert _close(field[row.start[1], row.start[0]], row.optimal_length), row.line


@pytest.mark.parametrize("scen", ["random-32-32-10-random-1.scen", "maze-32-32-2-even-10.scen"])
def test_cli_reproduces_every_row(scen: str) -> None:
    rows = read_scen(DATA / scen)
    runner = CliRunner()
    for row in rows:
        res = runner.invoke(cli, ["path", "--map", str(DATA / row.map_name), "--start", *map(str, row.start),
                                  "--goal", *map(str, row.goal), "--json"])
        assert res.exit_code == 0, res.output
        doc = json.loads(res.output)
        assert _close(doc["cost"], row.optimal_length), (row.line, doc["cost"])
        path = np.asarray(doc["path"])
        assert tuple(path[0]) == row.start and tuple(path[-1]) == row.goal


def test_cli_as_a_process_matches_the_contract_example() -> None:
    out = subprocess.run([sys.executable, "-m", "swarmpath.cli", "path", "--map", str(DATA / "random-32-32-10.map"),
                          "--start", "11", "6", "--goal", "7", "18", "--json"], capture_output=True, text=True,
                         check=True)
    doc = json.loads(out.stdout)
    assert abs(doc["cost"] - 13.65685425) < 1e-6
