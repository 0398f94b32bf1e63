"""Finishing together: the step on which every robot stands on its goal at once.

A run succeeds at the end of the first step on which every robot stands on its goal (the
simulator stops there, status ``all_reached``). Among moving obstacles that never stop, a
cautious robot does not stand on a goal that an obstacle may enter next step: it waits beside
it, and some goal is nearly always under such a threat, so the robots are rarely all home at
the same moment.

The last step of a run can be checked exactly, because in a step the obstacles move first and
then stand still while the robots move (the checker's phase 2): when every robot that is not
home can step straight onto its goal in this step, and those moves touch no static obstacle,
no obstacle where it now stands, and no other robot by :mod:`swarmpath.world.move_rules`,
the robots all step home and the run ends with zero contacts. The moves the obstacles may make
after the run are not part of it: a controller that must keep robots on their goals for ever
after (rather than deliver them) should leave this off.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.control.base import Decision
from swarmpath.control.cornered import move_weights
from swarmpath.control.hazards import safe_tier
from swarmpath.control.observation import Observation
from swarmpath.world.move_rules import GRID_MOVES, NO_CONFLICT, footprint_hits, move_conflicts
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]


def off_centre_discs(world: World, goal_centres: FloatArray) -> NDArray[np.bool_]:
    """Disc robots whose exact goal lies off its cell's centre (``goal_centres`` (n, 2)).
    Resting off the centre, a disc reaches into the next cells, where the centre-to-centre
    move rules of its neighbours do not see it, and a neighbour whose move it would graze is
    held back step after step (a deadlock). So while other robots are near (:func:`held_discs`)
    such a robot waits on its goal cell's centre; the finishing step or a quiet moment takes
    it onto the goal."""
    return (world.radii > 0) & (np.linalg.norm(world.goals - goal_centres, axis=1) > 1e-9)


#: A robot resting off its cell's centre can be grazed only by robots whose moves start within
#: this many cells (Chebyshev) of its cell: moves are one cell long.
HOLD_REACH = 2


def held_discs(hold: NDArray[np.bool_], cells: NDArray[np.int64], goal_cells: NDArray[np.int64],
               shape: tuple[int, int]) -> NDArray[np.bool_]:
    """The robots of ``hold`` (n,) (:func:`off_centre_discs`) that wait on their goal cell's
    centre this step: another robot is within ``HOLD_REACH`` cells of them (``cells`` (n, 2),
    x and y, on a grid of ``shape`` (height, width)), and not every robot is in its goal cell
    (then each goes home; no one passes any more)."""
    out = np.asarray(hold, bool).copy()
    if not out.any() or np.all(cells == goal_cells):
        return np.zeros_like(out)
    h, w = shape
    c = np.clip(np.asarray(cells, np.int64), 0, [w - 1, h - 1])
    count = np.zeros((h + 1, w + 1), np.int64)
    np.add.at(count, (c[:, 1] + 1, c[:, 0] + 1), 1)
    table = count.cumsum(0).cumsum(1)
    rows = np.flatnonzero(out)
    x0 = np.clip(c[rows, 0] - HOLD_REACH, 0, w)
    x1 = np.clip(c[rows, 0] + HOLD_REACH + 1, 0, w)
    y0 = np.clip(c[rows, 1] - HOLD_REACH, 0, h)
    y1 = np.clip(c[rows, 1] + HOLD_REACH + 1, 0, h)
    near = table[y1, x1] - table[y0, x1] - table[y1, x0] + table[y0, x0]
    out[rows] = near > 1          # itself and at least one other
    return out


def waiting_home(at_goal: NDArray[np.bool_], holding: NDArray[np.bool_], in_goal_cell: NDArray[np.bool_],
                 pos: FloatArray, centres: FloatArray) -> NDArray[np.bool_]:
    """The robots that count as home (n,): on their goals (``at_goal``), or held
    (:func:`held_discs`) and waiting on their goal cell's centre (``centres`` (n, 2), the
    centres of the robots' cells)."""
    return at_goal | (holding & in_goal_cell & (np.abs(pos - centres).max(axis=1) <= 1e-9))


