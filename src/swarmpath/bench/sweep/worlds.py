"""The worlds of a suite: each scenario entry expands into instances (one per agent count,
scen file, generator parameter combination and obstacle setting), and an instance builds its
World from a plain, picklable spec, in the parent (to check pairs) and in the workers.

Spec forms (``kind``): ``builtin`` (a built-in scenario's name), ``file`` (a scenario file,
absolute path), ``movingai`` (map + scen, agents, first_row) and ``generator`` (a name from
:data:`GENERATORS` with scalar parameters). Any of them may carry ``obstacles`` (moving
obstacles added by swarmpath.world.generators.with_obstacles).

An instance's identity, used for the job key, names files by the SHA-256 of their bytes, not
by their path: editing a scenario file makes new jobs, moving the suite does not.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from swarmpath.bench.sweep.generators import GENERATORS, GeneratorParamsError
from swarmpath.bench.sweep.suite import (
    MAX_LIST,
    OBSTACLE_MOTIONS,
    ScenarioEntryModel,
    Suite,
    SuiteError,
    counts,
)
from swarmpath.errors import ScenarioError, SwarmpathError
from swarmpath.world import limits
from swarmpath.world.limits import preview


@dataclass(frozen=True)
class Instance:
    """One world of a suite, before seeds: a label (the ``scenario`` column), a buildable
    spec, an identity for keys, a description for humans, and the entry's overrides."""

    label: str
    spec: dict[str, Any]
    identity: dict[str, Any]
    detail: str
    entry: int
    seeded: bool = False
    overrides: dict[str, Any] = field(default_factory=dict)

    @property
    def world_key(self) -> str:
        """A short digest of the identity (worker caches are keyed by it)."""
        return digest(self.identity)


def digest(doc: Any) -> str:
    """SHA-256 (hex, 20 characters) of a JSON-able document in canonical form."""
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:20]


def _file_hash(path: Path, what: str) -> str:
    data = limits.read_text_bounded(path, what, limits.MAX_MAP_BYTES, ScenarioError, encoding="latin-1")
    return hashlib.sha256(data.encode("latin-1")).hexdigest()


def _builtin(name: str) -> Path | None:
    from swarmpath.world.scenario import builtin_scenario_path

    return builtin_scenario_path(name)


def _scenario_file_identity(path: Path) -> str:
    """The hash of a scenario file and of the map file it refers to (both decide the world)."""
    from swarmpath.world.movingai import resolve_movingai
    from swarmpath.world.scenario import read_scenario_file

    parts = [_file_hash(path, "scenario")]
    doc, _ = read_scenario_file(path)
    ref = doc.get("map", {}).get("file") if isinstance(doc, dict) and isinstance(doc.get("map"), dict) else None
    if isinstance(ref, str):
        target = path.parent / ref
        target = target if target.exists() else resolve_movingai(ref)
        if target.is_file():
            parts.append(_file_hash(target, "map"))
    return hashlib.sha256("".join(parts).encode()).hexdigest()


def _resolve(base_dir: Path, text: str) -> Path:
    """A file relative to the suite's folder (or absolute), else a built-in MovingAI file named
    by its bare file name; never a file relative to the current folder."""
    from importlib import resources

    p = Path(text)
    candidate = p if p.is_absolute() else base_dir / p
    if candidate.exists():
        return candidate.resolve()
    if p.name == text:
        builtin = resources.files("swarmpath.data.movingai").joinpath(p.name)
        if builtin.is_file():
            return Path(str(builtin))
    return candidate


def _obstacle_settings(entry: ScenarioEntryModel | None) -> list[dict[str, Any] | None]:
    if entry is None or entry.obstacles is None:
        return [None]
    ob = entry.obstacles
    motions = ob.motion if isinstance(ob.motion, list) else [ob.motion]
    kinds: list[str] = []
    for m in motions:
        for k in (OBSTACLE_MOTIONS if m == "all" else (m,)):
            if k not in kinds:
                kinds.append(k)
    numbers = ob.count if isinstance(ob.count, list) else [ob.count]
    out = []
    for n in numbers:
        for k in kinds if n else kinds[:1]:
            doc = {"motion": k, "count": n, "speed": ob.speed, "radius": ob.radius}
            if ob.seed is not None:
                doc["seed"] = ob.seed
            out.append(doc if n else None)
    unique = []
    for d in out:
        if d not in unique:
            unique.append(d)
    return unique


