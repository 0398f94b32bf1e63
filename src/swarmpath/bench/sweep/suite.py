"""Suite files: what a sweep runs, in YAML (or JSON), validated like scenario files.

A suite names scenarios (built-in names, scenario files, MovingAI map + scen with agent
counts, or world generators), planners, controllers (each with optional parameters), peers
(other libraries' solvers), seeds, a step budget and a per-job time limit. The product of the
lists is the set of jobs (:mod:`swarmpath.bench.sweep.jobs`).

The pydantic models below ARE the schema: unknown fields and wrong types are errors naming
the file and the field (:class:`SuiteError`, one line, exit code 2 on the command line), and
:func:`suite_json_schema` derives the JSON Schema (docs/suite.schema.json) from them. Names and
parameters are then checked against the registries, and files against the disk, so a suite
that loads is a suite that can run.
"""
from __future__ import annotations

import inspect
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import BaseModel, ConfigDict, Discriminator, Field, Strict, Tag, ValidationError

from swarmpath.errors import SuiteError, SwarmpathError
from swarmpath.world import limits
from swarmpath.world.limits import DocumentError, preview
from swarmpath.world.model_errors import first_error

#: Most jobs one suite may expand to (a typo such as ``count: 1000000`` is refused, not run).
MAX_JOBS = 1_000_000
#: Most values in one list of a suite (seeds, agent counts, scenarios, ...).
MAX_LIST = 10_000
#: Longest per-job time limit, seconds (one day).
MAX_TIMEOUT_S = 86_400.0
#: Largest suite file, bytes.
MAX_SUITE_BYTES = 4 * 2**20

#: Motion kinds the obstacle generator knows (swarmpath.world.generators.with_obstacles).
OBSTACLE_MOTIONS = ("bounce", "random-walk", "redraw", "turn-every", "waypoints")


# ------------------------------------------------------------------ field types
_Name = Annotated[str, Strict(), Field(min_length=1, max_length=200)]
_PathText = Annotated[str, Strict(), Field(min_length=1, max_length=4096)]
_Count = Annotated[int, Strict(), Field(ge=1, le=10**6)]
_Seed = Annotated[int, Strict(), Field(ge=0, le=2**63 - 1)]
_Params = Annotated[dict[str, Any], Field(max_length=100)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)


def _either(plain: Any, model: type[BaseModel]) -> Any:
    """A field that is either a plain value (a name, a list) or a mapping of ``model``;
    errors then name only the form the user wrote."""

    def pick(value: Any) -> str:
        return "mapping" if isinstance(value, dict) else "plain"

    return Annotated[Union[Annotated[plain, Tag("plain")], Annotated[model, Tag("mapping")]], Discriminator(pick)]


class NamedModel(_Strict):
    """A planner, controller or peer with parameters for its constructor."""

    name: _Name
    params: _Params = Field(default_factory=dict, description="keyword arguments of the constructor")


Named = _either(_Name, NamedModel)


class MethodModel(_Strict):
    """One planner + controller pair (instead of the product of ``planners`` and ``controllers``)."""

    planner: Named = "none"
    controller: Named


class RangeModel(_Strict):
    """``from``, ``from + step``, ... up to and including ``to``."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)
    start: _Count = Field(alias="from")
    to: _Count
    step: _Count = 1


Counts = _either(Annotated[list[_Count], Field(min_length=1, max_length=MAX_LIST)], RangeModel)


class SeedCountModel(_Strict):
    """``count`` seeds from ``start``: start, start + 1, ..."""

    count: Annotated[int, Strict(), Field(ge=1, le=MAX_LIST)]
    start: _Seed = 0


Seeds = _either(Annotated[list[_Seed], Field(min_length=1, max_length=MAX_LIST)], SeedCountModel)


def _one_or_many(kind: Any) -> Any:
    return Union[kind, Annotated[list[kind], Field(min_length=1, max_length=MAX_LIST)]]


class ObstaclesModel(_Strict):
    """Moving obstacles added to every world of the entry (swarmpath.world.generators.with_obstacles):
    discs on free cells away from the robots' starts and goals."""

    motion: _one_or_many(Literal[OBSTACLE_MOTIONS + ("all",)]) = Field(  # type: ignore[valid-type]
        "bounce", description="motion kind(s); 'all' = every kind; a list expands into one world per kind")
    count: _one_or_many(Annotated[int, Strict(), Field(ge=0, le=100_000)]) = Field(  # type: ignore[valid-type]
        description="number of obstacles; a list expands into one world per count")
    speed: Annotated[float, Strict(), Field(gt=0, le=1e6, allow_inf_nan=False)] = 0.5
    radius: Annotated[float, Strict(), Field(gt=0, le=1e6, allow_inf_nan=False)] = 0.35
    seed: Optional[_Seed] = Field(None, description="placement seed; default: the job's seed")


