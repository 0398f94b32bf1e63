"""Linear prediction of moving obstacles (PSO-prediction paper 2013, section 2.C)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.pso_predictive import prediction as pred
from swarmpath.rng import make_rng
from swarmpath.world import RectBounds, Robot, World
from swarmpath.world.moving import MovingObstacle, TurnEvery, advance_obstacles, initial_obstacle_state
from swarmpath.world.shapes import Circle


def test_sampling_time_is_total_time_over_steps():
    assert pred.sampling_time(12.0, 4) == 3.0
    assert pred.sampling_time(0.0, 0, default=0.5) == 0.5     # before the obstacle moved


def test_linear_prediction_by_hand():
    prev = np.array([[1.0, 2.0], [0.0, 0.0]])
    cur = np.array([[2.0, 2.5], [0.0, 0.0]])
    # u = (1, 0.5) per time unit (samples one unit apart); dt' = 2 -> two units ahead
    np.testing.assert_allclose(pred.estimate_velocity(prev, cur, 1.0), [[1.0, 0.5], [0.0, 0.0]])
    np.testing.assert_allclose(pred.predict_linear(prev, cur, 1.0, 2.0), [[4.0, 3.5], [0.0, 0.0]])
    # samples 0.5 apart: u doubles
    np.testing.assert_allclose(pred.predict_linear(prev, cur, 0.5, 1.0), [[4.0, 3.5], [0.0, 0.0]])
    with pytest.raises(ValueError):
        pred.estimate_velocity(prev, cur, 0.0)


def test_turn_period_is_gcd_of_gaps():
    assert pred.estimate_turn_period([10]) is None
    assert pred.estimate_turn_period([10, 20]) == 10
    assert pred.estimate_turn_period([10, 30, 40]) == 10      # a turn at 20 was missed
    assert pred.estimate_turn_period([7, 13]) == 6


def test_turn_expected():
    assert pred.turn_expected(5, (), None)                     # unknown period: always
    assert pred.turn_expected(30, (10, 20), 10)
    assert not pred.turn_expected(31, (10, 20), 10)


def _turning_world(period: int = 10) -> World:
    return World(RectBounds(40, 40), robots=(Robot("a", (1, 1), (2, 2), 0.5, 1.0),),
                 moving_obstacles=(MovingObstacle("m", Circle((0, 0), 1.0), (20.0, 20.0), (0.3, 0.0),
                                                  TurnEvery(period)),))


def test_track_learns_the_turning_period_of_turn_every():
    """Fed the positions of a turn-every obstacle far from walls, the track records its
    deliberate turns, learns the period, and the linear prediction is exact between turns."""
    world = _turning_world(10)
    rng = make_rng(3, "obstacles")
    state = initial_obstacle_state(world)
    track = pred.ObstacleTrack()
    exact = 0
    prev_prev = None  # the positions two samples back, set from step 1 on
    for step in range(1, 36):
        new = advance_obstacles(world, state, rng)
        if step >= 2 and step % 10 != 0:
            guess = pred.predict_linear(prev_prev, state.positions, 1.0, track.sampling_times(1.0)[0])
            np.testing.assert_allclose(guess, new.positions, atol=1e-12)
            exact += 1
        prev_prev = state.positions
        track = pred.update_track(track, step, state.positions, new.positions, 1.0)
        track = pred.with_linear_possible(track, [True])
        state = new
    assert exact > 25
    assert track.turn_steps[0] == (10, 20, 30)
    assert track.periods() == [10]
    assert track.sampling_times(1.0)[0] == pytest.approx(1.0)
    assert pred.turn_expected(40, track.turn_steps[0], 10)
    assert not pred.turn_expected(37, track.turn_steps[0], 10)


def test_bounce_is_not_a_deliberate_turn():
    track = pred.ObstacleTrack()
    track = pred.update_track(track, 1, [[0.0, 0.0]], [[1.0, 0.0]], 1.0)
    track = pred.with_linear_possible(track, [False])         # the prediction would leave the map
    track = pred.update_track(track, 2, [[1.0, 0.0]], [[0.0, 0.0]], 1.0)
    assert track.turn_steps == ((),)
    track = pred.with_linear_possible(track, [True])
    track = pred.update_track(track, 3, [[0.0, 0.0]], [[0.0, 1.0]], 1.0)
    assert track.turn_steps == ((3,),)
