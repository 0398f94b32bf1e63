"""Deadlock handling: no-progress detection, and the cat swarm on the PIBT core resolving (or
honestly reporting) the classic deadlocks: head-on in a corridor, a robot parked on its goal
in the way, and a swap that has no room at all."""
from __future__ import annotations

import numpy as np

from swarmpath.control.cat_swarm import CatSwarmController
from swarmpath.control.cat_swarm.deadlock import DeadlockMonitor
from swarmpath.control.progress import progress_update
from swarmpath.metrics.summary import run_summary
from swarmpath.planning import plan
from swarmpath.sim import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import RectBounds, Robot, StaticMap, World

S2 = float(np.sqrt(2))


def test_progress_update_counts_steps_without_improvement() -> None:
    best = np.array([10.0, 5.0, 3.0])
    since = np.array([0, 4, 2])
    best, since = progress_update(best, since, np.array([9.0, 5.0, 4.0]), np.array([False, False, False]))
    assert best.tolist() == [9.0, 5.0, 3.0] and since.tolist() == [0, 5, 3]
    best, since = progress_update(best, since, np.array([9.0, 0.0, 4.0]), np.array([False, True, False]))
    assert best.tolist() == [9.0, np.inf, 3.0] and since.tolist() == [1, 0, 4]
    # robot 1, pushed off its goal, counts from where it lands
    best, since = progress_update(best, since, np.array([9.0, 1.0, 4.0]), np.array([False, False, False]))
    assert best.tolist() == [9.0, 1.0, 3.0] and since.tolist() == [2, 0, 5]


def test_monitor_marks_stuck_robots_urgent_and_reports_once() -> None:
    mon = DeadlockMonitor.start(2, patience=3, report_after=5)
    events = []
    for step in range(1, 8):
        events += mon.update(step, np.array([4.0, 10.0 - step]), np.array([False, False]))
    assert mon.urgent.tolist() == [True, False]
    assert mon.urgent_since[0] == 4  # stuck from its 4th step without progress
    assert [(e["robot"], e["kind"]) for e in events] == [(0, "deadlock")]
    events = mon.update(8, np.array([3.0, 2.0]), np.array([False, False]))
    assert [(e["robot"], e["kind"]) for e in events] == [(0, "deadlock_resolved")]
    assert mon.urgent.tolist() == [True, False]  # urgent until it reaches its goal
    mon.update(9, np.array([0.0, 1.0]), np.array([True, False]))
    assert mon.urgent.tolist() == [False, False]


# ---------------------------------------------------------------------------- scenarios
def corridor(length: int, niches: tuple[int, ...] = ()) -> StaticMap:
    """A one-cell corridor along row 1 of a 3-row map, with side pockets at the given x."""
    blocked = np.ones((3, length), bool)
    blocked[1, :] = False
    for x in niches:
        blocked[2, x] = False
    return StaticMap(blocked, 1.0)


def corridor_world(robots, length=7, niches=(3,)) -> World:
    return World(RectBounds(length, 3), static_map=corridor(length, niches),
                 robots=tuple(Robot(f"r{k}", (a + 0.5, 1.5), (b + 0.5, 1.5), 0.0, S2) for k, (a, b) in enumerate(robots)),
                 name="corridor")


def run(world, seed=0, max_steps=200):
    traj = Simulator(world, CatSwarmController(), plan(world, "astar"), seed=seed, max_steps=max_steps).run()
    assert validate_trajectory(world, traj) == []
    return traj


def test_head_on_in_a_corridor_is_resolved_through_the_niche() -> None:
    world = corridor_world([(0, 6), (6, 0)])
    for seed in range(3):
        traj = run(world, seed)
        assert traj.status == "all_reached"
        used_niche = np.any(np.floor(traj.positions[:, :, 1]) == 2)
        assert used_niche


def test_a_robot_parked_on_its_goal_yields_and_comes_back() -> None:
    world = corridor_world([(3, 3), (0, 6)])  # r0 sits on its goal in the way of r1
    traj = run(world)
    assert traj.status == "all_reached"
    assert np.any(traj.positions[:, 0] != world.goals[0])  # it left its goal ...
    assert np.allclose(traj.positions[-1], world.goals)     # ... and both are home
    assert "yield" in traj.mode_names


def test_a_swap_without_room_is_reported_never_counted_as_success() -> None:
    world = corridor_world([(0, 4), (4, 0)], length=5, niches=())
    traj = run(world, max_steps=150)
    assert traj.status != "all_reached"
    summary = run_summary(world, traj)
    assert summary.success is False
    assert summary.collisions == {"robot_robot": 0, "robot_static": 0, "robot_moving": 0}
    assert any(e["kind"] == "deadlock" for e in traj.events)
