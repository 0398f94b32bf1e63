"""The turn game against turning bounce8 obstacles (control/turn_game.py): its values
against a brute-force game solved on the motion model itself, and robots it gets out of
nooks the open-loop look-ahead left them in."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.control.hazards import ObstacleForecast
from swarmpath.control.pibt.core import static_moves
from swarmpath.control.turn_game import TurnGame, turning_obstacles
from swarmpath.world import Bounce8, RandomWalk, Rect, RectBounds, StaticMap, World
from swarmpath.world.motions._straight import EIGHT_DIRECTIONS
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import MovingObstacle

DEPTH = 4


def _world(seed: int, size: int = 16) -> tuple[World, np.ndarray, np.ndarray]:
    """A random size x size map, a bounce8 obstacle (index 0) that will meet a wall or a
    blocked cell within DEPTH steps, and a random walker (index 1); their positions now and a
    step earlier."""
    rng = np.random.default_rng(seed)
    while True:
        blocked = rng.random((size, size)) < 0.2
        free = np.argwhere(~blocked)[:, ::-1]
        a, b = free[rng.choice(len(free), 2, replace=False)]
        heading = EIGHT_DIRECTIONS[rng.integers(8)]
        box = Rect((-0.5, -0.5), (0.5, 0.5))
        world = World(RectBounds(size, size), static_map=StaticMap(blocked, 1.0), moving_obstacles=(
            MovingObstacle("b", box, tuple(a + 0.5), tuple(heading), Bounce8()),
            MovingObstacle("w", box, tuple(b + 0.5), (1.0, 0.0), RandomWalk())))
        now = np.array([a + 0.5 + heading, b + 0.5], float)
        previous = np.array([a + 0.5, b + 0.5], float)
        fc = ObstacleForecast(world, world.grid())
        if world.obstacle_fits(world.moving_obstacles[0], now[:1])[0] \
                and list(turning_obstacles(fc, now, previous, DEPTH)) == [0]:
            return world, now, previous


def _successors(world: World, p: np.ndarray, v: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every next state of a bounce8 obstacle, straight from the model's rule: straight on if
    it fits, else each other compass direction at the same speed that fits, else stand
    reversed."""
    ob = world.moving_obstacles[0]
    if world.obstacle_fits(ob, (p + v)[None])[0]:
        return [(p + v, v)]
    speed = float(np.hypot(*v))
    out = [(p + d * speed, d * speed) for d in EIGHT_DIRECTIONS
           if not np.allclose(d * speed, v) and world.obstacle_fits(ob, (p + d * speed)[None])[0]]
    return out or [(p, -v)]


def _swept(p: np.ndarray, q: np.ndarray) -> set[tuple[int, int]]:
    """Cells whose centre the unit box's sweep from p to q holds: those for which some t in
    [0, 1] puts the centre inside the open box p + t (q - p) + (-0.5, 0.5)^2 on both axes at
    once (the two open intervals of t, one per axis, intersect within [0, 1])."""
    d = q - p
    lo, hi = np.minimum(p, q) - 0.5, np.maximum(p, q) + 0.5

    def when(axis: int, cell: int) -> tuple[float, float]:
        # t with  p - 0.5 + t d < cell + 0.5  and  p + 0.5 + t d > cell + 0.5
        a, b = cell + 1 - p[axis], cell - p[axis]
        if abs(d[axis]) < 1e-12:
            return (-np.inf, np.inf) if a > 0 > b else (np.inf, -np.inf)
        t1, t2 = a / d[axis], b / d[axis]
        return (t2, t1) if d[axis] > 0 else (t1, t2)

    out = set()
    for x in range(int(np.floor(lo[0])) - 1, int(np.ceil(hi[0])) + 1):
        for y in range(int(np.floor(lo[1])) - 1, int(np.ceil(hi[1])) + 1):
            (ax, bx), (ay, by) = when(0, x), when(1, y)
            if max(ax, ay, 0.0) < min(bx, by, 1.0) - 1e-9:
                out.add((x, y))
    return out


def _reference(world: World, now: np.ndarray, previous: np.ndarray, cells: list[tuple[int, int]]) -> list[int]:
    """The game of the module docstring by brute force: for each cell, the steps a robot
    arriving there next step can keep clear, the walker taken at its open-loop worst (D_k of
    a forecast that knows only the walker)."""
    walker_only = World(world.bounds, static_map=world.static_map, moving_obstacles=world.moving_obstacles[1:])
    cover = ObstacleForecast(walker_only, walker_only.grid()).coverage(now[1:], previous[1:], DEPTH)
    blocked = world.grid().blocked
    moves = static_moves(blocked)
    h, w = blocked.shape
    memo: dict = {}
    branches: dict = {}

    def value(p, v, level, c):
        state = (round(p[0] * 1e6), round(p[1] * 1e6), round(v[0] * 1e6), round(v[1] * 1e6))
        key = state + (level, c)
        if key in memo:
            return memo[key]
        if state not in branches:
            branches[state] = [(q, u, _swept(p, q)) for q, u in _successors(world, p, v)]
        best = DEPTH - level
        for q, u, swept in branches[state]:
            if cover[level][c[1], c[0]] or c in swept:
                got = 0
            elif level == DEPTH - 1:
                got = 1
            else:
                got = 1 + max(value(q, u, level + 1, (c[0] + dx, c[1] + dy))
                              for a, (dx, dy) in enumerate(GRID_MOVES.tolist()) if moves[c[1], c[0], a])
            best = min(best, got)
        memo[key] = best
        return best

    return [value(now[0], now[0] - previous[0], 0, c) if 0 <= c[0] < w and 0 <= c[1] < h and not blocked[c[1], c[0]]
            else None for c in cells]


