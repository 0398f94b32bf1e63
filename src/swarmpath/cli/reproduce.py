"""``swarmpath reproduce`` and ``replay``: a paper's experiments, and pictures of a saved run."""
from __future__ import annotations

import click

from swarmpath.cli.common import NamesCommand, console, progress, safe, writable_file, writable_folder
from swarmpath.cli.group import cli


@cli.command(cls=NamesCommand, registry="REPRODUCTIONS", what="PAPER is one of")
@click.argument("paper", required=False)
@click.option("--list", "list_names", is_flag=True, help="list the papers and exit")
@click.option("--out", type=click.Path(file_okay=False), default=None, help="directory for the report")
@click.option("--runs", type=click.IntRange(min=1, max=100_000), default=None,
              help="runs per configuration (default: the paper's)")
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
def reproduce(paper: str | None, list_names: bool, out: str | None, runs: int | None, seed: int) -> None:
    """Run a paper's experiments and write tables and figures."""
    from swarmpath.errors import ConfigError
    from swarmpath.registry import REPRODUCTIONS

    if list_names:
        click.echo("\n".join(REPRODUCTIONS.names()))
        return
    if paper is None:
        raise ConfigError(f"give a PAPER: one of {', '.join(REPRODUCTIONS.names())}")
    experiment = REPRODUCTIONS.get(paper)
    out_dir = writable_folder(out or f"reproduce-{paper}", "--out")
    out_console = console(False)
    with progress(out_console, f"reproducing {paper}", None, "run") as advance:
        report = experiment(out_dir, runs=runs, seed=seed, progress=advance)
    out_console.print(f"wrote {safe(report)}")


@cli.command()
@click.argument("trajectory", type=click.Path(dir_okay=False))
@click.option("--html", "html_out", type=click.Path(dir_okay=False), default=None, help="write an HTML replay here")
@click.option("--gif", "gif_out", type=click.Path(dir_okay=False), default=None, help="write a GIF (or .mp4) here")
def replay(trajectory: str, html_out: str | None, gif_out: str | None) -> None:
    """Turn a saved trajectory (.npz or .json) into an HTML replay and/or an animation."""
    from swarmpath.errors import ConfigError
    from swarmpath.sim.trajectory import Trajectory

    if not (html_out or gif_out):
        raise ConfigError("give --html FILE and/or --gif FILE")
    for target, option in ((html_out, "--html"), (gif_out, "--gif")):
        if target:
            writable_file(target, option)
    traj = Trajectory.load(trajectory)
    if html_out:
        from swarmpath.viz.html_replay import write_replay_html

        click.echo(f"wrote {write_replay_html(traj, html_out)}")
    if gif_out:
        from swarmpath.viz.animation import save_animation

        with progress(console(False), "rendering the animation", None, "frame") as advance:
            written = save_animation(traj, gif_out, progress=advance)
        click.echo(f"wrote {written}")



