"""Experts: rolling out a registered controller's actions through the environment gives the
trajectory ``swarmpath run`` gives with the same seed, bit for bit (positions, obstacles,
contacts), and the recorded episodes are swarmpath Trajectories the validators and the HTML
replay accept."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("pettingzoo")

from swarmpath.env import NavigateEnv, parallel_env  # noqa: E402
from swarmpath.errors import ConfigError  # noqa: E402
from swarmpath.runner import run_world  # noqa: E402
from swarmpath.sim.trajectory import Trajectory  # noqa: E402
from swarmpath.testing import validate_trajectory  # noqa: E402
from swarmpath.viz.html_replay import write_replay_html  # noqa: E402
from swarmpath.world import load_scenario  # noqa: E402


def expert_rollout(env, controller, seed: int) -> tuple[Trajectory, int]:
    env.reset(seed=seed)
    inexact = 0
    while env.agents:
        actions = env.expert_actions(controller)
        inexact += sum(not ok for ok in env.expert_exact.values())
        env.step(actions)
    return env.trajectory(), inexact


def assert_same_run(a: Trajectory, b: Trajectory) -> None:
    assert a.positions.shape == b.positions.shape
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.obstacle_positions, b.obstacle_positions)
    assert [c.to_dict() for c in a.contacts] == [c.to_dict() for c in b.contacts]
    assert a.status == b.status


# `swarmpath run jaleel2016 --seed S` plans with hybrid-apf (the scenario's default) and runs
# cat-swarm; `swarmpath run prediction2013 --controller orca --seed S` plans nothing.
@pytest.mark.parametrize("scenario, controller, planner, options", [
    ("jaleel2016", "cat-swarm", "hybrid-apf", {}),
    ("prediction2013", "orca", None, {"goal_snap": 0.0}),
])
@pytest.mark.parametrize("seed", [0, 5])
def test_expert_rollout_is_swarmpath_run(scenario: str, controller: str, planner: str | None, options: dict,
                                         seed: int) -> None:
    world = load_scenario(scenario)
    run = run_world(world, controller=controller, seed=seed)
    assert run.planner == (planner or "none")
    env = parallel_env(scenario, planner=planner, stay_arrived=True, **options)
    traj, inexact = expert_rollout(env, controller, seed)
    assert inexact == 0
    assert_same_run(run.trajectory, traj)
    assert validate_trajectory(world, traj) == []
    assert bool(traj.planned_paths) == (planner is not None)


def test_a_controller_object_and_a_name_are_the_same_expert() -> None:
    from swarmpath.registry import CONTROLLERS

    env = parallel_env("prediction2013", stay_arrived=True)
    by_name, _ = expert_rollout(env, "pso-predictive", 2)
    by_object, _ = expert_rollout(parallel_env("prediction2013", stay_arrived=True),
                                  CONTROLLERS.get("pso-predictive")(), 2)
    assert np.array_equal(by_name.positions, by_object.positions)
    assert np.array_equal(by_name.positions, run_world(load_scenario("prediction2013"), seed=2).trajectory.positions)


def test_asking_twice_in_a_step_does_not_advance_the_expert() -> None:
    env = parallel_env("jaleel2016")
    env.reset(seed=1)
    first = env.expert_actions("cat-swarm")
    again = env.expert_actions("cat-swarm")
    assert first == again


def test_an_expert_that_needs_a_plan_says_so() -> None:
    env = parallel_env("apf-trap-gap")
    env.reset(seed=0)
    with pytest.raises(ConfigError, match="needs an offline plan"):
        env.expert_actions("follow")


def test_goal_snapping_is_reported_not_hidden() -> None:
    # with the default snap (a tenth of a step) ORCA's stops just short of a goal cannot be
    # reproduced; the env says which steps, and the rollout stays contact-free
    env = parallel_env("prediction2013", stay_arrived=True)
    traj, inexact = expert_rollout(env, "orca", 0)
    assert inexact > 0
    assert validate_trajectory(load_scenario("prediction2013"), traj) == []


def test_random_rollout_trajectory_validates_and_replays(tmp_path) -> None:
    world = load_scenario("jaleel2016")
    env = parallel_env(world, max_steps=40)
    env.reset(seed=4)
    for agent in env.possible_agents:
        env.action_space(agent).seed(1)
    seen = 0
    while env.agents:
        _, rewards, _, _, infos = env.step({a: env.action_space(a).sample() for a in env.agents})
        seen += sum(i["robot_robot"] + i["robot_static"] + i["robot_moving"] for i in infos.values())
    traj = env.trajectory()
    assert traj.n_steps == 40 and str(traj.status) == "truncated"
    violations = validate_trajectory(world, traj)
    assert len(traj.contacts) > 0
    # the validator re-checks with the same checker: one violation per contact found
    assert len(violations) == len(traj.contacts)
    assert seen >= len(traj.contacts)
    page = write_replay_html(traj, tmp_path / "replay.html")
    assert page.stat().st_size > 1000
    back = Trajectory.load(traj.save(tmp_path / "episode.npz"))
    assert np.array_equal(back.positions, traj.positions)


def test_navigate_others_follow_their_controller() -> None:
    # robot 0 taking pso-predictive's own action is the full pso-predictive run
    env = NavigateEnv("prediction2013", robot=0, others="pso-predictive", stay_arrived=True)
    env.reset(seed=3)
    done = False
    while not done:
        _, _, terminated, truncated, _ = env.step(env.expert_action("pso-predictive"))
        done = terminated or truncated
    run = run_world(load_scenario("prediction2013"), controller="pso-predictive", seed=3)
    assert np.array_equal(env.trajectory().positions, run.trajectory.positions)
