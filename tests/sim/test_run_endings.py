"""When a run ends (sim/simulator.py): a budget the caller gives is hard; the default budget
stretches while robots make progress, up to eight times itself; the stall rule ends runs where
nobody moves beyond two positions, and not runs where robots away from home wait while others
clear their way."""
from __future__ import annotations

import math

import numpy as np
import pytest

from swarmpath.control.base import Controller
from swarmpath.planning.base import Plan, PlanStatus, RobotPlan
from swarmpath.sim import Simulator, default_max_steps
from swarmpath.sim.simulator import MAX_EXTENSION, PROGRESS_GRACE
from swarmpath.testing import validate_trajectory
from swarmpath.world import RectBounds, Robot, World

#: small loop a robot paces while it waits (three positions, so it is not a stall)
PACE = np.array([(0.0, 0.0), (0.2, 0.0), (0.2, 0.2)])


def rows_world(n: int) -> World:
    """n robots, one per row, each 6 cells to the right of its start."""
    robots = tuple(Robot(f"r{i}", (0.5, 0.5 + i), (6.5, 0.5 + i), 0.0, 1.0) for i in range(n))
    return World(RectBounds(8, n), robots=robots, name="rows")


class Trickle(Controller):
    """Robot i paces beside its start until step ``i * gap``, then goes home at full speed."""

    def __init__(self, gap: int):
        self.gap = gap

    def reset(self, world, plan, rng):
        self.starts, self.goals, self.step = world.starts, world.goals, 0

    def act(self, obs):
        self.step += 1
        out = self.starts + PACE[self.step % 3]
        for i in range(len(out)):
            if self.step > i * self.gap:
                here = np.asarray(obs.positions[i], float)
                gap = self.goals[i] - here
                dist = float(np.linalg.norm(gap))
                out[i] = self.goals[i] if dist <= 1.0 else here + gap / dist
        return out


def test_the_default_budget_stretches_while_robots_make_progress() -> None:
    world = rows_world(8)
    budget = default_max_steps(world)
    gap = math.ceil(PROGRESS_GRACE * budget) - 10           # departures closer together than the grace
    assert 7 * gap > budget                                  # the last robot leaves after the budget
    traj = Simulator(world, Trickle(gap), seed=0).run()
    assert traj.status == "all_reached" and traj.n_steps > budget
    assert traj.meta["max_steps"] > budget
    assert validate_trajectory(world, traj) == []
    hard = Simulator(world, Trickle(gap), seed=0, max_steps=budget).run()
    assert hard.status == "truncated" and hard.n_steps == budget


def test_the_default_budget_does_not_stretch_without_progress() -> None:
    world = rows_world(2)
    budget = default_max_steps(world)
    never = Trickle(10 ** 6)                                 # pacing, never leaving
    traj = Simulator(world, never, seed=0).run()
    assert traj.status == "truncated" and traj.n_steps == budget
    # a pause longer than the grace: the run ends one grace after the second robot arrived,
    # before the third leaves
    world = rows_world(3)
    budget = default_max_steps(world)
    gap = budget - 5
    traj = Simulator(world, Trickle(gap), seed=0).run()
    assert traj.status == "truncated" and budget < traj.n_steps < 2 * gap
    home = np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9
    assert home.tolist() == [True, True, False]


def test_the_stretch_stops_at_four_times_the_budget() -> None:
    world = rows_world(40)
    budget = default_max_steps(world)
    gap = math.ceil(PROGRESS_GRACE * budget) // 2
    assert 39 * gap > MAX_EXTENSION * budget
    traj = Simulator(world, Trickle(gap), seed=0).run()
    assert traj.status == "truncated" and traj.n_steps == MAX_EXTENSION * budget


class WaitWhileOthersClear(Controller):
    """Robot 0 waits at its start until ``release``; robot 1, home from the start, walks three
    cells off its goal and back (period 6, home at every multiple of 6); then robot 0 goes
    home. The old stall rule looked at robot 0 alone and called a deadlock at step 60."""

    def __init__(self, release: int):
        self.release = release

    def reset(self, world, plan, rng):
        self.step = 0
        self.goals = world.goals

    def act(self, obs):
        self.step += 1
        out = np.array(obs.positions, float)
        off = [0, 1, 2, 3, 2, 1][self.step % 6]
        out[1] = self.goals[1] + (0.0, off)
        if self.step > self.release:
            gap = self.goals[0] - out[0]
            dist = float(np.linalg.norm(gap))
            out[0] = self.goals[0] if dist <= 1.0 else out[0] + gap / dist
        return out


def test_a_robot_waiting_while_others_clear_the_way_is_no_stall() -> None:
    robots = (Robot("w", (0.5, 0.5), (6.5, 0.5), 0.0, 1.0), Robot("h", (3.5, 2.5), (3.5, 2.5), 0.0, 1.0))
    world = World(RectBounds(8, 6), robots=robots, name="wait")
    traj = Simulator(world, WaitWhileOthersClear(release=100), seed=0).run()
    assert traj.status == "all_reached" and traj.n_steps > 100
    assert not [e for e in traj.events if e["kind"] == "deadlock"]


class Shuttle(Controller):
    """Robot 0 steps to and fro between two cells for ever; robot 1 stays home."""

    def reset(self, world, plan, rng):
        self.step = 0

    def act(self, obs):
        self.step += 1
        out = np.array(obs.positions, float)
        out[0, 0] += 1.0 if self.step % 2 else -1.0
        return out


def test_robots_that_only_shuttle_are_a_stall() -> None:
    robots = (Robot("s", (0.5, 0.5), (6.5, 0.5), 0.0, 1.0), Robot("h", (3.5, 2.5), (3.5, 2.5), 0.0, 1.0))
    world = World(RectBounds(8, 6), robots=robots, name="shuttle")
    traj = Simulator(world, Shuttle(), seed=0, deadlock_window=30).run()
    assert traj.status == "deadlock" and traj.n_steps == 30


@pytest.mark.parametrize("last", [5, 700])
def test_a_timed_plan_gets_a_budget_past_its_last_step(last: int) -> None:
    """A crowded plan waits: its robots may stand still for most of it. The budget counts the
    plan's last step, not only its length."""
    world = rows_world(1)
    path = np.array([(0.5, 0.5), (0.5, 0.5), (6.5, 0.5)])
    plan = Plan("test", (RobotPlan("r0", PlanStatus.EXACT, path, {}, np.array([0, last - 1, last])),), 0.0)
    assert default_max_steps(world, plan) >= 200 + 4 * last
