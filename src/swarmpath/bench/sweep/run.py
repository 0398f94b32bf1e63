"""A sweep from start to end: expand the suite, leave out the jobs already stored, run the
rest on an engine (the local pool, or Dask), and store each result as it arrives.

Whatever stops a sweep (Ctrl-C, a kill, a crash), the store keeps every job that finished,
and the next call runs only the others: no finished job is lost, none is stored twice.
"""
from __future__ import annotations

import signal
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from swarmpath.bench.sweep.jobs import Expansion, Job, expand, schedule
from swarmpath.bench.sweep.store import STATUSES, Store
from swarmpath.bench.sweep.suite import Suite
from swarmpath.errors import ConfigError


@dataclass
class SweepOutcome:
    """What one call did: jobs of the suite, already stored, run now (by status), skipped
    pairs, wall time, and whether it was interrupted."""

    suite: str
    total: int
    already: int
    ran: int = 0
    statuses: dict[str, int] = field(default_factory=lambda: {s: 0 for s in STATUSES})
    expansion: Expansion | None = None
    wall_s: float = 0.0
    interrupted: bool = False
    engine: str = "local"

    @property
    def remaining(self) -> int:
        return self.total - self.already - self.ran


def parse_retry(text: str | None) -> tuple[str, ...]:
    """``--retry error,timeout``: statuses whose stored jobs run again."""
    if not text:
        return ()
    chosen = tuple(s.strip() for s in text.split(",") if s.strip())
    bad = [s for s in chosen if s not in ("error", "timeout")]
    if bad:
        raise ConfigError(f"--retry: {bad[0]!r} is not a status to retry (choose from: error, timeout)")
    return chosen


def make_engine(workers: int, dask: str | None):
    """The local pool, or a Dask engine (one clear line when dask is not installed)."""
    if dask is None:
        from swarmpath.bench.sweep.pool import LocalEngine

        return LocalEngine(workers)
    from swarmpath.bench.sweep.dask_engine import DaskEngine, dask_missing

    missing = dask_missing()
    if missing:
        raise ConfigError(missing)
    if not dask.strip():
        raise ConfigError("--dask: give 'local' or a scheduler address such as tcp://127.0.0.1:8786")
    return DaskEngine(dask.strip(), workers)


class _Interrupt(Exception):
    """SIGTERM during a sweep: stop like Ctrl-C."""


class SweepInterrupted(KeyboardInterrupt):
    """A sweep stopped by Ctrl-C or SIGTERM; ``outcome`` says what was stored before."""

    def __init__(self, outcome: SweepOutcome):
        super().__init__("interrupted")
        self.outcome = outcome


def run_sweep(suite: Suite, store_path: str | Path, *, workers: int = 1, dask: str | None = None,
              retry: Sequence[str] = (), expansion: Expansion | None = None,
              progress: Callable[[int, int], None] | None = None) -> SweepOutcome:
    """Run the jobs of ``suite`` that ``store_path`` does not hold yet (and those stored with
    a status in ``retry``). Returns what happened; an interruption (Ctrl-C, SIGTERM) stops
    the workers, keeps what finished and raises :class:`SweepInterrupted`."""
    engine = make_engine(workers, dask)
    expansion = expansion or expand(suite)
    t0 = time.perf_counter()
    with Store(store_path).open(write=True) as store:
        store.record_skipped(suite.name, expansion.skipped)
        keys = [j.key for j in expansion.jobs]
        stored = store.stored_keys(keys)
        again = [k for k, status in stored.items() if status in retry]
        if again:
            store.forget(again)
            for k in again:
                del stored[k]
        todo = schedule([j for j in expansion.jobs if j.key not in stored])
        outcome = SweepOutcome(suite.name, len(keys), len(stored), expansion=expansion, engine=engine.name)
        sweep_id = store.begin_sweep(suite, engine.name, workers, len(keys), len(stored))

        def on_result(job: Job, result: dict[str, Any]) -> None:
            if store.add(job, result, engine.name):
                outcome.ran += 1
                outcome.statuses[result["status"]] = outcome.statuses.get(result["status"], 0) + 1
            if progress is not None:
                progress(outcome.ran, len(todo))

        previous = signal.getsignal(signal.SIGTERM)

        def on_term(signum: int, frame: Any) -> None:
            raise _Interrupt()

        state = "failed"
        try:
            signal.signal(signal.SIGTERM, on_term)
        except ValueError:          # not the main thread: leave SIGTERM alone
            previous = None
        try:
            if progress is not None:
                progress(0, len(todo))
            if todo:
                engine.run(todo, on_result)
            state = "finished"
        except (KeyboardInterrupt, _Interrupt):
            outcome.interrupted = True
            state = "interrupted"
            raise SweepInterrupted(outcome) from None
        finally:
            if previous is not None:
                signal.signal(signal.SIGTERM, previous)
            outcome.wall_s = time.perf_counter() - t0
            store.end_sweep(sweep_id, outcome.ran, state)
    return outcome
