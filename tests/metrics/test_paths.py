"""Path and time measures against hand-computed trajectories."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.metrics import arrival_steps, executed_lengths, path_length, waiting_steps
from swarmpath.metrics.paths import first_arrival_steps

# two robots, 5 recorded positions (4 steps); robot 0 reaches (2, 0), leaves, comes back
POS = np.array([
    [[0, 0], [5, 5]],
    [[1, 0], [5, 5]],
    [[2, 0], [5, 6]],
    [[2, 1], [5, 6]],
    [[2, 0], [5, 6]],
], float)
GOALS = np.array([[2, 0], [9, 9]], float)


def test_lengths() -> None:
    assert path_length([[0, 0], [3, 4], [3, 5]]) == pytest.approx(6.0)
    assert executed_lengths(POS).tolist() == pytest.approx([4.0, 1.0])


def test_arrivals() -> None:
    assert arrival_steps(POS, GOALS) == [4, None]          # stays at the goal from step 4
    assert first_arrival_steps(POS, GOALS) == [2, None]    # first stood on it at step 2


def test_waits_count_standing_still_away_from_the_goal() -> None:
    assert waiting_steps(POS, GOALS).tolist() == [0, 3]
