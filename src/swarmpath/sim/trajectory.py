"""Trajectory: everything that happened in one simulation, saved and loaded as .npz or .json.

It is self-contained: it carries the world description (scenario form, plus the raster of a
static map) so that metrics, figures and the HTML replay need nothing else.
"""
from __future__ import annotations

import enum
import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import SwarmpathError
from swarmpath.sim.collisions import ROBOT_MOVING, ROBOT_ROBOT, ROBOT_STATIC, Contact
from swarmpath.world.limits import preview, read_text_bounded

FloatArray = NDArray[np.float64]

class Termination(str, enum.Enum):
    """Why a run ended (Gymnasium's terminated vs truncated, plus a stall): every robot at its
    goal, the step budget spent, or the robots that had not arrived stopped making progress.
    The values are the strings of the JSON output (a ``str`` enum compares equal to them)."""

    ALL_REACHED = "all_reached"
    TRUNCATED = "truncated"
    DEADLOCK = "deadlock"

    def __str__(self) -> str:
        return self.value


ALL_REACHED, TRUNCATED, DEADLOCK = Termination.ALL_REACHED, Termination.TRUNCATED, Termination.DEADLOCK


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Positions of every robot and moving obstacle at every step, and what happened.

    positions : (n_steps + 1, n_robots, 2), row 0 = starts
    obstacle_positions : (n_steps + 1, n_obstacles, 2)
    modes : (n_steps, n_robots) int8 indices into ``mode_names`` (the controller's behaviour
        at each step, e.g. seek / trace / prey / wait), or None
    contacts : every collision the simulator's checker found
    events : other notable things (invalid moves, deadlock resolutions, ...), dicts with
        at least "step" and "kind"
    planned_paths : the offline plan of each robot (None without a planner)
    status : why the run ended (:class:`Termination`)
    world : the scenario dict of the world (``World.to_dict()``), ``static_map`` its raster
    """

    scenario: str
    seed: int
    dt: float
    resolution: float
    robot_ids: list[str]
    radii: FloatArray
    goals: FloatArray
    positions: FloatArray
    obstacle_ids: list[str]
    obstacle_positions: FloatArray
    contacts: list[Contact] = field(default_factory=list)
    events: list[dict] = field(default_factory=list)
    modes: NDArray[np.int8] | None = None
    mode_names: list[str] = field(default_factory=list)
    planned_paths: list[FloatArray | None] = field(default_factory=list)
    status: Termination = TRUNCATED
    world: dict = field(default_factory=dict)
    static_map: NDArray[np.bool_] | None = None
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "status", Termination(self.status))
        except ValueError:
            raise SwarmpathError(f"unknown trajectory status {self.status!r}; expected one of "
                                 f"{', '.join(t.value for t in Termination)}") from None

    @property
    def n_steps(self) -> int:
        return int(self.positions.shape[0]) - 1

    @property
    def n_robots(self) -> int:
        return int(self.positions.shape[1])

    # ------------------------------------------------------------------ io
    def _header(self) -> dict[str, Any]:
        return {
            "format": "swarmpath-trajectory", "version": 1, "scenario": self.scenario, "seed": self.seed,
            "dt": self.dt, "resolution": self.resolution, "robot_ids": self.robot_ids,
            "obstacle_ids": self.obstacle_ids, "contacts": [c.to_dict() for c in self.contacts],
            "events": self.events, "mode_names": self.mode_names, "status": self.status.value,
            "world": self.world, "meta": self.meta,
        }

    def to_json_dict(self) -> dict[str, Any]:
        """A JSON-ready dict; numbers are written in full (the .json copy reads back exactly as
        the .npz one, so validators give the same verdict on both)."""
        doc = self._header()
        doc.update({
            "radii": self.radii.tolist(), "goals": self.goals.tolist(),
            "positions": self.positions.tolist(),
            "obstacle_positions": self.obstacle_positions.tolist(),
            "modes": None if self.modes is None else self.modes.tolist(),
            "planned_paths": [None if p is None else np.asarray(p).tolist() for p in self.planned_paths],
            "static_map": None if self.static_map is None else ["".join("@" if b else "." for b in row)
                                                                for row in self.static_map],
        })
        return doc

    def save(self, path: str | Path) -> Path:
        """Write to ``path``: .json (text) or .npz (compact, exact)."""
        path = Path(path)
        if path.suffix == ".json":
            path.write_text(json.dumps(self.to_json_dict()), encoding="utf-8")
            return path
        arrays: dict[str, Any] = {
            "header": np.array(json.dumps(self._header())), "radii": self.radii, "goals": self.goals,
            "positions": self.positions, "obstacle_positions": self.obstacle_positions,
        }
        if self.modes is not None:
            arrays["modes"] = self.modes
        if self.static_map is not None:
            arrays["static_map"] = self.static_map
        for k, p in enumerate(self.planned_paths):
            if p is not None:
                arrays[f"planned_{k}"] = p
        arrays["n_planned"] = np.array(len(self.planned_paths))
        with path.open("wb") as fh:
            np.savez_compressed(fh, **arrays)
        return path

    @classmethod
    def load(cls, path: str | Path) -> "Trajectory":
        """Read a trajectory written by :meth:`save`; anything else is refused with one line
        saying what is wrong (never a traceback from numpy or json)."""
        path = Path(path)
        if path.suffix == ".json":
            text = read_text_bounded(path, "trajectory", MAX_TRAJECTORY_BYTES, SwarmpathError)
            try:
                doc = json.loads(text)
                return cls._from_json(doc)
            except json.JSONDecodeError as exc:
                problem = f"line {exc.lineno}: JSON syntax error: {exc.msg}"
            except RecursionError:
                problem = "nested too deeply"
            except (ValueError, KeyError, TypeError, AttributeError, IndexError) as exc:
                problem = preview(str(exc) or type(exc).__name__, 200)
            raise SwarmpathError(f"{path}: not a swarmpath trajectory: {problem}")
        try:
            with path.open("rb") as fh:
                magic = fh.read(4)
        except FileNotFoundError:
            raise SwarmpathError(f"{path}: no such trajectory file") from None
        except OSError as exc:
            raise SwarmpathError(f"{path}: cannot read the trajectory file: {exc.strerror or exc}") from None
        if magic != b"PK\x03\x04":
            raise SwarmpathError(f"{path}: not a swarmpath trajectory: not an .npz archive (save as .npz or .json)")
        try:
            with np.load(path, allow_pickle=False) as data:
                return cls._from_npz(data)
        except (ValueError, KeyError, TypeError, AttributeError, IndexError, OSError, EOFError,
                zipfile.BadZipFile, json.JSONDecodeError) as exc:
            problem = str(exc)
            if "pickle" in problem:
                problem = "an array in it holds Python objects, not numbers"
            raise SwarmpathError(f"{path}: not a swarmpath trajectory: {preview(problem, 200)}") from None

    @classmethod
    def _from_header(cls, h: Any, **arrays: Any) -> "Trajectory":
        _check_header(h)
        arrays = _check_arrays(h, arrays)
        return cls(scenario=h["scenario"], seed=h["seed"], dt=h["dt"], resolution=h["resolution"],
                   robot_ids=list(h["robot_ids"]), obstacle_ids=list(h["obstacle_ids"]),
                   contacts=[Contact(**c) for c in h["contacts"]], events=list(h["events"]),
                   mode_names=list(h["mode_names"]), status=h["status"], world=h["world"], meta=h["meta"],
                   **arrays)

    @classmethod
    def _from_json(cls, d: Any) -> "Trajectory":
        if not isinstance(d, dict):
            raise ValueError(f"the file holds a JSON {type(d).__name__}, not an object")
        _check_header(d)
        sm = d.get("static_map")
        n_rows = len(d["positions"]) if isinstance(d["positions"], list) else 0
        if sm is not None and not (isinstance(sm, list) and all(isinstance(row, str) for row in sm)):
            raise ValueError("static_map must be a list of strings")
        return cls._from_header(
            d, radii=np.asarray(d["radii"], float), goals=np.asarray(d["goals"], float),
            positions=np.asarray(d["positions"], float),
            obstacle_positions=np.asarray(d["obstacle_positions"], float).reshape(n_rows, -1, 2),
            modes=None if d.get("modes") is None else np.asarray(d["modes"], np.int64),
            planned_paths=[None if p is None else np.asarray(p, float) for p in d.get("planned_paths", [])],
            static_map=None if sm is None else np.array([[c == "@" for c in row] for row in sm], dtype=bool))

    @classmethod
    def _from_npz(cls, data) -> "Trajectory":
        if "header" not in data.files:
            raise ValueError("no header in the archive")
        h = json.loads(str(data["header"]))
        n_planned = int(data["n_planned"]) if "n_planned" in data.files else 0
        planned = [np.asarray(data[f"planned_{k}"]) if f"planned_{k}" in data.files else None for k in range(n_planned)]
        return cls._from_header(
            h, radii=np.asarray(data["radii"]), goals=np.asarray(data["goals"]),
            positions=np.asarray(data["positions"]), obstacle_positions=np.asarray(data["obstacle_positions"]),
            modes=np.asarray(data["modes"]) if "modes" in data.files else None, planned_paths=planned,
            static_map=np.asarray(data["static_map"]) if "static_map" in data.files else None)


#: Largest trajectory file read (bytes).
MAX_TRAJECTORY_BYTES = 2**30
_CONTACT_KEYS = {"step", "kind", "robot", "other", "detail"}


def _check_header(h: Any) -> None:
    """Refuse a header that is not what :meth:`Trajectory.save` writes (ValueError)."""
    if not isinstance(h, dict) or h.get("format") != "swarmpath-trajectory":
        raise ValueError("missing format marker 'swarmpath-trajectory'")
    for key, kinds in (("scenario", str), ("seed", int), ("dt", (int, float)), ("resolution", (int, float)),
                       ("robot_ids", list), ("obstacle_ids", list), ("contacts", list), ("events", list),
                       ("mode_names", list), ("status", str), ("world", dict), ("meta", dict)):
        if key not in h:
            raise ValueError(f"no {key!r} field")
        if not isinstance(h[key], kinds) or isinstance(h[key], bool):
            raise ValueError(f"{key!r} has the wrong type ({type(h[key]).__name__})")
    if not (h["dt"] > 0 and h["resolution"] > 0):
        raise ValueError("dt and resolution must be positive")
    for key in ("robot_ids", "obstacle_ids", "mode_names"):
        if not all(isinstance(v, str) for v in h[key]):
            raise ValueError(f"{key!r} must be a list of strings")
    if len(set(h["robot_ids"])) != len(h["robot_ids"]):
        raise ValueError("'robot_ids' has repeats")
    n = len(h["robot_ids"])
    for c in h["contacts"]:
        if not (isinstance(c, dict) and set(c) == _CONTACT_KEYS and c["kind"] in (ROBOT_ROBOT, ROBOT_STATIC, ROBOT_MOVING)
                and all(isinstance(c[k], int) and not isinstance(c[k], bool) for k in ("step", "robot", "other"))
                and isinstance(c["detail"], str) and 0 <= c["robot"] < n):
            raise ValueError(f"a contact is malformed: {preview(c, 120)}")
    if not all(isinstance(e, dict) for e in h["events"]):
        raise ValueError("'events' must be a list of objects")


def _check_arrays(h: dict, arrays: dict[str, Any]) -> dict[str, Any]:
    """Shapes and values consistent with the header (ValueError otherwise)."""
    n, m = len(h["robot_ids"]), len(h["obstacle_ids"])
    pos = np.asarray(arrays["positions"], dtype=float)
    if pos.ndim != 3 or pos.shape[0] < 1 or pos.shape[1:] != (n, 2):
        raise ValueError(f"positions have shape {pos.shape}, expected (steps + 1, {n}, 2)")
    if not np.all(np.isfinite(pos)):
        raise ValueError("positions hold non-finite numbers")
    obstacles = np.asarray(arrays["obstacle_positions"], dtype=float).reshape(pos.shape[0], -1, 2) \
        if np.size(arrays["obstacle_positions"]) or m == 0 else np.asarray(arrays["obstacle_positions"], float)
    if obstacles.shape != (pos.shape[0], m, 2):
        raise ValueError(f"obstacle positions have shape {obstacles.shape}, expected ({pos.shape[0]}, {m}, 2)")
    radii = np.asarray(arrays["radii"], dtype=float)
    goals = np.asarray(arrays["goals"], dtype=float).reshape(-1, 2) if np.size(arrays["goals"]) else np.zeros((0, 2))
    if radii.shape != (n,) or goals.shape != (n, 2):
        raise ValueError(f"radii/goals have shapes {radii.shape}/{goals.shape}, expected ({n},)/({n}, 2)")
    modes = arrays.get("modes")
    if modes is not None:
        modes = np.asarray(modes)
        if modes.ndim != 2 or modes.shape[1] != n or modes.shape[0] > pos.shape[0] - 1:
            raise ValueError(f"modes have shape {modes.shape}, expected (at most {pos.shape[0] - 1}, {n})")
        if modes.size and (modes.min() < 0 or modes.max() >= len(h["mode_names"])):
            raise ValueError("modes refer to behaviour names that are not listed")
        modes = modes.astype(np.int8)
    planned = []
    for p in arrays.get("planned_paths") or []:
        if p is not None:
            p = np.asarray(p, dtype=float)
            if p.ndim != 2 or p.shape[1] != 2:
                raise ValueError(f"a planned path has shape {p.shape}, expected (points, 2)")
        planned.append(p)
    static_map = arrays.get("static_map")
    if static_map is not None:
        static_map = np.asarray(static_map)
        if static_map.ndim != 2:
            raise ValueError("static_map must be 2-D")
        static_map = static_map.astype(bool)
    return {**arrays, "positions": pos, "obstacle_positions": obstacles, "radii": radii, "goals": goals,
            "modes": modes, "planned_paths": planned, "static_map": static_map}
