"""UTD, AUTD, APD and steps to reach the goals (PSO-prediction paper 2013, section 7)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.metrics import utd


def _two_robot_run() -> tuple[np.ndarray, np.ndarray]:
    goals = np.array([[3.0, 0.0], [0.0, 4.0]])
    positions = np.array([
        [[0.0, 0.0], [0.0, 0.0]],
        [[1.0, 0.0], [0.0, 2.0]],
        [[2.0, 0.0], [0.0, 4.0]],
        [[3.0, 0.0], [0.0, 4.0]],
    ])
    return positions, goals


def test_utd_by_hand():
    positions, goals = _two_robot_run()
    np.testing.assert_allclose(utd.uncovered_target_distance(positions, goals), [7.0, 4.0, 1.0, 0.0])
    with pytest.raises(ValueError):
        utd.uncovered_target_distance(positions, goals[:1])


def test_autd_pads_finished_runs_with_their_last_value():
    curves = [np.array([4.0, 2.0, 0.0]), np.array([6.0, 4.0, 2.0, 1.0, 0.0])]
    np.testing.assert_allclose(utd.average_uncovered_target_distance(curves), [5.0, 3.0, 1.0, 0.5, 0.0])
    np.testing.assert_allclose(utd.average_uncovered_target_distance(curves, length=2), [5.0, 3.0])
    np.testing.assert_allclose(utd.pad_curves([np.array([3.0])], 3), [[3.0, 3.0, 3.0]])
    with pytest.raises(ValueError):
        utd.average_uncovered_target_distance([])


def test_path_deviation_is_length_with_obstacles_minus_without():
    free = np.array([[[0.0, 0.0]], [[1.0, 0.0]], [[2.0, 0.0]]])           # length 2
    detour = np.array([[[0.0, 0.0]], [[1.0, 1.0]], [[2.0, 0.0]]])         # length 2 sqrt 2
    np.testing.assert_allclose(utd.path_deviation(detour, free), [2 * np.sqrt(2) - 2])
    apd = utd.average_path_deviation([detour, free], [free, free])
    assert apd == pytest.approx((2 * np.sqrt(2) - 2) / 2)
    with pytest.raises(ValueError):
        utd.average_path_deviation([detour], [])


def test_steps_to_reach_goals():
    positions, goals = _two_robot_run()
    assert utd.steps_to_reach_goals(positions, goals) == 3
    assert utd.steps_to_reach_goals(positions[:3], goals) is None     # robot 0 not there yet
