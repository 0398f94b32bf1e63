"""Agents' actions as the simulator's proposed positions, and back (for experts).

Grid worlds (:class:`GridActions`): action ``a`` sends a robot to the cell
``cell + MOVES[a]`` of the grid the grid controllers use (``world.grid(radius=largest
radius)``), with ``MOVES`` the stay move and the 8 (or 4) neighbours in
:data:`swarmpath.world.move_rules.GRID_MOVES` order. The robot goes to that cell's centre, or
to its exact goal when that cell is its goal cell; "stay" therefore settles a robot that
stands off a cell centre (an exact start on a cell corner) on its own cell's centre, as the
grid controllers do. Nothing is corrected: a move into a blocked cell, across a blocked corner
or out of reach goes to the simulator, whose checker counts the contact or whose validation
rejects the move.

Continuous worlds (:class:`ContinuousActions`): the action is a velocity ``v`` in
[-1, 1]^2 in units of the robot's ``max_speed``; the robot moves by ``v * max_speed * dt``,
with the norm of ``v`` clipped to 1 (norms up to 1 + 1e-9 pass, the simulator's own
tolerance on move lengths). A move that ends within ``goal_snap`` of the robot's goal, with
the goal in reach, ends on the goal.

``encode`` turns positions a controller proposed into the actions that reproduce them, bit
for bit where an action can (the expert rollouts then follow ``swarmpath run`` exactly), and
says which could not be reproduced.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.pibt.core import static_moves
from swarmpath.world.grid import OccupancyGrid
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
#: Indices into GRID_MOVES of the 4-connected actions (stay, +x, +y, -x, -y).
FOUR_CONNECTED = np.array([0, 1, 3, 5, 7], np.int64)
#: Relative tolerance of the simulator's move-length test.
LENGTH_TOLERANCE = 1e-9


class GridActions:
    """Discrete moves between cell centres (see the module docs) for the robots of ``world``."""

    def __init__(self, world: World, connectivity: int = 8):
        self.world = world
        self.connectivity = connectivity
        index = np.arange(9) if connectivity == 8 else FOUR_CONNECTED
        self.moves: IntArray = GRID_MOVES[index]
        self.grid: OccupancyGrid = world.grid(radius=float(world.radii.max(initial=0.0)))
        self.height, self.width = self.grid.blocked.shape
        self.goals = world.goals
        self.goal_cells = self.cells(self.goals)
        self.goal_off_centre = np.any(self.goals != self.grid.centers(self.goal_cells), axis=1)
        self.reach = world.max_speeds * world.dt
        self.static_ok = static_moves(self.grid.blocked, connectivity)[:, :, index]
        # from a cell centre, which moves' centres are in reach (most robots, most steps)
        lengths = np.linalg.norm(self.moves, axis=1) * self.grid.resolution
        self.centre_reach = lengths[None, :] <= self.reach[:, None] * (1 + LENGTH_TOLERANCE) + 1e-12

    @property
    def n_actions(self) -> int:
        return len(self.moves)

    def cells(self, points: FloatArray) -> IntArray:
        """Grid cells (n, 2) of points, clipped to the grid (as the grid controllers do)."""
        cells = self.grid.cell_of(np.asarray(points, float).reshape(-1, 2))
        return np.clip(cells, 0, [self.width - 1, self.height - 1])

    def decode(self, pos: FloatArray, actions: IntArray, rows: IntArray | None = None,
               cells: IntArray | None = None) -> FloatArray:
        """Proposed positions (k, 2) of robots ``rows`` (k,; default all) taking ``actions``
        (k,) at ``pos`` (k, 2) (in ``cells``, when known)."""
        goal_cells = self.goal_cells if rows is None else self.goal_cells[rows]
        goals = self.goals if rows is None else self.goals[rows]
        dest = (self.cells(pos) if cells is None else cells) + self.moves[actions]
        targets = self.grid.centers(dest)
        to_goal = np.all(dest == goal_cells, axis=1) & self._goal_in_reach(pos, goals, rows)
        return np.where(to_goal[:, None], goals, targets)

    def targets(self, pos: FloatArray, rows: IntArray | None = None, cells: IntArray | None = None) -> FloatArray:
        """Where every action takes robots ``rows`` (default all) standing at ``pos`` (in
        ``cells``, when known), shape (k, n_actions, 2)."""
        goal_cells = self.goal_cells if rows is None else self.goal_cells[rows]
        goals = self.goals if rows is None else self.goals[rows]
        dest = (self.cells(pos) if cells is None else cells)[:, None, :] + self.moves[None]
        targets = self.grid.centers(dest)
        to_goal = np.all(dest == goal_cells[:, None, :], axis=2) & self._goal_in_reach(pos, goals, rows)[:, None]
        return np.where(to_goal[..., None], goals[:, None, :], targets)

    def _goal_in_reach(self, pos: FloatArray, goals: FloatArray, rows: IntArray | None) -> NDArray[np.bool_]:
        """A move into the goal cell lands on the exact goal only when the goal is in reach;
        otherwise on the cell's centre first (a goal on a far corner), as the grid controllers do."""
        reach = self.reach if rows is None else self.reach[rows]
        gap = np.linalg.norm(np.asarray(goals, float) - np.asarray(pos, float).reshape(-1, 2), axis=1)
        return gap <= reach * (1 + LENGTH_TOLERANCE) + 1e-12

    def mask(self, pos: FloatArray, cells: IntArray | None = None) -> NDArray[np.bool_]:
        """Actions (n, n_actions) that pass the static grid (free target cell inside the grid,
        no corner cutting) and are within reach; staying is always allowed. Advice only: the
        simulator's checker decides."""
        cells = self.cells(pos) if cells is None else cells
        ok = self.static_ok[cells[:, 1], cells[:, 0]] & self.centre_reach
        # robots off a cell centre, or next to a goal cell whose goal is off its centre, have
        # other distances
        odd = np.flatnonzero(np.any(pos != self.grid.centers(cells), axis=1)
                             | (self.goal_off_centre & (np.max(np.abs(cells - self.goal_cells), axis=1) <= 1)))
        if len(odd):
            dist = np.linalg.norm(self.targets(pos[odd], odd, cells[odd]) - pos[odd, None, :], axis=2)
            ok[odd] = self.static_ok[cells[odd, 1], cells[odd, 0]] & \
                (dist <= self.reach[odd, None] * (1 + LENGTH_TOLERANCE) + 1e-12)
        ok[:, 0] = True
        return ok

    def encode(self, pos: FloatArray, proposed: FloatArray) -> tuple[IntArray, NDArray[np.bool_]]:
        """The action (n,) whose target is each proposed position, and whether it is exactly
        that position. A proposal no action reaches (a robot held off a cell centre, a move
        of two cells, a diagonal with 4-connectivity) gets the action of the nearest target."""
        targets = self.targets(pos)
        proposed = np.asarray(proposed, float)
        same = np.all(targets == proposed[:, None, :], axis=2)
        exact = same.any(axis=1)
        gap = np.linalg.norm(targets - proposed[:, None, :], axis=2)
        gap = np.where(np.isfinite(gap), gap, np.inf)
        actions = np.where(exact, np.argmax(same, axis=1), np.argmin(gap, axis=1))
        return actions.astype(np.int64), exact


