"""Objectives of AMOPSO path planning (planning/path_objectives.py) and the shortest-path
yardsticks (planning/reference_paths.py): values by hand, agreement with the world's exact
geometry, and the case-1 shortest length against its analytic value."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.planning import path_objectives as po
from swarmpath.planning.reference_paths import grid_shortest_path, shortcut_path, visibility_shortest_path
from swarmpath.testing import validate_paths
from swarmpath.testing.conformance import conformance_worlds
from swarmpath.world import Circle, CircleBounds, Polygon, Rect, RectBounds, Robot, World, load_scenario


def case1_shortest_analytic() -> float:
    """Tangent from (0, 0) to the circle (5.5, 5.5) r 1.5, the arc, the tangent to (10, 10)."""
    c, r = np.array([5.5, 5.5]), 1.5
    d0, d1 = np.linalg.norm(c), np.linalg.norm(c - 10)
    arc = (np.pi - np.arccos(r / d0) - np.arccos(r / d1)) * r
    return float(np.sqrt(d0**2 - r**2) + np.sqrt(d1**2 - r**2) + arc)


# ------------------------------------------------------------------------------- by hand
def test_decode_and_encode():
    X = np.array([[1, 2, 3, 4], [5, 6, 7, 8]], float)
    P = po.decode_paths(X, (0, 0), (9, 9))
    assert P.shape == (2, 4, 2)
    np.testing.assert_array_equal(P[1], [[0, 0], [5, 6], [7, 8], [9, 9]])
    np.testing.assert_array_equal(po.encode_waypoints(P[0, 1:-1]), X[0])


def test_lengths_danger_distances_f1_and_clearance_by_hand():
    paths = np.array([[[0, 0], [3, 4], [6, 0]]], float)                 # two 3-4-5 segments
    assert po.path_lengths(paths)[0] == pytest.approx(10.0)
    centers = np.array([[3, 0], [3, 7], [-3, -4]], float)
    d = po.danger_distances(paths, centers)
    # (3, 0) to segment (0,0)-(3,4): 12/5; (3, 7) to the vertex (3, 4): 3; (-3, -4) to (0, 0): 5
    np.testing.assert_allclose(d, [[2.4, 3.0, 5.0]])
    assert po.danger_inverse_sum(d)[0] == pytest.approx(1 / 10.4)       # eq. 1 over the polyline
    assert po.danger_clearance(d, [1.0, 2.5, 0.0])[0] == pytest.approx(0.5)
    none = po.danger_distances(paths, np.zeros((0, 2)))
    assert none.shape == (1, 0)
    assert po.danger_inverse_sum(none)[0] == 0.0 and po.danger_clearance(none, [])[0] == np.inf
    assert po.danger_inverse_sum(np.zeros((1, 2)))[0] == pytest.approx(1 / po.DANGER_FLOOR)


def test_obstacle_violation_by_hand():
    w = World(RectBounds(10, 10), obstacles=(Circle((5, 5), 1.0), Rect((1, 7), (3, 9)),
                                             Polygon(((6, 1), (9, 1), (9, 4)))))
    through_circle = np.array([[[2, 5], [8, 5]]], float)
    assert po.obstacle_violation(w, through_circle)[0] == pytest.approx(1.0)         # depth r
    assert po.obstacle_violation(w, through_circle, 0.5)[0] == pytest.approx(1.5)    # r + radius
    tangent = np.array([[[2, 6], [8, 6]]], float)
    assert po.obstacle_violation(w, tangent)[0] == 0.0
    assert po.obstacle_violation(w, tangent, 0.25)[0] == pytest.approx(0.25)
    through_rect = np.array([[[0.5, 8], [4, 8]]], float)                             # 2 units inside
    assert po.obstacle_violation(w, through_rect)[0] == pytest.approx(2.0)
    assert po.obstacle_violation(w, through_rect, 0.1)[0] == pytest.approx(2.1)
    # the line y = 2 crosses the triangle for 7 < x < 9; the depth at (x, 2) is
    # min((x - 7) / sqrt 2, 9 - x, 1), largest (2 / (1 + sqrt 2) = 0.828) at x = 8.17; the
    # probes (ends, crossings, midpoints, 9 even points) find a point at least 0.77 deep
    through_tri = np.array([[[5, 2], [9.5, 2]]], float)
    deepest = 2 / (1 + np.sqrt(2))
    assert 0.77 <= po.obstacle_violation(w, through_tri)[0] <= deepest + 1e-12
    outside = np.array([[[0.5, 0.5], [-0.5, 0.5], [0.5, 1.5]]], float)              # a vertex 0.5 outside
    assert po.obstacle_violation(w, outside)[0] == pytest.approx(0.5)
    free = np.array([[[0.5, 0.5], [4, 0.5], [9.5, 9.5]]], float)
    assert po.obstacle_violation(w, free)[0] == 0.0 and not po.static_collisions(w, free)[0]


def test_penalised_objectives():
    F = np.array([[14.0, 0.2], [15.0, 0.1]])
    out = po.penalised_objectives(F, np.array([0.0, 0.3]), np.array([False, True]), offset=100.0)
    np.testing.assert_allclose(out, [[14.0, 0.2], [15.0 + 100 + 300, 0.1 + 100 + 300]])
    assert po.penalty_offset([0, 0], [3, 4], 4) == pytest.approx(10 * (5 * 5 + 1 / po.DANGER_FLOOR))


def test_resample_keeps_corners():
    path = np.array([[0, 0], [4, 0], [4, 3], [8, 3]], float)
    wp = po.resample_polyline(path, 5)
    assert wp.shape == (5, 2)
    assert any(np.allclose(p, [4, 0]) for p in wp) and any(np.allclose(p, [4, 3]) for p in wp)
    full = np.vstack([path[0], wp, path[-1]])
    assert po.path_lengths(full[None])[0] == pytest.approx(11.0)                    # the same curve
    few = po.resample_polyline(path, 1)                                              # cuts the corners
    assert few.shape == (1, 2)


# ------------------------------------------------------------------ against the exact geometry
def _worlds():
    out = list(conformance_worlds())
    out.append(load_scenario("abbas-case1"))
    out.append(load_scenario("abbas-case2"))
    out.append(World(CircleBounds((5, 5), 5), obstacles=(Polygon(((3, 3), (7, 3), (5, 6))), Rect((1, 4), (2, 6)))))
    return out


@pytest.mark.parametrize("radius", [0.0, 0.3])
def test_segment_hits_is_world_static_hits(radius):
    rng = np.random.default_rng(5)
    for w in _worlds():
        lo, hi = np.zeros(2), np.array(w.bounds.extent, float)
        paths = rng.uniform(lo - 0.5, hi + 0.5, size=(300, 4, 2))
        hits = po.segment_hits(w, paths, radius)
        a, b = paths[:, :-1].reshape(-1, 2), paths[:, 1:].reshape(-1, 2)
        expected = w.static_hits(a, b, np.full(len(a), radius)).reshape(300, 3)
        np.testing.assert_array_equal(hits, expected)
        assert hits.any() and (~hits).any()
        # the violation is positive exactly on colliding paths
        v = po.obstacle_violation(w, paths, radius)
        coll = hits.any(axis=1)
        assert np.all(v[coll] > 0), w.name
        assert np.all(v[~coll] <= 1e-8), w.name
        v_fast = po.obstacle_violation(w, paths, radius, hits)
        np.testing.assert_allclose(v_fast[coll], v[coll])


def test_segment_hits_on_a_raster_map(data_dir):
    from swarmpath.world import world_from_movingai

    w = world_from_movingai(data_dir / "random-32-32-10.map", data_dir / "random-32-32-10-random-1.scen", 2)
    paths = np.random.default_rng(1).uniform(0, 32, size=(50, 3, 2))
    a, b = paths[:, :-1].reshape(-1, 2), paths[:, 1:].reshape(-1, 2)
    np.testing.assert_array_equal(po.segment_hits(w, paths).reshape(-1), w.static_hits(a, b, np.zeros(len(a))))


# ---------------------------------------------------------------------------- yardsticks
def test_visibility_shortest_path_case1_is_the_analytic_length():
    w = load_scenario("abbas-case1")
    path, length = visibility_shortest_path(w, w.robots[0])
    exact = case1_shortest_analytic()
    assert exact == pytest.approx(14.4648, abs=1e-4)
    assert exact <= length <= exact * (1 + 1 / 3000)          # upper bound within 0.03 %
    assert validate_paths(w, [path]) == []
    gpath, glength = grid_shortest_path(w, w.robots[0])
    assert validate_paths(w, [gpath]) == []
    assert length <= glength <= exact * 1.005                 # looser, still an upper bound


def test_visibility_shortest_path_with_disc_robots_and_polygons():
    w = World(RectBounds(10, 10), obstacles=(Rect((4, 0), (5, 7)), Polygon(((6, 3), (8, 3), (7, 9)))),
              robots=(Robot("a", (1, 1), (9, 1), 0.4, 1.0),))
    path, length = visibility_shortest_path(w, w.robots[0])
    assert validate_paths(w, [path]) == []
    # around the wall's top (corner (4..5, 7) grown by 0.4): at least the two legs to y = 7.4
    assert length >= 2 * np.hypot(3.4, 6.4) - 0.1
    # walls that pass beyond the workspace's edge, so no gap is left along the boundary
    walled = World(RectBounds(10, 10), obstacles=(Rect((6, 6), (11, 6.8)), Rect((6, 6), (6.8, 11))),
                   robots=(Robot("a", (1.5, 1.5), (8.5, 8.5), 0.0, 1.0),))
    assert visibility_shortest_path(walled, walled.robots[0]) == (None, None)
    assert grid_shortest_path(walled, walled.robots[0]) == (None, None)


def test_shortcut_path_is_free_and_not_longer():
    w = load_scenario("abbas-case2")
    zigzag = np.array([[0, 0], [1, 0.2], [2, 0], [3, 0.2], [4, 0.1], [9, 0.2], [10, 0]], float)
    w2 = w.replace(robots=(Robot("a", (0, 0), (10, 0), 0.0, 0.5),))
    assert validate_paths(w2, [zigzag]) == []
    pulled = shortcut_path(w2, zigzag)
    assert validate_paths(w2, [pulled]) == []
    np.testing.assert_array_equal(pulled, [[0, 0], [10, 0]])
