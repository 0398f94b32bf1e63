"""Plans as JSON files, for any planner: ``Plan.save(path)`` and ``Plan.load(path)``.

    {"format": "swarmpath-plan", "version": 1, "planner": "lacam", "wall_time_s": 0.002,
     "diagnostics": {...},
     "robots": [{"robot_id": "a0", "status": "exact", "path": [[x, y], ...], "times": [0, 1, ...],
                 "diagnostics": {...}}, ...]}

Paths are in world units (``times``, when present, are the steps of a timed plan); numbers
are written in full, so a plan reads back exactly. Diagnostics keep their types: numpy arrays
(``{"__ndarray__": [...], "dtype": "float64"}``), tuples (``{"__tuple__": [...]}``) and
non-finite floats (``{"__float__": "nan"}``) are tagged, numpy scalars are written as plain
numbers; anything else that JSON cannot hold is refused when saving, with the key that holds it.

This module reads and writes the file only; :class:`swarmpath.planning.base.Plan` passes its
own classes to :func:`read_plan`, so the plan types stay in one place.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.world.limits import preview, read_text_bounded

FORMAT = "swarmpath-plan"
VERSION = 1
#: Largest plan file read (bytes).
MAX_PLAN_BYTES = 2**30


def _encode(value: Any, where: str) -> Any:
    """A JSON-ready form of a diagnostics value (tagged where JSON has no such type)."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else {"__float__": repr(v)}
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            raise ConfigError(f"plan diagnostics {where}: an array of {value.dtype} cannot be saved")
        return {"__ndarray__": [_encode(v, where) for v in value.ravel().tolist()], "dtype": str(value.dtype),
                "shape": list(value.shape)}
    if isinstance(value, tuple):
        return {"__tuple__": [_encode(v, f"{where}[{k}]") for k, v in enumerate(value)]}
    if isinstance(value, list):
        return [_encode(v, f"{where}[{k}]") for k, v in enumerate(value)]
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise ConfigError(f"plan diagnostics {where}: key {preview(k)} is not a string")
            if k.startswith("__") and k.endswith("__"):
                raise ConfigError(f"plan diagnostics {where}: key {preview(k)} is reserved")
            out[k] = _encode(v, f"{where}.{k}" if where else k)
        return out
    raise ConfigError(f"plan diagnostics {where}: a {type(value).__name__} cannot be saved as JSON")


def _decode(value: Any) -> Any:
    if isinstance(value, list):
        return [_decode(v) for v in value]
    if not isinstance(value, dict):
        return value
    if "__float__" in value:
        return float(value["__float__"])
    if "__tuple__" in value:
        return tuple(_decode(v) for v in value["__tuple__"])
    if "__ndarray__" in value:
        flat = [_decode(v) for v in value["__ndarray__"]]
        return np.array(flat, dtype=np.dtype(value["dtype"])).reshape(value["shape"])
    return {k: _decode(v) for k, v in value.items()}


def plan_to_dict(plan: Any) -> dict[str, Any]:
    """The JSON document of a :class:`~swarmpath.planning.base.Plan`."""
    robots = []
    for k, r in enumerate(plan.robots):
        robots.append({
            "robot_id": r.robot_id, "status": r.status.value,
            "path": None if r.path is None else np.asarray(r.path, float).tolist(),
            "times": None if r.times is None else np.asarray(r.times, np.int64).tolist(),
            "diagnostics": _encode(dict(r.diagnostics), f"robots[{k}]"),
        })
    return {"format": FORMAT, "version": VERSION, "planner": plan.planner, "wall_time_s": float(plan.wall_time_s),
            "diagnostics": _encode(dict(plan.diagnostics), ""), "robots": robots}


def write_plan(plan: Any, path: str | Path) -> Path:
    """Write ``plan`` to ``path`` as JSON (see the module's docstring)."""
    path = Path(path)
    text = json.dumps(plan_to_dict(plan), allow_nan=False, separators=(",", ":"))
    path.write_text(text + "\n", encoding="utf-8")
    return path


def _unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"key {preview(key)} appears twice in one object")
        out[key] = value
    return out


def _points(value: Any, what: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2 or len(arr) == 0:
        raise ValueError(f"{what} must be a list of [x, y] points")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{what} holds a number that is not finite")
    return arr


def plan_from_dict(doc: Any, *, plan_type: type, robot_type: type, status_type: type) -> Any:
    """A plan from its JSON document (ValueError naming the field when it is malformed)."""
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise ValueError(f"missing format marker {FORMAT!r}")
    if doc.get("version") != VERSION:
        raise ValueError(f"version {preview(doc.get('version'))}, this swarmpath reads version {VERSION}")
    for key, kind in (("planner", str), ("wall_time_s", (int, float)), ("diagnostics", dict), ("robots", list)):
        if not isinstance(doc.get(key), kind) or isinstance(doc.get(key), bool):
            raise ValueError(f"{key!r} is missing or of the wrong type")
    statuses = {s.value: s for s in status_type}
    robots = []
    for k, r in enumerate(doc["robots"]):
        where = f"robots[{k}]"
        if not isinstance(r, dict) or set(r) != {"robot_id", "status", "path", "times", "diagnostics"}:
            raise ValueError(f"{where} must have robot_id, status, path, times and diagnostics")
        if not isinstance(r["robot_id"], str) or r["status"] not in statuses or not isinstance(r["diagnostics"], dict):
            raise ValueError(f"{where}: robot_id must be a string, status one of {', '.join(statuses)}")
        path = None if r["path"] is None else _points(r["path"], f"{where}.path")
        times = None
        if r["times"] is not None:
            if not (isinstance(r["times"], list) and all(isinstance(t, int) and not isinstance(t, bool)
                                                         for t in r["times"])):
                raise ValueError(f"{where}.times must be a list of integers")
            times = np.asarray(r["times"], np.int64)
            if path is None or len(times) != len(path) or np.any(np.diff(times) < 0):
                raise ValueError(f"{where}.times must be non-decreasing, one per point of the path")
        robots.append(robot_type(r["robot_id"], statuses[r["status"]], path, _decode(r["diagnostics"]), times))
    return plan_type(doc["planner"], tuple(robots), float(doc["wall_time_s"]), _decode(doc["diagnostics"]))


def read_plan(path: str | Path, *, plan_type: type, robot_type: type, status_type: type) -> Any:
    """Read a plan written by :func:`write_plan`; anything else is refused with one line
    naming the file and what is wrong (ConfigError)."""
    text = read_text_bounded(path, "plan", MAX_PLAN_BYTES, ConfigError)
    try:
        doc = json.loads(text, object_pairs_hook=_unique)
        return plan_from_dict(doc, plan_type=plan_type, robot_type=robot_type, status_type=status_type)
    except json.JSONDecodeError as exc:
        problem = f"line {exc.lineno}: JSON syntax error: {exc.msg}"
    except RecursionError:
        problem = "nested too deeply"
    except (ValueError, TypeError, KeyError) as exc:
        problem = preview(str(exc) or type(exc).__name__, 200)
    raise ConfigError(f"{preview(str(path), 200)}: not a swarmpath plan: {problem}")
