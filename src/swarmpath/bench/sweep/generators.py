"""World generators a suite can name (``{generator: NAME, params: {...}}``): each wraps a
function of swarmpath.world.generators with a parameter model, so a suite's parameters are
checked (names, types, ranges) before any world is built. A list value expands into one world
per value.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Annotated, Any, Callable

from pydantic import BaseModel, ConfigDict, Field, Strict, ValidationError

from swarmpath.errors import ConfigError
from swarmpath.world.limits import preview


class GeneratorParamsError(ConfigError):
    """A generator's parameters are wrong: ``field`` says where, ``problem`` what."""

    def __init__(self, problem: str, *, field: str):
        self.problem, self.field = problem, field
        super().__init__(f"{field}: {problem}")


_Pos = Annotated[float, Strict(), Field(gt=0, le=1e6, allow_inf_nan=False)]
_Int = Annotated[int, Strict(), Field(ge=1, le=100_000)]
_Seed = Annotated[int, Strict(), Field(ge=0, le=2**63 - 1)]


class _Params(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class AntipodalParams(_Params):
    n: _Int
    radius: _Pos = 0.3
    speed: _Pos = 0.5
    spacing: _Pos = 1.0


class RoomsParams(_Params):
    radius: _Pos = 0.3


class CrowdParams(_Params):
    n_obstacles: Annotated[int, Strict(), Field(ge=0, le=10_000)]
    motion: Annotated[str, Strict(), Field(pattern="^(bounce|random-walk|mixed)$")] = "mixed"
    size: _Pos = 12.0
    dt: _Pos = 0.5
    robot_speed: _Pos = 1.0
    obstacle_speed: _Pos = 0.5
    radius: _Pos = 0.3
    seed: _Seed | None = None


class MovingAIDiscsParams(_Params):
    name: Annotated[str, Strict(), Field(min_length=1, max_length=200)]
    n: _Int
    radius: _Pos = 0.4
    speed: _Pos = 1.0


#: Motion models the random grid can name (the others need parameters of their own).
GRID_MOTIONS = ("bounce", "bounce8", "random-walk", "turn-every", "redraw")


class RandomGridParams(_Params):
    n_robots: _Int = 100
    n_moving: Annotated[int, Strict(), Field(ge=0, le=100_000)] = 20
    size: Annotated[int, Strict(), Field(ge=2, le=4096)] = 64
    density: Annotated[float, Strict(), Field(ge=0, le=0.9, allow_inf_nan=False)] = 0.1
    motions: Annotated[str, Strict(), Field(pattern=f"^({'|'.join(GRID_MOTIONS)})(\\+({'|'.join(GRID_MOTIONS)}))*$")] \
        = "bounce8+random-walk"
    radius: Annotated[float, Strict(), Field(ge=0, le=0.5, allow_inf_nan=False)] = 0.0
    goal_offset: Annotated[float, Strict(), Field(ge=0, le=0.5, allow_inf_nan=False)] = 0.0
    seed: _Seed | None = None


@dataclass(frozen=True)
class Generator:
    """A world generator the suite can name: its parameter model, whether its world depends
    on a seed (drawn from the job's seed unless the entry fixes ``seed``), and the builder."""

    model: type[_Params]
    build: Callable[..., Any]
    seeded: bool = False
    description: str = ""

    def combinations(self, params: dict[str, Any], where: str, limit: int) -> list[dict[str, Any]]:
        """Every combination of the parameters (a list value expands), each validated; at
        most ``limit`` of them. Problems raise :class:`GeneratorParamsError` naming ``where``."""
        keys = sorted(params)
        values = [params[k] if isinstance(params[k], list) else [params[k]] for k in keys]
        total = 1
        for v in values:
            if not v:
                raise GeneratorParamsError("an empty list expands to nothing", field=where)
            total *= len(v)
        if total > limit:
            raise GeneratorParamsError(f"the parameter lists expand to {total} worlds (at most {limit})", field=where)
        out = []
        for combo in itertools.product(*values):
            doc = dict(zip(keys, combo))
            try:
                model = self.model.model_validate(doc)
            except ValidationError as exc:
                e = exc.errors()[0]
                loc = ".".join(str(p) for p in e["loc"])
                kind = e["type"]
                problem = ("unknown parameter (check the spelling; see docs/bench.md)" if kind == "extra_forbidden"
                           else "required parameter is missing" if kind == "missing"
                           else f"{e['msg']} (got {preview(e.get('input'))})")
                raise GeneratorParamsError(problem, field=f"{where}.{loc}" if loc else where) from None
            out.append(model.model_dump(exclude_none=True))
        return out

    def check(self, params: dict[str, Any], where: str, limit: int) -> None:
        self.combinations(params, where, limit)


def _antipodal(p: dict[str, Any], seed: int):
    from swarmpath.world.generators import antipodal

    return antipodal(p["n"], radius=p["radius"], speed=p["speed"], spacing=p["spacing"])


def _rooms(p: dict[str, Any], seed: int):
    from swarmpath.world.generators import rooms_with_doors

    return rooms_with_doors(radius=p["radius"])


def _crowd(p: dict[str, Any], seed: int):
    from swarmpath.world.generators import crowd_crossing

    return crowd_crossing(p["n_obstacles"], p.get("seed", seed), motion=p["motion"], size=p["size"], dt=p["dt"],
                          robot_speed=p["robot_speed"], obstacle_speed=p["obstacle_speed"], radius=p["radius"])


def _movingai_discs(p: dict[str, Any], seed: int):
    from swarmpath.world.generators import movingai

    return movingai(p["name"], p["n"], radius=p["radius"], speed=p["speed"])


def _random_grid(p: dict[str, Any], seed: int):
    from swarmpath.registry import MOTIONS
    from swarmpath.world.generators import random_grid_with_movers

    motions = tuple(MOTIONS.get(name)() for name in p["motions"].split("+"))
    return random_grid_with_movers(p.get("seed", seed), n_robots=p["n_robots"], n_moving=p["n_moving"],
                                   size=p["size"], density=p["density"], motions=motions, radius=p["radius"],
                                   goal_offset=p["goal_offset"])


#: World generators a suite can name (``{generator: NAME, params: {...}}``).
GENERATORS: dict[str, Generator] = {
    "antipodal": Generator(AntipodalParams, _antipodal, description="n disc robots on a circle, each to the "
                           "opposite point (n, radius 0.3, speed 0.5, spacing 1.0)"),
    "rooms-with-doors": Generator(RoomsParams, _rooms, description="four rooms with doors, six disc robots "
                                  "crossing them (radius 0.3)"),
    "crowd-crossing": Generator(CrowdParams, _crowd, seeded=True, description="one disc robot crosses a room "
                                "among n_obstacles moving discs that ignore it (motion bounce, random-walk or "
                                "mixed; seed: the job's unless given)"),
    "random-grid-movers": Generator(RandomGridParams, _random_grid, seeded=True, description="n_robots grid "
                                    "robots on a size x size map (density blocked) among n_moving 1-cell obstacles "
                                    "that never stop (motions in turn, e.g. bounce8+random-walk); the grid "
                                    "controllers' acceptance world; seed: the job's unless given"),
    "movingai-discs": Generator(MovingAIDiscsParams, _movingai_discs, description="a built-in MovingAI map "
                                "(name, e.g. den312d) with its first n even-10 agents as discs"),
}