class ContinuousActions:
    """Velocities in units of ``max_speed`` (see the module docs) for the robots of ``world``."""

    #: How far (in units in the last place) :meth:`encode` looks around the plain quotient.
    SEARCH_ULPS = 8

    def __init__(self, world: World, goal_snap: float | None = None):
        self.world = world
        self.goals = world.goals
        self.reach = world.max_speeds * world.dt
        self.snap = 0.1 * self.reach if goal_snap is None else np.full(world.n_robots, float(goal_snap))

    def decode(self, pos: FloatArray, actions: FloatArray) -> FloatArray:
        """Proposed positions (n, 2) of velocity ``actions`` (n, 2) taken at ``pos``."""
        v = np.clip(np.asarray(actions, float), -1.0, 1.0)
        norm = np.hypot(v[:, 0], v[:, 1])
        v = np.where((norm > 1 + LENGTH_TOLERANCE)[:, None], v / np.where(norm > 0, norm, 1.0)[:, None], v)
        new = pos + v * self.reach[:, None]
        goal_gap = np.linalg.norm(self.goals - pos, axis=1)
        snap = (np.linalg.norm(new - self.goals, axis=1) <= self.snap) & \
            (goal_gap <= self.reach * (1 + LENGTH_TOLERANCE) + 1e-12)
        return np.where(snap[:, None], self.goals, new)

    def encode(self, pos: FloatArray, proposed: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
        """Velocities (n, 2) that :meth:`decode` turns into the proposed positions, and
        whether exactly (a move longer than the robot's reach, or one stopping within
        ``goal_snap`` of the goal without reaching it, is not reproducible).

        The plain quotient ``(proposed - pos) / reach`` may miss the proposal by a rounding;
        the velocities a few units in the last place around it are tried, per axis."""
        proposed = np.asarray(proposed, float)
        scale = self.reach[:, None]
        base = np.clip((proposed - pos) / scale, -1.0, 1.0)
        base = np.where(np.isfinite(base), base, 0.0)
        # candidates base, base+1ulp, base-1ulp, base+2ulp, ... per component: (n, 2, k)
        up, down = [base], [base]
        for _ in range(self.SEARCH_ULPS):
            up.append(np.nextafter(up[-1], np.inf))
            down.append(np.nextafter(down[-1], -np.inf))
        order = [base] + [c for pair in zip(up[1:], down[1:]) for c in pair]
        cand = np.clip(np.stack(order, axis=-1), -1.0, 1.0)
        hit = (pos[..., None] + cand * scale[..., None]) == proposed[..., None]
        pick = np.where(hit.any(axis=-1), np.argmax(hit, axis=-1), 0)
        actions = np.take_along_axis(cand, pick[..., None], axis=-1)[..., 0]
        exact = np.all(self.decode(pos, actions) == proposed, axis=1)
        return actions, exact
