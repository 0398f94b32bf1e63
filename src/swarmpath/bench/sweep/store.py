"""The results store: one SQLite file (standard library), one row per job.

Tables:

- ``results``: the job's inputs (scenario, agents, planner, controller, parameters, seed,
  step budget), its status (``ok``, ``error``, ``timeout``) and error, and every field of
  ``swarmpath run --json`` except timings (flattened into columns, and whole in ``outcome``);
  outcomes only, so two stores of the same suite compare equal whatever ran them;
- ``timings``: per job, the run's wall time in the worker, the time spent building its world
  (0 when the worker had it already), planning and simulation time, the engine;
- ``skipped``: planner/controller pairs (and peers) a suite could not run, and why;
- ``sweeps``: each ``swarmpath bench`` call (suite, engine, workers, jobs run, start and end).

One process writes (the sweep's parent; workers never touch the file), and holds an
exclusive lock on it while it does, so a second sweep on the same store is refused instead
of running the same jobs twice. Each result is committed as it arrives: a sweep killed at any
moment keeps every job it finished. Readers (``bench report``, :func:`load`) may read while a
sweep writes (write-ahead log).
"""
from __future__ import annotations

import json
import math
import sqlite3
import time
from pathlib import Path
from typing import Any, Iterable

from swarmpath.errors import ConfigError

SCHEMA_VERSION = 1

#: Columns of ``results``, in order (name, SQL type); ``key`` is the primary key.
RESULT_COLUMNS: tuple[tuple[str, str], ...] = (
    ("key", "TEXT PRIMARY KEY"), ("suite", "TEXT"), ("scenario", "TEXT"), ("detail", "TEXT"),
    ("n_agents", "INTEGER"), ("n_moving", "INTEGER"), ("motion", "TEXT"),
    ("planner", "TEXT"), ("planner_params", "TEXT"), ("controller", "TEXT"), ("controller_params", "TEXT"),
    ("method", "TEXT"), ("source", "TEXT"), ("seed", "INTEGER"), ("max_steps", "INTEGER"),
    ("status", "TEXT"), ("error", "TEXT"),
    ("success", "INTEGER"), ("safe", "INTEGER"), ("run_status", "TEXT"), ("steps", "INTEGER"),
    ("reached", "INTEGER"), ("reached_once", "INTEGER"), ("n_robots", "INTEGER"),
    ("robot_robot", "INTEGER"), ("robot_static", "INTEGER"), ("robot_moving", "INTEGER"), ("contacts", "INTEGER"),
    ("deadlocks", "INTEGER"), ("invalid_moves", "INTEGER"), ("sum_of_lengths", "REAL"), ("makespan", "INTEGER"),
    ("sum_of_costs", "INTEGER"), ("flowtime", "INTEGER"), ("lower_bound", "INTEGER"), ("min_clearance", "REAL"),
    ("violations", "INTEGER"), ("swarmpath_version", "TEXT"), ("outcome", "TEXT"),
)
TIMING_COLUMNS: tuple[tuple[str, str], ...] = (
    ("key", "TEXT PRIMARY KEY"), ("wall_s", "REAL"), ("setup_s", "REAL"), ("planning_time_s", "REAL"),
    ("sim_time_s", "REAL"), ("engine", "TEXT"), ("finished_at", "REAL"),
)
STATUSES = ("ok", "error", "timeout")

_SCHEMA = f"""
CREATE TABLE IF NOT EXISTS meta (name TEXT PRIMARY KEY, value TEXT);
CREATE TABLE IF NOT EXISTS results ({", ".join(f"{n} {t}" for n, t in RESULT_COLUMNS)});
CREATE TABLE IF NOT EXISTS timings ({", ".join(f"{n} {t}" for n, t in TIMING_COLUMNS)});
CREATE TABLE IF NOT EXISTS skipped (suite TEXT, scenario TEXT, detail TEXT, planner TEXT, controller TEXT,
    reason TEXT, n_jobs INTEGER, PRIMARY KEY (suite, scenario, detail, planner, controller));
CREATE TABLE IF NOT EXISTS sweeps (id INTEGER PRIMARY KEY AUTOINCREMENT, suite TEXT, source TEXT,
    suite_sha256 TEXT, engine TEXT, workers INTEGER, jobs_total INTEGER, jobs_stored INTEGER,
    jobs_run INTEGER, started_at REAL, finished_at REAL, state TEXT);
CREATE INDEX IF NOT EXISTS results_suite ON results (suite);
"""


def _flowtime(outcome: dict[str, Any]) -> int:
    """Sum over robots of the step each arrived (for good), or the run's length if it did not."""
    return int(sum(r["arrival_step"] if r["arrival_step"] is not None else outcome["steps"]
                   for r in outcome["robots"]))


