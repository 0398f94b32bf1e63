"""The ``swarmpath`` command: a thin shell over the library (docs/guide.md lists the command
line). Bad input prints one line on stderr and exits with code 2; ``--json`` prints exactly
one JSON object on stdout.
"""
from __future__ import annotations

import sys
from typing import NoReturn

import click

from swarmpath.cli import maps, optimize, reproduce, run, scenarios  # noqa: F401  (they register commands)
from swarmpath.cli import bench  # noqa: F401  (swarmpath bench: sweeps, stores, reports)
from swarmpath.cli.common import EXIT_BAD_INPUT
from swarmpath.cli.group import cli
from swarmpath.errors import SwarmpathError

#: An error line is cut to this many characters (a message never echoes unbounded input).
MAX_ERROR_CHARS = 1000


def _fail(message: str) -> NoReturn:
    from swarmpath.world.limits import clean_text

    line = " ".join(clean_text(message).split())
    if len(line) > MAX_ERROR_CHARS:
        line = line[:MAX_ERROR_CHARS - 3] + "..."
    click.echo(f"swarmpath: error: {line}", err=True)
    sys.exit(EXIT_BAD_INPUT)


def main(argv: list[str] | None = None) -> None:
    """Console entry point: errors of the user's making become one line and exit code 2."""
    try:
        cli.main(args=argv, prog_name="swarmpath", standalone_mode=False)
    except SwarmpathError as exc:
        _fail(str(exc) or type(exc).__name__)
    except click.exceptions.Abort:
        click.echo("swarmpath: aborted", err=True)
        sys.exit(130)
    except click.ClickException as exc:
        _fail(exc.format_message())
    except KeyboardInterrupt:
        click.echo("swarmpath: interrupted", err=True)
        sys.exit(130)
    except BrokenPipeError:
        sys.exit(0)
    except RecursionError:
        _fail("the input is nested too deeply to process")
    except MemoryError:
        _fail("the input asks for more memory than this machine has; use a smaller problem")


__all__ = ["cli", "main"]