class ScenarioEntryModel(_Strict):
    """One scenario entry in mapping form: exactly one of ``scenario``, ``map`` (with ``scen``)
    or ``generator``; optionally moving obstacles added, and the suite's planners,
    controllers, peers or step budget replaced for this entry."""

    scenario: Optional[_PathText] = Field(None, description="a built-in scenario's name or a scenario file")
    map: Optional[_PathText] = Field(None, description="a MovingAI .map file (or a built-in map's file name)")
    scen: Optional[_one_or_many(_PathText)] = Field(  # type: ignore[valid-type]
        None, description="MovingAI .scen file(s) for the map; a list expands into one world per file")
    agents: Optional[Counts] = Field(None, description="agent counts: the first N rows of the scen (after first_row)")
    first_row: Annotated[int, Strict(), Field(ge=0, le=10**7)] = 0
    generator: Optional[_Name] = Field(None, description="a world generator's name (see docs/bench.md)")
    params: _Params = Field(default_factory=dict, description="the generator's parameters; a list expands")
    obstacles: Optional[ObstaclesModel] = None
    name: Optional[_Name] = Field(None, description="the label of this entry in the store and the report")
    planners: Optional[Annotated[list[Named], Field(min_length=1, max_length=1000)]] = None
    controllers: Optional[Annotated[list[Named], Field(min_length=1, max_length=1000)]] = None
    methods: Optional[Annotated[list[MethodModel], Field(max_length=1000)]] = Field(
        None, description="planner + controller pairs for this entry (instead of planners x controllers)")
    peers: Optional[Annotated[list[Named], Field(max_length=100)]] = None
    max_steps: Optional[Annotated[int, Strict(), Field(ge=1, le=10**9)]] = None


ScenarioItem = _either(_PathText, ScenarioEntryModel)


class SuiteModel(_Strict):
    """A swarmpath sweep suite, schema version 1."""

    schema_version: Literal[1] = 1
    name: _Name
    description: Annotated[str, Strict(), Field(max_length=10_000)] = ""
    scenarios: Annotated[list[ScenarioItem], Field(min_length=1, max_length=MAX_LIST)]
    planners: Annotated[list[Named], Field(min_length=1, max_length=1000)] = Field(
        default_factory=lambda: ["none"], description="default: [none]")
    controllers: Annotated[list[Named], Field(max_length=1000)] = Field(
        default_factory=list, description="may be empty when the suite runs peers only")
    methods: Optional[Annotated[list[MethodModel], Field(max_length=1000)]] = Field(
        None, description="planner + controller pairs (instead of the product of planners and controllers)")
    peers: Annotated[list[Named], Field(max_length=100)] = Field(
        default_factory=list, description="other libraries' solvers: pymapf-lacam, pymapf-pibt, pyrvo-orca")
    seeds: Seeds = Field(default_factory=lambda: [0])
    max_steps: Optional[Annotated[int, Strict(), Field(ge=1, le=10**9)]] = Field(
        None, description="step budget of every run; default: the simulator's, from the path lengths")
    timeout_s: Annotated[float, Strict(), Field(gt=0, le=MAX_TIMEOUT_S, allow_inf_nan=False)] = Field(
        600.0, description="per-job time limit, seconds (a job over it is stored with status 'timeout')")


def suite_json_schema() -> dict[str, Any]:
    """The JSON Schema of suite files, generated from the models."""
    schema = SuiteModel.model_json_schema(by_alias=True)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "swarmpath sweep suite (schema 1)"
    return schema


# ------------------------------------------------------------------ errors of the models
_TAGS = {"plain", "mapping"}


def _union_member(part: Any, prev: Any) -> bool:
    """pydantic's names of union members in an error's location; users never wrote them."""
    return part in _TAGS or (isinstance(part, str) and part.startswith(("list[", "literal[", "function-")))


def _first_error(exc: ValidationError) -> SuiteError:
    return first_error(exc, SuiteError, "docs/bench.md", _union_member)


# ------------------------------------------------------------------ the loaded suite
@dataclass(frozen=True)
class Suite:
    """A validated suite: its model, where it came from (``source`` for messages, ``base_dir``
    for relative files) and the bytes it was read from (for the store's provenance)."""

    model: SuiteModel
    source: str
    base_dir: Path
    text: str

    @property
    def name(self) -> str:
        return self.model.name

    def seeds(self) -> list[int]:
        """The suite's seeds as a list."""
        s = self.model.seeds
        return list(range(s.start, s.start + s.count)) if isinstance(s, SeedCountModel) else list(s)


