"""Acceptance of the online phase: the cat swarm (and pibt) against the simulator's own checker
on the paper's scenario, a crowded random map with moving obstacles, and a MovingAI
benchmark; plus determinism. Numbers are printed (run with -s to see them)."""
from __future__ import annotations

import hashlib

import numpy as np
import pytest

from swarmpath.control.cat_swarm import CatSwarmController
from swarmpath.data.movingai import MOVINGAI
from swarmpath.registry import PLANNERS
from swarmpath.runner import run_world
from swarmpath.search import astar
from swarmpath.sim import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import (
    Bounce,
    Bounce8,
    RandomWalk,
    Redraw,
    TurnEvery,
    load_scenario,
    world_from_movingai,
)
from swarmpath.world.generators import random_grid_with_movers

DATA = MOVINGAI
PLANNERS_FOR_JALEEL = [p for p in ("hybrid-apf", "astar") if p in PLANNERS]


# ---------------------------------------------------------------------------- the paper's scenario
@pytest.mark.slow
@pytest.mark.parametrize("planner", PLANNERS_FOR_JALEEL)
def test_jaleel2016_every_robot_arrives_without_any_collision_for_20_seeds(planner) -> None:
    world = load_scenario("jaleel2016")
    seek_share = []
    for seed in range(20):
        result = run_world(world, planner=planner, controller="cat-swarm", seed=seed, clearance=False)
        traj = result.trajectory
        assert validate_trajectory(world, traj) == [], f"seed {seed}"
        assert result.summary.collisions == {"robot_robot": 0, "robot_static": 0, "robot_moving": 0}
        assert result.summary.success, f"seed {seed}: {result.summary.reached} of 12 arrived"
        seek = traj.mode_names.index("seek") if "seek" in traj.mode_names else -1
        seek_share.append(float(np.mean(traj.modes == seek)))
    print(f"\njaleel2016 / {planner}: 20 of 20 seeds collision-free, every robot arrived; "
          f"mean share of robot-steps in seek mode {np.mean(seek_share):.3f}")


@pytest.mark.parametrize("controller", ["cat-swarm", "pibt"])
def test_jaleel2016_with_disc_robots_every_robot_arrives(controller) -> None:
    """The paper's scenario with robots of radius 0.1 (the grid's cells are 0.25 wide) instead
    of points: their goals lie on cell corners, off the centres. Seeds 0-2, every robot home
    and no contact. Before cells counted by their centres for discs and the off-centre rests
    were checked exactly, cat-swarm brought 11 of 12 home on each seed."""
    import dataclasses

    world = load_scenario("jaleel2016")
    world = dataclasses.replace(world, robots=tuple(dataclasses.replace(r, radius=0.1) for r in world.robots))
    for seed in range(3):
        result = run_world(world, planner=PLANNERS_FOR_JALEEL[0], controller=controller, seed=seed, clearance=False)
        assert validate_trajectory(world, result.trajectory) == [], (controller, seed)
        assert result.summary.success, (controller, seed, result.summary.reached, result.summary.collisions)


def test_jaleel2016_with_follow_collides() -> None:
    world = load_scenario("jaleel2016")
    planner = PLANNERS_FOR_JALEEL[0]
    found = [sum(run_world(world, planner=planner, controller="follow", seed=s, clearance=False)
                 .summary.collisions.values()) for s in range(3)]
    print(f"\njaleel2016 / {planner} / follow: collisions per seed {found}")
    assert sum(found) > 0


# ---------------------------------------------------------------------------- 100 robots, moving obstacles
#: The acceptance world: 100 robots on a 64 x 64 map (10 % blocked) among 20 obstacles that never
#: stop (half bounce8, half random-walk), from the library so benchmarks/bench_moving.py measures
#: the same worlds on other seeds.
random_world = random_grid_with_movers


