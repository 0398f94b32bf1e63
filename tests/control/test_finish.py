"""Finishing together (swarmpath.control.finish): the finishing step is taken exactly when the
simulator's checker finds no contact in the robots' move of that step, and it ends runs among
never-stopping obstacles with every robot home and no contact."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.finish import finish_positions
from swarmpath.errors import ConfigError, ScenarioError
from swarmpath.sim.collisions import step_contacts
from swarmpath.sim.stepper import WorldStepper
from swarmpath.world import Circle, Rect, RectBounds, Robot, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import Bounce8, MovingObstacle, RandomWalk
from swarmpath.world.static_map import StaticMap

S2 = float(np.sqrt(2))


def random_case(rng: np.random.Generator, radius: float) -> World | None:
    """A 7 x 7 grid with a few blocked cells, 4 robots whose goals lie one grid move (or two)
    from their starts, and 3 moving blocks or discs; None when the draw is not a valid world."""
    size = 7
    blocked = rng.random((size, size)) < 0.12
    free = np.argwhere(~blocked)[:, ::-1]
    if len(free) < 12:
        return None
    pick = free[rng.choice(len(free), size=7, replace=False)]
    starts = pick[:4]
    moves = GRID_MOVES[rng.integers(0, 9, size=4)] * rng.choice([1, 1, 1, 2], size=4)[:, None]
    goals = np.clip(starts + moves, 0, size - 1)
    robots = tuple(Robot(f"r{i}", tuple(starts[i] + 0.5), tuple(goals[i] + 0.5), radius, S2) for i in range(4))
    moving = []
    for k, c in enumerate(pick[4:]):
        shape = Rect((-0.5, -0.5), (0.5, 0.5)) if k % 2 == 0 else Circle((0.0, 0.0), 0.45)
        motion = RandomWalk() if k % 2 == 0 else Bounce8()
        moving.append(MovingObstacle(f"m{k}", shape, tuple(c + 0.5), (1.0, 0.0), motion))
    try:
        return World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), moving_obstacles=tuple(moving),
                     robots=robots, name="finish-case")
    except (ConfigError, ScenarioError):
        return None


@pytest.mark.parametrize("radius", [0.0, 0.3])
def test_finishing_step_is_taken_exactly_when_the_checker_finds_no_contact(radius) -> None:
    """Over many random worlds and steps: finish_positions returns the goals if and only if
    moving every robot to its goal in this step is within reach and the checker finds no
    contact (steps at which an obstacle already ran into a standing robot, phase 1, which
    happens whatever the robots do, are skipped)."""
    rng = np.random.default_rng(7)
    taken = refused = 0
    for _ in range(400):
        world = random_case(rng, radius)
        if world is None:
            continue
        stepper = WorldStepper(world, record=False)
        stepper.reset(int(rng.integers(1000)))
        for _ in range(3):
            stepper.begin_step()
            obs = stepper.observation()
            home = finish_positions(world, obs)
            goals = world.goals
            in_reach = np.all(np.linalg.norm(goals - obs.positions, axis=1) <= world.max_speeds * world.dt)
            contacts = step_contacts(world, obs.step, obs.positions, goals, obs.obstacle_previous,
                                     obs.obstacle_positions)
            if any(c.detail == "obstacle moved into robot" for c in contacts):
                # the checker keeps one contact per robot and obstacle in a step (the first,
                # phase 1), which would hide a phase-2 contact with the same obstacle
                stepper.end_step(obs.positions)
                continue
            own = contacts
            all_home = bool(np.all(obs.at_goal))
            expected = in_reach and not own and not all_home
            assert (home is not None) == expected, (world.robots, obs.obstacle_positions, own)
            if home is not None:
                np.testing.assert_array_equal(home, goals)
                taken += 1
            else:
                refused += 1
            stepper.end_step(obs.positions)    # stand still and look again next step
    assert taken > 20 and refused > 20     # both outcomes were exercised


def test_no_finish_when_a_robot_is_out_of_reach_or_two_robots_would_swap() -> None:
    robots = (Robot("a", (1.5, 1.5), (2.5, 1.5), 0.0, 1.0), Robot("b", (2.5, 1.5), (1.5, 1.5), 0.0, 1.0))
    world = World(RectBounds(6, 6), static_map=StaticMap(np.zeros((6, 6), bool), 1.0),
                  moving_obstacles=(MovingObstacle("m", Rect((-0.5, -0.5), (0.5, 0.5)), (5.5, 5.5), (0.0, 1.0),
                                                   RandomWalk()),), robots=robots, name="swap")
    stepper = WorldStepper(world)
    stepper.reset(0)
    stepper.begin_step()
    assert finish_positions(world, stepper.observation()) is None       # a swap
    far = world.replace(robots=(Robot("a", (1.5, 1.5), (3.5, 1.5), 0.0, 1.0),))
    stepper = WorldStepper(far)
    stepper.reset(0)
    stepper.begin_step()
    assert finish_positions(far, stepper.observation()) is None         # two cells away


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
@pytest.mark.parametrize("hover", [-1, 1.5, "near", True])
def test_a_bad_hover_is_one_clear_error(controller, hover) -> None:
    from swarmpath.registry import CONTROLLERS

    world = next(w for w in (random_case(np.random.default_rng(s), 0.0) for s in range(50)) if w is not None)
    with pytest.raises(ConfigError, match="hover must be a whole number"):
        CONTROLLERS.get(controller)(hover=hover).reset(world, None, np.random.default_rng(0))


@pytest.mark.parametrize("radius", [0.0, 0.3])
def test_a_gathering_step_is_safe_and_its_chance_of_the_finish_is_right(radius) -> None:
    """Over many random worlds and steps, whenever gathering_positions proposes a step: every
    robot ends it within one move of its goal, the step itself has no contact by the checker,
    no possible next step of the obstacles (sampled from their own motion models) runs into a
    gathered robot, and the share of sampled next steps in which every robot can then step
    home without contact is at least the chance it reports, and close to it (the walkers and
    bouncers here are independent, so the chance is exact)."""
    from swarmpath.control.finish import gathering_positions
    from swarmpath.control.hazards import ObstacleForecast
    from swarmpath.control.pibt.core import static_moves
    from swarmpath.world.moving import advance_obstacles

    rng = np.random.default_rng(11)
    proposed = 0
    gaps = []
    for _ in range(3000):
        world = random_case(rng, radius) if proposed < 40 else None
        if world is None:
            continue
        grid = world.grid()
        forecast = ObstacleForecast(world, grid, radius)
        moves = static_moves(grid.blocked, 8)
        stepper = WorldStepper(world, record=False)
        stepper.reset(int(rng.integers(1000)))
        for _ in range(3):
            stepper.begin_step()
            obs = stepper.observation()
            found = gathering_positions(world, obs, forecast, grid, moves, depth=3)
            if found is None:
                stepper.end_step(obs.positions)
                continue
            mid, chance = found
            now = step_contacts(world, obs.step, obs.positions, mid, obs.obstacle_previous, obs.obstacle_positions)
            if any(c.detail == "obstacle moved into robot" for c in now):
                stepper.end_step(obs.positions)   # hit before anyone moved: not the step's doing
                continue
            assert now == [], now
            cells, goal_cells = grid.cell_of(mid), grid.cell_of(world.goals)
            assert np.abs(cells - goal_cells).max() <= 1
            assert np.all(np.linalg.norm(world.goals - mid, axis=1) <= world.max_speeds * world.dt + 1e-9)
            samples = 100
            outcomes: dict[bytes, list] = {}      # the obstacles' next positions drawn, and how often
            for k in range(samples):
                after = advance_obstacles(world, stepper.state_, np.random.default_rng(k)).positions
                outcomes.setdefault(after.tobytes(), [after, 0])[1] += 1
            finished = 0
            for after, count in outcomes.values():
                standing = step_contacts(world, obs.step + 1, mid, mid, obs.obstacle_positions, after)
                assert standing == [], standing
                home = step_contacts(world, obs.step + 1, mid, world.goals, obs.obstacle_positions, after)
                finished += count * (home == [])
            share = finished / samples
            assert share >= chance - 4 * np.sqrt(chance * (1 - chance) / samples) - 1e-9, (share, chance)
            gaps.append(share - chance)
            proposed += 1
            stepper.end_step(mid)
    assert proposed >= 40
    assert abs(float(np.mean(gaps))) < 0.03


def off_centre_disc_world(seed: int, size: int = 20, n: int = 40, radius: float = 0.3, offset: float = 0.2,
                          moving: int = 0) -> World:
    """A size x size map with 12 % blocked cells, ``n`` disc robots of ``radius`` on distinct
    cells, each goal its cell's centre moved by up to ``offset`` on each axis (the disc stays
    inside its cell's square), and ``moving`` 1-cell blocks (bounce8 and random-walk in turn)."""
    from swarmpath.search import distance_field

    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < 0.12
    free = np.argwhere(~blocked)
    y, x = free[rng.integers(len(free))]
    connected = np.argwhere(np.isfinite(distance_field(blocked, (int(x), int(y)))))[:, ::-1]
    pick = connected[rng.choice(len(connected), size=2 * n + moving, replace=False)]
    shift = rng.uniform(-offset, offset, (n, 2))
    robots = tuple(Robot(f"r{i}", tuple(pick[i] + 0.5), tuple(pick[n + i] + 0.5 + shift[i]), radius, S2)
                   for i in range(n))
    obstacles = tuple(MovingObstacle(f"m{k}", Rect((-0.5, -0.5), (0.5, 0.5)), tuple(c + 0.5), (1.0, 0.0),
                                     RandomWalk() if k % 2 else Bounce8())
                      for k, c in enumerate(pick[2 * n:]))
    return World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), moving_obstacles=obstacles,
                 robots=robots, name=f"off-centre-{seed}")


