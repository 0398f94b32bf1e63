"""Paper-pure next to improved: outcomes of online runs, side by side and as an ablation
ladder.

A *ladder* starts from a paper's method exactly as printed (the paper-pure variant, rung 0)
and adds our additions one at a time, each rung on top of the one before, up to the
improved default. Every rung runs on the same world and seeds, so a column shows what one
addition changes. The rungs are data (:class:`Rung`): when an improved controller changes,
its paper's ladder is edited in one place and the tables are generated again.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from swarmpath.bench.formatting import fmt, table
from swarmpath.bench.progress import Progress
from swarmpath.bench.runner import Batch, run_batch
from swarmpath.control.base import Controller
from swarmpath.metrics.summary import RunSummary, run_summary
from swarmpath.planning.base import Plan
from swarmpath.sim.collisions import ROBOT_MOVING, ROBOT_ROBOT, ROBOT_STATIC
from swarmpath.sim.trajectory import DEADLOCK, Trajectory
from swarmpath.world.world import World


@dataclass(frozen=True)
class Rung:
    """One rung: the ``addition`` it makes (rung 0: the paper-pure variant), what that
    ``fixes``, the controller of its runs and, when the addition is in the world (a motion
    model), the world to run."""

    addition: str
    fixes: str
    controller: Callable[[], Controller]
    world: World | None = None


@dataclass(frozen=True)
class Outcome:
    """What the runs of one configuration gave (one entry per seed).

    success : every robot at its goal at the end and no contact (``RunSummary.success``)
    reached : every robot at its goal at the end
    contacts : (n_runs, 3) contacts per run: robot-robot, robot-moving, robot-static
    deadlocked : robots stuck away from their goals at the end, per run
    steps, lengths : steps of the run and the sum of executed lengths (world units)
    """

    label: str
    success: np.ndarray
    reached: np.ndarray
    contacts: np.ndarray
    deadlocked: np.ndarray
    stopped: np.ndarray
    steps: np.ndarray
    lengths: np.ndarray

    @property
    def n_runs(self) -> int:
        return len(self.success)

    @property
    def runs_with_contact(self) -> int:
        return int(np.sum(self.contacts.sum(axis=1) > 0))

    @property
    def runs_with_deadlock(self) -> int:
        """Runs that ended with a robot stuck (reported by the summary or the simulator)."""
        return int(np.sum((self.deadlocked > 0) | self.stopped))

    def contact_cell(self) -> str:
        """"total (robot-robot / robot-moving / robot-static)" over all runs."""
        c = self.contacts.sum(axis=0)
        return f"{int(c.sum())} ({int(c[0])} / {int(c[1])} / {int(c[2])})"


def summarise(world: World, plan: Plan | None) -> Callable[[Trajectory, float], RunSummary]:
    """The measure of a run for :func:`~swarmpath.bench.runner.run_batch`: its summary."""
    return lambda traj, _cpu: run_summary(world, traj, plan, clearance=False)


def outcome(label: str, batch: Batch[RunSummary]) -> Outcome:
    """The :class:`Outcome` of a batch of run summaries."""
    return outcome_of(label, batch.records)


def outcome_of(label: str, s: Sequence[RunSummary]) -> Outcome:
    """The :class:`Outcome` of run summaries (one per seed)."""
    kinds = (ROBOT_ROBOT, ROBOT_MOVING, ROBOT_STATIC)
    return Outcome(label, np.array([r.success for r in s], bool), np.array([r.all_reached for r in s], bool),
                   np.array([[r.collisions[k] for k in kinds] for r in s], np.int64).reshape(-1, 3),
                   np.array([r.deadlocks for r in s], np.int64), np.array([r.status == DEADLOCK for r in s], bool),
                   np.array([r.steps for r in s], float), np.array([r.sum_of_lengths for r in s], float))


def merge_outcomes(label: str, parts: Sequence[Outcome]) -> Outcome:
    """One :class:`Outcome` holding the runs of several (e.g. several robot counts)."""
    return Outcome(label, *(np.concatenate([getattr(p, f) for p in parts]) for f in
                            ("success", "reached", "contacts", "deadlocked", "stopped", "steps", "lengths")))


def run_outcome(label: str, world: World, controller: Callable[[], Controller], seeds: Sequence[int], *,
                plan: Plan | None = None, progress: Progress | None = None, keep: int = 0,
                ) -> tuple[Outcome, tuple[Trajectory, ...]]:
    """Run one configuration over ``seeds``; its :class:`Outcome` and the kept trajectories."""
    if progress is not None:
        progress.stage(label, len(seeds))
    batch = run_batch(world, controller, seeds, summarise(world, plan), plan=plan, label=label, keep=keep,
                      progress=progress)
    return outcome(label, batch), batch.kept


def run_ladder(world: World, rungs: Sequence[Rung], seeds: Sequence[int], *, plan: Plan | None = None,
               progress: Progress | None = None) -> list[Outcome]:
    """Every rung over ``seeds`` (same world and plan unless the rung brings its world)."""
    return [run_outcome(f"ladder: {r.addition}", r.world or world, r.controller, seeds, plan=plan,
                        progress=progress)[0] for r in rungs]


HEADER = ("runs ending with every robot at its goal and no contact", "runs with a contact",
          "contacts (robot-robot / robot-moving / robot-static)", "runs ending in a deadlock",
          "steps (median)", "sum of lengths (mean)")


def _cells(o: Outcome) -> list[str]:
    return [f"{int(o.success.sum())}/{o.n_runs}", f"{o.runs_with_contact}/{o.n_runs}", o.contact_cell(),
            f"{o.runs_with_deadlock}/{o.n_runs}", fmt(float(np.median(o.steps)), 0),
            fmt(float(np.mean(o.lengths)), 2)]


def ladder_table(rungs: Sequence[Rung], outcomes: Sequence[Outcome]) -> list[str]:
    """The ladder as a Markdown table: one row per rung, cumulative from the paper."""
    rows = []
    for k, (r, o) in enumerate(zip(rungs, outcomes)):
        rows.append([str(k), r.addition if k == 0 else f"+ {r.addition}", r.fixes, *_cells(o)])
    return table(["rung", "addition (cumulative)", "what it fixes", *HEADER], rows)


def side_by_side(outcomes: Sequence[Outcome]) -> list[str]:
    """Configurations as columns, the outcome measures as rows."""
    rows = [[name] + [_cells(o)[k] for o in outcomes] for k, name in enumerate(HEADER)]
    return table(["", *[o.label for o in outcomes]], rows)
