"""Goals sealed off by moving obstacles: why a run that ends short can end short.

Moving obstacles never react, so some worlds cannot be finished by any controller: a bouncer
shuttling for ever across the only way into a goal (a one-cell-wide pocket at a map's edge,
the obstacle on its middle cell every other step), or one parked in a passage. A run there
ends at its step budget (or in a deadlock) with the robot beside its goal, and the summary
should say that the obstacles, not the controller, held it back.

:func:`sealed_goals` reads that from the trajectory. A robot can only pass a cell if the cell
is clear of every obstacle on two steps in a row: in a step the obstacles move first, so a
robot that enters a cell on which an obstacle stands again next step is hit there. Over the
last ``window`` steps of the run (at least ``min_steps`` of them), a free grid cell that no
two consecutive steps left clear of every obstacle's bounding box counts as taken. A robot
away from its goal at the end has its goal *sealed* when, on the static grid, the goal lies
in the same connected area as the cell the robot ends on, but with the taken cells removed it
does not (or the goal cell is itself taken). Areas are 4-connected, which for robots moving
8-connected without cutting corners is the same connection. It is a diagnosis of the run's
last steps, not a proof that no controller could have finished: an obstacle may leave later,
and a bounding box takes more than a round or off-grid footprint does.
"""
from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from scipy.ndimage import label

#: Steps at the end of a run that :func:`sealed_goals` reads ...
SEALED_WINDOW = 200
#: ... and the fewest it needs to say anything (shorter runs: no goal is called sealed).
SEALED_MIN_STEPS = 20


def step_cover(world, positions: np.ndarray, grid) -> Iterator[np.ndarray]:
    """For each step of obstacle ``positions`` (T, m, 2): the grid cells (height, width) that
    some obstacle's bounding box overlaps (open overlap: a box that only touches a cell's edge
    does not count). One boolean grid a step, made when asked for: memory stays a grid."""
    h, w = grid.blocked.shape
    res = grid.resolution
    eps = 1e-9 * max(res, 1.0)
    positions = np.asarray(positions, float).reshape(len(positions), -1, 2)
    boxes = [ob.placed((0.0, 0.0)).bbox for ob in world.moving_obstacles]
    lo = np.array([b[0] for b in boxes], float).reshape(-1, 2)                                 # (m, 2)
    hi = np.array([b[1] for b in boxes], float).reshape(-1, 2)
    x0 = np.clip(np.floor((positions[..., 0] + lo[:, 0]) / res + eps).astype(np.int64), 0, w)
    y0 = np.clip(np.floor((positions[..., 1] + lo[:, 1]) / res + eps).astype(np.int64), 0, h)
    x1 = np.clip(np.ceil((positions[..., 0] + hi[:, 0]) / res - eps).astype(np.int64), 0, w)
    y1 = np.clip(np.ceil((positions[..., 1] + hi[:, 1]) / res - eps).astype(np.int64), 0, h)
    for t in range(len(positions)):
        some = (x1[t] > x0[t]) & (y1[t] > y0[t])
        a, b, c, d = x0[t][some], y0[t][some], x1[t][some], y1[t][some]
        diff = np.zeros((h + 1, w + 1), np.int32)
        np.add.at(diff, (b, a), 1)
        np.add.at(diff, (b, c), -1)
        np.add.at(diff, (d, a), -1)
        np.add.at(diff, (d, c), 1)
        yield diff.cumsum(axis=0).cumsum(axis=1)[:h, :w] > 0


def taken_cells(world, positions: np.ndarray, grid) -> np.ndarray:
    """The grid cells (height, width) that no two consecutive steps of obstacle ``positions``
    (T >= 2, m, 2) left clear of every obstacle's bounding box: no robot could pass them."""
    clear_twice = np.zeros(grid.blocked.shape, bool)
    before = None
    for cover in step_cover(world, positions, grid):
        if before is not None:
            clear_twice |= ~cover & ~before
        before = cover
    return ~clear_twice


def sealed_goals(world, traj, window: int = SEALED_WINDOW, min_steps: int = SEALED_MIN_STEPS) -> list[int]:
    """The robots (indices) away from their goals at the end of ``traj`` whose goal the moving
    obstacles had sealed off from them over its last ``window`` steps (module docstring);
    none when the run has fewer than ``min_steps`` steps."""
    if not world.moving_obstacles or traj.n_robots == 0 or traj.n_steps < max(2, int(min_steps)):
        return []
    final = traj.positions[-1]
    away = np.flatnonzero(np.linalg.norm(final - world.goals, axis=1) > 1e-9)
    if len(away) == 0:
        return []
    grid = world.grid(radius=float(world.radii.max(initial=0.0)))   # the free cells of the largest robot
    h, w = grid.blocked.shape
    taken = taken_cells(world, traj.obstacle_positions[-max(2, int(window)):], grid)
    goal = np.clip(grid.cell_of(world.goals[away]), 0, [w - 1, h - 1])
    here = np.clip(grid.cell_of(final[away]), 0, [w - 1, h - 1])
    static_area, _ = label(~grid.blocked)
    area, _ = label(~(grid.blocked | taken))
    s_goal, s_here = static_area[goal[:, 1], goal[:, 0]], static_area[here[:, 1], here[:, 0]]
    a_goal, a_here = area[goal[:, 1], goal[:, 0]], area[here[:, 1], here[:, 0]]
    reachable = (s_goal > 0) & (s_goal == s_here)
    cut = (a_goal == 0) | (a_goal != a_here)
    return [int(i) for i in away[reachable & cut]]
