"""B-spline smoothing that stays collision-free (Jaleel & Hassan 2016, Algorithm 1): exact
ends, bounded step, shorter than the grid path, and never a segment that fails the
independent check -- also on random obstacle layouts (property test)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from swarmpath.errors import ConfigError
from swarmpath.planning.grid_paths import cells_to_polyline
from swarmpath.search import astar
from swarmpath.search.smoothing import _resample_polyline, clamped_bspline, dedupe, sample_spline, smooth_path
from swarmpath.testing import validate_paths
from swarmpath.world import Circle, Rect, RectBounds, Robot, World


def length(p):
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def astar_polyline(world, robot):
    grid = world.grid(radius=robot.radius)
    res = astar(grid, grid.cell_of(robot.start), grid.cell_of(robot.goal))
    assert res
    return cells_to_polyline(grid, res.cells, robot.start, robot.goal)


def test_staircase_in_open_space_gets_shorter_and_keeps_its_ends():
    robot = Robot("a", (0.5, 0.5), (9.5, 4.5))
    w = World(RectBounds(10, 6), robots=(robot,))
    path = astar_polyline(w, robot)
    out = smooth_path(w, path, max_step=1.0)
    assert np.array_equal(out.path[0], path[0]) and np.array_equal(out.path[-1], path[-1])
    assert length(out.path) < length(path) - 0.05
    assert length(out.path) >= np.hypot(9, 4) - 1e-9
    assert np.linalg.norm(np.diff(out.path, axis=0), axis=1).max() <= 1.0 + 1e-12
    assert out.refinements == 0 and not out.fallback
    assert validate_paths(w, [out.path]) == []


def shortcut(world, path, radius=0.0):
    """Greedy string pulling with the exact check: a sparse polyline whose corners graze
    obstacle corners (the hard case for a spline, which rounds corners inward)."""
    out, i = [path[0]], 0
    while i < len(path) - 1:
        j = len(path) - 1
        while j > i + 1 and world.static_hits(path[i][None], path[j][None], [radius])[0]:
            j -= 1
        out.append(path[j])
        i = j
    return np.asarray(out)


def test_spline_that_would_cut_a_corner_keeps_control_points_there():
    # A polyline hugging a wall at 0.1: the plain cubic spline rounds its corners into the
    # wall; refinement raises the multiplicity of the control points there.
    w = World(RectBounds(10, 10), obstacles=(Rect((4, 0), (6, 7)),))
    path = np.array([[1.5, 1.5], [3.9, 4.0], [3.9, 7.1], [6.1, 7.1], [6.1, 4.0], [8.5, 1.5]])
    assert not w.static_hits(path[:-1], path[1:], np.zeros(len(path) - 1)).any()
    unrefined = smooth_path(w, path, max_rounds=0)
    assert unrefined.fallback  # the plain spline cuts the wall: the polyline comes back
    out = smooth_path(w, path)
    assert out.refinements > 0 and not out.fallback and out.kept_points > 0
    assert not w.static_hits(out.path[:-1], out.path[1:], np.zeros(len(out.path) - 1)).any()
    assert np.array_equal(out.path[[0, -1]], path[[0, -1]])
    assert length(out.path) < length(path)


def test_full_multiplicity_reproduces_the_control_polygon():
    pts = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [8.0, 3.0]])
    spline = clamped_bspline(np.repeat(pts, 3, axis=0), 3)
    _, samples = sample_spline(spline, 0.5)
    for p in pts:  # every control point is on the curve
        assert np.min(np.linalg.norm(samples - p, axis=1)) < 1e-9
    # and every sample lies on the polygon
    from swarmpath.world.geometry import point_segment_distance
    d = point_segment_distance(samples[:, None], pts[None, :-1], pts[None, 1:]).min(axis=1)
    assert d.max() < 1e-9


def test_short_paths_and_helpers():
    w = World(RectBounds(4, 4))
    two = np.array([[0.5, 0.5], [3.5, 0.5]])
    out = smooth_path(w, two, max_step=1.0)
    assert np.allclose(out.path[[0, -1]], two) and len(out.path) == 4
    assert len(dedupe([[0, 0], [0, 0], [1, 1]])) == 2
    r = _resample_polyline(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 0.5]]), 0.5)
    assert len(r) == 6 and np.allclose(np.diff(r, axis=0).sum(axis=0), [2.0, 0.5])
    with pytest.raises(ConfigError):
        smooth_path(w, two, degree=0)
    with pytest.raises(ConfigError):
        smooth_path(w, two, max_step=0.0)


# ----------------------------------------------------------------------------- property test
@st.composite
def layouts(draw):
    """A 12x12 world at resolution 0.5 with 1-6 circles and grid-aligned rectangles (whose
    sides touch free cells: no margin left for a spline to cut corners), a robot radius,
    and a start and goal on free cells."""
    n = draw(st.integers(1, 6))
    obstacles = []
    for _ in range(n):
        if draw(st.booleans()):
            c = (draw(st.floats(1, 11)), draw(st.floats(1, 11)))
            obstacles.append(Circle(c, draw(st.floats(0.3, 2.0))))
        else:
            x0, y0 = draw(st.integers(0, 20)) / 2, draw(st.integers(0, 20)) / 2
            obstacles.append(Rect((x0, y0), (x0 + draw(st.integers(1, 8)) / 2, y0 + draw(st.integers(1, 8)) / 2)))
    radius = draw(st.sampled_from([0.0, 0.0, 0.2, 0.4]))
    start = (draw(st.integers(0, 23)), draw(st.integers(0, 23)))
    goal = (draw(st.integers(0, 23)), draw(st.integers(0, 23)))
    return obstacles, radius, start, goal


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(layouts())
def test_smoothed_paths_never_fail_the_independent_check(layout):
    obstacles, radius, start_cell, goal_cell = layout
    w = World(RectBounds(12, 12), obstacles=tuple(obstacles), resolution=0.5)
    grid = w.grid(radius=radius)
    assume(start_cell != goal_cell and grid.is_free(start_cell) and grid.is_free(goal_cell))
    res = astar(grid, start_cell, goal_cell)
    assume(res)
    start, goal = grid.centers(start_cell), grid.centers(goal_cell)
    robot = Robot("a", tuple(start), tuple(goal), radius)
    world = w.replace(robots=(robot,))
    path = cells_to_polyline(grid, res.cells, start, goal)
    assert validate_paths(world, [path]) == []  # the input is valid (conservative raster)
    for control in (path, shortcut(world, path, radius)):
        out = smooth_path(world, control, radius, max_step=0.5)
        assert validate_paths(world, [out.path]) == []
        assert np.linalg.norm(np.diff(out.path, axis=0), axis=1).max() <= 0.5 + 1e-9
        assert length(out.path) <= length(control) + 1e-9
