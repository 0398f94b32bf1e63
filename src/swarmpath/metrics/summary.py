"""The run summary of ``swarmpath run --json``: a frozen :class:`RunSummary` built from a
trajectory (field names of the JSON form are part of the stable command line).

``success`` is honest: every robot at its goal at the end AND no contact of any kind;
``safe`` says the second half alone, and :meth:`RunSummary.verdict` says in words why a run
is not a success, naming the robots whose goals moving obstacles had sealed off
(:mod:`swarmpath.metrics.sealed`): a world no controller could finish as it ended.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping


from swarmpath.metrics.clearance import min_clearance
from swarmpath.metrics.paths import arrival_steps, executed_lengths, first_arrival_steps, waiting_steps
from swarmpath.metrics.sealed import sealed_goals
from swarmpath.sim.collisions import ROBOT_MOVING, ROBOT_ROBOT, ROBOT_STATIC
from swarmpath.sim.progress import distinct_positions
from swarmpath.sim.trajectory import Termination, Trajectory


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


def unfinished_reason(n_robots: int, reached: int, status: str, sealed: int = 0) -> str:
    """The verdict's words for robots away from their goals, e.g. "1 of 2 robots not at their
    goals (deadlock; 1 with its goal sealed off by moving obstacles)"; shared by
    :meth:`RunSummary.verdict` and the command line's printed summary."""
    why = status
    if sealed:
        why += f"; {sealed} with {'its goal' if sealed == 1 else 'their goals'} sealed off by moving obstacles"
    return f"{n_robots - reached} of {n_robots} robots not at their goals ({why})"


@dataclass(frozen=True)
class RobotOutcome:
    """One robot's outcome: executed and planned lengths (world units), the step after which
    it stays at its goal (None if it is not there at the end), the first step it stood there,
    and the steps it stood still away from its goal; with a planner, its plan's status and
    the reason in words (why a robot has no plan: a local minimum, an unreachable goal, ...);
    ``goal_sealed`` when it ended away from its goal and moving obstacles had sealed the goal
    off from it over the run's last steps (:func:`~swarmpath.metrics.sealed.sealed_goals`)."""

    id: str
    reached: bool
    path_length: float
    planned_length: float | None
    arrival_step: int | None
    first_arrival_step: int | None
    waits: int
    plan_status: str | None = None
    plan_reason: str | None = None
    goal_sealed: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {"id": self.id, "reached": self.reached, "path_length": self.path_length,
                "planned_length": self.planned_length, "arrival_step": self.arrival_step,
                "first_arrival_step": self.first_arrival_step, "waits": self.waits,
                "plan_status": self.plan_status, "plan_reason": self.plan_reason,
                "goal_sealed": self.goal_sealed}


@dataclass(frozen=True)
class RunSummary:
    """Everything ``swarmpath run`` reports about one run (see :meth:`to_dict` for the JSON)."""

    scenario: str
    planner: str | None
    controller: str | None
    seed: int
    status: Termination
    steps: int
    reached: int
    reached_once: int
    n_robots: int
    collisions: Mapping[str, int]
    deadlocks: int
    invalid_moves: int
    sum_of_lengths: float
    makespan: int | None
    sum_of_arrival_steps: int | None
    min_clearance: float | None
    planning_time_s: float
    sim_time_s: float
    robots: tuple[RobotOutcome, ...] = field(default_factory=tuple)
    sealed_goals: int = 0

    @property
    def contacts(self) -> int:
        """Contacts of all kinds."""
        return int(sum(self.collisions.values()))

    @property
    def safe(self) -> bool:
        """No contact of any kind happened."""
        return self.contacts == 0

    @property
    def all_reached(self) -> bool:
        """Every robot stands on its goal at the end."""
        return self.reached == self.n_robots

    @property
    def success(self) -> bool:
        """Every robot at its goal at the end AND zero contacts."""
        return self.all_reached and self.safe

    def verdict(self) -> str:
        """"success", or why not, in words ("3 of 12 robots not at their goals; 2 contacts")."""
        if self.success:
            return "success"
        reasons = []
        if not self.all_reached:
            reasons.append(unfinished_reason(self.n_robots, self.reached, self.status.value, self.sealed_goals))
        if not self.safe:
            reasons.append(f"{self.contacts} contact{'s' if self.contacts != 1 else ''}")
        return "; ".join(reasons)

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of ``swarmpath run --json``."""
        return {
            "scenario": self.scenario, "planner": self.planner, "controller": self.controller, "seed": self.seed,
            "success": self.success, "safe": self.safe, "status": self.status.value, "steps": self.steps,
            "makespan": self.makespan, "sum_of_lengths": self.sum_of_lengths,
            "sum_of_arrival_steps": self.sum_of_arrival_steps, "reached": self.reached,
            "reached_once": self.reached_once, "n_robots": self.n_robots, "collisions": dict(self.collisions),
            "deadlocks": self.deadlocks, "invalid_moves": self.invalid_moves, "min_clearance": self.min_clearance,
            "planning_time_s": self.planning_time_s, "sim_time_s": self.sim_time_s,
            "sealed_goals": self.sealed_goals, "robots": [r.to_dict() for r in self.robots],
        }


def run_summary(world, traj: Trajectory, plan=None, *, planner: str | None = None, controller: str | None = None,
                planning_time_s: float = 0.0, clearance: bool = True) -> RunSummary:
    """The summary of one run of ``world`` recorded in ``traj`` (with its offline ``plan``)."""
    lengths = executed_lengths(traj.positions)
    arrivals = arrival_steps(traj.positions, traj.goals)
    waits = waiting_steps(traj.positions, traj.goals)
    reached = [a is not None for a in arrivals]
    first = first_arrival_steps(traj.positions, traj.goals)
    sealed = set(sealed_goals(world, traj)) if not all(reached) else set()
    robots = []
    for i, rid in enumerate(traj.robot_ids):
        planned = status = reason = None
        if plan is not None and i < len(plan.robots):
            rp = plan.robots[i]
            planned, status, reason = rp.length, rp.status.value, rp.reason
        robots.append(RobotOutcome(rid, reached[i], float(lengths[i]), planned, arrivals[i], first[i], int(waits[i]),
                                   status, reason, i in sealed))
    everyone = all(reached)
    clearance_value = None
    if clearance and traj.n_robots:
        clearance_value = float(min_clearance(world, traj.positions, traj.obstacle_positions))
    return RunSummary(
        scenario=traj.scenario, planner=planner, controller=controller, seed=traj.seed, status=traj.status,
        steps=traj.n_steps, reached=int(sum(reached)), reached_once=sum(f is not None for f in first),
        n_robots=len(reached), collisions=collisions_by_kind(traj), deadlocks=len(deadlocked_robots(traj)),
        invalid_moves=sum(1 for e in traj.events if e.get("kind") == "invalid_move"),
        sum_of_lengths=float(lengths.sum()),
        makespan=max((a for a in arrivals if a is not None), default=0) if everyone else None,
        sum_of_arrival_steps=int(sum(a for a in arrivals if a is not None)) if everyone else None,
        min_clearance=clearance_value, planning_time_s=float(planning_time_s),
        sim_time_s=float(traj.meta.get("sim_time_s", 0.0)), robots=tuple(robots), sealed_goals=len(sealed))