def checked_run(controller: str, seed: int, motions: tuple | None = None, world_args: dict | None = None,
                **params) -> tuple:
    """``controller`` (defaults, or ``params``) in the 64 x 64 world of ``seed`` (made with
    ``world_args``, e.g. the robots' radius, if given) with the
    simulator's own step budget, checked: no robot-robot or robot-static contact, a contact
    with a moving obstacle only where the robot had reported that no move led out, and every
    robot on its goal at some step. Returns the trajectory and whether the run is a success
    (every robot on its goal at the end, no contact of any kind)."""
    from swarmpath.registry import CONTROLLERS

    world = random_world(seed, motions=motions, **(world_args or {}))
    traj = Simulator(world, CONTROLLERS.get(controller)(**params), PLANNERS.get("astar")().plan(world, rng=seed),
                     seed=seed).run()
    problems = validate_trajectory(world, traj)   # the independent check finds the recorded contacts only
    assert len(problems) == len(traj.contacts), (controller, seed)
    assert all(c.kind == "robot_moving" for c in traj.contacts), (controller, seed)
    cornered = {(e["step"], e["robot"]) for e in traj.events if e.get("kind") == "no_escape"}
    assert all((c.step, c.robot) in cornered or (c.step - 1, c.robot) in cornered for c in traj.contacts), seed
    at = np.linalg.norm(traj.positions - world.goals[None], axis=2) <= 1e-9
    assert at.any(axis=0).all(), (controller, seed)
    success = bool(at[-1].all()) and not problems
    if traj.status == "all_reached":
        assert at[-1].all() and any(e["kind"] == "finish_together" and e["step"] == traj.n_steps
                                    for e in traj.events), (controller, seed)
    return traj, success


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["cat-swarm", "pibt"])
def test_100_robots_among_20_moving_obstacles_all_home_at_once(controller) -> None:
    """20 seeds, the controllers' defaults: every robot reaches its goal, no robot-robot or
    robot-static contact, a robot-moving contact only after the robot reported ``no_escape``;
    and on 19 seeds or more every robot stands on its goal at the end with no contact of any
    kind (the run ends in the step on which all step home together; pibt 20, cat-swarm 20 of
    these 20; over seeds 2000-2399, held out, pibt 393, cat-swarm 391 of 400:
    docs/algorithms/pibt.md). The obstacles never stop, and a random walker can still catch a
    robot that dodges as well as it can."""
    wins = 0
    for seed in range(20):
        traj, success = checked_run(controller, seed)
        wins += success
        print(f"\nrandom64 {controller} seed {seed}: {traj.status} at step {traj.n_steps}, "
              f"contacts {len(traj.contacts)}, success {success}")
    assert wins >= 19, (controller, wins)


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["cat-swarm", "pibt"])
@pytest.mark.parametrize("kind", ["bounce", "turn-every", "mixed"])
def test_100_robots_among_20_obstacles_of_other_motion_models(controller, kind) -> None:
    """The same world with bounce obstacles (some get walled in, some shuttle between two
    cells on robots' ways), turn-every ones (a new heading every 10 steps), or five kinds in
    turn: seeds 0-9 (turn-every 0-4), every run passing the checks above and at most one in
    ten not a success. Before the forecast of walled-in bouncers and of turn-every between its
    turns, and the detours round lingering obstacles, 3 of the first 10 bounce seeds failed for
    each controller, every turn-every seed, and 2 (pibt) and 4 (cat-swarm) of the first 10
    mixed ones (docs/algorithms/pibt.md). One seed is allowed, as in the 20-seed test above:
    at about 98 % a seed, any change of behaviour moves single seeds both ways (the exact
    sweep cover with the ranked shallower cells lost mixed seed 3 for pibt and saved seed 38;
    seeds 0-49: 49 of 50 before and after)."""
    motions = {"bounce": (Bounce(),), "turn-every": (TurnEvery(),),
               "mixed": (Bounce(), Bounce8(), RandomWalk(), TurnEvery(), Redraw())}[kind]
    seeds = range(5 if kind == "turn-every" else 10)
    failed = [(seed, traj.status, len(traj.contacts))
              for seed in seeds for traj, success in [checked_run(controller, seed, motions)] if not success]
    assert len(failed) <= len(seeds) // 10, (controller, kind, failed)


def test_ways_out_that_a_sweep_box_or_a_failed_push_used_to_close() -> None:
    """Two held-out seeds read closely (docs/algorithms/pibt.md, "Exact sweeps" and "Pushed
    robots keep their shallower cells"), `pibt`: in 2691 a robot on its goal in a dead end had
    one way out, a corner of a diagonal sweep's bounding box that the sweep itself misses; in
    2784 a robot pushed a neighbour whose deepest tier had no free cell, stood, and was caught
    in a pocket a step later. Each run was caught before its change; now every robot is home
    and there is no contact of any kind."""
    for seed in (2691, 2784):
        traj, success = checked_run("pibt", seed)
        assert success, (seed, traj.status, [(c.step, c.robot, c.other) for c in traj.contacts])


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["cat-swarm", "pibt"])
def test_robots_leave_nooks_a_turning_bounce8_obstacle_heads_for(controller) -> None:
    """Seeds 1606 and 1673: a robot waits on its goal in a nook as a bounce8 obstacle heads
    for the wall beside it (1606), or in a corridor between two (1673). Under the square
    cover of point robots the open-loop look-ahead took all seven turns at once, found no cell
    safer than the goal, and the obstacle hit the robot after its turn; the turn game
    (control/turn_game.py, checked against a brute-force game in
    tests/control/test_turn_game.py) got it out in time. Since cells count by their centres
    the nooks leave room either way (no seed of 1500-2299 is saved by the game any more,
    docs/algorithms/pibt.md); every robot home, no contact of any kind, with and without it."""
    for seed in (1606, 1673):
        for turn_game in (True, False):
            traj, success = checked_run(controller, seed, turn_game=turn_game)
            assert success, (controller, seed, turn_game, traj.status, len(traj.contacts))


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["cat-swarm", "pibt"])
def test_disc_robots_among_20_moving_obstacles_all_home(controller) -> None:
    """The same world with disc robots of radius 0.3 whose goals lie up to 0.15 off their
    cells' centres: seeds 0-3, every one a success with the checks above. Cells count as
    covered by their centres for discs; with the square rule of point robots a 3 x 3 block
    around every obstacle was shut to them and no run brought every robot home, even with
    goals on the centres (pibt and cat-swarm: 0 of 10 seeds, docs/algorithms/pibt.md)."""
    for seed in range(4):
        traj, success = checked_run(controller, seed, world_args={"radius": 0.3, "goal_offset": 0.15})
        assert success, (controller, seed, traj.status, len(traj.contacts))


