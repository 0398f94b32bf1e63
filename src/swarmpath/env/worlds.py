"""Which world an environment runs: a World, a scenario file or built-in scenario name, or a
MovingAI map with its .scen (built-in MovingAI files resolve by file name)."""
from __future__ import annotations

from pathlib import Path

from swarmpath.errors import ConfigError
from swarmpath.world.movingai import world_from_movingai
from swarmpath.world.scenario import load_scenario
from swarmpath.world.world import World


def resolve_world(scenario: World | str | Path, scen: str | Path | None = None, agents: int | None = None) -> World:
    """The World of ``scenario``: a World as is; a ``.map`` file (with ``scen`` and the first
    ``agents`` rows of it as robots, by :func:`~swarmpath.world.world_from_movingai`); else a
    scenario file or built-in name (:func:`~swarmpath.world.load_scenario`)."""
    if isinstance(scenario, World):
        if scen is not None or agents is not None:
            raise ConfigError("scen and agents go with a MovingAI .map, not with a World")
        world = scenario
    elif isinstance(scenario, (str, Path)):
        if str(scenario).endswith(".map"):
            if scen is None:
                raise ConfigError(f"{scenario}: a MovingAI map needs its .scen file (scen=...) for the robots")
            world = world_from_movingai(scenario, scen, agents)
        else:
            if scen is not None or agents is not None:
                raise ConfigError("scen and agents go with a MovingAI .map, not with a scenario file")
            world = load_scenario(scenario)
    else:
        raise ConfigError(f"scenario must be a World, a file or a built-in name, got {type(scenario).__name__}")
    if world.n_robots == 0:
        raise ConfigError(f"world {world.name!r} has no robots, so no agents")
    return world
