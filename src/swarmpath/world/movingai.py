"""MovingAI benchmark files (movingai.com/benchmarks/formats.html): .map and .scen.

A .map file is ``type octile``, ``height H``, ``width W``, ``map`` and then H rows of W
terrain letters. Passable: ``.`` ``G`` ``S``; blocked: ``@`` ``O`` ``T`` and ``W`` (water,
which ground units cannot enter). Coordinates are x = column, y = row, (0, 0) top left.
A .scen file is ``version 1`` followed by tab-separated rows
``bucket map width height start_x start_y goal_x goal_y optimal_length``; optimal lengths are
8-connected octile lengths without corner cutting.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import MapFormatError, ScenarioError
from swarmpath.world.limits import MAX_GRID_CELLS, MAX_MAP_BYTES, read_text_bounded

PASSABLE = frozenset(".GS")
BLOCKED = frozenset("@OTW")
_BLOCKED_LUT = np.zeros(256, dtype=bool)
_BLOCKED_LUT[[ord(c) for c in BLOCKED]] = True


@dataclass(frozen=True, eq=False)
class MovingAIMap:
    """A parsed .map file: ``blocked[y, x]`` is True for impassable terrain."""

    blocked: NDArray[np.bool_]
    name: str = ""

    @property
    def width(self) -> int:
        return int(self.blocked.shape[1])

    @property
    def height(self) -> int:
        return int(self.blocked.shape[0])


@dataclass(frozen=True)
class ScenEntry:
    """One row of a .scen file (``line`` is its 1-based line number in the file)."""

    bucket: int
    map_name: str
    width: int
    height: int
    start: tuple[int, int]
    goal: tuple[int, int]
    optimal_length: float
    line: int = 0


def _read_text(path: str | Path, what: str) -> str:
    return read_text_bounded(resolve_movingai(path), what, MAX_MAP_BYTES, MapFormatError, encoding="ascii")


def builtin_movingai() -> list[str]:
    """File names of the MovingAI maps and scens shipped with swarmpath (package data)."""
    folder = resources.files("swarmpath.data.movingai")
    return sorted(e.name for e in folder.iterdir() if e.name.endswith((".map", ".scen")))


def resolve_movingai(path: str | Path) -> Path:
    """``path`` itself when it names an existing file, else the built-in MovingAI file of
    that name (``random-32-32-10.map`` works from any folder), else ``path`` unchanged (the
    reader then says it does not exist)."""
    p = Path(path)
    if p.exists() or p.name != str(path):
        return p
    entry = resources.files("swarmpath.data.movingai").joinpath(p.name)
    return Path(str(entry)) if entry.is_file() else p


def parse_map(text: str, source: str = "<map>") -> MovingAIMap:
    """Parse the text of a .map file; errors name ``source`` and the line."""
    lines = text.splitlines()
    header: dict[str, str] = {}
    i = 0
    while i < len(lines):
        raw = lines[i].strip()
        i += 1
        if not raw:
            continue
        if raw == "map":
            break
        key, _, value = raw.partition(" ")
        if key not in ("type", "height", "width"):
            raise MapFormatError(f"{source}: line {i}: unexpected header line {raw!r} "
                                 "(expected 'type octile', 'height H', 'width W', 'map')")
        if key in header:
            raise MapFormatError(f"{source}: line {i}: header field {key!r} given twice")
        header[key] = value.strip()
    else:
        raise MapFormatError(f"{source}: no 'map' line: the header must end with a line 'map'")
    for key in ("type", "height", "width"):
        if key not in header:
            raise MapFormatError(f"{source}: header lacks '{key}'")
    if header["type"] != "octile":
        raise MapFormatError(f"{source}: header: type must be 'octile', got {header['type']!r}")
    dims = {}
    for key in ("height", "width"):
        try:
            dims[key] = int(header[key])
        except ValueError:
            raise MapFormatError(f"{source}: header: {key} must be a whole number, got {header[key]!r}") from None
        if dims[key] <= 0:
            raise MapFormatError(f"{source}: header: {key} must be positive, got {dims[key]}")
    height, width = dims["height"], dims["width"]
    if height * width > MAX_GRID_CELLS:
        raise MapFormatError(f"{source}: header: {width} x {height} cells is more than swarmpath's limit of "
                             f"{MAX_GRID_CELLS:,} cells per map")
    rows = lines[i:]
    while rows and not rows[-1].strip():
        rows.pop()
    if len(rows) != height:
        raise MapFormatError(f"{source}: header says height {height} but {len(rows)} map rows follow")
    grid = np.zeros((height, width), dtype=bool)
    allowed = PASSABLE | BLOCKED
    for r, row in enumerate(rows):
        line_no = i + r + 1
        row = row.rstrip("\r")
        if len(row) != width:
            raise MapFormatError(f"{source}: line {line_no}: row {r} has {len(row)} letters, header says width {width}")
        bad = set(row) - allowed
        if bad:
            letter = sorted(bad)[0]
            raise MapFormatError(f"{source}: line {line_no}, column {row.index(letter) + 1}: unknown terrain "
                                 f"letter {letter!r} (passable: . G S; blocked: @ O T W)")
        grid[r] = _BLOCKED_LUT[np.frombuffer(row.encode("ascii"), dtype=np.uint8)]
    return MovingAIMap(grid, Path(source).name)


def read_map(path: str | Path) -> MovingAIMap:
    """Read a MovingAI .map file."""
    return parse_map(_read_text(path, "map"), str(path))


def write_map(path: str | Path, blocked: NDArray[np.bool_]) -> None:
    """Write ``blocked`` (shape (height, width)) as a .map file with ``.`` and ``@``."""
    blocked = np.asarray(blocked, dtype=bool)
    h, w = blocked.shape
    rows = ["".join("@" if b else "." for b in row) for row in blocked]
    Path(path).write_text(f"type octile\nheight {h}\nwidth {w}\nmap\n" + "\n".join(rows) + "\n", encoding="ascii")


def parse_scen(text: str, source: str = "<scen>", grid_map: MovingAIMap | None = None) -> list[ScenEntry]:
    """Parse the text of a .scen file; with ``grid_map`` also check sizes and cells."""
    lines = text.splitlines()
    if not lines or not lines[0].strip().lower().startswith("version"):
        raise MapFormatError(f"{source}: line 1: expected 'version 1', got {lines[0][:40]!r}" if lines
                             else f"{source}: empty scenario file")
    version = lines[0].split()[1:] or [""]
    if version[0] not in ("1", "1.0"):
        raise MapFormatError(f"{source}: line 1: unsupported version {version[0]!r} (expected 1)")
    entries = []
    for n, raw in enumerate(lines[1:], start=2):
        if not raw.strip():
            continue
        parts = raw.split("\t")
        if len(parts) != 9:
            parts = raw.split()
        if len(parts) != 9:
            raise MapFormatError(f"{source}: line {n}: expected 9 tab-separated fields "
                                 "(bucket map width height start_x start_y goal_x goal_y optimal_length), "
                                 f"got {len(parts)}")
        try:
            bucket, w, h, sx, sy, gx, gy = (int(parts[k]) for k in (0, 2, 3, 4, 5, 6, 7))
            optimal = float(parts[8])
        except ValueError:
            raise MapFormatError(f"{source}: line {n}: fields 1 and 3-8 must be whole numbers and "
                                 "field 9 a number") from None
        if not math.isfinite(optimal) or optimal < 0:
            raise MapFormatError(f"{source}: line {n}: optimal_length must be a non-negative number")
        entry = ScenEntry(bucket, parts[1], w, h, (sx, sy), (gx, gy), optimal, n)
        if grid_map is not None:
            _check_entry(entry, grid_map, source)
        entries.append(entry)
    return entries


def _check_entry(e: ScenEntry, m: MovingAIMap, source: str) -> None:
    if (e.width, e.height) != (m.width, m.height):
        raise MapFormatError(f"{source}: line {e.line}: map size {e.width}x{e.height} differs from the map's "
                             f"{m.width}x{m.height}")
    for which, (x, y) in (("start", e.start), ("goal", e.goal)):
        if not (0 <= x < m.width and 0 <= y < m.height):
            raise MapFormatError(f"{source}: line {e.line}: {which} ({x}, {y}) is outside the map "
                                 f"({m.width}x{m.height})")
        if m.blocked[y, x]:
            raise MapFormatError(f"{source}: line {e.line}: {which} ({x}, {y}) is a blocked cell")


def read_scen(path: str | Path, grid_map: MovingAIMap | None = None) -> list[ScenEntry]:
    """Read a MovingAI .scen file (checked against ``grid_map`` when given)."""
    return parse_scen(_read_text(path, "scen"), str(path), grid_map)


def world_from_movingai(map_path: str | Path, scen_path: str | Path | None = None, n_agents: int | None = None,
                        *, resolution: float = 1.0, radius: float = 0.0, max_speed: float | None = None,
                        name: str | None = None):
    """A World with the map's blocked cells as static obstacles and, from ``scen_path``, the
    first ``n_agents`` rows as robots placed at cell centres (x = column, y = row)."""
    from swarmpath.world.bounds import RectBounds
    from swarmpath.world.entities import Robot
    from swarmpath.world.static_map import StaticMap
    from swarmpath.world.world import World

    m = read_map(map_path)
    entries: list[ScenEntry] = []
    if scen_path is not None:
        entries = read_scen(scen_path, m)
        if not entries:
            raise MapFormatError(f"{scen_path}: the scenario has no rows, so no robots (at least one row is needed)")
        if n_agents is not None:
            if n_agents < 1:
                raise ScenarioError(f"must be >= 1, got {n_agents}", field="--agents")
            if n_agents > len(entries):
                raise ScenarioError(f"asks for {n_agents} agents but {scen_path} has only {len(entries)} rows",
                                    field="--agents")
            entries = entries[:n_agents]
    speed = max_speed if max_speed is not None else resolution * math.sqrt(2)
    robots = tuple(Robot(f"a{k}", ((e.start[0] + 0.5) * resolution, (e.start[1] + 0.5) * resolution),
                         ((e.goal[0] + 0.5) * resolution, (e.goal[1] + 0.5) * resolution), radius, speed)
                   for k, e in enumerate(entries))
    try:
        return World(bounds=RectBounds(m.width * resolution, m.height * resolution),
                     static_map=StaticMap(m.blocked, resolution, str(map_path)), robots=robots,
                     resolution=resolution, name=name or Path(map_path).stem)
    except ScenarioError as exc:
        if exc.field and exc.field.startswith("robots[") and entries:
            k = int(exc.field[7:exc.field.index("]")])
            raise MapFormatError(f"{scen_path}: line {entries[k].line}: {exc.problem}") from None
        raise
