"""ORCA's half-planes, static features and moving-obstacle forecasts: hand values and
properties (the reciprocal guarantee of eq. (6), closest points against the world)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmpath.control.orca import lp
from swarmpath.control.orca.halfplanes import (
    clearance_halfplanes,
    orca_halfplanes_robots,
)
from swarmpath.control.orca.obstacles import (
    RedrawGuard,
    _worst_case_next,
    forecast_obstacles,
)
from swarmpath.control.orca.static_features import (
    StaticFeatures,
    raster_boundary_segments,
)
from swarmpath.world import (
    Bounce,
    Circle,
    CircleBounds,
    Polygon,
    RandomWalk,
    Rect,
    RectBounds,
    Redraw,
    Robot,
    StaticMap,
    TurnEvery,
    Waypoints,
    World,
)
from swarmpath.world.moving import MovingObstacle


# ------------------------------------------------------------------------------ half-planes
def test_head_on_pair_projects_on_the_right_leg_by_hand():
    """A at 0 moving (1, 0), B at (4, 0) moving (-1, 0), combined radius 1, tau 2: the
    relative velocity (2, 0) points at B; the nearest point of the cone's boundary is on the
    right leg at angle -asin(1/4): u = (-1/8, -sqrt(15)/8), |u| = 1/2."""
    p, d = orca_halfplanes_robots([[4.0, 0.0]], [[2.0, 0.0]], [[1.0, 0.0]], 1.0, 2.0, 1.0, 0.5)
    u = np.array([-1 / 8, -np.sqrt(15) / 8])
    np.testing.assert_allclose(p[0], [1.0, 0.0] + 0.5 * u, atol=1e-12)
    np.testing.assert_allclose(d[0], [-np.sqrt(15) / 4, 1 / 4], atol=1e-12)
    assert lp.violation(p, d, [1.0, 0.0])[0] > 0          # the current velocity is forbidden
    assert lp.violation(p, d, [1.0, 0.0] + u)[0] <= 1e-12  # the full change u suffices


def test_cut_off_circle_and_contact_branch_by_hand():
    # far apart and slow: the relative velocity projects on the cut-off circle of radius R/tau
    p, d = orca_halfplanes_robots([[4.0, 0.0]], [[0.5, 0.0]], [[0.0, 0.0]], 1.0, 4.0, 1.0, 1.0)
    # w = (0.5, 0) - (1, 0) = (-0.5, 0); u = (R/tau - |w|) w/|w| = (0.25 - 0.5)(-1, 0) = (0.25, 0)
    np.testing.assert_allclose(p[0], [0.25, 0.0], atol=1e-12)
    np.testing.assert_allclose(d[0], [0.0, 1.0], atol=1e-12)
    # in contact (distance 0.5 < 1): the cut-off of one step dt = 1
    p, d = orca_halfplanes_robots([[0.5, 0.0]], [[0.0, 0.0]], [[0.0, 0.0]], 1.0, 4.0, 1.0, 1.0)
    # w = -(0.5, 0); u = (1 - 0.5)(-1, 0): move apart by 0.5 per step
    np.testing.assert_allclose(p[0], [-0.5, 0.0], atol=1e-12)
    assert lp.violation(p, d, [-0.5, 0.0])[0] <= 1e-12 < lp.violation(p, d, [-0.4, 0.0])[0]


pair = st.tuples(st.floats(-6, 6), st.floats(-6, 6), st.floats(-2, 2), st.floats(-2, 2), st.floats(-2, 2),
                 st.floats(-2, 2), st.floats(0.2, 1.5), st.floats(0.5, 5.0), st.floats(0, 1), st.floats(0, 1))


def min_distance(rel0, rel_v, tau):
    """Closest approach of relative position rel0 + t rel_v over t in [0, tau]."""
    vv = rel_v @ rel_v
    t = 0.0 if vv == 0 else float(np.clip(-(rel0 @ rel_v) / vv, 0.0, tau))
    return float(np.linalg.norm(rel0 + t * rel_v))


@settings(max_examples=200, deadline=None)
@given(pair)
def test_reciprocal_guarantee_of_eq_6(args):
    """Any velocities A and B choose inside their own ORCA half-planes keep them at least the
    combined radius apart for tau (the paper's guarantee), for pairs not yet in contact."""
    px, py, ax, ay, bx, by, R, tau, sa, sb = args
    rel = np.array([px, py])
    if np.linalg.norm(rel) <= R * 1.01:
        return
    va, vb = np.array([ax, ay]), np.array([bx, by])
    pa, da = orca_halfplanes_robots([rel], [va - vb], [va], R, tau, 0.1, 0.5)
    pb, db = orca_halfplanes_robots([-rel], [vb - va], [vb], R, tau, 0.1, 0.5)
    # a point on each boundary, moved into the permitted side by a random amount
    na = np.array([da[0, 1], -da[0, 0]])
    nb = np.array([db[0, 1], -db[0, 0]])
    new_a = pa[0] - sa * na + 3 * sb * da[0]
    new_b = pb[0] - sb * nb - 2 * sa * db[0]
    assert lp.violation(pa, da, new_a)[0] <= 1e-12 and lp.violation(pb, db, new_b)[0] <= 1e-12
    assert min_distance(rel, new_b - new_a, tau) >= R - 1e-7


def test_clearance_halfplane_by_hand():
    p, d = clearance_halfplanes([[2.0, 0.0]], [0.5], 1.0)              # v_x <= 1.5
    assert lp.violation(p, d, [1.5, 7.0])[0] == pytest.approx(0.0, abs=1e-12)
    assert lp.violation(p, d, [1.6, 0.0])[0] > 0
    p, d = clearance_halfplanes([[0.0, 0.2]], [0.5], 2.0)              # too close: floor 0
    assert lp.violation(p, d, [0.0, 0.0])[0] <= 0 < lp.violation(p, d, [0.0, 0.01])[0]
    p, d = clearance_halfplanes([[0.0, 0.2]], [0.5], 1.0, floor=None)  # firm: must back off 0.3
    assert lp.violation(p, d, [0.0, -0.3])[0] == pytest.approx(0.0, abs=1e-12)
    assert lp.violation(p, d, [0.0, -0.29])[0] > 0


# ------------------------------------------------------------------------------ static features
def test_raster_boundary_runs_are_merged():
    b = np.zeros((4, 5), bool)
    b[1, 1:3] = True                       # two blocked cells side by side
    segs = raster_boundary_segments(b, 1.0)
    lengths = sorted(np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).tolist())
    assert lengths == [1.0, 1.0, 2.0, 2.0]
    b[0, 0] = True                         # a corner cell touching them diagonally: its
    segs = raster_boundary_segments(b, 2.0)  # sides continue theirs along the same lines
    lengths = sorted(np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).tolist())
    assert lengths == [2.0, 4.0, 4.0, 6.0]


