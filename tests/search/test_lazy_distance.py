"""Lazy per-goal distance tables agree with the full distance fields, stay lazy, are shared
per goal and freed on release."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmpath.control.pibt.core import static_moves
from swarmpath.data.movingai import MOVINGAI
from swarmpath.errors import ConfigError
from swarmpath.search import astar, distance_field
from swarmpath.search.lazy_distance import LazyDistanceTables
from swarmpath.world.movingai import read_map

DATA = MOVINGAI
MAPS = ["random-32-32-10", "room-32-32-4", "maze-32-32-2", "den312d", "empty-8-8"]


def assert_same_field(lazy: np.ndarray, full: np.ndarray) -> None:
    """Same unreachable cells; equal costs up to the rounding of the field's running sums
    (the lazy tables compute straight + sqrt(2) * diagonal from exact move counts)."""
    assert np.array_equal(np.isinf(lazy), np.isinf(full))
    fin = np.isfinite(full)
    np.testing.assert_allclose(lazy[fin], full[fin], rtol=0, atol=1e-9)


@st.composite
def grids(draw):
    h = draw(st.integers(1, 14))
    w = draw(st.integers(1, 14))
    density = draw(st.floats(0.0, 0.6))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    blocked = rng.random((h, w)) < density
    free = np.argwhere(~blocked)
    if len(free) == 0:
        blocked[0, 0] = False
        free = np.argwhere(~blocked)
    gy, gx = free[rng.integers(len(free))]
    return blocked, (int(gx), int(gy)), seed


@settings(max_examples=150, deadline=None)
@given(grids(), st.sampled_from([4, 8]), st.sampled_from([0, 1, 3]))
def test_lazy_tables_match_distance_field_on_random_grids(case, connectivity, landmarks):
    blocked, goal, seed = case
    tables = LazyDistanceTables(blocked, connectivity=connectivity, landmarks=landmarks)
    handle = tables.acquire(goal)
    rng = np.random.default_rng(seed)
    h, w = blocked.shape
    # interleave single queries in random order before reading everything
    for _ in range(5):
        x, y = int(rng.integers(-1, w + 1)), int(rng.integers(-1, h + 1))
        d = tables.distance(handle, (x, y))
        if 0 <= x < w and 0 <= y < h and not blocked[y, x]:
            ref = distance_field(blocked, goal, connectivity=connectivity)[y, x]
            assert d == pytest.approx(ref, abs=1e-9) or (np.isinf(d) and np.isinf(ref))
        else:
            assert np.isinf(d)
    assert_same_field(tables.field(handle), distance_field(blocked, goal, connectivity=connectivity))


@pytest.mark.parametrize("name", MAPS)
@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("landmarks", [0, 8])
def test_lazy_tables_match_distance_field_on_movingai_maps(name, connectivity, landmarks):
    blocked = read_map(DATA / f"{name}.map").blocked
    rng = np.random.default_rng(7)
    free = np.argwhere(~blocked)
    tables = LazyDistanceTables(blocked, connectivity=connectivity, landmarks=landmarks)
    for _ in range(3):
        gy, gx = free[rng.integers(len(free))]
        handle = tables.acquire((gx, gy))
        full = distance_field(blocked, (gx, gy), connectivity=connectivity)
        # a few scattered queries first (they move the search's target around), then all
        cells = free[rng.permutation(len(free))[:40]][:, ::-1]
        got = tables.distances(np.full(len(cells), handle), cells)
        want = full[cells[:, 1], cells[:, 0]]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
        assert_same_field(tables.field(handle), full)


def test_costs_agree_with_astar_on_the_scenario_pairs():
    blocked = read_map(DATA / "den312d.map").blocked
    tables = LazyDistanceTables(blocked)
    rng = np.random.default_rng(3)
    free = np.argwhere(~blocked)[:, ::-1]
    for _ in range(30):
        s, g = free[rng.integers(len(free), size=2)]
        handle = tables.acquire(g)
        assert tables.distance(handle, s) == pytest.approx(astar(blocked, s, g).cost, abs=1e-9)
        tables.release(handle)
    assert tables.live == 0


def test_equal_costs_are_equal_doubles():
    """Costs are exact (straight, diagonal) counts: mirror cells of an open grid compare equal."""
    blocked = np.zeros((21, 21), bool)
    tables = LazyDistanceTables(blocked)
    handle = tables.acquire((10, 10))
    for dx in range(-10, 11):
        for dy in range(-10, 11):
            d = tables.distance(handle, (10 + dx, 10 + dy))
            for mx, my in ((dy, dx), (-dx, dy), (dx, -dy), (-dy, -dx)):
                assert tables.distance(handle, (10 + mx, 10 + my)) == d


def test_tables_expand_only_what_queries_need():
    blocked = np.zeros((200, 200), bool)
    tables = LazyDistanceTables(blocked)
    assert tables.memory_bytes() < 10_000           # tables that were never queried hold nothing
    handles = [tables.acquire((x, 100)) for x in range(0, 200, 2)]
    assert tables.memory_bytes() < 50_000
    near = tables.distance(handles[0], (3, 100))
    assert near == 3
    assert tables.expanded(handles[0]) < 50         # a straight line toward the query, not a disc
    assert tables.is_closed(handles[0], (1, 100)) and not tables.is_closed(handles[0], (150, 150))
    small = tables.memory_bytes()
    tables.distance(handles[1], (199, 199))
    assert tables.expanded(handles[1]) < 0.1 * blocked.size
    assert tables.memory_bytes() > small


def test_tables_are_shared_per_goal_and_freed_by_the_last_user():
    tables = LazyDistanceTables(np.zeros((10, 10), bool))
    a = tables.acquire((2, 3))
    b = tables.acquire(np.array([2, 3]))
    c = tables.acquire((4, 4))
    assert a == b != c and tables.live == 2
    tables.distance(a, (9, 9))
    tables.release(a)
    assert tables.live == 2   # the table still answers for its remaining user
    assert tables.distance(b, (9, 9)) == pytest.approx(distance_field(np.zeros((10, 10), bool), (2, 3))[9, 9])
    assert tables.distance(b, (2, 3)) == 0
    tables.release(b)
    assert tables.live == 1
    with pytest.raises(ConfigError):
        tables.release(a)
    assert tables.acquire((2, 3)) >= 0    # a released goal gets a fresh table


def test_unreachable_and_blocked_cells_are_infinite():
    blocked = np.zeros((5, 7), bool)
    blocked[:, 3] = True
    tables = LazyDistanceTables(blocked)
    h = tables.acquire((0, 0))
    assert np.isinf(tables.distance(h, (6, 4)))     # the other side of a wall: the search ends
    assert np.isinf(tables.distance(h, (3, 2)))     # blocked
    assert np.isinf(tables.distance(h, (-1, 0)))    # outside
    assert tables.distance(h, (2, 4)) == pytest.approx(2 + 2 * np.sqrt(2))


@pytest.mark.parametrize("connectivity", [4, 8])
def test_neighbour_costs_mark_impossible_moves(connectivity):
    blocked = read_map(DATA / "room-32-32-4.map").blocked
    tables = LazyDistanceTables(blocked, connectivity=connectivity)
    free = np.argwhere(~blocked)[:, ::-1]
    rng = np.random.default_rng(0)
    cells = free[rng.integers(len(free), size=200)]
    goal = free[5]
    handles = np.full(len(cells), tables.acquire(goal))
    costs = tables.neighbour_costs(handles, cells)
    moves = static_moves(blocked, connectivity)[cells[:, 1], cells[:, 0]]
    assert np.array_equal(~np.isnan(costs), moves)
    full = distance_field(blocked, goal, connectivity=connectivity)
    from swarmpath.world.move_rules import GRID_MOVES
    dest = cells[:, None, :] + GRID_MOVES[None]
    for r, a in np.argwhere(moves):
        assert costs[r, a] == pytest.approx(full[dest[r, a, 1], dest[r, a, 0]], abs=1e-9)


def test_landmarks_cut_the_expansions_on_a_cluttered_map():
    """The differential heuristic (ALT) bounds costs more tightly than the octile distance:
    the same exact answers from fewer closed cells."""
    blocked = read_map(DATA / "den312d.map").blocked
    free = np.argwhere(~blocked)[:, ::-1]
    rng = np.random.default_rng(4)
    pairs = free[rng.integers(len(free), size=(40, 2))]
    plain, alt = LazyDistanceTables(blocked), LazyDistanceTables(blocked, landmarks=8)
    assert len(alt.landmark_cells) == 8 and len(plain.landmark_cells) == 0
    h0, h1 = plain.acquire_many(pairs[:, 1]), alt.acquire_many(pairs[:, 1])
    d0, d1 = plain.distances(h0, pairs[:, 0]), alt.distances(h1, pairs[:, 0])
    np.testing.assert_allclose(d0, d1, rtol=0, atol=1e-9)
    e0 = sum(plain.expanded(h) for h in set(h0.tolist()))
    e1 = sum(alt.expanded(h) for h in set(h1.tolist()))
    assert e1 < 0.8 * e0


def test_bad_arguments_raise_config_errors():
    blocked = np.zeros((4, 4), bool)
    blocked[1, 1] = True
    with pytest.raises(ConfigError, match="connectivity"):
        LazyDistanceTables(blocked, connectivity=6)
    with pytest.raises(ConfigError, match="landmarks"):
        LazyDistanceTables(blocked, landmarks=-1)
    tables = LazyDistanceTables(blocked)
    with pytest.raises(ConfigError, match="blocked"):
        tables.acquire((1, 1))
    with pytest.raises(ConfigError, match="outside"):
        tables.acquire((9, 0))