@pytest.mark.parametrize("controller,params", [("pibt", {}), ("cat-swarm", {}),
                                               ("fish-swarm", {"food": "distance-field"})])
def test_disc_robots_with_goals_off_the_centre_all_arrive(controller, params) -> None:
    """Disc robots (radius 0.3) whose goals lie up to 0.2 off their cells' centres: resting on
    such a goal a disc reaches into the next cells, where its neighbours' centre-to-centre
    moves graze it, and those moves were withheld step after step until the run deadlocked
    (0 of 4 runs of 100 robots on 64 x 64 maps). They now wait on the centre and step home with
    the finishing step, or alone once no other robot is within two cells: every run ends with
    every robot home and no contact, checked by the independent checker. (fish-swarm: before
    robots resting off the centre were checked exactly, a neighbour's diagonal grazed one.)"""
    from swarmpath.registry import CONTROLLERS
    from swarmpath.sim import Simulator
    from swarmpath.testing import validate_trajectory

    for seed in range(5):
        world = off_centre_disc_world(seed)
        traj = Simulator(world, CONTROLLERS.get(controller)(**params), seed=seed).run()
        at = np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9
        assert validate_trajectory(world, traj) == [] and not traj.contacts, (controller, seed)
        assert traj.status == "all_reached" and at.all(), (controller, seed, traj.status, int(at.sum()))


def test_a_disc_waits_on_its_goal_cells_centre_only_while_another_robot_is_near() -> None:
    """held_discs: a robot of ``hold`` waits while another robot is within two cells
    (Chebyshev) of its cell, not when the nearest is three away, and no one waits once
    every robot is in its goal cell."""
    from swarmpath.control.finish import held_discs

    hold = np.array([True, False, True])
    goals = np.array([[5, 5], [0, 0], [9, 9]])
    cells = np.array([[5, 5], [7, 3], [9, 9]])      # robot 1 two cells from robot 0, three from robot 2
    assert held_discs(hold, cells, goals, (12, 12)).tolist() == [True, False, False]
    cells = np.array([[5, 5], [8, 8], [9, 9]])      # now within two cells of robot 2, three of robot 0
    assert held_discs(hold, cells, goals, (12, 12)).tolist() == [False, False, True]
    assert not held_discs(hold, goals, goals, (12, 12)).any()
