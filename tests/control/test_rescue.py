"""The stall rescue of the grid controllers (control/pibt/rescue.py): when PIBT stops making
progress in a static world, LaCAM plans the rest from where the robots stand. Every run is
checked by the independent validator."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from swarmpath.control.pibt.rescue import StallRescue
from swarmpath.errors import ConfigError
from swarmpath.registry import CONTROLLERS
from swarmpath.sim.simulator import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import Rect, RectBounds, Robot, World
from swarmpath.world.moving import Bounce, MovingObstacle
from swarmpath.world.static_map import StaticMap

S2 = float(np.sqrt(2))

#: A dead end behind a robot already home: A rests on its goal in the corridor, B's goal lies
#: beyond it at the bottom, C rests on its goal in a pocket beside the corridor's mouth. B
#: pushes A deeper instead of out (PIBT alone shuttles them for ever).
DEAD_END = ["@@@@@@@@",
            "@B.....@",
            "@......@",
            "@@@.@@@@",
            "@@C.A.@@",
            "@@@@@b@@",
            "@@@@@@@@"]


def text_world(rows: list[str], moving: tuple = ()) -> World:
    """A world from rows of text (row index = y): '@' blocked, an upper-case letter a robot
    resting there, the same letter in lower case its goal (none: its goal is its start)."""
    blocked = np.array([[c == "@" for c in r] for r in rows])
    goals = {c.upper(): (x, y) for y, r in enumerate(rows) for x, c in enumerate(r) if c.islower()}
    robots = []
    for y, r in enumerate(rows):
        for x, c in enumerate(r):
            if c.isupper():
                gx, gy = goals.get(c, (x, y))
                robots.append(Robot(c, (x + 0.5, y + 0.5), (gx + 0.5, gy + 0.5), 0.0, S2))
    h, w = blocked.shape
    return World(RectBounds(w, h), static_map=StaticMap(blocked, 1.0), robots=tuple(robots), moving_obstacles=moving)


def run(world: World, controller: str, seed: int, **params):
    return Simulator(world, CONTROLLERS.get(controller)(**params), None, seed=seed).run()


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_whose_goal_lies_behind_one_already_home_gets_there(controller) -> None:
    world = text_world(DEAD_END)
    for seed in range(4):
        without = run(world, controller, seed, rescue_after=0)
        assert without.status == "deadlock", (controller, seed)
        traj = run(world, controller, seed)
        assert traj.status == "all_reached", (controller, seed, traj.status)
        assert validate_trajectory(world, traj) == []
        assert np.allclose(traj.positions[-1], world.goals)
        assert [e["kind"] for e in traj.events if e["kind"].startswith("rescue")] == ["rescue"]
        assert "rescue" in traj.mode_names


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_the_rescue_budget_counts_robot_moves_not_seconds(controller) -> None:
    """A budget of one PIBT call runs out the same way on every machine: the search fails for
    want of work, no later stall starts another (the run's searches share the budget), and the
    run is step for step the same each time, its events included (they count the work done,
    not the seconds)."""
    world = text_world(DEAD_END)
    runs = [run(world, controller, 0, rescue_work=world.n_robots) for _ in range(2)]
    for traj in runs:
        failed = [e for e in traj.events if e["kind"] == "rescue_failed"]
        assert len(failed) == 1 and all("work_limit" in e["detail"] for e in failed)
        assert traj.status == "deadlock"
    assert np.array_equal(runs[0].positions, runs[1].positions)
    assert runs[0].events == runs[1].events


def test_the_rescue_plans_with_the_controllers_own_moves_on_four_connected_grids() -> None:
    world = text_world(DEAD_END)
    assert run(world, "pibt", 0, connectivity=4, rescue_after=0).status == "deadlock"
    traj = run(world, "pibt", 0, connectivity=4)
    assert traj.status == "all_reached" and validate_trajectory(world, traj) == []
    steps = np.abs(np.diff(traj.positions, axis=0)).sum(axis=2)
    assert np.all(steps <= 1.0 + 1e-9)    # no diagonal move, the plan's steps included


def dense_world(seed: int, n: int, size: int = 32, density: float = 0.2) -> World:
    """A size x size map with ``density`` random blocked cells and n point robots on distinct
    random starts and goals in its largest 4-connected free area (so every goal is reachable
    without corner cutting)."""
    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < density
    labels, count = ndimage.label(~blocked)
    largest = np.argmax(np.bincount(labels.ravel())[1:]) + 1
    cells = np.argwhere(labels == largest)[:, ::-1]
    pick = cells[rng.choice(len(cells), 2 * n, replace=False)] + 0.5
    robots = tuple(Robot(f"r{i}", tuple(pick[i]), tuple(pick[n + i]), 0.0, S2) for i in range(n))
    return World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), robots=robots)


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_crowds_on_dense_random_maps_all_arrive(controller) -> None:
    """32 x 32 maps with 20 % blocked (the density of MovingAI's random-32-32-20) and 250 or
    300 robots, seeds 0-5: every robot home, every run valid. Without the rescue some of these
    runs stall (counted, and at least one must)."""
    stalled = 0
    for seed in range(6):
        world = dense_world(seed, 250 + 50 * (seed % 2))
        without = run(world, controller, seed, rescue_after=0)
        stalled += without.status != "all_reached"
        traj = run(world, controller, seed)
        assert traj.status == "all_reached", (controller, seed, traj.status)
        assert validate_trajectory(world, traj) == [], (controller, seed)
    print(f"\n{controller}: {stalled} of 6 dense runs stall without the rescue; all arrive with it")
    assert stalled >= 1


def test_the_rescue_stays_out_where_its_plan_would_not_be_the_whole_truth() -> None:
    world = text_world(DEAD_END)
    grid = world.grid()
    from swarmpath.control.pibt.core import GridGraph
    from swarmpath.search.lazy_distance import LazyDistanceTables

    graph = GridGraph.build(grid.blocked, 8, 0.0, 1.0)
    tables = LazyDistanceTables(grid.blocked)
    rng = np.random.default_rng(0)
    assert StallRescue.build(world, grid, graph, tables, 8, rng) is not None
    assert StallRescue.build(world, grid, graph, tables, 8, rng, after=0) is None
    cart = MovingObstacle("cart", Rect((-0.4, -0.4), (0.4, 0.4)), (3.5, 1.5), (1.0, 0.0), Bounce())
    moving = text_world(DEAD_END, moving=(cart,))
    assert StallRescue.build(moving, grid, graph, tables, 8, rng) is None
    import dataclasses

    off = dataclasses.replace(world, robots=tuple(dataclasses.replace(r, goal=(4.3, 4.5)) if r.id == "A" else r
                                                  for r in world.robots))
    assert StallRescue.build(off, grid, graph, tables, 8, rng) is None
    slow = dataclasses.replace(world, robots=tuple(dataclasses.replace(r, max_speed=1.0) for r in world.robots))
    assert StallRescue.build(slow, grid, graph, tables, 8, rng) is None
    assert StallRescue.build(slow, grid, graph, tables, 4, rng) is not None


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
@pytest.mark.parametrize("params", [{"rescue_after": -1}, {"rescue_after": 2.5}, {"rescue_after": True},
                                    {"rescue_work": 0}, {"rescue_work": 1e8}, {"rescue_work": "5"}])
def test_bad_rescue_settings_give_one_clear_error(controller, params) -> None:
    with pytest.raises(ConfigError, match=next(iter(params))):
        run(text_world(DEAD_END), controller, 0, **params)
