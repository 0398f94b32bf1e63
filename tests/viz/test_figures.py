"""Figures: they are written, have the expected size, are not blank, and show what they claim
(robot colours, obstacles, map raster, danger zones, collisions)."""
from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest

from swarmpath.testing import validate_paths, validate_trajectory
from swarmpath.viz import curves, style
from swarmpath.viz.world_plot import (
    contact_points,
    executed_paths,
    plot_paths,
    plot_snapshots,
    plot_trajectory,
    plot_world,
    world_view,
)
from swarmpath.world import load_scenario, world_from_movingai


def test_robot_colours_are_distinct_and_stable():
    for n in (1, 12, 20, 21, 1000):
        cols = style.robot_colors(n)
        assert len(cols) == n
        assert cols == style.robot_colors(n)
        assert all(c.startswith("#") and len(c) == 7 for c in cols)
    assert len(set(style.robot_colors(20))) == 20
    assert len(set(style.robot_colors(60))) == 60
    many = style.robot_colors(1000)
    assert len(set(many)) == 60 and all(a != b for a, b in itertools.pairwise(many))
    assert style.robot_colors(50)[:5] == style.robot_colors(60)[:5]   # robot i keeps its colour


def test_titles_name_the_run():
    t = style.run_title("jaleel2016", "hybrid-apf", "cat-swarm", 3)
    assert t == "jaleel2016 - planner hybrid-apf, controller cat-swarm, seed 3"
    assert style.run_title("x") == "x"


def test_figures_are_outside_pyplot():
    import matplotlib.pyplot as plt

    before = plt.get_fignums()
    plot_world(load_scenario("jaleel2016"))
    assert plt.get_fignums() == before


def test_world_view_is_the_same_from_world_dict_and_trajectory(jaleel_run):
    world = jaleel_run.world
    a, b, c = world_view(world), world_view(world.to_dict()), world_view(jaleel_run.trajectory)
    for v in (b, c):
        assert v.bounds == a.bounds and v.robot_ids == a.robot_ids
        np.testing.assert_array_equal(v.starts, a.starts)
        np.testing.assert_array_equal(v.goals, a.goals)
        assert len(v.obstacles) == len(a.obstacles) == len(world.obstacles)
        assert len(v.moving) == len(world.moving_obstacles)
    assert not a.y_down


def test_world_figure(tmp_path, facts, colour_present):
    world = load_scenario("jaleel2016")
    path = style.save_figure(plot_world(world), tmp_path / "world.png")
    f = facts(path)
    assert 500 <= f["width"] <= 1200 and 450 <= f["height"] <= 900
    assert f["ink"] > 0.15 and f["colours"] > 50
    assert colour_present(f["pixels"], style.OBSTACLE, min_pixels=2000)      # obstacles are drawn
    assert colour_present(f["pixels"], style.MOVING, tolerance=12, min_pixels=20)
    for c in style.robot_colors(world.n_robots):                              # every robot's start/goal
        assert colour_present(f["pixels"], c, tolerance=20, min_pixels=5), c


def test_trajectory_figure_shows_planned_and_executed_paths(jaleel_run, tmp_path, facts, colour_present):
    traj = jaleel_run.trajectory
    assert validate_paths(jaleel_run.world, traj.planned_paths) == []
    # the crosses drawn are the collisions the independent validator finds
    found = [v for v in validate_trajectory(jaleel_run.world, traj) if "contact" in v.problem]
    assert len(contact_points(traj)) == len(found)
    fig = plot_trajectory(traj)
    assert "planner astar" in fig.axes[0].get_title() and "seed 0" in fig.axes[0].get_title()
    path = style.save_figure(fig, tmp_path / "paths.png")
    f = facts(path)
    assert f["ink"] > 0.2
    bare = facts(style.save_figure(plot_trajectory(traj, legend=False), tmp_path / "bare.png"))
    empty = facts(style.save_figure(plot_world(traj, legend=False), tmp_path / "world.png"))
    # paths add pixels in each robot's colour beyond its start/goal markers
    for c in style.robot_colors(traj.n_robots):
        target = np.array([int(c[i:i + 2], 16) for i in (1, 3, 5)])

        def count(px, target=target):
            return int(np.all(np.abs(px.reshape(-1, 3).astype(int) - target) <= 40, axis=1).sum())

        assert count(bare["pixels"]) > count(empty["pixels"]) + 100, c


def test_executed_paths_drop_waits():
    pos = np.array([[[0, 0]], [[0, 0]], [[1, 0]], [[1, 0]], [[1, 1]]], float)
    (p,) = executed_paths(pos)
    np.testing.assert_array_equal(p, [[0, 0], [1, 0], [1, 1]])


def test_collisions_and_danger_zones_are_marked(synthetic, tmp_path, facts, colour_present):
    traj = synthetic(5, 20)
    f = facts(style.save_figure(plot_trajectory(traj), tmp_path / "t.png"))
    assert colour_present(f["pixels"], style.CONTACT, tolerance=30, min_pixels=5)
    assert colour_present(f["pixels"], style.DANGER, tolerance=30, min_pixels=5)
    clean = synthetic(5, 20)
    clean = dataclasses.replace(clean, contacts=[])
    g = facts(style.save_figure(plot_trajectory(clean), tmp_path / "c.png"))
    assert not colour_present(g["pixels"], style.CONTACT, tolerance=10, min_pixels=5)


