"""Validate timed multi-robot plans (``RobotPlan.times``), independently of any planner.

A timed plan puts robot i on ``path[k]`` at step ``times[k]``; between two of its times the
robot stays on the earlier vertex and moves to the next one in the step that reaches the
later time (as the ``follow`` controller executes it); after its last time it stays on its
goal. :func:`validate_timed_plan` expands every robot to one position per step and checks:

- the plan has one robot plan per robot, a path for each (unless ``require_all=False``),
  times that are non-decreasing integers starting at 0, one per vertex;
- each path starts on the robot's start and ends on its goal;
- no step is longer than the robot's ``max_speed * dt``, and no step enters a static
  obstacle or leaves the workspace (``World.static_hits``: exact geometry with the robot's
  radius; for point robots on raster maps this also forbids cutting a blocked cell's corner);
- no two robots' moves of one step conflict by the checker's rule
  (:func:`swarmpath.world.move_rules.move_conflicts`: same cell, swap, crossing, or discs
  closer than the sum of their radii at any time of the step).

Nothing here trusts the planner; it shares only the move rules with the simulator.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.testing.validators import Violation
from swarmpath.world.move_rules import KIND_NAMES, move_conflicts

FloatArray = NDArray[np.float64]


def _check_times(i: int, path: FloatArray, times) -> tuple[NDArray[np.int64] | None, list[Violation]]:
    if times is None:
        return None, [Violation(i, "times", "the plan is not timed (times is None)")]
    t = np.asarray(times)
    if t.shape != (len(path),):
        return None, [Violation(i, "times", f"shape {t.shape} does not match {len(path)} path vertices")]
    if not np.all(np.equal(np.mod(t, 1), 0)) or (len(t) and t[0] != 0) or np.any(np.diff(t) < 0):
        return None, [Violation(i, "times", "must be non-decreasing whole numbers starting at 0")]
    return t.astype(np.int64), []


def expand_timed_paths(paths: list[FloatArray], times: list[NDArray[np.int64]], horizon: int) -> FloatArray:
    """Positions (horizon + 1, n, 2) of every robot at every step: the vertex whose time is
    the latest not after the step (the goal once the plan ends)."""
    steps = np.arange(horizon + 1)
    out = np.empty((horizon + 1, len(paths), 2))
    for i, (p, t) in enumerate(zip(paths, times)):
        k = np.searchsorted(t, steps, side="right") - 1
        out[:, i] = p[np.clip(k, 0, len(p) - 1)]
    return out


def validate_timed_plan(world, plan, *, require_all: bool = True, tolerance: float = 1e-6) -> list[Violation]:
    """Every violation of the timed ``plan`` (a :class:`~swarmpath.planning.base.Plan`) in
    ``world``; an empty list means the plan is valid. Robots without a path are violations
    when ``require_all`` (otherwise they are left out of every check)."""
    out: list[Violation] = []
    robots = world.robots
    if len(plan.robots) != len(robots):
        return [Violation(-1, "plan", f"{len(plan.robots)} robot plans for {len(robots)} robots")]
    keep, paths, times = [], [], []
    for i, (robot, rp) in enumerate(zip(robots, plan.robots)):
        if rp.path is None:
            if require_all:
                out.append(Violation(i, "path", f"no path ({rp.status.value})"))
            continue
        p = np.asarray(rp.path, float)
        if p.ndim != 2 or p.shape[1] != 2 or len(p) == 0 or not np.all(np.isfinite(p)):
            out.append(Violation(i, "path", f"must be finite with shape (n_points, 2), got {p.shape}"))
            continue
        t, bad = _check_times(i, p, rp.times)
        if bad:
            out.extend(bad)
            continue
        if np.linalg.norm(p[0] - robot.start) > tolerance:
            out.append(Violation(i, "path[0]", f"{p[0].tolist()} is not the start {list(robot.start)}"))
        if np.linalg.norm(p[-1] - robot.goal) > tolerance:
            out.append(Violation(i, f"path[{len(p) - 1}]", f"{p[-1].tolist()} is not the goal {list(robot.goal)}"))
        keep.append(i)
        paths.append(p)
        times.append(t)
    if not keep:
        return out
    horizon = int(max(t[-1] for t in times))
    pos = expand_timed_paths(paths, times, horizon)          # (T + 1, k, 2)
    idx = np.asarray(keep)
    radii = world.radii[idx]
    reach = world.max_speeds[idx] * world.dt * (1 + 1e-9) + 1e-12
    step_len = np.linalg.norm(np.diff(pos, axis=0), axis=2)    # (T, k)
    for t, r in np.argwhere(step_len > reach[None]):
        out.append(Violation(int(idx[r]), f"step {t + 1}", f"moves {step_len[t, r]:.6g} > max {reach[r]:.6g}"))
    moved = np.argwhere(step_len > 0)
    if len(moved):
        a = pos[moved[:, 0], moved[:, 1]]
        b = pos[moved[:, 0] + 1, moved[:, 1]]
        hits = world.static_hits(a, b, radii[moved[:, 1]])
        for (t, r) in moved[hits]:
            out.append(Violation(int(idx[r]), f"step {t + 1}", f"{pos[t, r].tolist()} -> {pos[t + 1, r].tolist()} "
                                                              "enters a static obstacle or leaves the workspace"))
    if len(keep) > 1:
        span = 2 * float(step_len.max(initial=0.0)) + 2 * float(radii.max(initial=0.0)) + 2 * world.resolution
        for t in range(horizon):
            pairs = cKDTree(pos[t]).query_pairs(span, output_type="ndarray")
            if len(pairs) == 0:
                continue
            i, j = pairs[:, 0], pairs[:, 1]
            kind = move_conflicts(pos[t, i], pos[t + 1, i], pos[t, j], pos[t + 1, j], radii[i], radii[j],
                                  world.resolution)
            for k in np.flatnonzero(kind):
                a, b = sorted((int(idx[i[k]]), int(idx[j[k]])))
                out.append(Violation(a, f"step {t + 1}", f"{KIND_NAMES[kind[k]]} conflict with robot {b}"))
    return out
