"""Public validators: check any plan or trajectory against the world, geometry only.

They return lists of violations (empty = valid) rather than a bool, so a failing test or a
user's plug-in check says exactly what went wrong. Nothing here trusts the planner, the
controller or the simulator that produced the data: trajectories are re-checked from their
recorded positions with the same geometric rules (:mod:`swarmpath.sim.collisions`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from swarmpath.errors import ConfigError
from swarmpath.sim.collisions import step_contacts
from swarmpath.world.world import World


def _check_world(world: object) -> None:
    if not isinstance(world, World):
        raise ConfigError(f"a validator needs a World, got {type(world).__name__}")


@dataclass(frozen=True)
class Violation:
    """One problem: which robot (index; -1 for the whole result), where (point or step), what."""

    robot: int
    where: str
    problem: str

    def __str__(self) -> str:
        who = f"robot {self.robot}" if self.robot >= 0 else "result"
        return f"{who}: {self.where}: {self.problem}"


def validate_paths(world, paths: Sequence[ArrayLike | None], *, require_all: bool = True,
                   goal_tolerance: float = 1e-6) -> list[Violation]:
    """Check one polyline per robot (shape (n_points, 2)): it starts at the robot's start,
    ends at its goal, and no segment enters a static obstacle or leaves the workspace
    (for the robot's radius). ``None`` is a violation when ``require_all``."""
    out: list[Violation] = []
    _check_world(world)
    if isinstance(paths, (str, bytes)) or not hasattr(paths, "__len__"):
        raise ConfigError(f"paths must be a sequence of one path per robot, got {type(paths).__name__}")
    if len(paths) != world.n_robots:
        return [Violation(-1, "paths", f"{len(paths)} paths for {world.n_robots} robots")]
    for i, (robot, path) in enumerate(zip(world.robots, paths)):
        if path is None:
            if require_all:
                out.append(Violation(i, "path", "no path"))
            continue
        try:
            p = np.asarray(path, dtype=float)
        except (TypeError, ValueError):
            out.append(Violation(i, "path", "is not an array of (x, y) points"))
            continue
        if p.ndim != 2 or p.shape[1] != 2 or len(p) < 1:
            out.append(Violation(i, "path", f"must have shape (n_points, 2), got {p.shape}"))
            continue
        if not np.all(np.isfinite(p)):
            out.append(Violation(i, "path", "contains non-finite numbers"))
            continue
        if np.linalg.norm(p[0] - robot.start) > goal_tolerance:
            out.append(Violation(i, "path[0]", f"{p[0].tolist()} is not the start {list(robot.start)}"))
        if np.linalg.norm(p[-1] - robot.goal) > goal_tolerance:
            out.append(Violation(i, f"path[{len(p) - 1}]", f"{p[-1].tolist()} is not the goal {list(robot.goal)}"))
        if len(p) > 1:
            hits = world.static_hits(p[:-1], p[1:], np.full(len(p) - 1, robot.radius))
            for k in np.flatnonzero(hits):
                out.append(Violation(i, f"segment {k}", f"{p[k].tolist()} -> {p[k + 1].tolist()} enters a static "
                                                        "obstacle or leaves the workspace"))
    return out


def validate_trajectory(world, traj) -> list[Violation]:
    """Re-check a recorded trajectory: starts match, no step exceeds a robot's speed, and no
    contact of any kind (robot-robot, robot-static, robot-moving) happened at any step."""
    out: list[Violation] = []
    _check_world(world)
    try:
        pos = np.asarray(traj.positions, float)
        obs = np.asarray(traj.obstacle_positions, float)
    except (AttributeError, TypeError, ValueError):
        raise ConfigError(f"validate_trajectory needs a Trajectory, got {type(traj).__name__}") from None
    if pos.ndim != 3 or pos.shape[1:] != (world.n_robots, 2) or pos.shape[0] < 1:
        return [Violation(-1, "positions", f"shape {pos.shape} does not fit {world.n_robots} robots")]
    if obs.shape != (pos.shape[0], len(world.moving_obstacles), 2):
        return [Violation(-1, "obstacle_positions", f"shape {obs.shape} does not fit "
                                                    f"{len(world.moving_obstacles)} obstacles")]
    bad = np.argwhere(~np.all(np.isfinite(pos), axis=2))
    if len(bad):
        return [Violation(int(i), f"step {int(t)}", "position is not a finite number") for t, i in bad[:20]]
    if not np.allclose(pos[0], world.starts):
        out.append(Violation(-1, "step 0", "positions do not start at the robots' starts"))
    steps = np.linalg.norm(np.diff(pos, axis=0), axis=2)
    limit = world.max_speeds * world.dt * (1 + 1e-9) + 1e-12
    for t, i in np.argwhere(steps > limit[None]):
        out.append(Violation(int(i), f"step {t + 1}", f"moved {steps[t, i]:.6g} > max {limit[i]:.6g}"))
    for t in range(1, pos.shape[0]):
        for c in step_contacts(world, t, pos[t - 1], pos[t], obs[t - 1], obs[t]):
            other = "" if c.other < 0 else f" with {'robot' if c.kind == 'robot_robot' else 'obstacle'} {c.other}"
            out.append(Violation(c.robot, f"step {t}", f"{c.kind} contact{other} ({c.detail})"))
    return out
