"""A*, distance fields and path costs agree with each other and with an independent
reference (scipy's Dijkstra on an explicitly built move graph) on random grids."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from swarmpath.errors import ConfigError
from swarmpath.search import astar, descend, distance_field, path_cost


def reference_costs(blocked: np.ndarray, source: tuple[int, int], connectivity: int) -> np.ndarray:
    """Costs from ``source`` by scipy's Dijkstra on the move graph built cell by cell."""
    h, w = blocked.shape
    rows, cols, vals = [], [], []
    moves = [(1, 0), (-1, 0), (0, 1), (0, -1)]
    if connectivity == 8:
        moves += [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    for y in range(h):
        for x in range(w):
            if blocked[y, x]:
                continue
            for dx, dy in moves:
                nx, ny = x + dx, y + dy
                if not (0 <= nx < w and 0 <= ny < h) or blocked[ny, nx]:
                    continue
                if dx and dy and (blocked[y, nx] or blocked[ny, x]):
                    continue  # no corner cutting
                rows.append(y * w + x)
                cols.append(ny * w + nx)
                vals.append(math.sqrt(2) if dx and dy else 1.0)
    graph = coo_matrix((vals, (rows, cols)), shape=(h * w, h * w)).tocsr()
    return dijkstra(graph, indices=source[1] * w + source[0]).reshape(h, w)


grids = st.integers(min_value=0, max_value=2**32 - 1).flatmap(
    lambda seed: st.tuples(st.just(seed), st.integers(3, 18), st.integers(3, 18), st.floats(0.0, 0.45)))


def make_grid(seed: int, w: int, h: int, density: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.random((h, w)) < density


def valid_moves(blocked: np.ndarray, cells: np.ndarray, connectivity: int) -> bool:
    d = np.diff(cells, axis=0)
    if np.any(np.abs(d) > 1) or np.any(np.all(d == 0, axis=1)):
        return False
    if connectivity == 4 and np.any(np.all(d != 0, axis=1)):
        return False
    if np.any(blocked[cells[:, 1], cells[:, 0]]):
        return False
    for (x, y), (dx, dy) in zip(cells[:-1], d):
        if dx and dy and (blocked[y, x + dx] or blocked[y + dy, x]):
            return False
    return True


@settings(max_examples=200, deadline=None)
@given(grids, st.sampled_from([(4, "astar"), (8, "astar"), (8, "jps")]), st.data())
def test_astar_equals_distance_field_and_reference(params, search, data) -> None:
    connectivity, method = search
    blocked = make_grid(*params)
    free = np.argwhere(~blocked)
    if len(free) < 2:
        return
    i, j = data.draw(st.integers(0, len(free) - 1)), data.draw(st.integers(0, len(free) - 1))
    start, goal = tuple(free[i][::-1]), tuple(free[j][::-1])
    ref = reference_costs(blocked, goal, connectivity)
    field = distance_field(blocked, goal, connectivity=connectivity)
    finite = np.isfinite(ref)
    assert np.array_equal(finite, np.isfinite(field))
    assert np.allclose(field[finite], ref[finite], rtol=1e-12, atol=1e-12)
    result = astar(blocked, start, goal, connectivity=connectivity, method=method)
    if not finite[start[1], start[0]]:
        assert not result and result.cost == math.inf and result.cells is None
        return
    assert result
    assert result.cost == pytest.approx(ref[start[1], start[0]], rel=1e-12)
    assert tuple(result.cells[0]) == start and tuple(result.cells[-1]) == goal
    assert valid_moves(blocked, result.cells, connectivity)
    assert path_cost(result.cells) == pytest.approx(result.cost, rel=1e-12)
    if connectivity == 8:
        down = descend(field, start, blocked)
        assert down is not None and valid_moves(blocked, down, 8)
        assert path_cost(down) == pytest.approx(result.cost, rel=1e-12)


def test_corner_cutting_is_forbidden() -> None:
    blocked = np.array([[0, 1], [1, 0]], dtype=bool)
    assert not astar(blocked, (0, 0), (1, 1))
    blocked = np.array([[0, 0], [1, 0]], dtype=bool)
    assert astar(blocked, (0, 0), (1, 1)).cost == 2.0


def test_multi_source_field_is_the_minimum_of_single_fields() -> None:
    blocked = make_grid(7, 20, 15, 0.25)
    free = np.argwhere(~blocked)[:: max(1, len(np.argwhere(~blocked)) // 3)][:3, ::-1]
    combined = distance_field(blocked, free)
    single = np.minimum.reduce([distance_field(blocked, c) for c in free])
    assert np.array_equal(np.isfinite(combined), np.isfinite(single))
    assert np.allclose(combined[np.isfinite(combined)], single[np.isfinite(single)])


@pytest.mark.parametrize("bad, message", [((9, 0), "outside"), ((1, 1), "blocked"), ((0.5, 0), "whole numbers")])
def test_bad_cells_raise_clear_errors(bad, message) -> None:
    blocked = np.zeros((3, 3), dtype=bool)
    blocked[1, 1] = True
    with pytest.raises(ConfigError, match=message):
        astar(blocked, bad, (0, 0))


def test_bad_connectivity() -> None:
    with pytest.raises(ConfigError, match="connectivity"):
        astar(np.zeros((2, 2), bool), (0, 0), (1, 1), connectivity=6)


def test_repeated_queries_on_different_grids_reuse_buffers_correctly() -> None:
    # The C search keeps its buffers between calls: results must not leak between grids.
    small = np.zeros((4, 4), dtype=bool)
    big = make_grid(3, 60, 50, 0.2)
    free = np.argwhere(~big)
    a, b = tuple(free[0][::-1]), tuple(free[-1][::-1])
    expected = astar(big, a, b).cost
    for _ in range(3):
        assert astar(small, (0, 0), (3, 3)).cost == pytest.approx(3 * math.sqrt(2))
        assert astar(big, a, b).cost == expected
