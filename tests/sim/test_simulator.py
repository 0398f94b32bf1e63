"""The simulator: validates moves, records everything, ends for the right reason, and its
trajectories survive saving and loading."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from reference_checker import reference_verdict

from swarmpath.control.base import Controller
from swarmpath.metrics.summary import run_summary
from swarmpath.planning import plan
from swarmpath.runner import run_world
from swarmpath.sim import Simulator, Trajectory
from swarmpath.testing import validate_trajectory
from swarmpath.world import RandomWalk, Rect, RectBounds, Robot, World, world_from_movingai
from swarmpath.world.moving import MovingObstacle

S2 = float(np.sqrt(2))


def open_world(**kw) -> World:
    robots = (Robot("a", (0.5, 0.5), (6.5, 0.5), 0.0, S2), Robot("b", (0.5, 4.5), (6.5, 4.5), 0.0, S2))
    return World(RectBounds(8, 6), robots=robots, name="open", **kw)


class Still(Controller):
    def reset(self, world, plan, rng):
        pass

    def act(self, obs):
        return obs.positions


class Jumper(Controller):
    def reset(self, world, plan, rng):
        pass

    def act(self, obs):
        return obs.goals  # too far in one step


def test_follow_reaches_goals_and_records_modes() -> None:
    world = open_world()
    traj = Simulator(world, __import__("swarmpath.control.follow", fromlist=["x"]).FollowController(),
                     plan(world, "astar"), seed=0).run()
    assert traj.status == "all_reached"
    assert np.allclose(traj.positions[-1], world.goals)
    assert traj.modes is not None and "follow" in traj.mode_names
    assert validate_trajectory(world, traj) == []


def test_invalid_moves_are_rejected_and_recorded() -> None:
    world = open_world()
    traj = Simulator(world, Jumper(), seed=0, max_steps=3).run()
    kinds = [e["kind"] for e in traj.events]
    assert kinds.count("invalid_move") == 6  # 2 robots x 3 steps
    assert np.allclose(traj.positions[-1], world.starts)
    assert traj.status == "truncated"


def test_a_controller_that_never_moves_is_reported_as_deadlock() -> None:
    world = open_world()
    traj = Simulator(world, Still(), seed=0, max_steps=1000, deadlock_window=20).run()
    assert traj.status == "deadlock" and traj.n_steps == 20
    summary = run_summary(world, traj)
    assert summary.deadlocks == 2 and not summary.success


def test_same_seed_same_trajectory_with_random_obstacles() -> None:
    cell = Rect((-0.5, -0.5), (0.5, 0.5))
    world = open_world(moving_obstacles=(MovingObstacle("m", cell, (3.5, 2.5), (0, 0), RandomWalk()),))
    a = run_world(world, planner="astar", controller="follow", seed=4).trajectory
    b = run_world(world, planner="astar", controller="follow", seed=4).trajectory
    c = run_world(world, planner="astar", controller="follow", seed=5).trajectory
    assert np.array_equal(a.obstacle_positions, b.obstacle_positions)
    assert not np.array_equal(a.obstacle_positions, c.obstacle_positions)


@pytest.mark.parametrize("suffix", [".npz", ".json"])
def test_trajectory_round_trip(tmp_path: Path, suffix: str, data_dir: Path) -> None:
    from swarmpath.world import world_from_movingai

    world = world_from_movingai(data_dir / "random-32-32-10.map", data_dir / "random-32-32-10-random-1.scen", 6)
    traj = run_world(world, planner="astar", controller="follow", seed=1).trajectory
    loaded = Trajectory.load(traj.save(tmp_path / f"t{suffix}"))
    assert np.allclose(loaded.positions, traj.positions, atol=1e-6)
    assert loaded.contacts == traj.contacts and loaded.status == traj.status
    assert loaded.robot_ids == traj.robot_ids and loaded.mode_names == traj.mode_names
    assert np.array_equal(loaded.static_map, traj.static_map)
    assert all(np.allclose(p, q, atol=1e-6) for p, q in zip(loaded.planned_paths, traj.planned_paths))


def test_simulator_contacts_equal_an_independent_recheck(data_dir) -> None:
    """Robot-robot contacts of a colliding run (A* paths followed blindly) equal those of a
    brute-force recheck that samples every step of every nearby pair (tests/reference_checker,
    no swarmpath code)."""
    world = world_from_movingai(data_dir / "random-32-32-10.map", data_dir / "random-32-32-10-random-1.scen", 40)
    traj = run_world(world, planner="astar", controller="follow", seed=0).trajectory
    found = {(c.step, c.robot, c.other) for c in traj.contacts if c.kind == "robot_robot"}
    assert len(found) > 5
    pos = traj.positions
    expected = set()
    for t in range(1, pos.shape[0]):
        p0, p1 = pos[t - 1], pos[t]
        for i in range(world.n_robots):
            for j in range(i + 1, world.n_robots):
                if np.max(np.abs(p0[i] - p0[j])) > 4.0:   # one-cell moves cannot meet from farther
                    continue
                verdict = reference_verdict(tuple(p0[i]), tuple(p1[i]), tuple(p0[j]), tuple(p1[j]), 0.0, 0.0,
                                            world.resolution, margin=1e-9)
                assert verdict is not None
                if verdict:
                    expected.add((t, i, j))
    assert found == expected


def test_loading_garbage_is_a_clear_error(tmp_path: Path) -> None:
    from swarmpath.errors import SwarmpathError

    p = tmp_path / "x.json"
    p.write_text('{"a": 1}')
    with pytest.raises(SwarmpathError, match="not a swarmpath trajectory"):
        Trajectory.load(p)