def finish_positions(world: World, obs: Observation) -> FloatArray | None:
    """Every robot's goal (n, 2) when all robots can end this step on their goals without any
    contact of the robots' move (phase 2 of the step, the simulator's own rules); else None.

    The move of each robot must be within its reach (``max_speed * dt``), touch no static
    obstacle or the workspace's edge, enter no moving obstacle's footprint where it stands now
    (``obs.obstacle_positions``), and conflict with no other robot's move.
    """
    pos = obs.positions
    goals = world.goals
    n = len(pos)
    if n == 0:
        return None
    step = goals - pos
    length = np.linalg.norm(step, axis=1)
    if np.any(length > world.max_speeds * world.dt):
        return None
    moving = np.flatnonzero(length > 0)
    if not len(moving):
        return None
    radii = world.radii
    if world.static_hits(pos[moving], goals[moving], radii[moving]).any():
        return None
    for k, ob in enumerate(world.moving_obstacles):
        centre = obs.obstacle_positions[k]
        near = np.flatnonzero(np.linalg.norm(goals[moving] - centre, axis=1)
                              <= ob.extent + radii[moving] + length[moving] + 1e-9)
        if len(near):
            rows = moving[near]
            if footprint_hits(ob.placed((0.0, 0.0)), pos[rows] - centre, goals[rows] - centre, radii[rows]).any():
                return None
    if n > 1:
        reach = 2 * float(length.max()) + 2 * float(radii.max(initial=0.0)) + 2 * world.resolution
        pairs = cKDTree(pos).query_pairs(reach, output_type="ndarray")
        if len(pairs):
            i, j = pairs[:, 0], pairs[:, 1]
            kinds = move_conflicts(pos[i], goals[i], pos[j], goals[j], radii[i], radii[j], world.resolution)
            if np.any(kinds != NO_CONFLICT):
                return None
    return goals.copy()


def finishing_step(world: World, obs: Observation) -> Decision | None:
    """The Decision of the finishing step (every robot to its goal, an event naming how many
    robots stepped home together) when :func:`finish_positions` allows it this step; else
    None and the controller acts as usual."""
    home = finish_positions(world, obs)
    if home is None:
        return None
    moved = int(np.count_nonzero(np.any(home != obs.positions, axis=1)))
    return Decision(home, ["arrived"] * len(home),
                    [{"robot": -1, "kind": "finish_together", "detail": f"{moved} robots stepped onto their goals"}])


#: Chance, at least, that a gathering step leads to the finishing step (see :func:`gathering_positions`).
GATHER_CHANCE = 0.5
#: A robot gathers only onto cells from which it can keep clear of every obstacle for this many
#: steps whatever they do (the look-ahead tiers of :mod:`swarmpath.control.hazards`).
GATHER_TIER = 2