def counts(value: Any) -> list[int]:
    """Agent counts of a list or a range."""
    if isinstance(value, RangeModel):
        return list(range(value.start, value.to + 1, value.step))
    return list(value)


def named(value: Any) -> tuple[str, dict[str, Any]]:
    """(name, params) of a planner/controller/peer entry."""
    return (value, {}) if isinstance(value, str) else (value.name, dict(value.params))


def builtin_suites() -> dict[str, str]:
    """Built-in suite names and their one-line descriptions."""
    out = {}
    for entry in sorted(resources.files("swarmpath.bench.sweep.suites").iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".yaml"):
            suite = parse_suite(entry.read_text(encoding="utf-8"), entry.name, Path(str(entry)).parent)
            out[suite.name] = (suite.model.description.strip().splitlines() or [""])[0]
    return out


def _builtin_suite_path(name: str) -> Path | None:
    entry = resources.files("swarmpath.bench.sweep.suites").joinpath(f"{name}.yaml")
    return Path(str(entry)) if entry.is_file() else None


def load_suite(path_or_name: str | Path) -> Suite:
    """A suite from a file, or a built-in suite by name (``mapf-static``, ``dynamic``,
    ``crowd``, ``papers``); every problem raises :class:`SuiteError` naming file and field."""
    p = Path(path_or_name)
    source = preview(str(path_or_name), 200)
    if not p.is_file():
        builtin = _builtin_suite_path(str(path_or_name)) if "/" not in str(path_or_name) else None
        if builtin is None:
            if p.exists():
                raise SuiteError("is a folder, not a suite file", source=source)
            known = ", ".join(builtin_suites())
            raise SuiteError(f"no such file, and no built-in suite of that name (built-in: {known})", source=source)
        p, source = builtin, f"{path_or_name} (built-in suite {p.name}.yaml)"
    text = limits.read_text_bounded(p, "suite", MAX_SUITE_BYTES, SuiteError)
    return parse_suite(text, source, p.parent)


def parse_suite(text: str, source: str, base_dir: Path) -> Suite:
    """Parse and validate suite text (YAML, or JSON when ``source`` ends in .json)."""
    try:
        doc = limits.parse_json_bounded(text) if source.endswith(".json") else limits.parse_yaml_bounded(text)
    except DocumentError as exc:
        raise SuiteError(str(exc), source=source) from None
    if not isinstance(doc, dict):
        kind = "empty" if doc is None else type(doc).__name__
        raise SuiteError(f"a suite must be a mapping of fields, got {kind}", source=source)
    try:
        model = SuiteModel.model_validate(doc)
    except ValidationError as exc:
        raise _first_error(exc).with_source(source) from None
    suite = Suite(model, source, base_dir, text)
    try:
        check_suite(suite)
    except SuiteError as exc:
        raise exc.with_source(source) from None
    return suite