def test_closest_features_agree_with_the_world_clearance():
    blocked = np.zeros((12, 16), bool)
    blocked[3:6, 9:11] = True
    blocked[8, 2:7] = True
    world = World(RectBounds(16, 12), obstacles=(Circle((4, 4), 1.0), Rect((12, 7), (14, 9)),
                                                 Polygon(((6, 9.5), (8, 11), (5, 11.5)))),
                  static_map=StaticMap(blocked, 1.0), robots=(Robot("a", (1, 1), (15, 1), 0.0, 1.0),))
    feats = StaticFeatures(world)
    rng = np.random.default_rng(3)
    pts = rng.uniform([0, 0], [16, 12], (400, 2))
    pts = pts[world.static_clearance(pts) > 0.05]
    owner, offset = feats.closest(pts, np.full(len(pts), 50.0))
    nearest = np.full(len(pts), np.inf)
    np.minimum.at(nearest, owner, np.linalg.norm(offset, axis=1))
    # the workspace's sides come as half-planes with their own normals
    side, normal, room = feats.bound_lines(pts, np.zeros(len(pts)), np.ones(len(pts)), np.full(len(pts), 50.0))
    np.minimum.at(nearest, side, room)
    np.testing.assert_allclose(nearest, world.static_clearance(pts), atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1.0)
    # with a small reach only the features that close come back
    owner, offset = feats.closest(pts, np.full(len(pts), 0.5))
    side, _, room = feats.bound_lines(pts, np.zeros(len(pts)), np.ones(len(pts)), np.full(len(pts), 0.5))
    assert np.all(np.linalg.norm(offset, axis=1) <= 0.5) and np.all(room <= 0.5 + 1e-9)
    near = set(owner.tolist()) | set(side.tolist())
    assert near == set(np.flatnonzero(world.static_clearance(pts) <= 0.5).tolist())


