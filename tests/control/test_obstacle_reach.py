"""Forecast boxes cut to the cells an obstacle can reach round walls (control/obstacle_reach.py):
every future the simulator's own motion models produce in thin-walled mazes stays inside the
cut forecast, the cut drops the cells behind a wall, and robots no longer wait at the mouth of
a dead end for a walker that cannot get there."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from swarmpath.control import hazards as H
from swarmpath.control.obstacle_reach import WallAwareReach, dilate, reach_rule, row_runs
from swarmpath.sim import Simulator
from swarmpath.registry import CONTROLLERS
from swarmpath.testing import validate_trajectory
from swarmpath.testing.motions import obstacle_track
from swarmpath.world import Circle, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.moving import Bounce8, MovingObstacle, RandomWalk, TurnEvery, initial_obstacle_state

S2 = float(np.sqrt(2))


def maze(rng: np.random.Generator, cols: int = 7, rows: int = 6) -> np.ndarray:
    """A maze of 2-wide passages behind walls one cell thick (a random spanning tree of rooms,
    plus a few extra openings so that there are loops)."""
    h, w = 3 * rows + 1, 3 * cols + 1
    blocked = np.ones((h, w), bool)
    for i in range(cols):
        for j in range(rows):
            blocked[3 * j + 1:3 * j + 3, 3 * i + 1:3 * i + 3] = False
    seen = {(0, 0)}
    stack = [(0, 0)]
    while stack:
        i, j = stack[-1]
        nxt = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
               if 0 <= i + di < cols and 0 <= j + dj < rows and (i + di, j + dj) not in seen]
        if not nxt:
            stack.pop()
            continue
        a, b = nxt[int(rng.integers(len(nxt)))]
        if a != i:
            blocked[3 * j + 1:3 * j + 3, 3 * max(a, i)] = False
        else:
            blocked[3 * max(b, j), 3 * i + 1:3 * i + 3] = False
        seen.add((a, b))
        stack.append((a, b))
    for _ in range(3):
        i, j = int(rng.integers(cols - 1)), int(rng.integers(rows))
        blocked[3 * j + 1:3 * j + 3, 3 * (i + 1)] = False
    return blocked


@dataclasses.dataclass(frozen=True)
class Unbounded(TurnEvery):
    """turn-every that does not declare it stays clear of walls: nothing of it is cut."""

    stays_clear = False


def maze_world(seed: int) -> World:
    rng = np.random.default_rng(seed)
    blocked = maze(rng)
    free = np.argwhere(~blocked)[:, ::-1]
    shapes = [Rect((-0.5, -0.5), (0.5, 0.5)), Circle((0.0, 0.0), 0.4), Rect((-0.3, -0.3), (0.3, 0.3)),
              Circle((0.0, 0.0), 0.2)]
    # speeds per axis under 1 + 2e, at it, and beyond (a step that may clear a wall)
    motions = [(RandomWalk(), 1.0), (RandomWalk(), S2), (RandomWalk(), 1.9), (TurnEvery(3), S2), (Bounce8(), 1.0),
               (TurnEvery(2), 2.2), (Unbounded(2), S2)]
    obstacles = []
    for k, c in enumerate(free[rng.choice(len(free), 14, replace=False)]):
        motion, speed = motions[k % len(motions)]
        angle = rng.uniform(0, 2 * np.pi)
        obstacles.append(MovingObstacle(f"m{k}", shapes[k % len(shapes)], tuple(c + 0.5),
                                        (speed * np.cos(angle), speed * np.sin(angle)), motion))
    h, w = blocked.shape
    robot = Robot("a", tuple(free[0] + 0.5), tuple(free[-1] + 0.5), 0.0, S2)
    return World(RectBounds(w, h), static_map=StaticMap(blocked), moving_obstacles=tuple(obstacles), robots=(robot,),
                 name=f"maze{seed}")


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("radius", [0.0, 0.3])
def test_cut_forecasts_hold_every_simulated_future_in_thin_walled_mazes(seed, radius):
    """Walkers, turn-every and bounce8 obstacles of several footprints and speeds (some fast
    enough to clear a wall in one step), run by the simulator's motion models in a maze of
    1-cell walls: every sweep an obstacle makes k steps later lies in the cut D_k, and the cut
    sets lie inside the boxes; on most steps the cut removes cells."""
    world = maze_world(seed)
    rng = np.random.default_rng(100 + seed)
    track = obstacle_track(world, 150, rng)
    start = initial_obstacle_state(world)
    path = np.concatenate([(start.positions - start.velocities * world.dt)[None], track])
    fc = H.ObstacleForecast(world, world.grid(), robot_radius=radius)
    assert fc.reach_cut is not None
    boxes = H.ObstacleForecast(world, world.grid(), robot_radius=radius)
    boxes.reach_cut = None                      # the forecast as it was: boxes only
    depth, cut_steps = 5, 0
    for t in range(1, len(path) - depth):
        coverage = fc.coverage(path[t], path[t - 1], depth)
        loose = boxes.coverage(path[t], path[t - 1], depth)
        assert all(not (c & ~lc).any() for c, lc in zip(coverage, loose))
        cut_steps += int(sum(c.sum() for c in coverage) < sum(c.sum() for c in loose))
        for k in range(1, depth + 1):
            a, b = path[t + k - 1], path[t + k]
            swept = H.paint(coverage[0].shape, fc.sweep_ranges(a, b, fc.keep_lo, fc.keep_hi)[0])
            assert not (swept & ~coverage[k - 1]).any(), (t, k)
    assert cut_steps > (len(path) - depth) // 2


def corridors_world(motion, speed: float = S2, robot_radius: float = 0.0) -> World:
    """Two 2-wide corridors, side by side behind a wall one cell thick and joined at their left
    end only: one walker paces the lower one."""
    blocked = np.ones((8, 24), bool)
    blocked[1:3, 1:23] = False      # lower corridor, y = 1, 2
    blocked[4:6, 1:23] = False      # upper corridor, y = 4, 5
    blocked[1:6, 1:3] = False       # joined at x = 1, 2
    walker = MovingObstacle("w", Rect((-0.5, -0.5), (0.5, 0.5)), (15.5, 1.5), (speed, 0.0), motion)
    robot = Robot("a", (15.5, 4.5), (20.5, 5.5), robot_radius, S2)
    return World(RectBounds(24, 8), static_map=StaticMap(blocked), moving_obstacles=(walker,), robots=(robot,),
                 name="corridors")


def test_a_walker_behind_a_wall_does_not_reach_the_next_corridor():
    """Five steps of a walker in the lower corridor cover the upper one only with the box; the
    cut keeps it to its own corridor (and the wall), as the way round is 26 cells."""
    for motion in (RandomWalk(), TurnEvery(3)):
        world = corridors_world(motion)
        fc = H.ObstacleForecast(world, world.grid())
        now = np.array([[15.5, 1.5]])
        cut = fc.coverage(now, now - [[S2, 0.0]], 5)
        fc.reach_cut = None
        box = fc.coverage(now, now - [[S2, 0.0]], 5)
        upper = np.zeros_like(cut[0])
        upper[4:6, 3:23] = True
        assert all((c & upper).sum() == 0 for c in cut)
        assert (box[-1] & upper).sum() > 10


def test_models_that_may_leave_the_free_cells_keep_their_boxes():
    """A model that does not declare it stays clear of walls, and one that may jump a wall in a
    step (1.9 cells a step against a footprint 0.6 wide), are not cut through the wall."""
    for motion, speed in ((Unbounded(3), S2), (RandomWalk(), 1.9)):
        world = dataclasses.replace(corridors_world(motion, speed), moving_obstacles=(
            MovingObstacle("w", Rect((-0.3, -0.3), (0.3, 0.3)), (15.5, 1.5), (speed, 0.0), motion),))
        fc = H.ObstacleForecast(world, world.grid())
        now = np.array([[15.5, 1.5]])
        cut = fc.coverage(now, now - [[speed, 0.0]], 3)
        assert cut[-1][4, 15], motion


def test_reach_sets_go_round_walls_and_runs_rebuild_the_mask():
    """The reach set of a cell in one corridor grows along it and round the end, never through
    the wall; row runs list exactly the True cells; a walker of one cell's width covers one
    cell round its reach set, and one whose step may clear a wall jumps."""
    world = corridors_world(RandomWalk())
    free = ~world.static_map.blocked
    reach = WallAwareReach(free)
    x0, y0, mask = reach.covered((15, 1), 1, 4, 0)
    cells = {(x0 + x, y0 + y) for y, x in zip(*np.nonzero(mask))}
    assert (15, 4) not in cells and (19, 2) in cells and (11, 1) in cells and (20, 1) not in cells
    rng = np.random.default_rng(0)
    for _ in range(20):
        m = rng.random((7, 9)) < 0.4
        runs = row_runs(m, 3, 5)
        back = np.zeros_like(m)
        for a, b, c, d in runs:
            back[b - 5:d - 5, a - 3:c - 3] = True
        assert np.array_equal(back, m)
        assert np.array_equal(dilate(m, 1)[1:-1, 1:-1],
                              np.max([m[1 + dy:m.shape[0] - 1 + dy, 1 + dx:m.shape[1] - 1 + dx]
                                      for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0))
    assert reach_rule(1.0, S2, 0.5, 0.5, True) == (1, False, 1)
    assert reach_rule(S2, 2.0, 0.5, 0.9, True) == (2, False, 1)       # a disc robot beside a fast walker
    assert reach_rule(S2, 2.0, 0.2, 0.2, True)[1]                      # 1.41 per axis clears a wall 0.4 wide
    assert reach_rule(S2, S2, 0.2, 0.2, False)[1] and not reach_rule(S2, S2, 0.3, 0.3, False)[1]


def dead_end_world(seed: int) -> World:
    """A robot whose goal lies at the bottom of a 2-wide dead end; beside it, behind a wall one
    cell thick, a walker paces a closed passage of its own and can never get out."""
    blocked = np.ones((12, 14), bool)
    blocked[9:11, 1:13] = False     # the room along the top, y = 9, 10
    blocked[1:9, 1:3] = False       # the dead end, x = 1, 2, open to the room at its top
    blocked[1:8, 4:6] = False       # the walker's passage, x = 4, 5, closed all round
    walker = MovingObstacle("w", Rect((-0.5, -0.5), (0.5, 0.5)), (4.5, 4.5), (1.0, 1.0), RandomWalk())
    robot = Robot("a", (11.5, 10.5), (1.5, 1.5), 0.0, S2)
    return World(RectBounds(14, 12), static_map=StaticMap(blocked), moving_obstacles=(walker,), robots=(robot,),
                 name=f"dead-end{seed}")


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_enters_a_dead_end_beside_a_walled_in_walker(controller):
    """The walker can never reach the dead end, but its box did (through the wall, within the
    look-ahead), so the robot waited at the mouth until the budget ran out. Now it goes in."""
    for seed in range(5):
        world = dead_end_world(seed)
        traj = Simulator(world, CONTROLLERS.get(controller)(), seed=seed, max_steps=200).run()
        validate_trajectory(world, traj)
        assert traj.status == "all_reached", (controller, seed, traj.status)
        assert not traj.contacts
        assert traj.n_steps < 40
