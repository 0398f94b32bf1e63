"""The environment's parts: the step loop equals the simulator's, actions decode and encode as
documented, observations show what is there, rewards and infos count what the checker found.
(These parts need neither gymnasium nor pettingzoo.)"""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.base import Controller, Decision
from swarmpath.env.actions import ContinuousActions, GridActions
from swarmpath.env.core import EnvCore
from swarmpath.env.observations import (
    ContinuousObservations,
    FootprintRaster,
    GridObservations,
)
from swarmpath.env.options import EnvOptions, Rewards
from swarmpath.errors import ConfigError
from swarmpath.registry import CONTROLLERS
from swarmpath.rng import make_rng
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.stepper import WorldStepper, validate_moves
from swarmpath.world import (
    Circle,
    MovingObstacle,
    Rect,
    RectBounds,
    Robot,
    World,
    load_scenario,
)


def small_grid_world(**robot) -> World:
    """A 6 x 4 grid, a wall cell at (2, 1); one or two point robots."""
    blocked = (Rect((2, 1), (3, 2)),)
    robots = (Robot("a", (0.5, 0.5), (4.5, 0.5), 0.0, robot.get("speed", 1.5)),
              Robot("b", (0.5, 2.5), (5.5, 3.5), 0.0, 1.5))
    return World(RectBounds(6, 4), obstacles=blocked, robots=robots, name="small")


# ---------------------------------------------------------------- the step loop
def test_validate_moves_rejects_long_and_non_finite_moves() -> None:
    rng = np.random.default_rng(0)
    for _ in range(50):
        pos = rng.uniform(0, 5, (7, 2))
        proposed = pos + rng.normal(0, 1.2, (7, 2))
        proposed[rng.random(7) < 0.2] = np.nan
        speeds = rng.uniform(0.5, 2.0, 7)
        events: list = []
        new, rejected = validate_moves(proposed, pos, speeds, 3, events)
        length = np.linalg.norm(proposed - pos, axis=1)
        bad = ~np.isfinite(length) | (length > speeds * (1 + 1e-9) + 1e-12)
        assert np.array_equal(rejected, bad) and rejected.sum() == len(events)
        assert np.array_equal(new[bad], pos[bad]) and np.array_equal(new[~bad], proposed[~bad])
        assert all(e["kind"] == "invalid_move" and e["step"] == 3 for e in events)


class Recorder(Controller):
    """pibt, remembering the observations it was given."""

    def __init__(self):
        self.inner = CONTROLLERS.get("pibt")()
        self.seen = []

    def reset(self, world, plan, rng):
        self.inner.reset(world, plan, rng)

    def act(self, obs):
        self.seen.append(obs)
        return self.inner.act(obs)


def test_the_stepper_driven_by_a_controller_is_the_simulator() -> None:
    from swarmpath.world import world_from_movingai
    from swarmpath.world.generators import with_obstacles

    world = with_obstacles(world_from_movingai("room-32-32-4.map", "room-32-32-4-even-10.scen", 8), "redraw", 4, 1)
    ref = Recorder()
    traj = Simulator(world, ref, seed=9).run()
    ctrl = Recorder()
    ctrl.reset(world, None, make_rng(9, "controller"))
    st = WorldStepper(world)
    st.reset(9)
    for _ in range(traj.n_steps):
        st.begin_step()
        st.end_step(ctrl.act(st.observation()).positions)
    assert np.array_equal(st.trajectory().positions, traj.positions)
    assert np.array_equal(st.trajectory().obstacle_positions, traj.obstacle_positions)
    for a, b in zip(ref.seen, ctrl.seen):
        assert a.step == b.step and np.array_equal(a.obstacle_previous, b.obstacle_previous)
        assert np.array_equal(a.sensed.robot_pairs, b.sensed.robot_pairs)


def test_the_stepper_refuses_steps_out_of_order() -> None:
    st = WorldStepper(small_grid_world())
    st.reset(0)
    with pytest.raises(ConfigError, match="begin_step"):
        st.end_step(st.positions)
    st.begin_step()
    with pytest.raises(ConfigError, match="twice"):
        st.begin_step()


