"""Scenario files (schema 1) in YAML or JSON, and the built-in scenarios shipped with swarmpath.

The pydantic models below ARE the schema: unknown fields, missing fields and wrong types are
errors naming the file and the field, and ``scenario_json_schema()`` derives the JSON Schema
(docs/scenario.schema.json) from them. ``load_scenario`` turns a file into a :class:`World`,
which then checks geometry (starts inside obstacles, clashing robots, ...).
"""
from __future__ import annotations

import math
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import BaseModel, ConfigDict, Field, Strict, ValidationError, create_model

from swarmpath.errors import MapFormatError, ScenarioError
from swarmpath.world import limits
from swarmpath.world.fields import Name, NonNegativeFloat, PositiveFloat, Vec2
from swarmpath.world.limits import DocumentError
from swarmpath.world.model_errors import first_error, located_errors


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)


class CircleModel(_Strict):
    type: Literal["circle"]
    center: Vec2
    radius: PositiveFloat
    id: Name = ""


class RectangleModel(_Strict):
    type: Literal["rectangle"]
    min: Vec2
    max: Vec2
    id: Name = ""


class PolygonModel(_Strict):
    type: Literal["polygon"]
    points: list[Vec2] = Field(min_length=3, max_length=limits.MAX_POLYGON_POINTS)
    id: Name = ""


ObstacleModel = Annotated[Union[CircleModel, RectangleModel, PolygonModel], Field(discriminator="type")]


class RectBoundsModel(_Strict):
    type: Literal["rectangle"]
    width: PositiveFloat
    height: PositiveFloat


class CircleBoundsModel(_Strict):
    type: Literal["circle"]
    center: Vec2
    radius: PositiveFloat


BoundsModel = Annotated[Union[RectBoundsModel, CircleBoundsModel], Field(discriminator="type")]


class MapModel(_Strict):
    file: Annotated[str, Strict(), Field(min_length=1, max_length=4096)] = Field(
        description="MovingAI .map file, relative to the scenario file (or a built-in map's name)")


class DangerZoneModel(_Strict):
    center: Vec2
    radius: NonNegativeFloat = 0.0
    weight: NonNegativeFloat = 1.0
    id: Name = ""


class MovingCircleModel(_Strict):
    type: Literal["circle"]
    radius: PositiveFloat


class MovingRectangleModel(_Strict):
    type: Literal["rectangle"]
    width: PositiveFloat
    height: PositiveFloat


MovingShapeModel = Annotated[Union[MovingCircleModel, MovingRectangleModel], Field(discriminator="type")]


class _MovingObstacleFields(_Strict):
    id: Optional[Name] = None
    shape: MovingShapeModel
    start: Vec2
    velocity: Vec2 = (0.0, 0.0)


def _moving_obstacle_model() -> type[BaseModel]:
    """The model of one moving obstacle: its common fields, ``motion`` (the registered motion
    names) and the parameters every registered motion declares (each optional; the builder
    refuses a parameter that the chosen motion does not use)."""
    from swarmpath.registry import MOTIONS

    fields: dict[str, Any] = {}
    for _, motion in MOTIONS.items():
        for name, (annotation, info) in motion.parameters.items():
            fields.setdefault(name, (annotation, info))
    kinds = tuple(MOTIONS.names())
    return create_model("MovingObstacleModel", __base__=_MovingObstacleFields,
                        motion=(Literal[kinds], Field("bounce", description="the motion model (see docs/scenarios.md)")),
                        **fields)


MovingObstacleModel = _moving_obstacle_model()


class RobotModel(_Strict):
    id: Optional[Name] = None
    start: Vec2
    goal: Vec2
    radius: NonNegativeFloat = 0.0
    max_speed: Optional[PositiveFloat] = Field(
        None, description="world units per time unit; default: one grid cell incl. diagonals")


class DefaultsModel(_Strict):
    planner: Optional[Name] = None
    controller: Optional[Name] = None