def gathering_positions(world: World, obs: Observation, forecast, grid, moves: NDArray[np.bool_], *,
                        depth: int = 3, min_tier: int = GATHER_TIER, min_chance: float = GATHER_CHANCE
                        ) -> tuple[FloatArray, float] | None:
    """A step that sets up the finishing step: every robot moves (or stays) onto a cell one move
    from its goal, so that next step all can step home together; or None.

    The finishing step (:func:`finish_positions`) needs every robot within one move of its
    goal at one moment. Robots keep clear of obstacles that linger near goals, so when all are
    within two cells of their goals, the moment is often missed for tens of steps, in which
    every waiting robot stays exposed. This step makes the moment happen: it is taken when

    - every robot is within two cells (Chebyshev) of its goal cell, on a cell centre or on its
      goal;
    - every robot has a cell one move from its goal (or its goal) that it can reach this step
      without crossing an obstacle where it stands now, from which it can keep clear of every
      obstacle for ``min_tier`` steps whatever they do (the look-ahead tiers, up to
      ``depth``: the deepest tier is preferred, then staying, then the goal itself), and whose
      move home is within reach and touches nothing static;
    - the moves now and the moves home next step conflict with no other robot's (the
      checker's rules), and
    - the chance that no obstacle stands on a move home next step, from the obstacles' motion
      models (:func:`~swarmpath.control.cornered.move_weights`, independent obstacles), is at
      least ``min_chance``.

    Returns (positions (n, 2), that chance). No robot ends the step where an obstacle may be
    next step, so a gathering step that does not lead to the finish costs no contact; the
    controller then carries on from there.
    """
    pos = obs.positions
    goals = world.goals
    n = len(pos)
    if n == 0 or forecast is None or forecast.m == 0:
        return None
    h, w = grid.blocked.shape
    cells = np.clip(grid.cell_of(pos), 0, [w - 1, h - 1])
    goal_cells = np.clip(grid.cell_of(goals), 0, [w - 1, h - 1])
    if np.any(np.abs(cells - goal_cells).max(axis=1) > 2):
        return None
    home = np.linalg.norm(pos - goals, axis=1) <= 1e-9
    centred = np.linalg.norm(pos - grid.centers(cells), axis=1) <= 1e-9
    if not np.all(home | centred):
        return None
    covered = forecast.coverage(obs.obstacle_positions, obs.obstacle_previous, depth)
    tier = np.zeros((h, w), np.int64)
    for d in range(depth, 0, -1):
        safe = safe_tier(covered, moves, d, forecast.robot_radius == 0)[0] if d > 1 else ~covered[0]
        tier = np.where((tier == 0) & safe, d, tier)
    dest = cells[:, None, :] + GRID_MOVES[None]                                     # (n, 9, 2)
    dx, dy = np.clip(dest[..., 0], 0, w - 1), np.clip(dest[..., 1], 0, h - 1)
    ok = moves[cells[:, 1], cells[:, 0]].copy()
    ok &= tier[dy, dx] >= min_tier
    targets = grid.centers(dest)
    to_goal = np.all(dest == goal_cells[:, None, :], axis=2)
    targets = np.where(to_goal[..., None], goals[:, None, :], targets)
    targets[:, 0] = pos                                                             # staying is staying
    reach = (world.max_speeds * world.dt)[:, None] * (1 + 1e-9) + 1e-12
    ok &= np.linalg.norm(targets - pos[:, None, :], axis=2) <= reach
    ok &= np.linalg.norm(goals[:, None, :] - targets, axis=2) <= reach
    flat_t = targets.reshape(-1, 2)
    flat_g = np.repeat(goals, 9, axis=0)
    radii = world.radii
    ok &= ~world.static_hits(flat_t, flat_g, np.repeat(radii, 9)).reshape(n, 9)
    ok &= ~forecast.crossings(pos, targets, obs.obstacle_positions)
    # a cell speaks for its centre only: a robot resting off it is checked where it rests
    ok &= ~forecast.off_centre_hits(targets, grid.centers(dest), obs.obstacle_positions, obs.obstacle_previous)
    if not ok.any(axis=1).all():
        return None
    # one cell each, the most constrained robot first; moves now must not conflict
    rank = np.where(ok, -10 * tier[dy, dx] - 2 * (np.arange(9) == 0) - to_goal, np.iinfo(np.int64).max)
    choice = np.full(n, -1)
    res = world.resolution
    for i in np.argsort(ok.sum(axis=1), kind="stable"):
        done = np.flatnonzero(choice >= 0)
        done = done[np.abs(cells[done] - cells[i]).max(axis=1) <= 2]
        for a in np.argsort(rank[i], kind="stable"):
            if not ok[i, a]:
                break
            if len(done) and np.any(move_conflicts(pos[i], targets[i, a], pos[done], targets[done, choice[done]],
                                                   radii[i], radii[done], res) != NO_CONFLICT):
                continue
            choice[i] = a
            break
        if choice[i] < 0:
            return None
    mid = targets[np.arange(n), choice]
    span = 2 * float(np.max(world.max_speeds * world.dt)) + 2 * float(radii.max(initial=0.0)) + 2 * res
    for a, b in ((pos, mid), (mid, goals)):
        pairs = cKDTree(a).query_pairs(span, output_type="ndarray")
        if len(pairs):
            i, j = pairs[:, 0], pairs[:, 1]
            if np.any(move_conflicts(a[i], b[i], a[j], b[j], radii[i], radii[j], res) != NO_CONFLICT):
                return None
    # the chance that no obstacle stands on a move home next step
    p = np.asarray(obs.obstacle_positions, float).reshape(forecast.m, 2)
    cand, possible, extra = forecast.next_positions(p, obs.obstacle_previous)
    weight = move_weights(possible, extra)
    going = np.flatnonzero(np.any(mid != goals, axis=1))
    clear = 1.0
    for j, ob in enumerate(world.moving_obstacles):
        shape = ob.placed((0.0, 0.0))
        blocked = 0.0
        for s in np.flatnonzero(weight[j] > 0):
            c = cand[j, s]
            near = going[np.linalg.norm(goals[going] - c, axis=1)
                         <= ob.extent + extra[j] + radii[going] + np.linalg.norm(goals[going] - mid[going], axis=1) + 1e-9]
            if not len(near):
                continue
            if extra[j] > 0 or footprint_hits(shape, mid[near] - c, goals[near] - c, radii[near]).any():
                blocked += weight[j, s]
        clear *= 1.0 - min(blocked, 1.0)
        if clear < min_chance:
            return None
    return mid, clear


def gathering_step(world: World, obs: Observation, forecast, grid, moves: NDArray[np.bool_], depth: int
                   ) -> Decision | None:
    """The Decision of a gathering step (:func:`gathering_positions`, look-ahead tiers up to
    ``depth``) with an event giving the chance that it leads to the finish, or None."""
    found = gathering_positions(world, obs, forecast, grid, moves, depth=depth)
    if found is None:
        return None
    mid, chance = found
    moved = int(np.count_nonzero(np.any(mid != obs.positions, axis=1)))
    return Decision(mid, ["gather"] * len(mid),
                    [{"robot": -1, "kind": "gather", "detail": f"{moved} robots moved within one move of their "
                                                              f"goals; chance of finishing next step {chance:.2f}"}])