# ---------------------------------------------------------------- actions
def test_grid_actions_go_to_neighbour_centres_and_the_exact_goal() -> None:
    world = World(RectBounds(4, 4), robots=(Robot("a", (1.0, 1.0), (2.3, 1.7), 0.0, 1.5),), name="off-centre")
    ga = GridActions(world)
    pos = world.starts                                   # on a cell corner: cell (1, 1)
    assert np.array_equal(ga.decode(pos, np.array([0])), [[1.5, 1.5]])      # stay settles on the centre
    assert np.array_equal(ga.decode(pos, np.array([1])), [[2.3, 1.7]])      # +x enters the goal cell
    assert np.array_equal(ga.decode(pos, np.array([6])), [[0.5, 0.5]])      # -x -y
    actions, exact = ga.encode(pos, np.array([[2.3, 1.7]]))
    assert actions.tolist() == [1] and exact.all()
    actions, exact = ga.encode(pos, pos)                 # held off the centre: no action does that
    assert not exact.any()


def test_four_connected_actions() -> None:
    ga = GridActions(small_grid_world(), connectivity=4)
    assert ga.n_actions == 5
    pos = small_grid_world().starts
    assert np.array_equal(ga.decode(pos, np.array([1, 2])), [[1.5, 0.5], [0.5, 3.5]])
    _, exact = ga.encode(pos, pos + 1.0)                 # a diagonal is not among the actions
    assert not exact.any()


def test_grid_action_mask() -> None:
    world = small_grid_world()
    ga = GridActions(world)
    mask = ga.mask(np.array([[1.5, 1.5], [0.5, 2.5]]))
    # from (1, 1): +x is the wall cell (2, 1); the diagonals (1,1)->(2,2) and (2,0) cut its corner
    assert mask[0].tolist() == [True, False, False, True, True, True, True, True, False]
    # from (0, 2): nothing to the left
    assert not mask[1, 4] and not mask[1, 5] and not mask[1, 6] and mask[1, 1]


def test_continuous_actions_clip_snap_and_reproduce_proposals() -> None:
    world = load_scenario("prediction2013")
    ca = ContinuousActions(world)
    n = world.n_robots
    pos = world.starts
    out = ca.decode(pos, np.tile([3.0, 4.0], (n, 1)))          # clipped to [-1, 1], then norm 1
    assert np.allclose(np.linalg.norm(out - pos, axis=1), 0.5)
    near = world.goals + [0.03, 0.0]
    snapped = ca.decode(near, np.tile([-0.01, 0.0], (n, 1)))   # ends 0.025 from the goal < 0.05
    assert np.array_equal(snapped, world.goals)
    rng = np.random.default_rng(1)
    for _ in range(200):
        p = rng.uniform(1, 30, (n, 2))
        d = rng.normal(0, 1, (n, 2))
        d *= (rng.uniform(0, 0.5, n) / np.linalg.norm(d, axis=1))[:, None]
        actions, exact = ca.encode(p, p + d)
        assert exact.all() and np.array_equal(ca.decode(p, actions), p + d)
        assert np.all(np.abs(actions) <= 1)
    actions, exact = ca.encode(pos, pos + [0.6, 0.0])          # longer than the reach of 0.5
    assert not exact.any()


# ---------------------------------------------------------------- observations
def test_grid_patch_channels() -> None:
    world = small_grid_world()
    ob = MovingObstacle("m", Rect((-0.5, -0.5), (0.5, 0.5)), (1.5, 3.5), (0.0, 0.0))
    world = world.replace(moving_obstacles=(ob,))
    ga = GridActions(world)
    go = GridObservations(world, ga.grid, view=2)
    cells = ga.cells(world.starts)
    patch, goal = go.observe(cells, world.starts, world.goals, ga.goal_cells, np.array([[1.5, 3.5]]),
                             np.array([[1.5, 2.5]]))
    assert patch.shape == (2, 5, 5, 5)
    a = patch[0]                                  # robot a at cell (0, 0): patch[c, 2 + dy, 2 + dx]
    assert a[0, 2, 0] == 1 and a[0, 0, 2] == 1    # outside the map is blocked
    assert a[0, 3, 4] == 1                        # the wall cell (2, 1)
    assert a[1, 4, 2] == 1 and a[1].sum() == 1    # robot b at (0, 2), not oneself
    assert a[4, 2, 4] == 1 and a[4].sum() == 1    # goal (4, 0) is 4 cells right: on the border
    b = patch[1]                                  # robot b at (0, 2); the obstacle at (1, 3), before (1, 2)
    assert b[2, 3, 3] == 1 and b[2].sum() == 1
    assert b[3, 2, 3] == 1 and b[3].sum() == 1
    assert a[2].sum() == 0                        # out of a's view
    assert goal[0].tolist() == pytest.approx([1.0, 0.0, 4 / np.hypot(6, 4)])