@pytest.mark.parametrize("seed", range(12))
def test_values_match_the_game_solved_by_brute_force(seed) -> None:
    world, now, previous = _world(seed)
    blocked = world.grid().blocked
    fc = ObstacleForecast(world, world.grid())
    look = TurnGame(fc, static_moves(blocked), depth=DEPTH, budget=10 ** 6)
    centre = np.floor(now[0]).astype(int)
    rng = np.random.default_rng(seed)
    robots = np.clip(centre + rng.integers(-DEPTH - 2, DEPTH + 3, size=(3, 2)), 0, blocked.shape[0] - 1)
    owned = fc.owned_step_ranges(now, previous, DEPTH)
    origin, values, _, solved = look.clear_steps(now, previous, np.array([0]), owned, robots.min(axis=0)[None],
                                              robots.max(axis=0)[None])
    assert solved.all()
    cells = sorted({(int(x + dx), int(y + dy)) for x, y in robots for dx, dy in GRID_MOVES.tolist()})
    ref = _reference(world, now, previous, cells)
    got = [int(values[0, c[1] - origin[0, 1], c[0] - origin[0, 0]]) for c in cells]
    checked = [(c, r, g) for c, r, g in zip(cells, ref, got) if r is not None]
    assert checked and all(r == g for _, r, g in checked), [x for x in checked if x[1] != x[2]]
    # the open-loop look-ahead (a path clear of D_1 ... D_4 of both obstacles) never finds more
    opened = _open_loop(fc, now, previous, blocked, [c for c, _, _ in checked])
    assert all(o <= g for o, (_, _, g) in zip(opened, checked))


def _open_loop(fc, now, previous, blocked, cells) -> list[int]:
    """Steps a robot arriving in each cell next step keeps clear on the best fixed path."""
    cover = fc.coverage(now, previous, DEPTH)
    moves = static_moves(blocked)
    h, w = blocked.shape
    value = np.where(cover[DEPTH - 1], 0, 1)
    for level in range(DEPTH - 2, -1, -1):
        pad = np.zeros((h + 2, w + 2), int)
        pad[1:-1, 1:-1] = value
        best = np.zeros_like(value)
        for a, (dx, dy) in enumerate(GRID_MOVES.tolist()):
            best = np.maximum(best, np.where(moves[..., a], pad[1 + dy:1 + dy + h, 1 + dx:1 + dx + w], 0))
        value = np.where(cover[level], 0, 1 + best)
    return [int(value[y, x]) for x, y in cells]


def test_the_game_finds_room_the_open_loop_look_ahead_does_not() -> None:
    """Over the random cases: cells a robot can keep clear of longer when it reacts to the
    turn than on any fixed path (the point of the module)."""
    more = 0
    for seed in range(12):
        world, now, previous = _world(seed)
        blocked = world.grid().blocked
        fc = ObstacleForecast(world, world.grid())
        look = TurnGame(fc, static_moves(blocked), depth=DEPTH)
        c = np.floor(now[:1]).astype(int)
        owned = fc.owned_step_ranges(now, previous, DEPTH)
        origin, values, _, solved = look.clear_steps(now, previous, np.array([0]), owned, c - DEPTH, c + DEPTH)
        ys, xs = np.mgrid[-DEPTH:DEPTH + 1, -DEPTH:DEPTH + 1]
        cells = [(int(c[0, 0] + x), int(c[0, 1] + y)) for x, y in zip(xs.ravel(), ys.ravel())
                 if 0 <= c[0, 0] + x < blocked.shape[1] and 0 <= c[0, 1] + y < blocked.shape[0]
                 and not blocked[c[0, 1] + y, c[0, 0] + x]]
        opened = _open_loop(fc, now, previous, blocked, cells)
        got = [int(values[0, y - origin[0, 1], x - origin[0, 0]]) for x, y in cells]
        assert all(o <= g for o, g in zip(opened, got))
        more += sum(o < g for o, g in zip(opened, got))
    assert more > 0


def test_a_tree_over_the_budget_is_not_solved() -> None:
    world, now, previous = _world(0)
    fc = ObstacleForecast(world, world.grid())
    look = TurnGame(fc, static_moves(world.grid().blocked), depth=DEPTH, budget=1)
    c = np.floor(now[:1]).astype(int)
    _, _, _, solved = look.clear_steps(now, previous, np.array([0]), fc.owned_step_ranges(now, previous, DEPTH), c, c)
    assert not solved.any()


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_turn_game_setting_is_checked(controller) -> None:
    from swarmpath.errors import ConfigError
    from swarmpath.registry import CONTROLLERS
    from swarmpath.sim import Simulator

    from swarmpath.world import Robot

    world, _, _ = _world(0)
    free = np.argwhere(~world.grid().blocked)[:, ::-1]
    world = World(world.bounds, static_map=world.static_map, moving_obstacles=world.moving_obstacles,
                  robots=(Robot("r", tuple(free[0] + 0.5), tuple(free[-1] + 0.5), 0.0, float(np.sqrt(2))),))
    with pytest.raises(ConfigError, match="turn_game"):
        Simulator(world, CONTROLLERS.get(controller)(turn_game="yes"), None, seed=0, max_steps=2).run()
