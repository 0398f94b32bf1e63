"""The store: results apart from timings, one writer at a time, resumable, readable while a
sweep writes, and ``swarmpath.bench.load`` returning its rows (a DataFrame with pandas)."""
from __future__ import annotations

import sqlite3
import sys
from pathlib import Path

import pytest

from swarmpath.bench.sweep.jobs import expand
from swarmpath.bench.sweep.run import run_sweep
from swarmpath.bench.sweep.store import RESULT_COLUMNS, Store
from swarmpath.bench.sweep.suite import load_suite
from swarmpath.errors import ConfigError


def test_a_sweep_stores_each_job_once_and_resumes(tiny_suite: Path, tmp_path: Path) -> None:
    db = tmp_path / "r.db"
    suite = load_suite(tiny_suite)
    first = run_sweep(suite, db, workers=1)
    assert (first.total, first.already, first.ran, first.statuses["ok"]) == (2, 0, 2, 2)
    again = run_sweep(suite, db, workers=1)
    assert (again.already, again.ran) == (2, 0)
    with Store(db).open() as s:
        rows = s.rows()
        assert [r["seed"] for r in sorted(rows, key=lambda r: r["seed"])] == [0, 1]
        assert all(r["status"] == "ok" and r["wall_s"] > 0 and r["engine"] == "local" for r in rows)
        assert [x["jobs_run"] for x in s.sweeps()] == [2, 0]
        assert all(x["state"] == "finished" for x in s.sweeps())
    # results hold no timings: planning and simulation times live in the timings table
    names = {n for n, _ in RESULT_COLUMNS}
    assert not names & {"wall_s", "planning_time_s", "sim_time_s"}
    import json

    assert not {"planning_time_s", "sim_time_s"} & set(json.loads(rows[0]["outcome"]))


def test_retry_runs_failed_jobs_again(tmp_path: Path) -> None:
    p = tmp_path / "s.yaml"
    p.write_text("name: r\nscenarios: [karim2014]\ncontrollers: [fish-swarm, {name: cat-swarm, params: "
                 "{mixture_ratio: 2.0}}]\n")
    db = tmp_path / "r.db"
    suite = load_suite(p)
    assert run_sweep(suite, db, workers=1).statuses == {"ok": 1, "error": 1, "timeout": 0}
    again = run_sweep(suite, db, workers=1, retry=("error",))
    assert (again.already, again.ran, again.statuses["error"]) == (1, 1, 1)


def test_one_writer_at_a_time(tiny_suite: Path, tmp_path: Path) -> None:
    db = tmp_path / "r.db"
    with Store(db).open(write=True):
        with pytest.raises(ConfigError, match="another sweep is writing to this store"):
            run_sweep(load_suite(tiny_suite), db, workers=1)
        with Store(db).open() as reader:          # readers are welcome meanwhile
            assert reader.rows() == []
    assert run_sweep(load_suite(tiny_suite), db, workers=1).ran == 2


def test_a_foreign_or_missing_file_is_one_line(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="no such results store"):
        Store(tmp_path / "none.db").open()
    junk = tmp_path / "junk.db"
    junk.write_text("not sqlite at all " * 100)
    with pytest.raises(ConfigError, match="not a swarmpath results store"):
        Store(junk).open()
    other = tmp_path / "other.db"
    sqlite3.connect(other).execute("CREATE TABLE t (x)").connection.commit()
    with pytest.raises(ConfigError, match="not a swarmpath results store"):
        Store(other).open()


def test_load_gives_a_dataframe_or_plain_rows(tiny_suite: Path, tmp_path: Path, monkeypatch) -> None:
    import swarmpath.bench

    db = tmp_path / "r.db"
    run_sweep(load_suite(tiny_suite), db, workers=1)
    pd = pytest.importorskip("pandas")
    frame = swarmpath.bench.load(db)
    assert isinstance(frame, pd.DataFrame) and len(frame) == 2
    assert {"key", "scenario", "controller", "seed", "success", "wall_s"} <= set(frame.columns)
    monkeypatch.setitem(sys.modules, "pandas", None)       # as if pandas were not installed
    rows = swarmpath.bench.load(db)
    assert isinstance(rows, list) and sorted(r["seed"] for r in rows) == [0, 1]
    assert list(frame["key"]) == [r["key"] for r in rows]


def test_expansion_does_not_touch_the_store(tiny_suite: Path, tmp_path: Path) -> None:
    expand(load_suite(tiny_suite))
    assert not (tmp_path / "r.db").exists()
