"""Line of sight never passes through or touches blocked cells, and agrees with an exact
segment-versus-square test on random grids."""
from __future__ import annotations

import numpy as np

from swarmpath.search import line_of_sight
from swarmpath.world.geometry import segment_box_distance


def test_clear_and_blocked_lines() -> None:
    blocked = np.zeros((5, 5), dtype=bool)
    blocked[2, 2] = True
    assert line_of_sight(blocked, [0.5, 0.5], [4.5, 0.5])[0]
    assert not line_of_sight(blocked, [0.5, 2.5], [4.5, 2.5])[0]
    # Passing exactly through the corner between two blocked cells counts as touching them.
    blocked = np.zeros((2, 2), dtype=bool)
    blocked[0, 1] = blocked[1, 0] = True
    assert not line_of_sight(blocked, [0.5, 0.5], [1.5, 1.5])[0]


def test_matches_exact_square_test() -> None:
    rng = np.random.default_rng(1)
    for _ in range(200):
        blocked = rng.random((12, 12)) < 0.15
        a, b = rng.uniform(0, 12, size=(2, 2))
        ys, xs = np.nonzero(blocked)
        d = segment_box_distance(a, b, np.stack([xs, ys], 1), np.stack([xs + 1, ys + 1], 1))
        expected = not np.any(d < 1e-9)
        assert line_of_sight(blocked, a, b)[0] == expected
