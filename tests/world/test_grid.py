"""The rasteriser is conservative: any move between centres of 8-adjacent free cells (no
corner cutting) is collision-free under the exact geometry, for any robot radius."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmpath.world import Circle, CircleBounds, Polygon, Rect, RectBounds, World


def random_world(seed: int, circle_bounds: bool) -> World:
    rng = np.random.default_rng(seed)
    obstacles = []
    for _ in range(rng.integers(1, 6)):
        kind = rng.integers(3)
        c = rng.uniform(2, 10, size=2)
        if kind == 0:
            obstacles.append(Circle(tuple(c), float(rng.uniform(0.3, 2.0))))
        elif kind == 1:
            half = rng.uniform(0.2, 1.5, size=2)
            obstacles.append(Rect(tuple(c - half), tuple(c + half)))
        else:
            angles = np.sort(rng.uniform(0, 2 * np.pi, size=rng.integers(3, 7)))
            radius = rng.uniform(0.5, 2.0, size=len(angles))
            pts = c + np.stack([np.cos(angles), np.sin(angles)], 1) * radius[:, None]
            obstacles.append(Polygon(tuple(map(tuple, pts))))
    bounds = CircleBounds((6, 6), 6) if circle_bounds else RectBounds(12, 12)
    return World(bounds, obstacles=tuple(obstacles), name="random")


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10**6), st.booleans(), st.sampled_from([0.0, 0.2, 0.45, 0.8]), st.sampled_from([0.5, 1.0, 0.3]))
def test_moves_between_free_cells_are_collision_free(seed, circle_bounds, radius, resolution) -> None:
    world = random_world(seed, circle_bounds)
    grid = world.grid(resolution, radius)
    free = grid.free
    h, w = free.shape
    a_list, b_list = [], []
    for dx, dy in [(1, 0), (0, 1), (1, 1), (1, -1)]:
        ys, xs = np.nonzero(free)
        nx, ny = xs + dx, ys + dy
        ok = (nx >= 0) & (nx < w) & (ny >= 0) & (ny < h)
        xs, ys, nx, ny = xs[ok], ys[ok], nx[ok], ny[ok]
        ok = free[ny, nx]
        if dx and dy:
            ok &= free[ys, nx] & free[ny, xs]
        a_list.append(np.stack([xs[ok], ys[ok]], 1))
        b_list.append(np.stack([nx[ok], ny[ok]], 1))
    a = grid.centers(np.concatenate(a_list))
    b = grid.centers(np.concatenate(b_list))
    if len(a):
        hits = world.static_hits(a, b, np.full(len(a), radius))
        assert not hits.any(), (a[hits][:3], b[hits][:3])


def test_raster_blocks_cells_overlapping_obstacles() -> None:
    world = World(RectBounds(4, 4), obstacles=(Rect((1.0, 1.0), (2.0, 2.0)),), name="one")
    blocked = world.grid(1.0).blocked
    assert blocked.sum() == 1 and blocked[1, 1]
    # a circle touching a cell only at its boundary does not block it
    world = World(RectBounds(4, 4), obstacles=(Circle((2.0, 2.0), 0.5),), name="c")
    assert world.grid(1.0).blocked.sum() == 4
    # inflation for a radius beyond half a cell blocks the neighbours
    assert world.grid(1.0, radius=0.7).blocked.sum() > 4


def test_circle_workspace_blocks_cells_outside() -> None:
    world = World(CircleBounds((5, 5), 5), name="disc")
    g = world.grid(1.0)
    centres = g.centers(np.argwhere(g.free)[:, ::-1])
    assert np.all(np.linalg.norm(centres - 5, axis=1) <= 5 - 0.5)
    assert g.blocked[0, 0] and not g.blocked[5, 5]


def test_points_on_the_far_edge_belong_to_the_last_cell() -> None:
    g = World(RectBounds(10, 10), name="edge").grid(1.0)
    assert g.cell_of([10.0, 10.0]).tolist() == [9, 9]
    assert g.cell_of([[0.0, 10.0], [5.0, 5.0]]).tolist() == [[0, 9], [5, 5]]
    assert g.cell_of([10.5, 3.0]).tolist() == [10, 3]  # outside stays outside