def test_static_map_is_drawn_with_rows_downward(data_dir, tmp_path, facts, colour_present):
    world = world_from_movingai(data_dir / "random-32-32-10.map", data_dir / "random-32-32-10-even-10.scen", 5)
    view = world_view(world)
    assert view.y_down and view.static_map is not None
    fig = plot_world(world)
    ax = fig.axes[0]
    assert ax.get_ylim()[0] > ax.get_ylim()[1]                                # y grows downward
    f = facts(style.save_figure(fig, tmp_path / "map.png"))
    assert colour_present(f["pixels"], style.MAP_BLOCKED, tolerance=6, min_pixels=1000)


def test_y_direction_can_be_chosen(synthetic):
    traj = synthetic(2, 5)
    up, down = plot_world(traj).axes[0].get_ylim(), plot_world(traj, y_down=True).axes[0].get_ylim()
    assert up[0] < up[1] and down[0] > down[1]


def test_snapshots(synthetic, tmp_path, facts, colour_present):
    traj = synthetic(3, 30)
    fig = plot_snapshots(traj, n_panels=4)
    assert [ax.get_title() for ax in fig.axes] == ["step 0", "step 10", "step 20", "step 30"]
    f = facts(style.save_figure(fig, tmp_path / "snap.png"))
    assert f["width"] > 3 * f["height"] / 2 and f["ink"] > 0.1
    assert colour_present(f["pixels"], style.MOVING, tolerance=25, min_pixels=20)


def test_many_robots_figure(synthetic, tmp_path, facts):
    traj = synthetic(300, 30, size=60.0)
    fig = plot_trajectory(traj)
    assert fig.axes[0].get_legend() is not None
    assert len(fig.axes[0].get_legend().get_texts()) < 20                     # no per-robot legend
    f = facts(style.save_figure(fig, tmp_path / "many.png"))
    assert f["ink"] > 0.2


def test_plot_paths_without_plans(synthetic, tmp_path, facts):
    traj = synthetic(3, 10)
    fig = plot_paths(traj, executed=executed_paths(traj.positions))
    assert facts(style.save_figure(fig, tmp_path / "p.png"))["ink"] > 0.05


# ---------------------------------------------------------------------------------- curves
def test_stack_runs_pads_with_last_value():
    arr = curves.stack_runs([[3, 2, 1], [5, 4]])
    np.testing.assert_array_equal(arr, [[3, 2, 1], [5, 4, 4]])
    np.testing.assert_array_equal(curves.stack_runs([1.0, 2.0]), [[1.0, 2.0]])
    assert curves.stack_runs(np.ones((4, 7))).shape == (4, 7)


def test_band_centre_and_spread():
    runs = np.array([[0.0, 2.0], [2.0, 4.0], [4.0, 9.0]])
    mid, lo, hi = curves.band(runs, "mean", "minmax")
    np.testing.assert_allclose(mid, [2, 5])
    np.testing.assert_allclose(lo, [0, 2])
    np.testing.assert_allclose(hi, [4, 9])
    mid, lo, hi = curves.band(runs, "median", "std")
    np.testing.assert_allclose(mid, [2, 4])
    np.testing.assert_allclose(hi - mid, runs.std(axis=0, ddof=1))
    with pytest.raises(ValueError):
        curves.band(runs, "mode")


def test_pareto_mask_by_hand():
    pts = np.array([[1, 5], [2, 2], [3, 3], [5, 1], [2, 2.5], [4, 1]])
    np.testing.assert_array_equal(curves.pareto_mask(pts), [True, True, False, False, False, True])


@pytest.mark.parametrize("kind", ["utd", "convergence", "pareto", "bars"])
def test_curve_figures(kind, tmp_path, facts):
    rng = np.random.default_rng(0)
    if kind == "utd":
        fig = curves.plot_utd_curves({"with prediction": [np.linspace(80, 0, 30 + k) for k in range(10)],
                                      "without": np.linspace(80, 5, 45)[None] + rng.normal(0, 2, (10, 45))},
                                     title="UTD")
    elif kind == "convergence":
        fig = curves.plot_convergence({"pso": np.exp(-np.arange(120) / 30)[None] * rng.uniform(1, 3, (20, 1)),
                                       "amopso1": np.exp(-np.arange(120) / 10)}, title="sphere")
        assert fig.axes[0].get_yscale() == "log"
    elif kind == "pareto":
        fig = curves.plot_pareto_fronts({"mopso": rng.uniform(0, 1, (50, 2))}, objectives=("danger", "length"),
                                        highlight={"weighted sum": [0.3, 0.3]})
    else:
        fig = curves.plot_grouped_bars([2, 4, 6], {"prediction": [10, 12, 14], "none": [12, 15, 20]},
                                       errors={"prediction": [1, 1, 2]}, ylabel="steps")
    f = facts(style.save_figure(fig, tmp_path / f"{kind}.png"))
    assert 400 <= f["width"] <= 900 and 300 <= f["height"] <= 600
    assert f["ink"] > 0.05 and f["colours"] > 20
    assert len(fig.axes[0].get_legend().get_texts()) >= 2
