"""The move-rules kernel against a brute-force reference that samples the motion (no shared
code), on randomised moves: grid moves between cell centres and free continuous moves of
discs. Also the grid lookup table against the kernel."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from reference_checker import reference_verdict
from swarmpath.world.move_rules import (GRID_MOVES, NEAR_OFFSETS, NO_CONFLICT, SWAP, VERTEX, grid_conflict_table,
                                        move_conflicts)

coord = st.floats(-3.0, 3.0, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord)
radius = st.sampled_from([0.1, 0.25, 0.3, 0.5, 0.75])


@settings(max_examples=300, deadline=None)
@given(a0=point, a1=point, b0=point, b1=point, ra=radius, rb=radius)
def test_disc_moves_agree_with_sampling(a0, a1, b0, b1, ra, rb) -> None:
    kernel = move_conflicts(a0, a1, b0, b1, ra, rb, 1.0) != NO_CONFLICT
    ref = reference_verdict(a0, a1, b0, b1, ra, rb, 1.0, margin=1e-6)
    if ref is not None:
        assert kernel == ref


cell = st.integers(-3, 3)
move = st.integers(0, 8)


@settings(max_examples=400, deadline=None)
@given(ax=cell, ay=cell, bx=cell, by=cell, ma=move, mb=move,
       res=st.sampled_from([1.0, 0.25, 2.0]))
def test_point_robots_on_cell_centres_agree_with_sampling(ax, ay, bx, by, ma, mb, res) -> None:
    if (ax, ay) == (bx, by):
        return
    a0 = ((ax + 0.5) * res, (ay + 0.5) * res)
    b0 = ((bx + 0.5) * res, (by + 0.5) * res)
    a1 = (a0[0] + GRID_MOVES[ma][0] * res, a0[1] + GRID_MOVES[ma][1] * res)
    b1 = (b0[0] + GRID_MOVES[mb][0] * res, b0[1] + GRID_MOVES[mb][1] * res)
    kernel = int(move_conflicts(a0, a1, b0, b1, 0.0, 0.0, res))
    ref = reference_verdict(a0, a1, b0, b1, 0.0, 0.0, res, margin=1e-9)
    assert ref is not None  # centre-to-centre moves meet exactly at a sample or stay apart
    assert (kernel != NO_CONFLICT) == ref


def test_the_kinds_are_named_as_the_checker_reports_them() -> None:
    assert move_conflicts((0.5, 0.5), (1.5, 0.5), (1.5, 0.5), (0.5, 0.5), 0.0, 0.0, 1.0) == SWAP
    assert move_conflicts((0.5, 0.5), (1.5, 0.5), (2.5, 0.5), (1.5, 0.5), 0.0, 0.0, 1.0) == VERTEX
    # following a robot into the cell it leaves is fine; crossing diagonals is not
    assert move_conflicts((0.5, 0.5), (1.5, 0.5), (1.5, 0.5), (2.5, 0.5), 0.0, 0.0, 1.0) == NO_CONFLICT
    assert move_conflicts((0.5, 0.5), (1.5, 1.5), (1.5, 0.5), (0.5, 1.5), 0.0, 0.0, 1.0) != NO_CONFLICT


def test_the_grid_table_is_the_kernel_on_cell_centres() -> None:
    for ra, rb in [(0.0, 0.0), (0.3, 0.3), (0.5, 0.5), (0.0, 0.4)]:
        table = grid_conflict_table(ra, rb)
        for k, (dx, dy) in enumerate(NEAR_OFFSETS):
            if dx == 0 and dy == 0:
                assert table[k].all()
                continue
            for a, ma in enumerate(GRID_MOVES):
                for b, mb in enumerate(GRID_MOVES):
                    a0 = np.array([0.5, 0.5])
                    b0 = a0 + (dx, dy)
                    expected = move_conflicts(a0, a0 + ma, b0, b0 + mb, ra, rb, 1.0) != NO_CONFLICT
                    assert table[k, a, b] == expected
    # half-cell discs may not follow around a corner; points may
    follow = (NEAR_OFFSETS.tolist().index([1, 0]), 1, 3)   # j east of i; i moves E, j moves N
    assert grid_conflict_table(0.5, 0.5)[follow] and not grid_conflict_table(0.0, 0.0)[follow]


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10**6), reach=st.sampled_from([0.0, 0.3, 1.7]), cell=st.sampled_from([0.5, 1.0, 2.0]))
def test_raster_clearance_equals_brute_force(seed, reach, cell) -> None:
    """The raster's segment clearance walks only the cells a segment's band can touch; it
    must equal the distance to every blocked square taken one by one."""
    from swarmpath.world import geometry as g
    from swarmpath.world.static_map import StaticMap

    rng = np.random.default_rng(seed)
    h, w = rng.integers(3, 20, 2)
    sm = StaticMap(rng.random((h, w)) < 0.3, cell)
    a = rng.uniform(-2, w * cell + 2, (20, 2))
    b = a + rng.normal(0, 4, (20, 2)) * rng.choice([0, 1, 0.01], (20, 1))
    ys, xs = np.nonzero(sm.blocked)
    lo = np.stack([xs, ys], 1) * cell
    d = g.segment_box_distance(a[:, None], b[:, None], lo[None], lo[None] + cell) if len(xs) else np.full((20, 1), np.inf)
    expected = np.where(d <= reach + g.EPS, d, np.inf).min(axis=1)
    assert np.array_equal(sm.segment_clearance(a, b, reach), expected)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10**6), cell=st.sampled_from([0.5, 1.0, 2.0]))
def test_raster_hits_of_centre_to_centre_moves_equal_the_general_rule(seed, cell) -> None:
    """The shortcut for point robots moving between neighbouring cell centres gives what
    the general clearance computation gives (cells off the map included)."""
    from swarmpath.world import geometry as g
    from swarmpath.world.static_map import StaticMap

    rng = np.random.default_rng(seed)
    h, w = rng.integers(2, 12, 2)
    sm = StaticMap(rng.random((h, w)) < 0.35, cell)
    start = rng.integers(-1, [w + 1, h + 1], (200, 2))
    a = (start + 0.5) * cell
    b = (start + GRID_MOVES[rng.integers(0, 9, 200)] + 0.5) * cell
    general = sm.segment_clearance(a, b, 0.0) < g.EPS
    assert np.array_equal(sm.segment_hits(a, b, np.zeros(200)), general)