def result_row(job: Any, result: dict[str, Any]) -> dict[str, Any]:
    """The ``results`` row of a job and its result."""
    from swarmpath import __version__

    o = result.get("outcome") or {}
    c = o.get("collisions") or {}
    ok = result["status"] == "ok"
    row = {
        "key": job.key, "suite": job.suite, "scenario": job.scenario, "detail": job.detail,
        "n_agents": job.n_agents, "n_moving": job.n_moving, "motion": job.motion,
        "planner": job.planner, "planner_params": _canonical(job.planner_params), "controller": job.controller,
        "controller_params": _canonical(job.controller_params), "method": job.method,
        "source": result.get("source") or "", "seed": job.seed, "max_steps": job.max_steps,
        "status": result["status"], "error": result.get("error"),
        "success": int(o["success"]) if ok else None, "safe": int(o["safe"]) if ok else None,
        "run_status": o.get("status"), "steps": o.get("steps"), "reached": o.get("reached"),
        "reached_once": o.get("reached_once"), "n_robots": o.get("n_robots", job.n_agents),
        "robot_robot": c.get("robot_robot"), "robot_static": c.get("robot_static"),
        "robot_moving": c.get("robot_moving"), "contacts": sum(c.values()) if ok else None,
        "deadlocks": o.get("deadlocks"), "invalid_moves": o.get("invalid_moves"),
        "sum_of_lengths": o.get("sum_of_lengths"), "makespan": o.get("makespan"),
        "sum_of_costs": o.get("sum_of_arrival_steps"), "flowtime": _flowtime(o) if ok else None,
        "lower_bound": result.get("lower_bound"), "min_clearance": o.get("min_clearance"),
        "violations": result.get("violations"), "swarmpath_version": __version__,
        "outcome": json.dumps(o, sort_keys=True, allow_nan=True) if ok else None,
    }
    return row


def _canonical(doc: Any) -> str:
    return json.dumps(doc, sort_keys=True, separators=(",", ":"))


