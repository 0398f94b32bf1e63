"""Priority yielding of :class:`~swarmpath.control.orca.coordination.Coordination`, shared by
every improved continuous controller: robots parked on their goals make way for a robot that
must pass, also when one parked robot stands in the way of another. Every trajectory is
re-checked by validate_trajectory."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.registry import CONTROLLERS
from swarmpath.sim.simulator import Simulator
from swarmpath.sim.trajectory import ALL_REACHED
from swarmpath.testing import validate_trajectory
from swarmpath.world.generators import movingai


@pytest.mark.slow
def test_parked_robots_in_a_door_and_behind_it_make_way_on_room_32_32_4():
    """room-32-32-4, the first 20 agents as discs of radius 0.4: robot 10's goal is the
    one-cell door at (18.5, 12.5) and robot 2's the cell just behind it, and robot 9 must pass
    through both. With the chain (``yield_chain=4``, the default) robot 10 backs away from
    robot 9 into robot 2, which backs away in turn; without it (``yield_chain=0``) robot 10
    pushes into robot 2, nothing moves, and robots 2, 9 and 10 never all arrive (17 of 20 with
    ``pso-reactive`` and ``pso-predictive``)."""
    world = movingai("room-32-32-4", 20, radius=0.4)
    assert world.robots[10].goal == (18.5, 12.5) and world.robots[2].goal == (18.5, 11.5)
    traj = Simulator(world, CONTROLLERS.get("pso-reactive")(), seed=0, max_steps=800).run()
    assert validate_trajectory(world, traj) == []
    assert traj.status == ALL_REACHED
    np.testing.assert_array_equal(traj.positions[-1], world.goals)
    left = np.linalg.norm(traj.positions - world.goals[None], axis=2) > 0.5
    arrived_first = np.argmax(np.linalg.norm(traj.positions - world.goals[None], axis=2) <= 1e-9, axis=0)
    for parked in (10, 2):     # both left their goals after first reaching them
        assert left[arrived_first[parked]:, parked].any(), parked


def test_the_chain_depth_is_validated():
    from swarmpath.control.orca.coordination import Coordination
    from swarmpath.errors import ConfigError

    for bad in (-1, 1.5, True):
        with pytest.raises(ConfigError):
            Coordination(chain=bad)
        with pytest.raises(ConfigError):
            CONTROLLERS.get("pso-predictive")(yield_chain=bad)
    assert Coordination().chain == 0 and Coordination(chain=4).chain == 4
