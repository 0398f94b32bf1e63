"""``swarmpath run ... --out DIR`` writes the summary, the trajectory, the figures, the GIF and
the replay; the potential-field figure is added for potential-field planners."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from swarmpath.sim.trajectory import Trajectory
from swarmpath.viz.run_outputs import potential_field_figure, write_run_outputs

EXPECTED = {"summary.json", "trajectory.npz", "world.png", "paths.png", "animation.gif", "replay.html"}


def test_cli_run_writes_every_output(tmp_path, facts, capsys):
    from swarmpath.cli import main

    out = tmp_path / "run"
    main(["run", "jaleel2016", "--planner", "astar", "--controller", "follow", "--out", str(out), "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert {p.name for p in out.iterdir()} == EXPECTED
    assert json.loads((out / "summary.json").read_text()) == summary
    traj = Trajectory.load(out / "trajectory.npz")
    assert traj.n_steps == summary["steps"]
    assert (out / "animation.gif").stat().st_size < 10_000_000
    for png in ("world.png", "paths.png"):
        f = facts(out / png)
        assert f["width"] > 500 and f["height"] > 400 and f["ink"] > 0.15, png
    html = (out / "replay.html").read_text(encoding="utf-8")
    assert "jaleel2016" in html and "http://" not in html and "https://" not in html


def test_write_run_outputs_parts(jaleel_run, tmp_path):
    written = write_run_outputs(tmp_path, jaleel_run, animation=False, replay=False)
    assert [p.name for p in written] == ["summary.json", "trajectory.npz", "world.png", "paths.png"]
    back = Trajectory.load(tmp_path / "trajectory.npz")
    np.testing.assert_array_equal(back.positions, jaleel_run.trajectory.positions)


def test_potential_field_figure_for_field_planners(jaleel_run, tmp_path, facts, monkeypatch):
    pytest.importorskip("swarmpath.viz.potential_field", reason="written with the APF planner (issue 3)")
    from swarmpath.viz import potential_field as pf

    calls = []
    real = pf.plot_potential_field

    def spy(world, field, paths=None, *args, **kwargs):
        calls.append((world, paths))
        return real(world, field, paths, *args, **kwargs)

    monkeypatch.setattr(pf, "plot_potential_field", spy)
    run = jaleel_run
    apf_run = dataclasses.replace(run, planner="hybrid-apf")   # the figure depends on the planner's name only
    written = write_run_outputs(tmp_path, apf_run, animation=False, replay=False)
    assert (tmp_path / "potential_field.png") in written
    f = facts(tmp_path / "potential_field.png")
    assert f["ink"] > 0.5 and f["colours"] > 100                 # a heatmap
    (world, paths), = calls
    assert world is run.world and len(paths) == world.n_robots
    calls.clear()
    other = tmp_path / "other"
    write_run_outputs(other, run, animation=False, replay=False)    # planner astar: no field figure
    assert calls == [] and not (other / "potential_field.png").exists()


def test_a_failing_field_figure_does_not_lose_the_run(jaleel_run, monkeypatch):
    pytest.importorskip("swarmpath.viz.potential_field", reason="written with the APF planner (issue 3)")
    from swarmpath.viz import potential_field as pf

    def broken(*args, **kwargs):
        raise ValueError("boom")

    monkeypatch.setattr(pf, "plot_potential_field", broken)
    with pytest.warns(RuntimeWarning, match="boom"):
        assert potential_field_figure(dataclasses.replace(jaleel_run, planner="apf")) is None
