"""Progress of a long reproduction: a callback for the command line's bar, plain lines when
nobody watches a terminal, and where the time went.

``swarmpath reproduce`` hands every reproduction a ``progress(done, total)`` callback (a
progress bar on a terminal, a no-op otherwise). :class:`Progress` wraps it: the reproduction
names each *stage* (a batch of runs: "cat-swarm-paper, 20 seeds") and ticks once per run.
When a callback is given but standard output is not a terminal (a log file, CI), it also
writes plain lines to standard error: the stage that starts and its share of the whole, and
at the end a table of the time each stage took (the command line's own lines say how many
runs are done). Given a stream explicitly, it also writes, every ``every_s`` seconds, how far
it got. Library callers that pass no callback get neither.
"""
from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TextIO

ProgressCallback = Callable[[int, int], None]


@dataclass
class StageTime:
    """Runs and CPU/wall seconds spent in one stage."""

    name: str
    runs: int = 0
    cpu_s: float = 0.0
    wall_s: float = 0.0


def _auto_stream(callback: ProgressCallback | None) -> TextIO | None:
    """Standard error when a callback is given and standard output is not a terminal."""
    if callback is None:
        return None
    try:
        interactive = sys.stdout.isatty()
    except (AttributeError, ValueError):  # a closed or replaced stdout
        interactive = False
    return None if interactive else sys.stderr


class Progress:
    """Counts finished runs of one reproduction and reports them.

    Parameters
    ----------
    label : str
        Name of the reproduction, printed at the start of every plain line.
    total : int
        Runs the reproduction will make (the callback's ``total``).
    callback : callable, optional
        ``callback(done, total)`` after every run (the command line's bar).
    stream : file, "auto" or None
        Where plain lines go; "auto" (default): standard error when a callback is given and
        standard output is not a terminal; None: nowhere.
    every_s : float
        Least time between two count lines within a stage.
    counts : bool, optional
        Whether plain lines also count runs every ``every_s`` seconds (default: only with an
        explicit stream; the command line counts runs itself).
    """

    def __init__(self, label: str, total: int, callback: ProgressCallback | None = None, *,
                 stream: TextIO | None | str = "auto", every_s: float = 10.0, counts: bool | None = None):
        self.label = label
        self.total = max(int(total), 1)
        self.callback = callback
        self.stream = _auto_stream(callback) if stream == "auto" else stream
        self.every_s = every_s
        self.counts = (stream != "auto") if counts is None else counts
        self.done = 0
        self.stages: list[StageTime] = []
        self._t0 = time.perf_counter()
        self._last_line = 0.0
        self._stage_wall0 = self._t0
        self._stage_cpu0 = time.process_time()
        if callback is not None:
            callback(0, self.total)

    # ------------------------------------------------------------------ stages
    def stage(self, name: str, runs: int | None = None) -> None:
        """Start a stage called ``name`` (of ``runs`` runs, for the plain line)."""
        self._close_stage()
        self.stages.append(StageTime(name))
        self._stage_wall0, self._stage_cpu0 = time.perf_counter(), time.process_time()
        if self.stream is not None:
            share = f", {runs} runs ({100 * runs / self.total:.0f} % of all)" if runs else ""
            self._line(f"stage {len(self.stages)}: {name}{share}")

    def _close_stage(self) -> None:
        if self.stages:
            s = self.stages[-1]
            s.wall_s += time.perf_counter() - self._stage_wall0
            s.cpu_s += time.process_time() - self._stage_cpu0
            self._stage_wall0, self._stage_cpu0 = time.perf_counter(), time.process_time()

    # ------------------------------------------------------------------ runs
    def tick(self, n: int = 1) -> None:
        """``n`` more runs finished."""
        self.done += n
        if self.stages:
            self.stages[-1].runs += n
        if self.callback is not None:
            self.callback(min(self.done, self.total), self.total)
        now = time.perf_counter()
        if self.stream is not None and self.counts and now - self._last_line >= self.every_s:
            where = f" in '{self.stages[-1].name}'" if self.stages else ""
            self._line(f"{self.done}/{self.total} runs{where}, {now - self._t0:.0f} s so far")

    def ticker(self) -> ProgressCallback:
        """A ``(k, total)`` callback for code that counts its own runs from 0 (an optimiser
        benchmark): it advances this progress to where that count has got."""
        start = self.done

        def advance(k: int, _total: int | None = None) -> None:
            if start + k > self.done:
                self.tick(start + k - self.done)

        return advance

    def finish(self) -> list[StageTime]:
        """Close the last stage; write where the time went (stages of the same name added up);
        returns the stage times."""
        self._close_stage()
        merged: dict[str, StageTime] = {}
        for s in self.stages:  # a stage run several times (one per robot count, say) counts once
            m = merged.setdefault(s.name, StageTime(s.name))
            m.runs, m.cpu_s, m.wall_s = m.runs + s.runs, m.cpu_s + s.cpu_s, m.wall_s + s.wall_s
        if self.stream is not None and merged:
            wall = sum(s.wall_s for s in merged.values()) or 1e-12
            self._line(f"done: {self.done} runs in {time.perf_counter() - self._t0:.0f} s; time by stage:")
            for s in sorted(merged.values(), key=lambda s: -s.wall_s):
                per = f", {s.wall_s / s.runs:.2f} s per run" if s.runs else ""
                self.stream.write(f"  {100 * s.wall_s / wall:5.1f} %  {s.wall_s:7.1f} s wall  {s.cpu_s:7.1f} s CPU  "
                                  f"{s.name} ({s.runs} runs{per})\n")
            self.stream.flush()
        return list(merged.values())

    def _line(self, text: str) -> None:
        self._last_line = time.perf_counter()
        assert self.stream is not None
        self.stream.write(f"[{self.label}] {text}\n")
        self.stream.flush()