def test_a_point_robot_on_the_workspace_edge_may_move_inwards():
    """A point robot may stand on the edge (abbas-case2 starts there): the side keeps its
    outward normal, so only outward moves are cut."""
    world = World(RectBounds(10, 10), robots=(Robot("a", (0.0, 7.5), (10.0, 0.0), 0.0, 0.5),))
    feats = StaticFeatures(world)
    side, normal, room = feats.bound_lines(world.starts, np.zeros(1), np.full(1, 0.5))
    assert side.tolist() == [0] and normal.tolist() == [[-1.0, 0.0]] and room.tolist() == [0.0]
    from swarmpath.control.orca import ORCASolver

    solver = ORCASolver()
    solver.reset(world)
    v, _ = solver.velocities(world.starts, np.zeros((1, 2)), np.array([[0.3, -0.4]]), None)
    np.testing.assert_allclose(v, [[0.3, -0.4]])


def test_raster_features_use_the_kd_tree_on_large_maps(data_dir):
    from swarmpath.world import world_from_movingai

    world = world_from_movingai(data_dir / "den312d.map", data_dir / "den312d-even-10.scen", 5)
    feats = StaticFeatures(world)
    assert feats._tree is not None
    grid = world.grid()
    free = np.argwhere(~grid.blocked)[::37][:, ::-1]
    pts = grid.centers(free) + 0.13
    pts = pts[world.static_clearance(pts) > 0.01]
    owner, offset = feats.closest(pts, np.full(len(pts), 3.0))
    nearest = np.full(len(pts), np.inf)
    np.minimum.at(nearest, owner, np.linalg.norm(offset, axis=1))
    expect = world.static_clearance(pts)
    close = expect <= 3.0
    np.testing.assert_allclose(nearest[close], expect[close], atol=1e-9)


def test_circular_workspace_line_keeps_the_step_inside():
    world = World(CircleBounds((5, 5), 5), robots=(Robot("a", (5, 5), (5, 9), 0.3, 1.0),))
    feats = StaticFeatures(world)
    pos = np.array([[5.0, 9.4], [5.0, 5.0]])
    owner, normal, room = feats.bound_lines(pos, np.array([0.3, 0.3]), np.array([1.0, 1.0]))
    assert owner.tolist() == [0]
    # every point of the half-plane within one step of the robot lies inside radius 4.7
    ang = np.linspace(0, 2 * np.pi, 721)
    for s in np.linspace(0, 1, 11):
        ends = pos[0] + s * np.stack([np.cos(ang), np.sin(ang)], 1)
        inside = (ends - pos[0]) @ normal[0] <= room[0] + 1e-12
        assert np.all(np.linalg.norm(ends[inside] - [5, 5], axis=1) <= 4.7 + 1e-9)


# ------------------------------------------------------------------------------ moving obstacles
def walled(motion, start=(5.0, 5.0), velocity=(0.5, 0.0), shape=None):
    ob = MovingObstacle("m", shape or Circle((0, 0), 0.4), start, velocity, motion)
    return World(RectBounds(10, 10), moving_obstacles=(ob,), robots=(Robot("a", (1.5, 1.5), (8.5, 8.5), 0.3, 1.0),))


