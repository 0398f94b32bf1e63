"""What every command shares: one JSON object on stdout, escaped user text, registry-driven
help, progress (a bar on a terminal, plain lines in logs and pipes) and early checks of
output folders."""
from __future__ import annotations

import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable

import click

from swarmpath.errors import ConfigError

EXIT_BAD_INPUT = 2


def emit_json(doc: Any) -> None:
    """Print ``doc`` as one JSON object on stdout (NaN/inf become null)."""
    click.echo(json.dumps(doc, allow_nan=False, default=_json_default))


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return None if not math.isfinite(obj) else float(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def console(json_mode: bool):
    """A rich console for human output; on stderr when stdout must hold only JSON."""
    from rich.console import Console

    return Console(stderr=json_mode, highlight=False)


def safe(text: Any) -> str:
    """User text (names, ids) ready for a rich console: control characters blanked and
    markup escaped, so ``[/red]`` prints as itself and ESC cannot move the cursor."""
    from rich.markup import escape

    from swarmpath.world.limits import clean_text

    return escape(clean_text(str(text)))


class NamesOption(click.Option):
    """An option whose help ends with the names registered in ``registry`` (read when the
    help is shown, so plug-ins appear too)."""

    def __init__(self, *args: Any, registry: str, **kwargs: Any):
        self.registry = registry
        super().__init__(*args, **kwargs)

    def get_help_record(self, ctx: click.Context):
        from swarmpath import registry

        names = ", ".join(getattr(registry, self.registry).names())
        self.help = f"{self.help.split(' (choose from')[0]} (choose from: {names})"
        return super().get_help_record(ctx)


class NamesCommand(click.Command):
    """A command whose help ends with the names registered in ``registry`` (for a NAME
    argument such as ``reproduce PAPER``)."""

    def __init__(self, *args: Any, registry: str, what: str, **kwargs: Any):
        self.registry, self.what = registry, what
        super().__init__(*args, **kwargs)

    def format_epilog(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        from swarmpath import registry

        names = ", ".join(getattr(registry, self.registry).names())
        with formatter.section(self.what):
            formatter.write_text(names)


def writable_folder(path: str | Path, option: str = "--out") -> Path:
    """``path`` as a folder that exists and can be written, checked before long work starts."""
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".swarmpath-write-check-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except FileExistsError:
        raise ConfigError(f"{option} {folder}: exists and is not a folder") from None
    except OSError as exc:
        raise ConfigError(f"{option} {folder}: cannot write there ({exc.strerror or exc})") from None
    return folder


def writable_file(path: str | Path, option: str) -> Path:
    """``path`` as a file that can be written (its folder exists or can be made)."""
    target = Path(path)
    if target.is_dir():
        raise ConfigError(f"{option} {target}: is a folder, not a file")
    writable_folder(target.parent if str(target.parent) else ".", option)
    return target


def _elapsed(seconds: float) -> str:
    m, s = divmod(int(seconds), 60)
    return f"{m}m{s:02d}s" if m else f"{s}s"


class progress:
    """Progress of long work as a context manager yielding ``update(done, total=None)``.

    On a terminal: a transient rich bar. Otherwise (CI logs, pipes): a plain line on stderr
    at most every ``every_s`` seconds and one at the end, e.g.
    ``simulating jaleel2016: step 400/1400 (12s)``. ``enabled=False`` makes it silent."""

    def __init__(self, out_console, label: str, total: int | None = None, unit: str = "", *,
                 enabled: bool = True, every_s: float = 5.0):
        self.console, self.label, self.total, self.unit = out_console, label, total, unit
        self.enabled, self.every_s = enabled, every_s
        self._bar = None
        self._t0 = time.perf_counter()
        self._last = self._t0
        self._state = (0, total)

    def __enter__(self) -> Callable[..., None]:
        if not self.enabled:
            return lambda *_args, **_kw: None
        if self.console.is_terminal:
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self._bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                 TimeElapsedColumn(), console=self.console, transient=True)
            self._bar.__enter__()
            task = self._bar.add_task(self.label, total=self.total)

            def bar(done: int, total: int | None = None) -> None:
                self._bar.update(task, completed=done, total=total if total is not None else self._bar.tasks[0].total)

            return bar

        def line(done: int, total: int | None = None) -> None:
            self._state = (done, total if total is not None else self._state[1])
            now = time.perf_counter()
            if now - self._last >= self.every_s:
                self._last = now
                self._print()

        return line

    def _print(self) -> None:
        done, total = self._state
        unit = f"{self.unit} " if self.unit else ""
        count = f"{unit}{done}/{total}" if total else f"{unit}{done}"
        print(f"{self.label}: {count} ({_elapsed(time.perf_counter() - self._t0)})", file=sys.stderr, flush=True)

    def __exit__(self, *exc: Any) -> bool:
        if self._bar is not None:
            self._bar.__exit__(*exc)
        elif self.enabled and exc[0] is None and self._last != self._t0:
            self._print()   # a last line when lines were printed at all
        return False
