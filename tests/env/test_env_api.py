"""The environments follow their APIs: PettingZoo's parallel API and seed tests on a grid and a
continuous world with moving obstacles, Gymnasium's env checker on swarmpath/Navigate-v0, and
the [env] extra stays out of ``import swarmpath`` and ``import swarmpath.env``."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("pettingzoo")

from gymnasium.utils.env_checker import check_env  # noqa: E402
from pettingzoo.test import parallel_api_test, parallel_seed_test  # noqa: E402

from swarmpath.env import NavigateEnv, parallel_env  # noqa: E402
from swarmpath.errors import ConfigError  # noqa: E402
from swarmpath.world import load_scenario  # noqa: E402

# jaleel2016: 12 point robots on a 0.25 grid, 3 bounce8 blocks; prediction2013: 6 discs, one
# turn-every disc obstacle
WORLDS = {"grid": "jaleel2016", "continuous": "prediction2013"}


@pytest.mark.parametrize("mode", sorted(WORLDS))
def test_parallel_api(mode: str) -> None:
    env = parallel_env(WORLDS[mode], max_steps=80)
    assert env.mode == mode
    assert len(env.world.moving_obstacles) > 0
    parallel_api_test(env, num_cycles=200)


@pytest.mark.parametrize("mode", sorted(WORLDS))
def test_parallel_seed(mode: str) -> None:
    parallel_seed_test(lambda: parallel_env(WORLDS[mode], max_steps=80), num_cycles=100)


@pytest.mark.parametrize("mode", sorted(WORLDS))
def test_same_seed_same_episode_other_seed_other_obstacles(mode: str) -> None:
    def episode(seed: int) -> np.ndarray:
        env = parallel_env(WORLDS[mode], max_steps=30)
        env.reset(seed=seed)
        for agent in env.possible_agents:
            env.action_space(agent).seed(7)
        while env.agents:
            env.step({a: env.action_space(a).sample() for a in env.agents})
        return env.trajectory().obstacle_positions

    assert np.array_equal(episode(3), episode(3))
    assert not np.array_equal(episode(3), episode(4))


def test_reset_without_seed_runs_the_next_seed() -> None:
    env = parallel_env("prediction2013", max_steps=5, seed=11)
    env.reset()
    assert env.core.seed_ == 11
    env.reset()
    assert env.core.seed_ == 12
    env.reset(seed=3)
    env.reset()
    assert env.core.seed_ == 4


@pytest.mark.parametrize("scenario", ["jaleel2016", "prediction2013", "karim2014"])
def test_gymnasium_env_checker(scenario: str) -> None:
    env = gymnasium.make("swarmpath/Navigate-v0", scenario=scenario, max_steps=40)
    check_env(env.unwrapped)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    assert isinstance(reward, float) and {"robot_robot", "robot_static", "robot_moving"} <= set(info)


def test_navigate_truncates_at_the_budget_and_knows_the_robot() -> None:
    env = NavigateEnv("prediction2013", robot="R3", max_steps=4)
    assert env.robot == 2 and env.others == "pso-predictive"
    env.reset(seed=1)
    ends = [env.step(np.zeros(2))[2:4] for _ in range(4)]
    assert ends[-1] == (False, True) and all(e == (False, False) for e in ends[:-1])
    with pytest.raises(ConfigError, match="robot must be"):
        NavigateEnv("prediction2013", robot="nobody")


def test_movingai_map_and_scen() -> None:
    env = parallel_env("random-32-32-10.map", scen="random-32-32-10-random-1.scen", agents=16, view=3)
    obs, infos = env.reset(seed=0)
    assert env.mode == "grid" and len(env.agents) == 16
    assert obs["a0"]["patch"].shape == (5, 7, 7)
    assert infos["a0"]["action_mask"].shape == (9,)
    with pytest.raises(ConfigError, match="needs its .scen"):
        parallel_env("random-32-32-10.map")


def test_world_object_and_bad_options() -> None:
    world = load_scenario("karim2014")
    assert parallel_env(world, connectivity=4).action_space("robot").n == 5
    with pytest.raises(ConfigError, match="unknown environment option 'speed'"):
        parallel_env(world, speed=2)
    with pytest.raises(ConfigError, match="connectivity"):
        parallel_env(world, connectivity=6)
    with pytest.raises(ConfigError, match="unknown reward weight"):
        parallel_env(world, rewards={"bonus": 1.0})
    with pytest.raises(ConfigError, match="radius"):
        parallel_env("prediction2013", mode="grid")      # discs wider than half a cell


def test_actions_are_checked() -> None:
    env = parallel_env("karim2014")
    env.reset(seed=0)
    with pytest.raises(ConfigError, match="no action for agent 'robot'"):
        env.step({})
    with pytest.raises(ConfigError, match="not in 0..8"):
        env.step({"robot": 9})
    with pytest.raises(ConfigError, match="one whole number"):
        env.step({"robot": 1.5})


def test_the_episode_ends_and_stays_ended() -> None:
    env = parallel_env("karim2014", max_steps=3)
    env.reset(seed=0)
    for _ in range(3):
        obs, rewards, terminated, truncated, infos = env.step({a: 0 for a in env.agents})
    assert truncated == {"robot": True} and env.agents == []
    assert env.step({}) == ({}, {}, {}, {}, {})


def _run(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip()


def test_the_env_extra_is_imported_lazily() -> None:
    code = ("import sys, swarmpath, swarmpath.env; swarmpath.env.EnvOptions; "
            "print([m for m in ('gymnasium', 'pettingzoo') if m in sys.modules])")
    assert _run(code) == "[]"


def test_registration_with_gymnasium() -> None:
    # gymnasium first: importing swarmpath.env registers the id
    code = ("import gymnasium, swarmpath.env; "
            "e = gymnasium.make('swarmpath/Navigate-v0', scenario='karim2014'); print(e.spec.id)")
    assert _run(code) == "swarmpath/Navigate-v0"
    # the module:id form imports swarmpath.env itself
    code = ("import gymnasium; e = gymnasium.make('swarmpath.env:swarmpath/Navigate-v0', scenario='karim2014'); "
            "print(type(e.unwrapped).__name__)")
    assert _run(code) == "NavigateEnv"
