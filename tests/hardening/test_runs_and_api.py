"""Runs that used to hang, crash or mislead, and Python API misuse: every case ends in bounded
time with the right outcome, or raises a SwarmpathError with a message."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from cli_helpers import one_error_line, swarmpath

from swarmpath.control.base import Controller, Decision
from swarmpath.errors import SwarmpathError
from swarmpath.runner import run_world
from swarmpath.sim import Simulator, Trajectory
from swarmpath.testing import validate_paths, validate_trajectory
from swarmpath.world import Rect, RectBounds, Robot, World, load_scenario

S2 = math.sqrt(2)


def walled_in(radius: float = 0.0) -> World:
    """The goal sits in a closed box: no controller can reach it."""
    return World(RectBounds(10, 10), obstacles=(Rect((6, 6), (10, 6.8)), Rect((6, 6), (6.8, 10))),
                 robots=(Robot("a", (1.5, 1.5), (8.5, 8.5), radius, S2 if radius == 0 else 0.5),), name="walled")


@pytest.mark.parametrize("controller", ["fish-swarm", "cat-swarm", "pibt"])
def test_an_unreachable_goal_is_known_before_the_run_and_ends_it(controller) -> None:
    result = run_world(walled_in(), planner="none", controller=controller, seed=0, max_steps=1_000_000_000)
    t = result.trajectory
    assert t.status == "deadlock" and t.n_steps <= 1
    assert [e["kind"] for e in t.events if e.get("robot") == 0][:1] == ["goal_unreachable"]
    assert not result.summary.success


def test_a_continuous_livelock_ends_by_the_progress_window() -> None:
    """pso-reactive wanders before the wall for ever; the no-progress rule ends the run."""
    world = walled_in(radius=0.3)
    t = Simulator(world, __import__("swarmpath.registry", fromlist=["x"]).CONTROLLERS.get("pso-reactive")(),
                  seed=0, max_steps=1_000_000_000, progress_window=300).run()
    assert t.status == "deadlock" and t.n_steps < 10_000
    assert any("no robot came closer" in e.get("detail", "") for e in t.events)


def test_success_is_false_whenever_a_contact_happened() -> None:
    for seed in range(3):
        s = run_world(load_scenario("jaleel2016"), planner="astar", controller="follow", seed=seed).summary
        assert s.all_reached and s.contacts > 0
        assert s.success is False and s.safe is False and s.to_dict()["success"] is False
        assert "contact" in s.verdict()


def test_the_table_says_why_a_run_is_not_a_success() -> None:
    p = swarmpath("run", "jaleel2016", "--planner", "astar", "--controller", "follow", "--seed", "2")
    assert p.returncode == 0 and "not a success" in p.stdout and "contacts" in p.stdout


def test_a_planner_failure_is_explained_per_robot() -> None:
    p = swarmpath("run", "apf-trap-u-shape", "--planner", "apf", "--json")
    doc = json.loads(p.stdout)
    stuck = [r for r in doc["robots"] if r["plan_status"] == "local_minimum"]
    assert stuck and "local minimum" in stuck[0]["plan_reason"]
    table = swarmpath("run", "apf-trap-u-shape", "--planner", "apf").stdout
    assert "stuck in a local" in table


def test_a_grid_controller_refuses_robots_too_slow_to_leave_their_cell() -> None:
    world = World(RectBounds(5, 5), robots=(Robot("slow", (0.5, 0.5), (4.5, 4.5), 0.0, 0.5),), name="slow")
    for controller in ("fish-swarm", "cat-swarm", "pibt"):
        with pytest.raises(SwarmpathError, match="slow.*max_speed"):
            run_world(world, planner="none", controller=controller)


def test_json_trajectories_validate_exactly_like_npz(tmp_path) -> None:
    world = load_scenario("prediction2013")
    traj = run_world(world, seed=0, max_steps=60).trajectory
    for suffix in (".json", ".npz"):
        loaded = Trajectory.load(traj.save(tmp_path / f"t{suffix}"))
        assert np.array_equal(loaded.positions, traj.positions)
        assert validate_trajectory(world, loaded) == validate_trajectory(world, traj)


class ManyModes(Controller):
    def reset(self, world, plan, rng):
        self.n_ = world.n_robots

    def act(self, obs):
        return Decision(obs.positions.copy(), [f"mode-{obs.step}"] * self.n_)


def test_api_misuse_raises_swarmpath_errors() -> None:
    world = load_scenario("karim2014")
    with pytest.raises(SwarmpathError, match="World"):
        run_world(None)
    with pytest.raises(SwarmpathError, match="max_steps"):
        run_world(world, max_steps=2.5)
    with pytest.raises(SwarmpathError, match="127 distinct"):
        Simulator(world, ManyModes(), max_steps=200, deadlock_window=1000, progress_window=1000).run()
    with pytest.raises(SwarmpathError, match="sequence"):
        validate_paths(world, "not paths")
    assert validate_paths(world, [[[0, 0], [1]]])[0].problem.startswith("is not an array")
    traj = run_world(world, seed=0).trajectory
    broken = Trajectory(**{**traj.__dict__, "positions": np.where(np.arange(traj.n_steps + 1)[:, None, None] == 3,
                                                                     np.nan, traj.positions)})
    problems = validate_trajectory(world, broken)
    assert problems and "finite" in problems[0].problem


def test_a_hundred_thousand_robots_validate() -> None:
    rng = np.random.default_rng(0)
    n = 100_000
    cells = rng.choice(1000 * 1000, 2 * n, replace=False)
    xy = np.stack([cells % 1000, cells // 1000], 1) + 0.5
    world = World(RectBounds(1000, 1000), robots=tuple(Robot(f"r{i}", tuple(xy[i]), tuple(xy[n + i]), 0.0, 1.5)
                                                       for i in range(n)))
    assert world.n_robots == n
    clash = [*world.robots[:-1], Robot("x", world.robots[0].start, (999.5, 999.5), 0.0, 1.5)]
    with pytest.raises(SwarmpathError, match=r"robots\[99999\]\.start"):
        World(RectBounds(1000, 1000), robots=tuple(clash))


def test_help_lists_the_registered_names() -> None:
    assert "apso" in swarmpath("optimize", "--help").stdout and "spso" in swarmpath("optimize", "--help").stdout
    assert "amopso-follow" in swarmpath("run", "--help").stdout
    assert "prediction2013" in swarmpath("reproduce", "--help").stdout


def test_builtin_maps_resolve_from_any_folder(tmp_path) -> None:
    p = swarmpath("path", "--map", "den312d.map", "--start", "64", "77", "--goal", "5", "20", "--json", cwd=tmp_path)
    assert p.returncode == 0 and json.loads(p.stdout)["cost"] > 0
    one_error_line(swarmpath("path", "--map", "no-such.map", "--start", "0", "0", "--goal", "1", "1", cwd=tmp_path),
                   "no-such.map")


def test_one_cell_is_not_pluralised(tmp_path) -> None:
    m = tmp_path / "m.map"
    m.write_text("type octile\nheight 1\nwidth 2\nmap\n..\n")
    assert "(1 cell expanded)" in swarmpath("path", "--map", str(m), "--start", "0", "0", "--goal", "0", "0").stdout


def test_plain_progress_lines_when_not_on_a_terminal(capsys) -> None:
    from rich.console import Console

    from swarmpath.cli.common import progress

    with progress(Console(file=open("/dev/null", "w")), "simulating x", 10, "step", every_s=0.0) as update:
        for k in range(1, 4):
            update(k)
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("simulating x: step 1/10") and err[-1].startswith("simulating x: step 3/10")