# ------------------------------------------------------------------ checks beyond the schema
def check_suite(suite: Suite) -> None:
    """Names against the registries, parameters against constructors, entries against their
    own rules; the files and worlds themselves are checked when the jobs are expanded."""
    from swarmpath.bench.sweep.generators import GENERATORS, GeneratorParamsError
    from swarmpath.bench.sweep.peers import PEERS
    from swarmpath.registry import CONTROLLERS, PLANNERS

    m = suite.model
    seeds = suite.seeds()
    if len(set(seeds)) != len(seeds):
        raise SuiteError("a seed appears twice", field="seeds")

    def check_list(items: list[Any], where: str, registry: Any, kind: str, indexed: bool = True) -> None:
        seen = set()
        for k, item in enumerate(items):
            name, params = named(item)
            field = f"{where}[{k}]" if indexed else where
            if name not in registry:
                known = ", ".join(registry.names() if hasattr(registry, "names") else sorted(registry))
                raise SuiteError(f"unknown {kind} '{preview(name)}' (choose from: {known})", field=field)
            cls = registry.get(name) if hasattr(registry, "get") else registry[name]
            check_params(cls, params, f"{field}.params", f"{kind} {name}")
            ident = (name, repr(sorted(params.items())))
            if ident in seen:
                raise SuiteError(f"{kind} {name} with these parameters appears twice", field=field)
            seen.add(ident)

    def check_methods(owner: Any, where: str) -> None:
        if owner.methods is None:
            return
        both = [k for k in ("planners", "controllers") if k in owner.model_fields_set]
        if both:
            raise SuiteError(f"give {both[0]} or methods, not both", field=f"{where}{'.' if where else ''}methods")
        seen = set()
        for k, pair in enumerate(owner.methods):
            field = f"{where}{'.' if where else ''}methods[{k}]"
            check_list([pair.planner], f"{field}.planner", PLANNERS, "planner", indexed=False)
            check_list([pair.controller], f"{field}.controller", CONTROLLERS, "controller", indexed=False)
            ident = repr((named(pair.planner), named(pair.controller)))
            if ident in seen:
                raise SuiteError("this planner + controller pair appears twice", field=field)
            seen.add(ident)

    check_list(m.planners, "planners", PLANNERS, "planner")
    check_list(m.controllers, "controllers", CONTROLLERS, "controller")
    check_list(m.peers, "peers", PEERS, "peer")
    check_methods(m, "")

    def runs_something(entry: Any) -> bool:
        o = {} if isinstance(entry, str) else {k: getattr(entry, k) for k in ("controllers", "methods", "peers")}
        methods = o.get("methods") if o.get("methods") is not None else m.methods
        controllers = o.get("controllers") if o.get("controllers") is not None else m.controllers
        peers = o.get("peers") if o.get("peers") is not None else m.peers
        return bool(methods or controllers or peers)

    if not any(runs_something(e) for e in m.scenarios):
        raise SuiteError("the suite runs nothing: give controllers, methods or peers", field="controllers")
    for i, entry in enumerate(m.scenarios):
        where = f"scenarios[{i}]"
        if isinstance(entry, str):
            continue
        forms = [f for f in ("scenario", "map", "generator") if getattr(entry, f) is not None]
        if len(forms) != 1:
            raise SuiteError("give exactly one of scenario, map (with scen) or generator"
                             + (f" (found {', '.join(forms)})" if forms else ""), field=where)
        form = forms[0]
        if form == "map":
            if entry.scen is None:
                raise SuiteError("map goes with scen (a MovingAI .scen file)", field=f"{where}.scen")
        else:
            for key in ("scen", "agents"):
                if getattr(entry, key) is not None:
                    raise SuiteError("only used with map", field=f"{where}.{key}")
            if entry.first_row:
                raise SuiteError("only used with map", field=f"{where}.first_row")
        if form != "generator" and entry.params:
            raise SuiteError("only used with generator (the generator's parameters)", field=f"{where}.params")
        if entry.agents is not None:
            if isinstance(entry.agents, RangeModel) and entry.agents.to < entry.agents.start:
                raise SuiteError("'to' must be >= 'from'", field=f"{where}.agents")
            if len(counts(entry.agents)) > MAX_LIST:
                raise SuiteError(f"more than {MAX_LIST} agent counts", field=f"{where}.agents")
        if form == "generator":
            if entry.generator not in GENERATORS:
                raise SuiteError(f"unknown generator '{preview(entry.generator)}' (choose from: "
                                 f"{', '.join(sorted(GENERATORS))})", field=f"{where}.generator")
            try:
                GENERATORS[entry.generator].check(entry.params, f"{where}.params", MAX_LIST)
            except GeneratorParamsError as exc:
                raise SuiteError(exc.problem, field=exc.field) from None
        for key, registry, kind in (("planners", PLANNERS, "planner"), ("controllers", CONTROLLERS, "controller"),
                                    ("peers", PEERS, "peer")):
            if getattr(entry, key) is not None:
                check_list(getattr(entry, key), f"{where}.{key}", registry, kind)
        check_methods(entry, where)


def check_params(cls: Any, params: dict[str, Any], field: str, what: str) -> None:
    """``cls`` must accept ``params`` (through :func:`~swarmpath.bench.sweep.params.construct`):
    known keyword names, and values the constructor takes (constructors store configuration
    only, so this is cheap)."""
    from swarmpath.bench.sweep.params import construct, describe

    try:
        sig = inspect.signature(cls)
    except (TypeError, ValueError):
        sig = None
    if sig is not None:
        try:
            sig.bind(**params)
        except TypeError:
            takes = [p.name for p in sig.parameters.values()
                     if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) and p.name != "self"]
            unknown = [k for k in params if k not in takes]
            problem = (f"unknown parameter '{preview(unknown[0])}' of {what}" if unknown
                       else f"parameters do not fit {what}")
            raise SuiteError(f"{problem} (it takes: {describe(cls)})", field=field) from None
    try:
        construct(cls, params)
    except SwarmpathError as exc:
        raise SuiteError(str(exc), field=field) from None
    except (TypeError, ValueError) as exc:
        raise SuiteError(f"{what} refuses these parameters: {preview(str(exc), 200)} (it takes: {describe(cls)})",
                         field=field) from None
