"""Goals sealed off by moving obstacles (metrics/sealed.py): the cover count against a plain
loop over cells, and the diagnosis on runs that cannot be finished and runs that can."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.metrics.sealed import sealed_goals, taken_cells
from swarmpath.metrics.summary import run_summary
from swarmpath.runner import simulate
from swarmpath.testing import validate_trajectory
from swarmpath.world import Circle, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.moving import Bounce, MovingObstacle, RandomWalk


def pocket_world(bouncer_in_pocket: bool) -> World:
    """A 10 x 8 room whose east column is wall but for a one-cell-wide pocket (9, 2)-(9, 4),
    entered only from (8, 3) onto (9, 3): the walls at (8, 2) and (8, 4) cut the diagonals.
    Robot 0's goal is the pocket's top cell, robot 1's a cell in the room. The bouncer either
    shuttles up and down the pocket for ever (no controller can bring robot 0 home without a
    contact) or runs along the room's top row, clear of both goals."""
    blocked = np.zeros((8, 10), bool)
    blocked[:, 9] = True
    blocked[2:5, 9] = False
    blocked[2, 8] = blocked[4, 8] = True
    robots = (Robot("r0", (1.5, 3.5), (9.5, 4.5), 0.0, float(np.sqrt(2))),
              Robot("r1", (1.5, 1.5), (5.5, 1.5), 0.0, float(np.sqrt(2))))
    if bouncer_in_pocket:
        bouncer = MovingObstacle("m0", Rect((-0.5, -0.5), (0.5, 0.5)), (9.5, 2.5), (0.0, 1.0), Bounce())
    else:
        bouncer = MovingObstacle("m0", Rect((-0.5, -0.5), (0.5, 0.5)), (0.5, 7.5), (1.0, 0.0), Bounce())
    return World(RectBounds(10, 8), static_map=StaticMap(blocked, 1.0), moving_obstacles=(bouncer,), robots=robots,
                 name="pocket")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_goal_a_bouncer_shuttles_over_is_reported_sealed(controller):
    world = pocket_world(bouncer_in_pocket=True)
    traj = simulate(world, controller, seed=3, max_steps=250)
    problems = validate_trajectory(world, traj)
    assert not [p for p in problems if "robot_robot" in str(p) or "robot_static" in str(p)]
    summary = run_summary(world, traj, controller=controller)
    assert not summary.success and summary.reached == 1
    assert sealed_goals(world, traj) == [0]
    assert summary.sealed_goals == 1
    assert [r.goal_sealed for r in summary.robots] == [True, False]
    assert "sealed off by moving obstacles" in summary.verdict()
    assert summary.to_dict()["sealed_goals"] == 1 and summary.to_dict()["robots"][0]["goal_sealed"] is True


def test_a_goal_left_open_is_not_reported_sealed():
    world = pocket_world(bouncer_in_pocket=False)
    traj = simulate(world, "pibt", seed=3, max_steps=250)
    assert not validate_trajectory(world, traj)
    summary = run_summary(world, traj, controller="pibt")
    assert summary.success and summary.sealed_goals == 0
    # cut short by the step budget, far from home: away, but not sealed
    short = simulate(world, "pibt", seed=3, max_steps=3)
    assert sealed_goals(world, short) == []
    summary = run_summary(world, short, controller="pibt")
    assert not summary.all_reached and summary.sealed_goals == 0
    assert "sealed" not in summary.verdict()


def test_the_taken_cells_match_a_plain_loop_over_cells():
    rng = np.random.default_rng(7)
    h, w = 9, 11
    shapes = [Rect((-0.5, -0.5), (0.5, 0.5)), Circle((0.0, 0.0), 0.4), Rect((-1.0, -0.5), (1.0, 0.5)),
              Rect((-0.5, -0.5), (0.5, 0.5))]
    moving = tuple(MovingObstacle(f"m{k}", s, (2.5 + 2 * k, 4.5), (1.0, 0.0), RandomWalk())
                   for k, s in enumerate(shapes))
    world = World(RectBounds(w, h), static_map=StaticMap(np.zeros((h, w), bool), 1.0), moving_obstacles=moving,
                  robots=(Robot("r0", (0.5, 0.5), (1.5, 0.5), 0.0, 1.0),))
    # cell centres, half cells, and arbitrary points; some beyond the map's edge
    positions = np.concatenate([np.floor(rng.uniform(-1, 12, (20, 4, 2))) + 0.5,
                                np.round(rng.uniform(-1, 12, (20, 4, 2)) * 2) / 2,
                                rng.uniform(-1, 12, (20, 4, 2))])
    positions[:, 0] = (3.5, 2.5)                  # parked: its cell is taken
    positions[::2, 1] = (6.5, 6.5)                # two obstacles taking turns on one cell
    positions[1::2, 3] = (6.5, 6.5)
    got = taken_cells(world, positions, world.grid())
    clear = []
    for step in positions:
        hit = np.zeros((h, w), bool)
        for ob, p in zip(moving, step):
            lo, hi = ob.placed(tuple(p)).bbox
            for y in range(h):
                for x in range(w):
                    if x < hi[0] - 1e-9 and x + 1 > lo[0] + 1e-9 and y < hi[1] - 1e-9 and y + 1 > lo[1] + 1e-9:
                        hit[y, x] = True
        clear.append(~hit)
    want = np.ones((h, w), bool)
    for y in range(h):
        for x in range(w):
            want[y, x] = not any(clear[t][y, x] and clear[t + 1][y, x] for t in range(len(clear) - 1))
    assert np.array_equal(got, want)
    assert want[2, 3] and want[6, 6] and not want.all()


def test_the_printed_summary_names_the_sealed_goal():
    from rich.console import Console

    from swarmpath.cli.run import print_run_summary
    from swarmpath.runner import run_world

    result = run_world(pocket_world(bouncer_in_pocket=True), planner=None, controller="pibt", seed=3)
    console = Console(record=True, width=200)
    print_run_summary(console, result.summary.to_dict())
    text = console.export_text()
    assert "no (goal sealed)" in text and "1 with its goal sealed off by moving obstacles" in text
