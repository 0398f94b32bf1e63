"""Trajectory: everything that happened in one simulation, saved and loaded as .npz or .json.

It is self-contained: it carries the world description (scenario form, plus the raster of a
static map) so that metrics, figures and the HTML replay need nothing else.
"""
from __future__ import annotations

import enum
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import SwarmpathError
from swarmpath.sim.collisions import Contact

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
        """A JSON-ready dict (positions rounded to 1e-6 world units)."""
        doc = self._header()
        doc.update({
            "radii": self.radii.tolist(), "goals": self.goals.tolist(),
            "positions": np.round(self.positions, 6).tolist(),
            "obstacle_positions": np.round(self.obstacle_positions, 6).tolist(),
            "modes": None if self.modes is None else self.modes.tolist(),
            "planned_paths": [None if p is None else np.round(p, 6).tolist() for p in self.planned_paths],
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
        """Read a trajectory written by :meth:`save`."""
        path = Path(path)
        try:
            if path.suffix == ".json":
                return cls._from_json(json.loads(path.read_text(encoding="utf-8")))
            with np.load(path, allow_pickle=False) as data:
                return cls._from_npz(data)
        except FileNotFoundError:
            raise SwarmpathError(f"{path}: no such trajectory file") from None
        except (ValueError, KeyError, OSError, json.JSONDecodeError) as exc:
            raise SwarmpathError(f"{path}: not a swarmpath trajectory ({type(exc).__name__}: {exc})") from None

    @classmethod
    def _from_header(cls, h: dict, **arrays: Any) -> "Trajectory":
        if h.get("format") != "swarmpath-trajectory":
            raise ValueError("missing format marker")
        return cls(scenario=h["scenario"], seed=h["seed"], dt=h["dt"], resolution=h["resolution"],
                   robot_ids=list(h["robot_ids"]), obstacle_ids=list(h["obstacle_ids"]),
                   contacts=[Contact(**c) for c in h["contacts"]], events=list(h["events"]),
                   mode_names=list(h["mode_names"]), status=h["status"], world=h["world"], meta=h["meta"],
                   **arrays)

    @classmethod
    def _from_json(cls, d: dict) -> "Trajectory":
        sm = d.get("static_map")
        return cls._from_header(
            d, radii=np.asarray(d["radii"], float), goals=np.asarray(d["goals"], float).reshape(-1, 2),
            positions=np.asarray(d["positions"], float).reshape(len(d["positions"]), -1, 2),
            obstacle_positions=np.asarray(d["obstacle_positions"], float).reshape(len(d["positions"]), -1, 2),
            modes=None if d.get("modes") is None else np.asarray(d["modes"], np.int8),
            planned_paths=[None if p is None else np.asarray(p, float) for p in d.get("planned_paths", [])],
            static_map=None if sm is None else np.array([[c == "@" for c in row] for row in sm], dtype=bool))

    @classmethod
    def _from_npz(cls, data) -> "Trajectory":
        h = json.loads(str(data["header"]))
        n_planned = int(data["n_planned"])
        planned = [np.asarray(data[f"planned_{k}"]) if f"planned_{k}" in data.files else None for k in range(n_planned)]
        return cls._from_header(
            h, radii=np.asarray(data["radii"]), goals=np.asarray(data["goals"]),
            positions=np.asarray(data["positions"]), obstacle_positions=np.asarray(data["obstacle_positions"]),
            modes=np.asarray(data["modes"]) if "modes" in data.files else None, planned_paths=planned,
            static_map=np.asarray(data["static_map"]) if "static_map" in data.files else None)
