"""The run summary of ``swarmpath run --json`` (field names fixed by DESIGN.md)."""
from __future__ import annotations

from typing import Any


from swarmpath.metrics.clearance import min_clearance
from swarmpath.metrics.paths import arrival_steps, executed_lengths, first_arrival_steps, waiting_steps
from swarmpath.sim.collisions import ROBOT_MOVING, ROBOT_ROBOT, ROBOT_STATIC
from swarmpath.sim.simulator import distinct_positions
from swarmpath.sim.trajectory import Trajectory


def collisions_by_kind(traj: Trajectory) -> dict[str, int]:
    """Number of contacts of each kind."""
    out = {ROBOT_ROBOT: 0, ROBOT_STATIC: 0, ROBOT_MOVING: 0}
    for c in traj.contacts:
        out[c.kind] += 1
    return out


def deadlocked_robots(traj: Trajectory, window: int = 60) -> list[int]:
    """Robots not at their goal at the end that visited at most two positions in the last
    ``window`` steps (stuck, or oscillating between two cells)."""
    arrival = arrival_steps(traj.positions, traj.goals)
    unfinished = [i for i, a in enumerate(arrival) if a is None]
    if not unfinished or traj.n_steps < 2:
        return []
    tail = traj.positions[-min(window, traj.n_steps + 1):, unfinished]
    counts = distinct_positions(tail)
    return [i for i, c in zip(unfinished, counts) if c <= 2]


def run_summary(world, traj: Trajectory, plan=None, *, planner: str | None = None, controller: str | None = None,
                planning_time_s: float = 0.0, clearance: bool = True) -> dict[str, Any]:
    """The JSON-ready summary of one run."""
    lengths = executed_lengths(traj.positions)
    arrivals = arrival_steps(traj.positions, traj.goals)
    waits = waiting_steps(traj.positions, traj.goals)
    reached = [a is not None for a in arrivals]
    first = first_arrival_steps(traj.positions, traj.goals)
    robots = []
    for i, rid in enumerate(traj.robot_ids):
        planned = None
        if plan is not None and i < len(plan.robots):
            planned = plan.robots[i].length
        robots.append({"id": rid, "reached": reached[i], "path_length": float(lengths[i]),
                       "planned_length": planned, "arrival_step": arrivals[i], "first_arrival_step": first[i],
                       "waits": int(waits[i])})
    success = all(reached)
    collisions = collisions_by_kind(traj)
    return {
        "scenario": traj.scenario, "planner": planner, "controller": controller, "seed": traj.seed,
        "success": bool(success), "status": traj.status, "steps": traj.n_steps,
        "makespan": max((a for a in arrivals if a is not None), default=0) if success else None,
        "sum_of_lengths": float(lengths.sum()),
        "sum_of_arrival_steps": int(sum(a for a in arrivals if a is not None)) if success else None,
        "reached": int(sum(reached)), "reached_once": sum(f is not None for f in first), "n_robots": len(reached),
        "collisions": collisions, "deadlocks": len(deadlocked_robots(traj)),
        "invalid_moves": sum(1 for e in traj.events if e.get("kind") == "invalid_move"),
        "min_clearance": float(min_clearance(world, traj.positions, traj.obstacle_positions)) if clearance else None,
        "planning_time_s": float(planning_time_s), "sim_time_s": float(traj.meta.get("sim_time_s", 0.0)),
        "robots": robots,
    }
