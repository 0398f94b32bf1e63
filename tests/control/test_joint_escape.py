"""Robots in danger beside one another choose their moves jointly (pibt/joint_escape.py)."""

import itertools

import numpy as np
import pytest

from swarmpath.control.pibt.core import GridGraph, conflict_table, pibt_step_escaping
from swarmpath.control.pibt.joint_escape import (
    best_joint_moves,
    danger_groups,
    joint_escapes,
    prefer_joint_escapes,
)
from swarmpath.world.move_rules import GRID_MOVES, NEAR_OFFSETS

STAY = 0


def conflicting(cells, moves, table) -> bool:
    """Brute force: any pair of robots whose moves the table forbids."""
    for i, j in itertools.combinations(range(len(cells)), 2):
        off = cells[j] - cells[i]
        if np.abs(off).max() <= 2:
            k = int(np.flatnonzero((NEAR_OFFSETS == off).all(axis=1))[0])
            if table[k, moves[i], moves[j]]:
                return True
    return False


@pytest.mark.parametrize("radius", [0.0, 0.5])
def test_joint_moves_are_the_cheapest_combination_the_checker_allows(radius):
    """Against plain enumeration of every combination of allowed moves, on 300 random groups
    of 2-4 robots packed into a 4 x 4 area: the same least total, and the moves returned are
    allowed, conflict-free and add up to it."""
    table = conflict_table(radius, 1.0)
    rng = np.random.default_rng(7)
    found = none = 0
    for _ in range(300):
        k = int(rng.integers(2, 5))
        cells = np.argwhere(np.ones((4, 4)))[rng.choice(16, k, replace=False)][:, ::-1]
        allowed = rng.random((k, 9)) < 0.5
        cost = rng.integers(0, 4, (k, 9)) * 1e8 + rng.random((k, 9))
        cost[rng.random((k, 9)) < 0.1] = np.inf
        best = np.inf
        for combo in itertools.product(*[np.flatnonzero(allowed[i] & np.isfinite(cost[i])) for i in range(k)]):
            if not conflicting(cells, combo, table):
                best = min(best, sum(cost[i, a] for i, a in enumerate(combo)))
        moves = best_joint_moves(cells, cost, allowed, table, budget=10**6)
        if not np.isfinite(best):
            assert moves is None
            none += 1
            continue
        found += 1
        assert moves is not None and allowed[np.arange(k), moves].all()
        assert not conflicting(cells, moves, table)
        assert cost[np.arange(k), moves].sum() == pytest.approx(best, rel=1e-12)
    assert found > 200 and none > 0


def test_a_search_over_budget_gives_up():
    table = conflict_table(0.0, 1.0)
    cells = np.array([[0, 0], [1, 0], [2, 0], [3, 0]])
    cost = np.random.default_rng(1).random((4, 9))
    allowed = np.ones((4, 9), bool)
    assert best_joint_moves(cells, cost, allowed, table, budget=5) is None
    assert best_joint_moves(cells, cost, allowed, table, budget=10**6) is not None


def test_groups_chain_robots_within_two_cells():
    cells = np.array([[0, 0], [2, 1], [4, 3], [9, 9], [12, 9], [20, 20]])
    groups = danger_groups(cells, np.arange(6))
    assert [g.tolist() for g in groups] == [[0, 1, 2]]      # 3 and 4 are 3 apart; 5 alone
    assert [g.tolist() for g in danger_groups(cells, np.array([0, 2]))] == []


def test_two_robots_in_danger_take_the_pair_of_cells_of_least_total_cost():
    """A (left) and B (right) stand on a row an obstacle may sweep next step and may only go
    down. A's cheap way out is its diagonal to (1, 0), its other one costs 5; B's cheap one is
    straight down to (1, 0), its other one, the diagonal to (2, 0), costs 10 (say a walker
    is near). Deciding one at a time with A first, A takes (1, 0) and B pays 10 (total 11).
    Jointly both go straight down (total 6), in either order."""
    south, south_east = 7, 8
    graph = GridGraph.build(np.zeros((2, 3), bool), 8, 0.0, 1.0)
    cells = np.array([[0, 1], [1, 1]])                      # A, B
    flat = (cells[:, 1] * 3 + cells[:, 0]).astype(np.int32)
    allowed = np.zeros((2, 9), bool)
    allowed[:, [south, south_east]] = True
    dist = np.full((2, 9), np.nan)
    dist[0, south_east], dist[0, south] = 1.0, 5.0
    dist[1, south], dist[1, south_east] = 1.0, 10.0
    kw = {"danger": np.array([True, True]), "rank": np.zeros((2, 9), np.int64), "goals": np.full(2, 5, np.int32)}
    plain = pibt_step_escaping(graph, flat, np.nan_to_num(dist, nan=np.inf), allowed, np.zeros((2, 9)),
                               np.array([0, 1], np.int32), **kw)
    assert plain.moves.tolist() == [south_east, south_east]
    joint = prefer_joint_escapes(dist, cells, allowed, np.arange(2), graph.table, (2, 3), 1e7)
    for order in ([0, 1], [1, 0]):
        out = pibt_step_escaping(graph, flat, np.nan_to_num(joint, nan=np.inf), allowed, np.zeros((2, 9)),
                                 np.array(order, np.int32), **kw)
        assert out.moves.tolist() == [south, south] and out.conflicts == 0


def test_other_robots_keep_off_the_chosen_cells():
    """A calm robot beside a group pays the claim for moving onto a cell the group chose
    (including a robot's own cell when it stays), and nothing for other cells."""
    table = conflict_table(0.0, 1.0)
    cells = np.array([[2, 2], [3, 2], [4, 4]])
    allowed = np.ones((3, 9), bool)
    dist = np.zeros((3, 9))
    dist[0] = np.arange(9.0)        # robot 0 prefers to stay
    dist[1] = 9.0 - np.arange(9.0)  # robot 1 prefers its last move (south east)
    out = prefer_joint_escapes(dist, cells, allowed, np.arange(2), table, (8, 8), 100.0)
    moves = joint_escapes(cells, np.where(np.isnan(dist), np.inf, dist), allowed, np.arange(2), table)
    assert moves[2] == -1 and moves[0] >= 0 and moves[1] >= 0
    chosen = {tuple(cells[i] + GRID_MOVES[moves[i]]) for i in range(2)}
    for a in range(9):
        claimed = tuple(cells[2] + GRID_MOVES[a]) in chosen
        assert out[2, a] == dist[2, a] + (100.0 if claimed else 0.0)
    for i in range(2):
        assert out[i, moves[i]] < np.delete(out[i], moves[i]).min()


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
@pytest.mark.parametrize("value", ["yes", 1, None])
def test_a_joint_escape_setting_that_is_not_true_or_false_is_one_clear_error(controller, value):
    from swarmpath.errors import ConfigError
    from swarmpath.registry import CONTROLLERS
    from swarmpath.world import MovingObstacle, RandomWalk, Rect, RectBounds, Robot, World

    world = World(RectBounds(8, 8), robots=(Robot("r0", (0.5, 0.5), (6.5, 6.5)),),
                  moving_obstacles=(MovingObstacle("m0", Rect((-0.5, -0.5), (0.5, 0.5)), (4.5, 4.5), (1.0, 0.0),
                                                   RandomWalk()),))
    with pytest.raises(ConfigError, match="joint_escape must be True or False"):
        CONTROLLERS.get(controller)(joint_escape=value).reset(world, None, np.random.default_rng(0))