class ScenarioModel(_Strict):
    """A swarmpath scenario, schema version 1."""

    schema_version: Literal[1]
    name: Annotated[str, Strict(), Field(min_length=1, max_length=200)]
    description: Annotated[str, Strict(), Field(max_length=10_000)] = ""
    resolution: PositiveFloat = 1.0
    dt: PositiveFloat = 1.0
    bounds: Optional[BoundsModel] = None
    map: Optional[MapModel] = None
    obstacles: list[ObstacleModel] = Field([], max_length=limits.MAX_SHAPES)
    danger_zones: list[DangerZoneModel] = Field([], max_length=limits.MAX_SHAPES)
    moving_obstacles: list[MovingObstacleModel] = Field([], max_length=limits.MAX_SHAPES)
    robots: list[RobotModel] = Field(min_length=1)
    defaults: Optional[DefaultsModel] = None


def scenario_json_schema() -> dict[str, Any]:
    """The JSON Schema of scenario files, generated from the models."""
    schema = ScenarioModel.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "swarmpath scenario (schema 1)"
    return schema


_UNION_TAGS = {"circle", "rectangle", "polygon"}


def _union_tag(part: Any, prev: Any) -> bool:
    """pydantic adds the union tag to an error's location; users never wrote it."""
    return part in _UNION_TAGS and (isinstance(prev, int) or prev in ("bounds", "shape"))


def _first_error(exc: ValidationError) -> ScenarioError:
    return first_error(exc, ScenarioError, "docs/scenarios.md", _union_tag)


def scenario_problems(doc: Any) -> list[ScenarioError]:
    """Every schema problem of a parsed document (empty list when it matches the schema)."""
    try:
        ScenarioModel.model_validate(doc)
    except ValidationError as exc:
        return located_errors(exc, ScenarioError, "docs/scenarios.md", _union_tag)
    return []


def parse_document(text: str, source: str) -> Any:
    """Parse YAML or JSON text (JSON when the source ends in .json), with line numbers in
    errors; duplicate keys, alias bombs and deep nesting are refused (swarmpath.world.limits)."""
    try:
        if source.endswith(".json"):
            return limits.parse_json_bounded(text)
        return limits.parse_yaml_bounded(text)
    except DocumentError as exc:
        raise ScenarioError(str(exc), source=source) from None


def world_from_dict(doc: Any, source: str = "<scenario>", base_dir: Path | None = None):
    """Validate a parsed scenario document and build its World."""
    if not isinstance(doc, dict):
        kind = "empty" if doc is None else type(doc).__name__
        raise ScenarioError(f"a scenario must be a mapping of fields, got {kind}", source=source)
    try:
        model = ScenarioModel.model_validate(doc)
    except ValidationError as exc:
        raise _first_error(exc).with_source(source) from None
    try:
        return _build_world(model, base_dir or Path("."), source)
    except ScenarioError as exc:
        raise exc.with_source(source) from None


