"""The ``swarmpath`` command group that every subcommand module registers with."""
from __future__ import annotations

import click


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="swarmpath")
def cli() -> None:
    """Plan, simulate, compare and visualise many robots with swarm intelligence."""
