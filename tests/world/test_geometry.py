"""Geometry kernels against hand-computed values."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.world import Circle, Polygon, Rect
from swarmpath.world import geometry as g


def test_point_segment_distance() -> None:
    assert g.point_segment_distance([0, 1], [-1, 0], [1, 0]) == pytest.approx(1)
    assert g.point_segment_distance([3, 4], [0, 0], [0, 0]) == pytest.approx(5)
    assert g.point_segment_distance([2, 1], [-1, 0], [1, 0]) == pytest.approx(np.sqrt(2))


def test_segment_box() -> None:
    lo, hi = np.array([0.0, 0.0]), np.array([1.0, 1.0])
    assert g.segment_box_distance([-1, 0.5], [2, 0.5], lo, hi) == 0
    assert g.segment_box_distance([2, 2], [3, 2], lo, hi) == pytest.approx(np.sqrt(2))
    assert g.segment_box_distance([-1, 2], [2, 2], lo, hi) == pytest.approx(1)
    assert g.segment_crosses_open_box([-1, 0.5], [2, 0.5], lo, hi)
    assert not g.segment_crosses_open_box([-1, 1.0], [2, 1.0], lo, hi)  # along an edge: touching


def test_shapes_signed_distance() -> None:
    assert Circle((0, 0), 1).signed_distance([[2, 0]])[0] == pytest.approx(1)
    assert Rect((0, 0), (2, 2)).signed_distance([[1, 1]])[0] == pytest.approx(-1)
    tri = Polygon(((0, 0), (4, 0), (0, 4)))
    assert tri.signed_distance([[1, 1]])[0] == pytest.approx(-1)
    assert tri.signed_distance([[-1, 0]])[0] == pytest.approx(1)


def test_polygon_segment_interior() -> None:
    square = Polygon(((0, 0), (2, 0), (2, 2), (0, 2)))
    assert square.segment_crosses_interior([[-1, 1]], [[3, 1]])[0]
    assert not square.segment_crosses_interior([[-1, 2]], [[3, 2]])[0]   # along an edge
    assert not square.segment_crosses_interior([[-1, 3]], [[3, 3]])[0]
    assert square.segment_clearance([[-1, 3]], [[3, 3]])[0] == pytest.approx(1)
    concave = Polygon(((0, 0), (4, 0), (4, 4), (3, 4), (3, 1), (1, 1), (1, 4), (0, 4)))  # a U
    assert not concave.segment_crosses_interior([[2, 3.5]], [[2, 1.5]])[0]  # inside the U's mouth
    assert concave.segment_crosses_interior([[2, 3.5]], [[2, 0.5]])[0]


def test_relative_min_distance_catches_crossings() -> None:
    # two points swapping diagonals meet in the middle of the step
    assert g.relative_min_distance([0, 0], [1, 1], [1, 0], [0, 1]) == pytest.approx(0)
    # following one another at constant distance
    assert g.relative_min_distance([0, 0], [1, 0], [1, 0], [2, 0]) == pytest.approx(1)