class Store:
    """A results store at ``path``; :meth:`open` connects (for writing: creating the file and
    taking the writer's lock)."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self.db: sqlite3.Connection | None = None
        self._lock = None

    # ------------------------------------------------------------------ opening
    def open(self, *, write: bool = False) -> "Store":
        """Connect; ``write`` creates the store if needed and takes the single-writer lock."""
        if self.path.is_dir():
            raise ConfigError(f"{self.path}: is a folder, not a results store")
        if not write and not self.path.is_file():
            raise ConfigError(f"{self.path}: no such results store (swarmpath bench SUITE --store FILE makes one)")
        try:
            if write:
                self.path.parent.mkdir(parents=True, exist_ok=True)
                self._take_lock()
                self.db = sqlite3.connect(self.path, timeout=30.0, isolation_level=None)
                self.db.execute("PRAGMA journal_mode=WAL")
                self.db.execute("PRAGMA synchronous=NORMAL")
                self.db.executescript(_SCHEMA)
                self._check_schema(create=True)
            else:
                self.db = sqlite3.connect(f"file:{self.path.resolve()}?mode=ro", uri=True, timeout=30.0)
                self._check_schema(create=False)
        except sqlite3.DatabaseError as exc:
            self.close()
            raise ConfigError(f"{self.path}: not a swarmpath results store ({exc})") from None
        except OSError as exc:
            self.close()
            raise ConfigError(f"{self.path}: cannot open the results store ({exc.strerror or exc})") from None
        self.db.row_factory = sqlite3.Row
        return self

    def _take_lock(self) -> None:
        try:
            import fcntl
        except ImportError:    # pragma: no cover - not POSIX: SQLite's own locking only
            return
        fh = open(self.path.with_name(self.path.name + ".lock"), "a+")
        try:
            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.close()
            raise ConfigError(f"{self.path}: another sweep is writing to this store; wait for it to end "
                              "(or give another --store)") from None
        self._lock = fh

    def _check_schema(self, *, create: bool) -> None:
        row = self.db.execute("SELECT value FROM meta WHERE name = 'schema_version'").fetchone() \
            if self._has_table("meta") else None
        if row is None:
            if not create:
                raise ConfigError(f"{self.path}: not a swarmpath results store (no schema version)")
            self.db.execute("INSERT INTO meta (name, value) VALUES ('schema_version', ?)", (str(SCHEMA_VERSION),))
            return
        if row[0] != str(SCHEMA_VERSION):
            raise ConfigError(f"{self.path}: results store of schema {row[0]}, this swarmpath reads schema "
                              f"{SCHEMA_VERSION}")

    def _has_table(self, name: str) -> bool:
        return self.db.execute("SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?", (name,)).fetchone() \
            is not None

    def close(self) -> None:
        if self.db is not None:
            self.db.close()
            self.db = None
        if self._lock is not None:
            self._lock.close()
            self._lock = None

    def __enter__(self) -> "Store":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    # ------------------------------------------------------------------ writing
    def stored_keys(self, keys: Iterable[str] | None = None) -> dict[str, str]:
        """Key -> status of the stored jobs (of ``keys`` only, when given)."""
        rows = self.db.execute("SELECT key, status FROM results").fetchall()
        out = {r[0]: r[1] for r in rows}
        if keys is not None:
            wanted = set(keys)
            out = {k: v for k, v in out.items() if k in wanted}
        return out

    def forget(self, keys: Iterable[str]) -> int:
        """Remove the rows of ``keys`` (to run those jobs again); the number removed."""
        keys = list(keys)
        with self.db:
            self.db.execute("BEGIN")
            for k in keys:
                self.db.execute("DELETE FROM results WHERE key = ?", (k,))
                self.db.execute("DELETE FROM timings WHERE key = ?", (k,))
        return len(keys)

    def add(self, job: Any, result: dict[str, Any], engine: str) -> bool:
        """Store one job's result (committed at once); False if its key was already stored."""
        row = result_row(job, result)
        t = result.get("timings") or {}
        names = [n for n, _ in RESULT_COLUMNS]
        self.db.execute("BEGIN IMMEDIATE")
        try:
            cur = self.db.execute(f"INSERT OR IGNORE INTO results ({', '.join(names)}) VALUES "
                                  f"({', '.join('?' for _ in names)})", [row[n] for n in names])
            added = cur.rowcount == 1
            if added:
                self.db.execute("INSERT OR REPLACE INTO timings (key, wall_s, setup_s, planning_time_s, sim_time_s, "
                                "engine, finished_at) VALUES (?, ?, ?, ?, ?, ?, ?)",
                                (job.key, t.get("wall_s"), t.get("setup_s"), t.get("planning_time_s"),
                                 t.get("sim_time_s"), engine, time.time()))
            self.db.execute("COMMIT")
        except BaseException:
            self.db.execute("ROLLBACK")
            raise
        return added

    def record_skipped(self, suite: str, skipped: Iterable[Any]) -> None:
        """Replace the suite's list of skipped pairs."""
        with self.db:
            self.db.execute("BEGIN")
            self.db.execute("DELETE FROM skipped WHERE suite = ?", (suite,))
            for s in skipped:
                self.db.execute("INSERT OR REPLACE INTO skipped VALUES (?, ?, ?, ?, ?, ?, ?)",
                                (suite, s.scenario, s.detail, s.planner, s.controller, s.reason, s.n_jobs))

    def begin_sweep(self, suite: Any, engine: str, workers: int, total: int, stored: int) -> int:
        import hashlib

        cur = self.db.execute(
            "INSERT INTO sweeps (suite, source, suite_sha256, engine, workers, jobs_total, jobs_stored, jobs_run, "
            "started_at, state) VALUES (?, ?, ?, ?, ?, ?, ?, 0, ?, 'running')",
            (suite.name, suite.source, hashlib.sha256(suite.text.encode("utf-8")).hexdigest(), engine, workers,
             total, stored, time.time()))
        return int(cur.lastrowid)

    def end_sweep(self, sweep_id: int, ran: int, state: str) -> None:
        self.db.execute("UPDATE sweeps SET jobs_run = ?, finished_at = ?, state = ? WHERE id = ?",
                        (ran, time.time(), state, sweep_id))

    # ------------------------------------------------------------------ reading
    def rows(self, suite: str | None = None) -> list[dict[str, Any]]:
        """Every stored job (results with their timings), ordered by key."""
        timing = ", ".join(f"t.{n}" for n, _ in TIMING_COLUMNS[1:])
        sql = f"SELECT r.*, {timing} FROM results r LEFT JOIN timings t ON t.key = r.key"
        args: tuple[Any, ...] = ()
        if suite is not None:
            sql += " WHERE r.suite = ?"
            args = (suite,)
        return [dict(r) for r in self.db.execute(sql + " ORDER BY r.key", args).fetchall()]

    def outcomes(self) -> list[tuple[Any, ...]]:
        """The ``results`` table as tuples ordered by key: what must be identical whatever the
        engine or the number of workers."""
        return [tuple(r) for r in self.db.execute("SELECT * FROM results ORDER BY key").fetchall()]

    def skipped(self) -> list[dict[str, Any]]:
        return [dict(r) for r in self.db.execute("SELECT * FROM skipped ORDER BY suite, scenario, planner, controller")]

    def sweeps(self) -> list[dict[str, Any]]:
        return [dict(r) for r in self.db.execute("SELECT * FROM sweeps ORDER BY id")]


def load(path: str | Path) -> Any:
    """The jobs of a results store, one row each (results with their timings): a pandas
    DataFrame when pandas is installed (the ``[bench]`` or ``[dask]`` extra), else a list of
    dicts. ``None`` stands for a missing value (NaN in a DataFrame)."""
    with Store(path).open() as store:
        rows = store.rows()
    try:
        import pandas as pd
    except ImportError:
        return rows
    columns = [n for n, _ in RESULT_COLUMNS] + [n for n, _ in TIMING_COLUMNS[1:]]
    return pd.DataFrame(rows, columns=columns)


def is_number(value: Any) -> bool:
    """A finite number (not None, not NaN)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
