"""``swarmpath optimize``: an optimiser on a benchmark function over seeded runs."""
from __future__ import annotations

import click

from swarmpath.cli.common import NamesOption, console, emit_json, progress
from swarmpath.cli.group import cli


@cli.command()
@click.option("--algorithm", cls=NamesOption, registry="OPTIMIZERS", required=True, help="optimiser name")
@click.option("--function", "function", cls=NamesOption, registry="FUNCTIONS", required=True,
              help="benchmark function")
@click.option("--dim", type=click.IntRange(min=1, max=100_000), default=30, show_default=True)
@click.option("--particles", type=click.IntRange(min=1, max=1_000_000), default=30, show_default=True)
@click.option("--iterations", type=click.IntRange(min=1, max=10**9), default=1000, show_default=True)
@click.option("--runs", type=click.IntRange(min=1, max=100_000), default=1, show_default=True)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--json", "json_mode", is_flag=True, help="print one JSON object")
def optimize(algorithm: str, function: str, dim: int, particles: int, iterations: int, runs: int, seed: int,
             json_mode: bool) -> None:
    """Run an optimiser on a benchmark function over several seeded runs."""
    from swarmpath.optim import run_benchmark

    out = console(json_mode)
    with progress(out, f"{algorithm} on {function}", runs, "run", enabled=runs > 1) as advance:
        doc = run_benchmark(algorithm, function, dim, particles, iterations, runs, seed, progress=advance)
    if json_mode:
        emit_json(doc)
        return
    out.print(f"{algorithm} on {function} ({dim}-D, {particles} particles x {iterations} iterations, "
              f"{runs} run{'s' if runs > 1 else ''}, seed {seed})")
    out.print(f"min {doc['min']:.6g}   mean {doc['mean']:.6g}   std {doc['std']:.6g}")