def _build_world(m: ScenarioModel, base_dir: Path, source: str):
    from swarmpath.world.moving import MovingObstacle
    from swarmpath.world.bounds import CircleBounds, RectBounds
    from swarmpath.world.entities import DangerZone, Robot
    from swarmpath.world.movingai import read_map, resolve_movingai
    from swarmpath.world.shapes import Circle, Polygon, Rect
    from swarmpath.world.static_map import StaticMap
    from swarmpath.world.world import World

    res = m.resolution
    static_map = None
    if m.map is not None:
        path = base_dir / m.map.file
        if not path.exists():
            path = resolve_movingai(m.map.file)   # a built-in map by its file name
        try:
            grid_map = read_map(path)
        except MapFormatError as exc:
            raise ScenarioError(str(exc), field="map.file") from None
        static_map = StaticMap(grid_map.blocked, res, str(path))
    if m.bounds is None:
        if static_map is None:
            raise ScenarioError("required field is missing (give bounds or a map)", field="bounds")
        bounds = RectBounds(static_map.width * res, static_map.height * res)
    elif isinstance(m.bounds, RectBoundsModel):
        bounds = RectBounds(m.bounds.width, m.bounds.height)
    else:
        bounds = CircleBounds(m.bounds.center, m.bounds.radius)

    obstacles = []
    for ob in m.obstacles:
        if isinstance(ob, CircleModel):
            obstacles.append(Circle(ob.center, ob.radius, ob.id))
        elif isinstance(ob, RectangleModel):
            obstacles.append(Rect(ob.min, ob.max, ob.id))
        else:
            obstacles.append(Polygon(tuple(tuple(p) for p in ob.points), ob.id))

    moving = []
    for i, mo in enumerate(m.moving_obstacles):
        shape = (Circle((0.0, 0.0), mo.shape.radius) if isinstance(mo.shape, MovingCircleModel)
                 else Rect((-mo.shape.width / 2, -mo.shape.height / 2), (mo.shape.width / 2, mo.shape.height / 2)))
        where = f"moving_obstacles[{i}]"
        model = _build_motion(mo, where)
        moving.append(MovingObstacle(mo.id or f"m{i + 1}", shape, mo.start, mo.velocity, model))

    default_speed = res * math.sqrt(2)
    robots = tuple(Robot(r.id or f"r{i + 1}", r.start, r.goal, r.radius,
                         r.max_speed if r.max_speed is not None else default_speed)
                   for i, r in enumerate(m.robots))
    dz = tuple(DangerZone(d.center, d.radius, d.weight, d.id) for d in m.danger_zones)
    defaults = {k: v for k, v in (m.defaults.model_dump() if m.defaults else {}).items() if v}
    return World(bounds=bounds, obstacles=tuple(obstacles), static_map=static_map, danger_zones=dz,
                 moving_obstacles=tuple(moving), robots=robots, resolution=res, dt=m.dt, name=m.name,
                 defaults=defaults)


def _build_motion(mo: Any, where: str):
    """The motion model of a moving obstacle's model, refusing parameters of other motions."""
    from swarmpath.registry import MOTIONS

    motion = MOTIONS.get(mo.motion)
    values = {}
    for name in type(mo).model_fields:
        if name in _MovingObstacleFields.model_fields or name == "motion":
            continue
        value = getattr(mo, name)
        if name in motion.parameters:
            values[name] = value
        elif value is not None:
            users = sorted(k for k, m in MOTIONS.items() if name in m.parameters)
            raise ScenarioError(f"only used with motion: {' or '.join(users)}", field=f"{where}.{name}")
    try:
        return motion.from_parameters(values)
    except ScenarioError as exc:
        raise ScenarioError(exc.problem, field=f"{where}.{exc.field}" if exc.field else where) from None


def read_scenario_file(path: str | Path) -> tuple[Any, str]:
    """Read and parse a scenario file: (document, source name)."""
    text = limits.read_text_bounded(path, "scenario", limits.MAX_SCENARIO_BYTES, ScenarioError)
    return parse_document(text, str(path)), str(path)


def builtin_scenarios() -> dict[str, str]:
    """Built-in scenario names and their one-line descriptions."""

    out = {}
    for entry in sorted(resources.files("swarmpath.data.scenarios").iterdir(), key=lambda e: e.name):
        if entry.name.endswith((".yaml", ".json")):
            doc = parse_document(entry.read_text(encoding="utf-8"), entry.name)
            if not isinstance(doc, dict) or not isinstance(doc.get("name"), str):
                raise ScenarioError("a built-in scenario needs a name", source=entry.name)
            description = str(doc.get("description") or "").strip()
            out[doc["name"]] = description.splitlines()[0] if description else ""
    return out


def builtin_scenario_path(name: str) -> Path | None:
    """The file of the built-in scenario ``name``, or None."""
    for ext in (".yaml", ".json"):
        entry = resources.files("swarmpath.data.scenarios").joinpath(name + ext)
        if entry.is_file():
            return Path(str(entry))
    return None


def load_scenario(name_or_path: str | Path):
    """The World of a scenario file, or of a built-in scenario given by name."""
    p = Path(name_or_path)
    if not p.is_file():
        builtin = builtin_scenario_path(str(name_or_path))
        if builtin is None:
            known = ", ".join(builtin_scenarios())
            raise ScenarioError(f"no such file, and no built-in scenario of that name (built-in: {known})",
                                source=str(name_or_path))
        p = builtin
    doc, source = read_scenario_file(p)
    return world_from_dict(doc, source, p.parent)
