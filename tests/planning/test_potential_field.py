"""The potential field (Jaleel & Hassan 2016, eq. 1-8): kernels against hand-computed values,
gradients against finite differences, and the grid field against the point-wise one."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.planning.potential_field import (FieldParameters, attractive_gradient, attractive_potential,
                                                obstacle_distances, potential_at, potential_field,
                                                repulsive_field, repulsive_gradient, repulsive_potential)
from swarmpath.world import Circle, CircleBounds, Polygon, Rect, RectBounds, Robot, StaticMap, World


# ----------------------------------------------------------------------------- kernels by hand
def test_attractive_potential_hand_values():
    # zeta 0.5, d*_goal 15: quadratic 0.25 d^2 inside, 7.5 d - 56.25 outside
    d = np.array([0.0, 2.0, 15.0, 20.0])
    assert np.allclose(attractive_potential(d, 0.5, 15.0), [0.0, 1.0, 56.25, 93.75])
    # continuous at d*_goal from both sides
    assert attractive_potential(15.0 + 1e-9, 0.5, 15.0) == pytest.approx(56.25, abs=1e-6)


def test_attractive_gradient_hand_values():
    goal = np.array([1.0, 1.0])
    q = np.array([[4.0, 5.0], [31.0, 41.0], [1.0, 1.0]])  # d = 5, 50, 0
    g = attractive_gradient(q, goal, 0.5, 15.0)
    assert np.allclose(g[0], [1.5, 2.0])        # zeta (q - goal)
    assert np.allclose(g[1], [4.5, 6.0])        # d* zeta (q - goal) / d, magnitude 7.5
    assert np.allclose(g[2], [0.0, 0.0])


def test_repulsive_potential_hand_values():
    D = np.array([0.25, 0.5, 1.0, 2.0, 0.0, -0.1])
    u = repulsive_potential(D, 1.0, 1.0)
    assert np.allclose(u[:4], [4.5, 0.5, 0.0, 0.0])  # 0.5 (1/D - 1)^2 within Q* = 1
    assert np.isinf(u[4]) and np.isinf(u[5])
    assert repulsive_potential(0.5, 2.0, 2.0) == pytest.approx(0.5 * 2.0 * (2.0 - 0.5) ** 2)


def test_repulsive_gradient_hand_values():
    away = np.array([[1.0, 0.0], [0.0, 1.0], [0.6, 0.8]])
    g = repulsive_gradient(np.array([0.5, 0.25, 2.0]), away, 1.0, 1.0)
    assert np.allclose(g[0], [-4.0, 0.0])     # (1 - 2) / 0.25: points toward the obstacle
    assert np.allclose(g[1], [0.0, -48.0])    # (1 - 4) / 0.0625
    assert np.allclose(g[2], [0.0, 0.0])      # beyond Q*


def test_parameters_are_checked():
    with pytest.raises(ConfigError, match="attractive_gain"):
        FieldParameters(attractive_gain=0.0)
    with pytest.raises(ConfigError, match="influence_range"):
        FieldParameters(influence_range=float("nan"))
    assert FieldParameters() == FieldParameters(0.5, 15.0, 1.0, 1.0)  # the paper's values


# ----------------------------------------------------------------------------- exact distances
def mixed_world() -> World:
    return World(CircleBounds((10, 10), 10), obstacles=(
        Circle((6, 10), 1.5), Rect((11, 5), (14, 7)), Polygon(((10, 13), (14, 13), (12, 16)))), resolution=0.25)


def test_obstacle_distances_hand_values():
    w = mixed_world()
    p = np.array([[6.0, 12.0], [12.0, 4.5], [10.0, 10.0]])
    dists = obstacle_distances(w, p)
    bounds, circle, rect, _ = dists
    assert np.allclose(bounds[0], [10 - np.hypot(4, 2), 10 - np.hypot(2, 5.5), 10.0])
    assert np.allclose(circle[0][0], 0.5) and np.allclose(circle[1][0], [0.0, 1.0])
    assert np.allclose(rect[0][1], 0.5) and np.allclose(rect[1][1], [0.0, -1.0], atol=1e-6)
    assert np.allclose(bounds[1][1], np.array([-2.0, 5.5]) / np.hypot(2, 5.5))  # away from the rim
    shrunk = obstacle_distances(w, p, radius=0.2)
    assert np.allclose(shrunk[1][0][0], 0.3)


def test_potential_at_sums_every_obstacle_in_range():
    w = World(RectBounds(10, 10), obstacles=(Circle((3, 5), 1.0), Circle((7, 5), 1.0)))
    q = np.array([5.0, 5.0])  # 1 from each circle's surface: at Q*, no repulsion
    goal = np.array([5.0, 9.0])
    u, _ = potential_at(w, q, goal)
    assert u == pytest.approx(0.25 * 16)
    q2 = np.array([4.5, 5.0])  # 0.5 from the left circle, 1.5 from the right one
    u2, g2 = potential_at(w, q2, goal)
    assert u2 == pytest.approx(0.25 * (0.25 + 16) + 0.5)
    # attraction (0.5 * (-0.5, -4)) plus repulsion (-4 along +x)
    assert np.allclose(g2, [-0.25 - 4.0, -2.0])


def finite_difference(w, points, goal, radius=0.0, h=1e-6):
    ex, ey = np.array([h, 0.0]), np.array([0.0, h])
    gx = (potential_at(w, points + ex, goal, radius)[0] - potential_at(w, points - ex, goal, radius)[0]) / (2 * h)
    gy = (potential_at(w, points + ey, goal, radius)[0] - potential_at(w, points - ey, goal, radius)[0]) / (2 * h)
    return np.stack([gx, gy], axis=-1)


@pytest.mark.parametrize("radius", [0.0, 0.3])
def test_gradient_matches_finite_differences(radius):
    w = mixed_world()
    rng = np.random.default_rng(3)
    pts = rng.uniform(0.5, 19.5, size=(4000, 2))
    clearance = np.min([d for d, _ in obstacle_distances(w, pts, radius)], axis=0)
    pts = pts[clearance > 0.05][:600]
    assert len(pts) == 600
    near = np.min([d for d, _ in obstacle_distances(w, pts, radius)], axis=0) < 1.0
    assert near.sum() > 50  # plenty of points feel the repulsion
    for goal in (np.array([10.0, 3.0]), np.array([2.0, 12.0])):  # quadratic and conic regions
        _, g = potential_at(w, pts, goal, radius)
        fd = finite_difference(w, pts, goal, radius)
        assert np.allclose(g, fd, rtol=1e-4, atol=1e-4)


# ----------------------------------------------------------------------------- fields on a grid
@pytest.mark.parametrize("goal", [(12.3, 9.1), (1.6, 10.2)])  # the second: conic beyond 15
def test_grid_field_equals_pointwise_field_at_cell_centres(goal):
    w = mixed_world()
    goal = np.array(goal)
    f = potential_field(w, goal)
    grid = w.grid()
    assert f.total.shape == (grid.height, grid.width)
    free = np.argwhere(~grid.blocked)[:, ::-1]  # (x, y)
    u, g = potential_at(w, grid.centers(free), goal)
    assert np.allclose(f.total[free[:, 1], free[:, 0]], u)
    assert np.allclose(f.gradient[free[:, 1], free[:, 0]], g, atol=1e-5)
    assert np.all(np.isinf(f.total[grid.blocked]))
    d = np.linalg.norm(grid.centers(free) - goal, axis=1)
    assert np.allclose(f.attractive[free[:, 1], free[:, 0]], attractive_potential(d, 0.5, 15.0))


def test_grid_field_hand_computed_cell():
    w = World(RectBounds(10, 10), obstacles=(Circle((5, 5), 1.0),), resolution=0.5)
    f = potential_field(w, (8.25, 5.25))
    # cell (3, 10): centre (1.75, 5.25); goal 6.5 away; 1.75 from the left wall; 2.26 from the circle
    assert f.total[10, 3] == pytest.approx(0.25 * 6.5 ** 2)
    # cell (0, 10): centre (0.25, 5.25): 0.25 from the left wall
    assert f.total[10, 0] == pytest.approx(0.25 * 8.0 ** 2 + 0.5 * (4 - 1) ** 2)
    # cell (12, 10): centre (6.25, 5.25): within Q* of the circle only
    D = np.hypot(1.25, 0.25) - 1.0
    assert f.total[10, 12] == pytest.approx(0.25 * 2.0 ** 2 + 0.5 * (1 / D - 1) ** 2)
    assert np.allclose(f.gradient[10, 12], [0.5 * -2.0, 0.0] + (1 - 1 / D) / D ** 2
                       * np.array([1.25, 0.25]) / np.hypot(1.25, 0.25))


def test_repulsive_part_is_shared_and_cached():
    w = mixed_world()
    a = potential_field(w, (3.0, 10.0))
    b = potential_field(w, (15.0, 12.0))
    assert a.repulsive is b.repulsive
    assert repulsive_field(w) is a.repulsive
    assert repulsive_field(w, radius=0.3) is not a.repulsive
    assert not np.array_equal(a.total, b.total)
    with pytest.raises(ValueError):
        a.repulsive.potential[0, 0] = 1.0  # read-only


def test_workspace_boundary_repels():
    w = World(CircleBounds((5, 5), 5), resolution=0.25)
    rep = repulsive_field(w)
    grid = w.grid()
    cells = np.argwhere(~grid.blocked)[:, ::-1]
    centres = grid.centers(cells)
    rim = 5 - np.linalg.norm(centres - 5, axis=1)
    vals = rep.potential[cells[:, 1], cells[:, 0]]
    assert np.all(vals[rim < 1 - 1e-9] > 0) and np.all(vals[rim >= 1] == 0)
    # the force -grad U points inward near the rim
    inward = (5 - centres) @ np.array([1.0, 0.0])
    g = rep.gradient[cells[:, 1], cells[:, 0]]
    near = (rim < 0.9) & (np.abs(centres[:, 1] - 5) < 0.2) & (centres[:, 0] > 5)
    assert near.any() and np.all(-g[near, 0] * inward[near] > 0)


def test_static_map_repulsion_from_distance_transform():
    blocked = np.zeros((8, 8), dtype=bool)
    blocked[3:5, 3:5] = True
    w = World(RectBounds(8, 8), static_map=StaticMap(blocked, 1.0), resolution=0.5,
              robots=(Robot("a", (0.5, 0.5), (7.5, 7.5)),))
    rep = repulsive_field(w)
    grid = w.grid()
    assert np.all(np.isinf(rep.potential[grid.blocked]))
    # the cell whose centre is 0.25 left of the block: D = 0.25, U = 0.5 (4 - 1)^2 (+ nothing else)
    y, x = int(3.75 / 0.5), int(2.75 / 0.5)
    assert rep.clearance[y, x] == pytest.approx(0.25)
    assert rep.potential[y, x] == pytest.approx(4.5)
    assert rep.gradient[y, x, 0] > 0 and abs(rep.gradient[y, x, 1]) < 1e-12  # pushes left
    # far from the block and the walls: nothing
    assert rep.potential[int(1.75 / 0.5), int(1.75 / 0.5)] == 0.0


# ----------------------------------------------------------------------------- the figure
def test_plot_potential_field_writes_a_picture(tmp_path):
    from matplotlib.figure import Figure

    from swarmpath.planning.apf import APFPlanner
    from swarmpath.viz.potential_field import display_values, plot_potential_field, write_offline_figures
    from swarmpath.world import load_scenario

    w = load_scenario("apf-trap-u-shape")
    field = potential_field(w, w.robots[0].goal)
    partial = APFPlanner().plan(w).robots[0].diagnostics["partial_path"]
    fig = plot_potential_field(w, field, [partial], title="u")
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    assert len(ax.images) == 1 and len(ax.collections) >= 1  # heatmap and arrows
    assert any(np.allclose(line.get_xydata(), partial) for line in ax.lines)
    fig.savefig(tmp_path / "f.png", dpi=40)
    assert (tmp_path / "f.png").stat().st_size > 500
    # a plain array works too; blocked cells are not drawn
    fig2 = plot_potential_field(w, np.asarray(field.total))
    shown_array = np.ma.masked_invalid(fig2.axes[0].images[0].get_array())
    assert np.array_equal(np.ma.getmaskarray(shown_array), w.grid().blocked)
    shown = display_values(field.total)
    assert np.nanmin(shown) == 0.0
    files = write_offline_figures(w, tmp_path / "out", dpi=30)
    assert [f.name for f in files] == ["apf-field.png", "apf-paths.png", "hybrid-paths.png"]