def instances(suite: Suite) -> list[Instance]:
    """Every world of the suite, in the suite's order (files checked and hashed here)."""
    from swarmpath.world.movingai import read_map, read_scen

    out: list[Instance] = []
    for i, item in enumerate(suite.model.scenarios):
        where = f"scenarios[{i}]"
        entry = None if isinstance(item, str) else item
        overrides = {} if entry is None else {k: getattr(entry, k) for k in ("planners", "controllers", "methods",
                                                                            "peers", "max_steps")
                                              if getattr(entry, k) is not None}
        bases: list[tuple[str, dict[str, Any], dict[str, Any], str, bool]] = []
        try:
            if entry is None or entry.scenario is not None:
                text = item if entry is None else entry.scenario
                path = _resolve(suite.base_dir, text)
                builtin = None if path.is_file() else _builtin(text)
                if path.is_file():
                    label = entry.name if entry is not None and entry.name else path.stem
                    bases.append((label, {"kind": "file", "path": str(path)},
                                  {"kind": "file", "sha256": _scenario_file_identity(path)}, text, False))
                elif builtin is not None:
                    label = entry.name if entry is not None and entry.name else text
                    bases.append((label, {"kind": "builtin", "name": text},
                                  {"kind": "builtin", "name": text, "sha256": _scenario_file_identity(builtin)},
                                  text, False))
                else:
                    from swarmpath.world.scenario import builtin_scenarios

                    raise SuiteError(f"no such scenario file (relative to the suite's folder), and no built-in "
                                     f"scenario of that name (built-in: {', '.join(builtin_scenarios())})",
                                     field=where if entry is None else f"{where}.scenario")
            elif entry.map is not None:
                map_path = _resolve(suite.base_dir, entry.map)
                if not map_path.is_file():
                    raise SuiteError(f"no such map file: {preview(entry.map, 200)}", field=f"{where}.map")
                grid_map = read_map(map_path)
                scens = entry.scen if isinstance(entry.scen, list) else [entry.scen]
                for k, scen in enumerate(scens):
                    scen_field = f"{where}.scen" + (f"[{k}]" if isinstance(entry.scen, list) else "")
                    scen_path = _resolve(suite.base_dir, scen)
                    if not scen_path.is_file():
                        raise SuiteError(f"no such scen file: {preview(scen, 200)}", field=scen_field)
                    rows = len(read_scen(scen_path, grid_map))
                    numbers = counts(entry.agents) if entry.agents is not None else [rows - entry.first_row]
                    for n in numbers:
                        if n < 1 or entry.first_row + n > rows:
                            raise SuiteError(f"asks for {n} agents from row {entry.first_row} but "
                                             f"{scen_path.name} has {rows} rows", field=f"{where}.agents")
                        label = entry.name or map_path.stem
                        spec = {"kind": "movingai", "map": str(map_path), "scen": str(scen_path), "agents": n,
                                "first_row": entry.first_row}
                        ident = {"kind": "movingai", "map": _file_hash(map_path, "map"),
                                 "scen": _file_hash(scen_path, "scen"), "agents": n, "first_row": entry.first_row}
                        rows_text = f" from row {entry.first_row}" if entry.first_row else ""
                        bases.append((label, spec, ident, f"{scen_path.name}, {n} agents{rows_text}", False))
            else:
                gen = GENERATORS[entry.generator]
                try:
                    combos = gen.combinations(entry.params, f"{where}.params", MAX_LIST)
                except GeneratorParamsError as exc:
                    raise SuiteError(exc.problem, field=exc.field) from None
                for params in combos:
                    spec = {"kind": "generator", "generator": entry.generator, "params": params}
                    seeded = gen.seeded and "seed" not in params
                    shown = ", ".join(f"{k}={v}" for k, v in sorted(params.items()))
                    bases.append((entry.name or entry.generator, spec, dict(spec), shown, seeded))
        except SuiteError:
            raise
        except SwarmpathError as exc:
            raise SuiteError(str(exc), field=where) from None
        for label, spec, ident, detail, seeded in bases:
            for obstacles in _obstacle_settings(entry):
                s, d, text = dict(spec), dict(ident), detail
                if obstacles is not None:
                    s["obstacles"] = d["obstacles"] = obstacles
                    text += f"; {obstacles['count']} {obstacles['motion']} obstacles"
                ob_seeded = obstacles is not None and "seed" not in obstacles
                out.append(Instance(label, s, d, text, i, seeded or ob_seeded, overrides))
    if len(out) > MAX_LIST * 10:
        raise SuiteError(f"the scenarios expand to {len(out)} worlds (at most {MAX_LIST * 10})", field="scenarios")
    return out


def build_world(spec: dict[str, Any], seed: int):
    """The World of an instance spec for a job's ``seed`` (used only by seeded generators
    and obstacle placements whose seed the suite leaves open)."""
    from swarmpath.world import load_scenario, world_from_movingai

    kind = spec["kind"]
    if kind == "builtin":
        world = load_scenario(spec["name"])
    elif kind == "file":
        world = load_scenario(spec["path"])
    elif kind == "movingai":
        first, n = spec["first_row"], spec["agents"]
        world = world_from_movingai(spec["map"], spec["scen"], first + n)
        if first:
            world = world.replace(robots=world.robots[first:])
    elif kind == "generator":
        world = GENERATORS[spec["generator"]].build(spec["params"], seed)
    else:
        raise ScenarioError(f"unknown instance kind {kind!r}")
    ob = spec.get("obstacles")
    if ob is not None:
        from swarmpath.world.generators import with_obstacles

        try:
            world = with_obstacles(world, ob["motion"], ob["count"], ob.get("seed", seed), speed=ob["speed"],
                                   radius=ob["radius"])
        except ValueError:
            raise ScenarioError(f"no room for {ob['count']} moving obstacles of radius {ob['radius']:g} at least "
                                "2.5 away from every robot's start and goal (use fewer obstacles or robots, or a "
                                "larger map)", field="obstacles") from None
    return world
