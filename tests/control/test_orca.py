"""The ``orca`` controller: acceptance runs (antipodal circle, rooms with doors, MovingAI
maps, moving obstacles of every motion model), determinism, the exact per-step check, visible
deadlocks, parameters. Every trajectory is re-checked by validate_trajectory."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.orca import ORCAController, ORCAParams, ORCASolver
from swarmpath.control.orca.obstacles import forecast_obstacles
from swarmpath.errors import ConfigError
from swarmpath.registry import CONTROLLERS, PLANNERS
from swarmpath.sim.collisions import ROBOT_STATIC
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import ALL_REACHED
from swarmpath.testing import validate_trajectory
from swarmpath.world import Circle, Rect, RectBounds, Robot, World
from swarmpath.world.generators import (
    antipodal,
    movingai,
    rooms_with_doors,
    with_obstacles,
)
from swarmpath.world.move_rules import NO_CONFLICT, move_conflicts


def run(world, controller=None, plan=None, seed=0, max_steps=None):
    return Simulator(world, controller or ORCAController(), plan, seed=seed, max_steps=max_steps).run()


def arrived(world, traj) -> int:
    return int(np.sum(np.linalg.norm(traj.positions[-1] - world.goals, axis=1) <= 1e-9))


# ------------------------------------------------------------------------------ registry and parameters
def test_registered_with_its_capabilities():
    cls = CONTROLLERS.get("orca")
    assert cls is ORCAController
    caps = cls.capabilities
    assert caps.continuous and caps.moving_obstacles and caps.multi_robot and not caps.needs_plan


@pytest.mark.parametrize("kwargs", [{"time_horizon": 0}, {"obstacle_time_horizon": -1}, {"neighbour_distance": 0},
                                    {"max_neighbours": -1}, {"safety_margin": -0.1}, {"side_bias": 2.0},
                                    {"patience": 0}, {"yield_after": -1}])
def test_bad_parameters_raise_config_error(kwargs):
    with pytest.raises(ConfigError):
        ORCAController(**kwargs)


# ------------------------------------------------------------------------------ antipodal circle
@pytest.mark.parametrize("n", [24, 100])
def test_antipodal_circle_all_arrive_without_contact(n):
    world = antipodal(n)
    traj = run(world, max_steps=1500)
    assert traj.status == ALL_REACHED and arrived(world, traj) == n
    assert traj.contacts == []
    assert validate_trajectory(world, traj) == []


def test_same_seed_same_trajectory_bit_for_bit():
    world = with_obstacles(rooms_with_doors(), "random-walk", 3, seed=4)
    a = run(world, seed=7, max_steps=60)
    b = run(world, seed=7, max_steps=60)
    assert np.array_equal(a.positions, b.positions)
    assert a.events == b.events


def test_head_on_pair_passes_on_a_consistent_side():
    world = World(RectBounds(12, 6), robots=(Robot("a", (1, 3), (11, 3), 0.4, 1.0), Robot("b", (11, 3), (1, 3), 0.4, 1.0)))
    traj = run(world)
    assert traj.status == ALL_REACHED and validate_trajectory(world, traj) == []
    # both swerve to their own right: a (heading +x) goes below, b (heading -x) above
    mid = traj.positions[np.argmin(np.abs(traj.positions[:, 0, 0] - traj.positions[:, 1, 0]))]
    assert mid[0, 1] < 3 < mid[1, 1]


def test_point_robots_on_a_grid_never_share_or_swap_cells():
    s2 = float(np.sqrt(2))
    world = World(RectBounds(8, 8), robots=(Robot("a", (0.5, 3.5), (7.5, 3.5), 0.0, s2),
                                            Robot("b", (7.5, 3.5), (0.5, 3.5), 0.0, s2),
                                            Robot("c", (3.5, 0.5), (3.5, 7.5), 0.0, s2)))
    traj = run(world)
    assert traj.status == ALL_REACHED and validate_trajectory(world, traj) == []


# ------------------------------------------------------------------------------ static geometry
def test_rooms_with_doors_all_arrive():
    world = rooms_with_doors()
    traj = run(world)
    assert traj.status == ALL_REACHED and validate_trajectory(world, traj) == []


@pytest.mark.parametrize("name,radius,n", [("room-32-32-4", 0.4, 20), ("room-32-32-4", 0.3, 20),
                                           ("maze-32-32-2", 0.4, 20), ("random-32-32-10", 0.4, 10),
                                           ("den312d", 0.3, 10)])
def test_movingai_maps_all_arrive(name, radius, n):
    """Robots parked on their goals in doors (room-32-32-4 with 20 robots) back away from a
    stalled robot and return: everyone arrives."""
    world = movingai(name, n, radius=radius)
    traj = run(world)
    assert traj.status == ALL_REACHED and arrived(world, traj) == n
    assert validate_trajectory(world, traj) == []


def test_follows_an_offline_plan():
    world = movingai("maze-32-32-2", 4)
    plan = PLANNERS.get("astar")().plan(world, rng=0)
    traj = run(world, plan=plan)
    assert traj.status == ALL_REACHED and validate_trajectory(world, traj) == []


def test_polygon_obstacles_and_a_circular_workspace():
    from swarmpath.world import CircleBounds, Polygon

    world = World(CircleBounds((6, 6), 6), obstacles=(Polygon(((4, 5), (8, 5), (6, 8))), Circle((6, 3), 0.8)),
                  robots=(Robot("a", (6, 10.5), (6, 1.5), 0.3, 0.8), Robot("b", (6, 1.2), (6, 10.8), 0.3, 0.8),
                          Robot("c", (1.5, 6), (10.5, 6), 0.3, 0.8)))
    traj = run(world)
    assert traj.status == ALL_REACHED and validate_trajectory(world, traj) == []


# ------------------------------------------------------------------------------ moving obstacles
@pytest.mark.parametrize("kind", ["redraw", "turn-every", "random-walk", "waypoints"])
@pytest.mark.parametrize("where", ["rooms", "room-32-32-4"])
def test_moving_obstacles_never_push_robots_into_walls(kind, where):
    base = rooms_with_doors() if where == "rooms" else movingai("room-32-32-4", 4)
    for seed in range(10):
        world = with_obstacles(base, kind, 3, seed)
        traj = run(world, seed=seed, max_steps=40)
        kinds = [c.kind for c in traj.contacts]
        assert ROBOT_STATIC not in kinds, f"seed {seed}"
        assert "robot_robot" not in kinds, f"seed {seed}"
        assert not [e for e in traj.events if e["kind"] == "invalid_move"]
        # the independent re-check agrees: nothing but obstacles reaching robots
        assert all("robot_moving" in v.problem for v in validate_trajectory(world, traj))
        # phase 2 is entirely the robot's choice: it never walks into a footprint
        assert not [c for c in traj.contacts if c.detail == "robot moved into obstacle"
                    and c.robot not in _hit_in_phase1(world, traj, c.step)]


def slow_redraw_room(seed: int) -> World:
    """A walled 12 x 12 room with a wall stub, four robots of speed 0.5 (half a cell per step)
    and three redraw obstacles: a robot must cross the band between two cells, where some
    redraw could land next to it, in steps shorter than the band."""
    base = World(RectBounds(12, 12), obstacles=(Rect((5.5, 0), (6.5, 5)),),
                 robots=tuple(Robot(f"r{i}", (1.0, 2.0 + 2 * i), (11.0, 10.0 - 2 * i), 0.3, 0.5) for i in range(4)))
    return with_obstacles(base, "redraw", 3, seed)


def test_slow_robots_get_past_redraw_obstacles():
    """Standing still is always clear of a redraw's next jump here, so the exact check used
    to keep such robots still for good (deadlock); a robot held still only by the obstacles'
    next moves now tries the ring of sideways moves for one that keeps clear and makes
    progress."""
    for seed in range(5):
        world = slow_redraw_room(seed)
        traj = run(world, seed=seed, max_steps=300)
        assert traj.status == ALL_REACHED and traj.contacts == [], f"seed {seed}"
        assert validate_trajectory(world, traj) == []


def _hit_in_phase1(world, traj, step):
    from swarmpath.sim.collisions import robot_moving_contacts

    pos, obs = traj.positions, traj.obstacle_positions
    radii = world.radii
    same = robot_moving_contacts(world, pos[step - 1], pos[step - 1], obs[step - 1], obs[step], radii)
    return {i for i, _, _ in same}


# ------------------------------------------------------------------------------ the exact check
@pytest.mark.parametrize("seed", range(6))
def test_make_safe_leaves_no_conflict_and_standing_still_is_safe(seed):
    """Random crowds of discs and point robots with random moves (many conflicting): the
    checked moves conflict with no pair by the simulator's rules and never enter a wall; a
    robot whose move was cut to nothing stands where it was."""
    rng = np.random.default_rng(seed)
    walls = (Rect((4, 4), (6, 6)), Circle((2, 8), 1.0))
    robots, pts = [], []
    while len(robots) < 40:
        p = rng.uniform(0.5, 9.5, 2)
        r = 0.0 if len(robots) % 5 == 0 else float(rng.uniform(0.1, 0.4))
        probe = World(RectBounds(10, 10), obstacles=walls)
        if probe.static_clearance(p[None], r)[0] <= 0.01:
            continue
        if pts and np.min(np.linalg.norm(np.array(pts) - p, axis=1) - [q.radius + r for q in robots]) <= 0.01:
            continue
        if r == 0 and pts and np.any(np.all(np.floor(np.array(pts)) == np.floor(p), axis=1)):
            continue
        robots.append(Robot(f"r{len(robots)}", tuple(p), tuple(p), r, 1.0))
        pts.append(p)
    world = World(RectBounds(10, 10), obstacles=walls, robots=tuple(robots))
    solver = ORCASolver(ORCAParams())
    solver.reset(world)
    p0 = world.starts
    p1 = p0 + rng.uniform(-0.7, 0.7, p0.shape)
    safe = solver.make_safe(p0, p1, None)
    out = safe.positions
    i, j = np.triu_indices(len(p0), 1)
    kinds = move_conflicts(p0[i], out[i], p0[j], out[j], world.radii[i], world.radii[j], world.resolution)
    assert np.all(kinds == NO_CONFLICT)
    assert not world.static_hits(p0, out, world.radii).any()
    still = safe.scale == 0
    assert np.array_equal(out[still], p0[still])
    assert still.any() and (safe.scale == 1).any()       # the instance had conflicts and free moves


def test_forecast_feeds_the_firm_lines():
    """A robot right in the path of a bouncing obstacle moves out of its next sweep."""
    from swarmpath.world import Bounce
    from swarmpath.world.moving import MovingObstacle

    world = World(RectBounds(10, 10), robots=(Robot("a", (5.0, 5.0), (5.0, 9.0), 0.3, 1.0),),
                  moving_obstacles=(MovingObstacle("m", Circle((0, 0), 0.4), (3.8, 5.0), (0.5, 0.0)),))
    solver = ORCASolver()
    solver.reset(world)
    now, prev = np.array([[4.3, 5.0]]), np.array([[3.8, 5.0]])
    fc = forecast_obstacles(world, now, prev, 1, 1.0)
    v, status = solver.velocities(world.starts, np.zeros((1, 2)), np.array([[-1.0, 0.0]]), fc)
    end = world.starts[0] + v[0]
    seg = np.linalg.norm(end - np.clip(end, [4.3, 5.0], [4.8, 5.0]))
    assert seg >= 0.3 + 0.4 - 1e-9
    assert status[0] == 0
    assert Bounce().kind == "bounce"


# ------------------------------------------------------------------------------ deadlocks are visible
def test_a_deadlock_that_remains_is_reported():
    """Two robots head-on in a closed corridor one robot wide cannot pass: the run ends
    without success and the controller says so."""
    walls = (Rect((0, 0), (12, 2)), Rect((0, 3), (12, 5)))
    world = World(RectBounds(12, 5), obstacles=walls,
                  robots=(Robot("a", (1.5, 2.5), (10.5, 2.5), 0.45, 1.0), Robot("b", (10.5, 2.5), (1.5, 2.5), 0.45, 1.0)))
    traj = run(world, max_steps=200)
    assert traj.status != ALL_REACHED
    assert any(e["kind"] == "deadlock" for e in traj.events)
    assert validate_trajectory(world, traj) == []