def test_footprint_raster() -> None:
    world = World(RectBounds(6, 6), moving_obstacles=(
        MovingObstacle("disc", Circle((0, 0), 0.6), (2.5, 2.5)),
        MovingObstacle("box", Rect((-1.0, -0.5), (1.0, 0.5)), (4.0, 4.5)),
    ), robots=(Robot("r", (0.5, 0.5), (5.5, 0.5)),))
    fr = FootprintRaster(world, world.grid())
    cells = fr.cells(np.array([[2.5, 2.5], [4.0, 4.5]]))
    assert set(map(tuple, np.argwhere(cells)[:, ::-1].tolist())) == {
        (2, 2), (1, 2), (3, 2), (2, 1), (2, 3),           # the disc reaches 0.1 into the 4 neighbours
        (3, 4), (4, 4)}                                   # the box covers x in (3, 5), y in (4, 5)


def test_continuous_vector_sees_neighbours_obstacles_and_walls() -> None:
    world = load_scenario("prediction2013")
    st = WorldStepper(world)
    st.reset(0)
    st.begin_step()
    co = ContinuousObservations(world, 2, 1, 3, 6 * world.resolution)
    vec = co.observe(st.observation(), st.previous_positions)
    assert vec.shape == (6, co.size) and np.all(np.abs(vec) <= 1)
    # R1 starts at (1.5, 1.5): the walls are within 3, no robot is (R5 is 6.6 away)
    r1 = vec[0]
    assert r1[6] == 0 and r1[6 + 12] == 0
    static = r1[6 + 12 + 6:].reshape(3, 3)
    assert static[:, 0].tolist() == [1, 1, 1]
    assert r1[0:2].tolist() == pytest.approx([0.0, 1.0])            # the goal is straight down


# ---------------------------------------------------------------- rewards and infos
class Scripted(Controller):
    def __init__(self, moves):
        self.moves = moves

    def reset(self, world, plan, rng):
        self.k = 0

    def act(self, obs):
        self.k += 1
        return Decision(obs.positions + self.moves[self.k - 1])


def test_rewards_and_contact_counts() -> None:
    world = small_grid_world()
    weights = Rewards(progress=1.0, arrival=10.0, step=-0.1, robot_contact=-2.0, static_contact=-3.0,
                      moving_contact=-4.0, invalid_move=-5.0)
    core = EnvCore(world, EnvOptions(rewards=weights))
    core.reset(0)
    # a: +x into (1, 0) (progress 1 cell); b: +x +y 2 cells (rejected: reach 1.5)
    core.step(np.array([[1.5, 0.5], [2.5, 4.5]]))
    assert core.last_rejected_.tolist() == [False, True]
    assert core.last_rewards_ == pytest.approx([1.0 / 1.5 - 0.1, -0.1 - 5.0])
    # a: +x +y into the wall cell (2, 1): a static contact
    core.step(np.array([[2.5, 1.5], [0.5, 2.5]]))
    assert core.last_counts_[0].tolist() == [0, 1, 0]
    gained = np.hypot(3, 0) - np.hypot(2, 1)
    assert core.last_rewards_[0] == pytest.approx(gained / 1.5 - 0.1 - 3.0)
    rows = core.info_rows(np.array([0, 1]))
    assert rows[0]["robot_static"] == 1 and rows[0]["contacts_total"] == 1 and rows[1]["invalid_move"] is False


def test_arrival_terminates_and_parks_or_waits_for_all() -> None:
    world = World(RectBounds(4, 2), robots=(Robot("a", (0.5, 0.5), (1.5, 0.5)), Robot("b", (3.5, 1.5), (0.5, 1.5))),
                  name="two")
    core = EnvCore(world, EnvOptions())
    core.reset(0)
    core.step(np.array([[1.5, 0.5], [2.5, 1.5]]))
    assert core.terminated_.tolist() == [True, False] and core.live_.tolist() == [False, True]
    assert core.last_rewards_[0] == pytest.approx(1.0 / 1.5 + 10.0)
    core = EnvCore(world, EnvOptions(stay_arrived=True, max_steps=2))
    core.reset(0)
    core.step(np.array([[1.5, 0.5], [2.5, 1.5]]))
    assert core.terminated_.tolist() == [False, False]
    core.step(np.array([[1.5, 0.5], [1.5, 1.5]]))
    assert core.truncated_.tolist() == [True, True]


def test_grid_mode_needs_grid_robots() -> None:
    slow = small_grid_world(speed=0.5)
    assert EnvCore(slow, EnvOptions()).mode == "continuous"
    with pytest.raises(ConfigError, match="one grid cell per step"):
        EnvCore(slow, EnvOptions(mode="grid"))
