"""The safety layer (swarmpath.control.orca.SafetyLayer) in front of a naive "straight to the
goal" proposer, standalone; and the shared guidance (swarmpath.control.orca.Guidance)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.capabilities import Capabilities
from swarmpath.control.base import Controller, Decision
from swarmpath.control.orca import Guidance, SafetyLayer
from swarmpath.errors import ConfigError
from swarmpath.registry import PLANNERS
from swarmpath.sim.collisions import ROBOT_ROBOT, ROBOT_STATIC
from swarmpath.sim.simulator import Simulator
from swarmpath.testing import validate_trajectory
from swarmpath.world import Rect, RectBounds, Robot, World
from swarmpath.world.generators import (
    antipodal,
    crowd_crossing,
    movingai,
    rooms_with_doors,
    with_obstacles,
)


class StraightToGoal(Controller):
    """The naive proposer: every robot heads straight for its goal at full speed, through
    walls and other robots alike; optionally behind the safety layer."""

    capabilities = Capabilities(continuous=True)

    def __init__(self, safety: bool = True):
        self.safety = safety

    def reset(self, world, plan, rng):
        self.goals_ = world.goals
        self.reach_ = world.max_speeds * world.dt
        self.layer_ = SafetyLayer() if self.safety else None
        if self.layer_ is not None:
            self.layer_.reset(world)
        self.adjusted_ = 0

    def act(self, obs):
        d = self.goals_ - obs.positions
        dist = np.linalg.norm(d, axis=1)
        f = np.minimum(1.0, self.reach_ / np.maximum(dist, 1e-12))
        proposed = np.where((dist <= self.reach_)[:, None], self.goals_, obs.positions + d * f[:, None])
        if self.layer_ is None:
            return Decision(proposed)
        positions, adjusted = self.layer_.safe_positions(obs, proposed)
        self.adjusted_ += int(adjusted.sum())
        return Decision(positions, events=tuple(self.layer_.events(adjusted)))


def run(world, ctrl, seed=0, max_steps=None):
    return Simulator(world, ctrl, None, seed=seed, max_steps=max_steps).run()


def test_the_naive_proposer_collides_and_the_layer_removes_every_contact():
    """The layer makes the naive proposer safe, not clever: on the antipodal circle the
    robots meet without contact and stall in the middle (breaking that symmetry is the
    controller's job, as the orca controller does)."""
    world = antipodal(24)
    bare = run(world, StraightToGoal(safety=False), max_steps=80)
    assert any(c.kind == ROBOT_ROBOT for c in bare.contacts)
    ctrl = StraightToGoal()
    safe = run(world, ctrl, max_steps=300)
    assert safe.contacts == [] and validate_trajectory(world, safe) == []
    assert ctrl.adjusted_ > 0
    # on four crossing robots with room to swerve, everyone arrives
    world = World(RectBounds(12, 12), robots=(Robot("a", (1, 6), (11, 6), 0.3, 1.0), Robot("b", (6, 1), (6.5, 11), 0.3, 1.0),
                                              Robot("c", (11, 5), (1, 7), 0.3, 1.0), Robot("d", (5, 11), (7, 1), 0.3, 1.0)))
    traj = run(world, StraightToGoal(), max_steps=200)
    assert traj.contacts == [] and traj.status == "all_reached"


def test_never_through_a_wall_nor_out_of_the_workspace():
    world = rooms_with_doors()
    bare = run(world, StraightToGoal(safety=False), max_steps=40)
    assert any(c.kind == ROBOT_STATIC for c in bare.contacts)
    traj = run(world, StraightToGoal(), max_steps=80)
    assert validate_trajectory(world, traj) == []
    world = movingai("maze-32-32-2", 10)
    traj = run(world, StraightToGoal(), max_steps=60)
    assert validate_trajectory(world, traj) == []


@pytest.mark.parametrize("kind", ["redraw", "turn-every", "random-walk", "waypoints"])
def test_moving_obstacles_never_push_through_walls(kind):
    for seed in range(3):
        world = with_obstacles(rooms_with_doors(), kind, 3, seed)
        traj = run(world, StraightToGoal(), seed=seed, max_steps=40)
        assert not [c for c in traj.contacts if c.kind in (ROBOT_STATIC, ROBOT_ROBOT)]


def test_a_safe_proposal_comes_back_unchanged_bit_for_bit():
    world = World(RectBounds(10, 10), robots=(Robot("a", (1.0, 1.0), (9.0, 1.0), 0.3, 1.0),
                                              Robot("b", (1.0, 9.0), (9.0, 9.0), 0.3, 1.0)))
    layer = SafetyLayer()
    layer.reset(world)
    from swarmpath.control.observation import Observation, SensingConfig
    from swarmpath.sim.sensing import sense

    pos = world.starts
    obs = Observation(1, 1.0, pos, world.goals, np.zeros(2, bool), np.zeros((0, 2)), np.zeros((0, 2)),
                      sense(pos, np.zeros((0, 2)), SensingConfig(), 1.0))
    proposed = pos + np.array([[0.7123456789, 0.1], [0.3, -0.55]])
    out, adjusted = layer.safe_positions(obs, proposed)
    assert np.array_equal(out, proposed) and not adjusted.any()
    # into the wall: shortened, flagged
    out, adjusted = layer.safe_positions(obs, pos + np.array([[-0.9, 0.0], [0.0, 0.9]]))
    assert adjusted.tolist() == [True, True]
    assert not world.static_hits(pos, out, world.radii).any()
    with pytest.raises(ConfigError):
        layer.safe_positions(obs, np.zeros((3, 2)))
    with pytest.raises(ConfigError):
        SafetyLayer(time_horizon=0)


def test_crowd_crossing_with_the_layer_has_no_wall_or_robot_contacts():
    for seed in range(3):
        world = crowd_crossing(10, seed)
        traj = run(world, StraightToGoal(), seed=seed, max_steps=120)
        assert not [c for c in traj.contacts if c.kind == ROBOT_STATIC]


# ------------------------------------------------------------------------------ guidance
def test_guidance_heads_straight_in_open_worlds_and_around_walls_otherwise():
    world = World(RectBounds(10, 10), obstacles=(Rect((4, 0), (5, 8)),),
                  robots=(Robot("a", (1.5, 1.5), (8.5, 1.5), 0.3, 1.0), Robot("b", (1.5, 9.0), (8.5, 9.0), 0.3, 1.0)))
    g = Guidance()
    g.reset(world)
    target, is_goal = g.targets(world.starts)
    assert is_goal.tolist() == [False, True]
    assert np.array_equal(target[1], world.goals[1])
    # robot a's steering point is visible and closer to the goal along the field
    assert not world.static_hits(world.starts[:1], target[:1], world.radii[:1]).any()
    at_target = g.remaining(np.vstack([target[0], world.starts[1]]))[0]
    assert at_target < g.remaining(world.starts)[0] - 3.0
    v = g.preferred_velocities(world.starts, world.max_speeds, 1.0)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), [1.0, 1.0])


def test_guidance_follows_a_plan_and_lands_on_the_goal():
    world = movingai("room-32-32-4", 3)
    plan = PLANNERS.get("astar")().plan(world, rng=0)
    g = Guidance()
    g.reset(world, plan)
    target, _ = g.targets(world.starts)
    for i in range(3):
        path = plan.paths[i]
        assert np.any(np.all(np.isclose(path, target[i]), axis=1)) or np.allclose(target[i], world.goals[i])
    # one step from the goal: exactly the velocity that lands on it
    near = world.goals - np.array([[0.05, 0.0], [0.0, 0.04], [0.03, 0.03]])
    v = g.preferred_velocities(near, world.max_speeds, 1.0)
    np.testing.assert_allclose(near + v, world.goals, atol=1e-12)


def test_guidance_rejects_bad_parameters():
    for kw in ({"window": 0}, {"lookahead": 0}, {"clearance": -1}, {"batch": 0}, {"straight_weight": 1.0}):
        with pytest.raises(ConfigError):
            Guidance(**kw)
