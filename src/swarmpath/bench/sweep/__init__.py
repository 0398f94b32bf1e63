"""Sweeps: many runs from one suite file, on a local process pool or a Dask cluster, into a
resumable SQLite store, and reports from it (``swarmpath bench``; docs/bench.md).

Importing this package is cheap and needs neither dask nor pandas: the parts load on first
use. ``load(path)`` reads a store's rows (a pandas DataFrame when pandas is installed).

- :mod:`~swarmpath.bench.sweep.suite`: the suite file's models, validation, JSON Schema
- :mod:`~swarmpath.bench.sweep.worlds`: scenario entries -> worlds (files, MovingAI, generators)
- :mod:`~swarmpath.bench.sweep.jobs`: the jobs, their keys, pairs skipped
- :mod:`~swarmpath.bench.sweep.execute`: one job in a worker
- :mod:`~swarmpath.bench.sweep.pool`, :mod:`~swarmpath.bench.sweep.dask_engine`: the engines
- :mod:`~swarmpath.bench.sweep.store`: the SQLite store
- :mod:`~swarmpath.bench.sweep.run`: a sweep from start to end
- :mod:`~swarmpath.bench.sweep.report`: tables and plots
- :mod:`~swarmpath.bench.sweep.peers`: pymapf's PIBT and LaCAM, RVO2's ORCA
"""
from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "load": "swarmpath.bench.sweep.store",
    "Store": "swarmpath.bench.sweep.store",
    "load_suite": "swarmpath.bench.sweep.suite",
    "builtin_suites": "swarmpath.bench.sweep.suite",
    "suite_json_schema": "swarmpath.bench.sweep.suite",
    "expand": "swarmpath.bench.sweep.jobs",
    "run_sweep": "swarmpath.bench.sweep.run",
    "write_report": "swarmpath.bench.sweep.report",
}


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'swarmpath.bench.sweep' has no attribute {name!r}")


__all__ = sorted(_EXPORTS)