def goal_danger_steps(seed: int, steps: int = 250) -> tuple[np.ndarray, int]:
    """For the 64 x 64 world of ``seed``: per step, how many goals lie where a moving obstacle
    may be at the next step (D_1 of the forecast, every move its motion model allows); and a
    lower bound on the step at which every robot can first be on its goal (the longest
    shortest path, in steps). The obstacles here never react to robots, so their motion, and
    this count, is the same whatever the controller does."""
    from swarmpath.control.base import Controller, Decision
    from swarmpath.control.hazards import ObstacleForecast

    class Still(Controller):
        def reset(self, world, plan, rng):
            pass

        def act(self, obs):
            return Decision(obs.positions.copy())

    world = random_world(seed)
    traj = Simulator(world, Still(), seed=seed, max_steps=steps, deadlock_window=10 ** 6,
                     progress_window=10 ** 6).run()
    grid = world.grid()
    fc = ObstacleForecast(world, grid)
    cells = grid.cell_of(world.goals)
    count = np.array([fc.danger(traj.obstacle_positions[t], traj.obstacle_positions[t - 1])[cells[:, 1], cells[:, 0]]
                      .sum() for t in range(1, traj.n_steps + 1)])
    first = max(int(np.max(np.abs(grid.cell_of(r.goal) - grid.cell_of(r.start)))) for r in world.robots)
    return count, first


@pytest.mark.slow
def test_all_robots_home_at_once_within_250_steps_is_out_of_reach_on_seed_0() -> None:
    """Why robots cannot simply sit on their goals until all are home: on seed 0, after the
    earliest step at which all robots could first be home, more than nine steps in ten up to
    250 have some goal within an obstacle's next-step reach (cells by their centres; 11 of 189
    steps are clear). A robot standing there would be hit at the next step whenever the
    obstacle moves its way. All home at once therefore comes mostly from robots waiting beside
    threatened goals and stepping on together in the step that ends the run
    (swarmpath.control.finish; the test above)."""
    count, first = goal_danger_steps(0)
    assert first > 23
    assert np.mean(count[first - 1:] > 0) > 0.9
    assert np.mean(count) > 2      # on average more than two goals are in reach at every step


# ---------------------------------------------------------------------------- MovingAI
def test_movingai_random_32_32_10_with_50_agents() -> None:
    world = world_from_movingai(DATA / "random-32-32-10.map", DATA / "random-32-32-10-random-1.scen", 50)
    grid = world.grid()
    optimal = sum(astar(grid, grid.cell_of(r.start), grid.cell_of(r.goal)).cost for r in world.robots)
    for planner in ("astar", "none"):
        result = run_world(world, planner=planner, controller="cat-swarm", seed=0)
        assert validate_trajectory(world, result.trajectory) == []
        assert result.summary.success
        ratio = result.summary.sum_of_lengths / optimal
        print(f"\nrandom-32-32-10, 50 agents, planner {planner}: success, collisions 0, "
              f"sum of lengths / sum of optimal octile lengths = {ratio:.3f}, makespan {result.summary.makespan}")
        assert ratio <= 1.3


# ---------------------------------------------------------------------------- determinism and conformance
def trajectory_hash(traj) -> str:
    h = hashlib.sha256(np.ascontiguousarray(traj.positions).tobytes())
    h.update(np.ascontiguousarray(traj.obstacle_positions).tobytes())
    if traj.modes is not None:
        h.update(np.ascontiguousarray(traj.modes).tobytes())
    return h.hexdigest()


def test_same_seed_same_trajectory() -> None:
    world = random_world(3, n_robots=40, n_moving=8, size=32)
    plan = PLANNERS.get("astar")().plan(world, rng=0)
    runs = [Simulator(world, CatSwarmController(), plan, seed=s, max_steps=80).run() for s in (5, 5, 6)]
    assert trajectory_hash(runs[0]) == trajectory_hash(runs[1])
    assert trajectory_hash(runs[0]) != trajectory_hash(runs[2])  # the seed matters (obstacles, ties)




def test_reproduce_jaleel2016_writes_the_table_and_figures(tmp_path) -> None:
    from swarmpath.registry import REPRODUCTIONS

    calls = []
    report = REPRODUCTIONS.get("jaleel2016")(tmp_path, runs=2, progress=lambda d, t: calls.append((d, t)))
    text = report.read_text()
    assert "## Table 1 in kind (2 runs)" in text and "| R12 |" in text
    assert "collision-free runs (robot-robot, robot-static, robot-moving) | 1/1 (claimed) | 2/2 |" in text
    for png in ("jaleel2016-paths-before-after.png", "jaleel2016-behaviours.png", "jaleel2016-length-change.png"):
        assert (tmp_path / png).stat().st_size > 10_000
    assert calls[-1][0] == calls[-1][1]