def test_worst_case_next_move_per_motion_model():
    w = walled(Bounce())
    ob = w.moving_obstacles[0]
    nxt, reach = _worst_case_next(ob, w, np.array([5.0, 5.0]), np.array([4.5, 5.0]), 3, 1.0)
    np.testing.assert_allclose(nxt, [5.5, 5.0])
    assert reach == 0.0
    # the next move would leave the room: it bounces, direction unknown here
    nxt, reach = _worst_case_next(ob, w, np.array([9.5, 5.0]), np.array([9.0, 5.0]), 3, 1.0)
    assert reach == 0.5 and np.array_equal(nxt, [9.5, 5.0])
    # stood still last step (a bounce reversal): heading unknown
    assert _worst_case_next(ob, w, np.array([5.0, 5.0]), np.array([5.0, 5.0]), 3, 1.0)[1] == 0.5
    w = walled(TurnEvery(period=4))
    ob = w.moving_obstacles[0]
    assert _worst_case_next(ob, w, np.array([5.0, 5.0]), np.array([4.5, 5.0]), 2, 1.0)[1] == 0.0
    assert _worst_case_next(ob, w, np.array([5.0, 5.0]), np.array([4.5, 5.0]), 3, 1.0)[1] == 0.5  # turns at 4
    w = walled(RandomWalk(), velocity=(0.5, 0.0))
    assert _worst_case_next(w.moving_obstacles[0], w, np.array([5.0, 5.0]), np.array([4.5, 5.0]), 1, 1.0)[1] == \
        pytest.approx(0.5 * np.sqrt(2))
    w = walled(Waypoints(points=((7.0, 5.0), (7.0, 8.0))), velocity=(0.5, 0.0))
    ob = w.moving_obstacles[0]
    assert _worst_case_next(ob, w, np.array([6.0, 5.0]), np.array([5.5, 5.0]), 1, 1.0)[1] == 0.0
    assert _worst_case_next(ob, w, np.array([6.75, 5.0]), np.array([6.25, 5.0]), 1, 1.0)[1] == 0.5  # corner


def test_worst_case_reads_the_motion_registry():
    """A model the forecast does not know as straight (orbit: it turns every step) keeps its
    whole declared reach clear, even when its last move happened to be one full step."""
    from swarmpath.world.motions.orbit import Orbit

    w = walled(Orbit((5.0, 5.0)), start=(7.0, 5.0), velocity=(0.0, 0.5))
    ob = w.moving_obstacles[0]
    now, prev = np.array([7.0, 5.0]), np.array([7.0, 4.5])
    nxt, reach = _worst_case_next(ob, w, now, prev, 1, 1.0)
    assert np.array_equal(nxt, now) and reach == pytest.approx(ob.max_step(1.0, w.resolution))


def test_uniform_redraw_has_no_guard():
    """The paper's uniform redraw may land on the robot's own cell: no end is safer, so the
    guard leaves it out (the hits are counted by the checker, not avoided)."""
    guard = RedrawGuard(walled(Redraw(avoid_robots=False)))
    assert guard.fits == {}
    assert not guard.danger(np.array([[4.0, 3.5]]), np.array([0.3])).any()


def test_forecast_marks_redraw_as_jumping():
    w = walled(Redraw())
    fc = forecast_obstacles(w, np.array([[5.5, 5.5]]), np.array([[2.5, 2.5]]), 1, 1.0)
    assert fc.jumping.tolist() == [True] and np.array_equal(fc.velocity, [[0.0, 0.0]])


def test_redraw_guard_spares_a_robot_on_its_cell_centre_only():
    w = walled(Redraw(), shape=Circle((0, 0), 0.45))
    guard = RedrawGuard(w)
    radii = np.array([0.3, 0.3, 0.3])
    ends = np.array([[3.5, 3.5], [4.0, 3.5], [3.5, 3.9]])
    # centre: neighbours 1 away, 0.3 + 0.45 < 1; on the border between two cells: 0.5 away
    assert guard.danger(ends, radii).tolist() == [False, True, True]
