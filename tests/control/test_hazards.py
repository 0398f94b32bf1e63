"""The moving-obstacle look-ahead on windows (control/hazards.py): the windows hold exactly the
whole-grid cell sets, and the tiers computed on them are the whole-grid backward induction, so
a controller's per-step cost follows the robots near obstacles, not the map."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from swarmpath.control import hazards as H
from swarmpath.control.cat_swarm import kernels as K
from swarmpath.control.pibt.core import static_moves
from swarmpath.sim import Simulator
from swarmpath.world import Circle, Rect, RectBounds, Robot, StaticMap, World
from swarmpath.world.move_rules import GRID_MOVES
from swarmpath.world.moving import Bounce, Bounce8, MovingObstacle, RandomWalk, Redraw, TurnEvery

S2 = float(np.sqrt(2))


def world_with_obstacles(seed: int, size: int = 24):
    rng = np.random.default_rng(seed)
    blocked = rng.random((size, size)) < 0.12
    motions = [Bounce(), Bounce8(), RandomWalk(), TurnEvery(3), Redraw()]
    free = np.argwhere(~blocked)[:, ::-1]
    obstacles = []
    for j, c in enumerate(free[rng.choice(len(free), 8, replace=False)]):
        shape = Rect((-0.4, -0.4), (0.4, 0.4)) if j % 2 else Circle((0, 0), 0.45)
        heading = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][j % 4]
        obstacles.append(MovingObstacle(f"m{j}", shape, tuple(c + 0.5), heading, motions[j % len(motions)]))
    robots = (Robot("a", tuple(free[0] + 0.5), tuple(free[-1] + 0.5), 0.0, S2),)
    world = World(RectBounds(size, size), static_map=StaticMap(blocked), moving_obstacles=tuple(obstacles),
                  robots=robots, name=f"hz{seed}")
    now = np.array([o.start for o in obstacles], float)
    previous = now - np.array([o.velocity for o in obstacles], float) * rng.uniform(0, 1, (len(obstacles), 1))
    return world, now, previous, rng


@pytest.mark.parametrize("seed", range(6))
def test_windows_hold_exactly_the_whole_grid_sets(seed):
    world, now, previous, rng = world_with_obstacles(seed)
    fc = H.ObstacleForecast(world, world.grid())
    full = fc.coverage(now, previous, 4, margin=seed % 2)
    size = 7
    origins = rng.integers(-4, 22, size=(30, 2))
    win = fc.windows(now, previous, 4, origins, size, margin=seed % 2)
    h, w = full[0].shape
    for k in range(4):
        for r, (ox, oy) in enumerate(origins.tolist()):
            for dy in range(size):
                for dx in range(size):
                    x, y = ox + dx, oy + dy
                    expected = bool(full[k][y, x]) if 0 <= x < w and 0 <= y < h else False
                    assert win[k, r, dy, dx] == expected


def test_window_moves_are_the_static_moves():
    rng = np.random.default_rng(1)
    blocked = rng.random((9, 11)) < 0.3
    padded = np.pad(blocked, 1, constant_values=True)
    for connectivity in (4, 8):
        assert np.array_equal(H.window_moves(padded, connectivity), static_moves(blocked, connectivity))
    assert np.array_equal(H.window_moves(padded), K.move_table(blocked))


@pytest.mark.parametrize("spare", [False, True])
@pytest.mark.parametrize("seed", range(4))
def test_tiers_on_windows_are_the_whole_grid_cascade(seed, spare):
    """The cascade of HazardWindows.tiers equals the same backward induction on the whole
    grid (what the controllers computed before the windows); with ``spare``, within a tier
    the candidates with two ways on (moves into the next tier's cells) when a robot has any."""
    world, now, previous, rng = world_with_obstacles(seed)
    grid = world.grid()
    fc = H.ObstacleForecast(world, grid)
    depth = 4
    full = fc.coverage(now, previous, depth)
    moves = K.move_table(grid.blocked)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    cells = free[rng.choice(len(free), 25, replace=False)]
    pad = depth + 2
    hz = H.hazard_windows(fc, now, previous, cells + 0.5, cells, np.pad(grid.blocked, pad, constant_values=True),
                          pad, depth, depth)
    assert hz is not None
    r = hz.rows
    dest = cells[r, None, :] + K.OFFSETS[None]
    h, w = grid.blocked.shape
    xs, ys = np.clip(dest[..., 0], 0, w - 1), np.clip(dest[..., 1], 0, h - 1)
    allowed = K.moves_at(grid.blocked, cells[r]) & ~full[0][ys, xs]
    fallback = rng.random(len(r)) < 0.3
    got, threatened, rank, ways = hz.tiers(allowed, dest, depth, spare=spare)
    kept, threatened_too, rank_too, ways_too = hz.tiers(allowed, dest, depth, spare=spare, fallback=fallback)
    # the whole-grid reference
    exits = K.moves_at(grid.blocked, np.stack([xs, ys], axis=-1).reshape(-1, 2)).reshape(len(r), 9, 9)
    # the moves of the step after, made while the obstacles stand where it left them
    exits &= H.moves_past(moves, H.standing_cells(full, 1))[ys, xs]
    around = np.stack([xs, ys], axis=-1)[:, :, None, :] + K.OFFSETS
    ax, ay = np.clip(around[..., 0], 0, w - 1), np.clip(around[..., 1], 0, h - 1)
    expected = allowed.copy()
    expected_threat = np.zeros(len(r), bool)
    undecided = np.ones(len(r), bool)
    # each candidate's rank: 2 per tier below the deepest (the deepest tier d it lies in; tier 1:
    # in none from 2 up), 1 more for a single way on there (with the spare way)
    expected_rank = np.full(allowed.shape, 2 * (depth - 1))
    expected_ways = np.zeros(allowed.shape, np.int64)
    seen = np.zeros(allowed.shape, bool)
    for d in range(depth, 1, -1):
        tier, after = H.safe_tier(full, moves, d)
        strict = allowed & tier[ys, xs]
        n_ways = np.sum(exits & after[ay, ax], axis=-1)
        new = strict & ~seen
        expected_rank[new] = (2 * (depth - d) + (spare & (n_ways < 2)))[new]
        expected_ways[new] = n_ways[new]
        seen |= new
        if spare:
            wide = strict & (np.sum(exits & after[ay, ax], axis=-1) >= 2)
            strict = np.where(wide.any(axis=1)[:, None], wide, strict)
        usable = strict.any(axis=1) & undecided
        expected = np.where(usable[:, None], strict, expected)
        expected_threat |= usable & ~strict[:, 0]
        undecided &= ~usable
    assert np.array_equal(got, expected)
    assert np.array_equal(threatened, expected_threat)
    assert np.array_equal(rank[allowed], expected_rank[allowed])
    assert np.array_equal(ways[allowed], expected_ways[allowed])
    # robots with a fallback keep every candidate (ranked the same); the others are cut as before
    assert np.array_equal(kept, np.where(fallback[:, None], allowed, expected))
    assert np.array_equal(threatened_too, threatened) and np.array_equal(rank_too, rank)
    assert np.array_equal(ways_too, ways)
    assert (allowed & ~got).any()   # the look-ahead really cut candidates here


def test_only_robots_an_obstacle_can_reach_get_a_window():
    world, now, previous, _ = world_with_obstacles(0, size=60)
    grid = world.grid()
    fc = H.ObstacleForecast(world, grid)
    free = np.argwhere(~grid.blocked)[:, ::-1]
    cells = free[::37]
    hz = H.hazard_windows(fc, now, previous, cells + 0.5, cells, np.pad(grid.blocked, 7, constant_values=True), 7,
                          5, 5)
    reach = fc.influence(5) + 6 * grid.resolution
    near = np.array([np.min(np.max(np.abs(now - (c + 0.5)), axis=1)) <= reach for c in cells])
    assert hz is not None and np.array_equal(np.sort(hz.rows), np.flatnonzero(near))
    assert hz.covered.shape == (5, len(hz.rows), 11, 11)   # windows, never the 60 x 60 grid


def test_cornered_penalty_only_for_robots_without_a_deepest_tier_cell():
    allowed = np.array([[True, True, False], [True, True, True]])
    rank = np.array([[0, 2, 0], [2, 3, 2]])
    ways = np.array([[1, 4, 9], [5, 1, 3]])
    out = H.cornered_penalty(allowed, rank, ways)
    assert out[0].tolist() == [0, 0, 0]          # has a candidate of rank 0: no penalty
    assert out[1].tolist() == [4, 8, 6]          # 9 - ways: most ways on ranks first


# ---------------------------------------------------------------------------- forecasts against the models
class _Choose:
    """An rng stand-in for the motion models: ``choice`` returns option ``k`` and records how
    many options there were, so every branch a model can take is run in turn."""

    def __init__(self, k: int = 0):
        self.k, self.options = k, 1

    def choice(self, options):
        self.options = len(options)
        return options[self.k]


def bounce_futures(world, ob, p, v, steps):
    """Every sweep (from, to) the bounce or bounce8 model can make at step 1 ... ``steps``
    from position ``p`` with velocity ``v``, found by running the model's own step with each
    choice."""
    from swarmpath.world.motions._straight import straight_step

    out = [[] for _ in range(steps)]

    def go(p, v, k):
        if k == steps:
            return
        probe = _Choose()
        eight = ob.motion.new_direction_on_hit
        straight_step(world, ob, p, v, world.dt, probe, eight=eight)
        for i in range(probe.options):
            q, w = straight_step(world, ob, p, v, world.dt, _Choose(i), eight=eight)
            out[k].append((p, q))
            go(q, w, k + 1)

    go(np.asarray(p, float), np.asarray(v, float), 0)
    return out


@pytest.mark.parametrize("motion", [Bounce8(), Bounce()], ids=["bounce8", "bounce"])
@pytest.mark.parametrize("seed", range(8))
def test_bounce_coverage_is_exactly_every_future_of_the_model(seed, motion):
    """A moving bounce or bounce8 obstacle turns only where it is blocked: D_2 ... D_4 hold
    exactly the cells of the sweeps the model can make (no box around the place of the first
    turn, and no corner of a diagonal sweep's bounding box); D_1 may hold more for bounce
    (every reflection, in case the heading is unsure)."""
    rng = np.random.default_rng(seed)
    size = 14
    blocked = rng.random((size, size)) < 0.2
    free = np.argwhere(~blocked)[:, ::-1]
    start = free[rng.integers(len(free))] + 0.5
    heading = H.UNIT_DIRECTIONS[rng.integers(8)] * (1.0 if seed % 2 else 0.7)
    shape = Rect((-0.5, -0.5), (0.5, 0.5)) if seed % 3 else Circle((0, 0), 0.35)
    ob = MovingObstacle("m", shape, tuple(start), tuple(heading), motion)
    world = World(RectBounds(size, size), static_map=StaticMap(blocked), moving_obstacles=(ob,),
                  robots=(Robot("a", tuple(free[0] + 0.5), tuple(free[-1] + 0.5), 0.0, S2),), name="b8")
    fc = H.ObstacleForecast(world, world.grid(), robot_radius=0.1 * (seed % 3))
    now = np.array([start])
    coverage = fc.coverage(now, now - heading * world.dt, 4)
    for k, sweeps in enumerate(bounce_futures(world, ob, start, heading, 4)):
        a = np.array([s[0] for s in sweeps])
        b = np.array([s[1] for s in sweeps])
        expected = H.paint(blocked.shape, fc.sweep_ranges(a, b, fc.keep_lo, fc.keep_hi)[0])
        if k or isinstance(motion, Bounce8):
            assert np.array_equal(coverage[k], expected), k
        else:
            assert not (expected & ~coverage[k]).any()



@pytest.mark.parametrize("centres", [False, True], ids=["squares", "centres"])
def test_sweep_cells_are_exactly_those_the_moving_box_covers(centres) -> None:
    """sweep_cell_ranges against a dense sampling of the sweep (4,001 positions of the box):
    every cell a sampled box covers is listed, none beyond the sweep's bounding box, and over
    600 random sweeps (any direction, grid steps among them) at most a few cells more than
    the sampling finds (its own slack); diagonal sweeps leave out some box corners."""
    rng = np.random.default_rng(7)
    size = 25
    ys, xs = np.mgrid[0:size, 0:size]
    extra = saved = 0
    for trial in range(600):
        a = rng.uniform(5, 15, 2)
        angle = rng.uniform(0, 2 * np.pi)
        d = np.array([np.cos(angle), np.sin(angle)]) * rng.uniform(0.2, 2.0)
        d = np.round(d) if trial % 5 == 0 else d
        half = rng.uniform(0.3, 1.2, 2)
        ranges, owner = H.sweep_cell_ranges(a[None], (a + d)[None], -half[None], half[None], 1.0, centres)
        assert (owner == 0).all()
        got = H.paint((size, size), ranges)
        rule = H.centre_cell_ranges if centres else H.box_cell_ranges
        box = H.paint((size, size), rule(np.minimum(a, a + d)[None] - half, np.maximum(a, a + d)[None] + half, 1.0))
        want = np.zeros((size, size), bool)
        for t in np.linspace(0, 1, 4001):
            lo, hi = a + t * d - half + 1e-7, a + t * d + half - 1e-7
            if centres:
                want |= (xs + 0.5 > lo[0]) & (xs + 0.5 < hi[0]) & (ys + 0.5 > lo[1]) & (ys + 0.5 < hi[1])
            else:
                want |= (xs < hi[0]) & (xs + 1 > lo[0]) & (ys < hi[1]) & (ys + 1 > lo[1])
        assert not (want & ~got).any(), trial
        assert not (got & ~box).any(), trial
        extra += int((got & ~want).sum())
        saved += int((box & ~got).sum())
    assert extra <= 3
    assert saved > 100


def test_forecasts_hold_every_simulated_future():
    """Obstacles of every forecast class, of several shapes and speeds, run by the simulator's
    own motion models in a cluttered world: each sweep an obstacle makes k steps later lies in
    the D_k forecast from its position and velocity now."""
    from swarmpath.testing.motions import obstacle_track
    from swarmpath.world.moving import initial_obstacle_state

    world, _, _, rng = world_with_obstacles(3, size=20)
    obs = [o for o in world.moving_obstacles if o.motion.forecast != "teleport"]   # redraw jumps anywhere
    obs += [MovingObstacle(f"w{k}", Rect((-0.5, -0.5), (0.5, 0.5)), o.start, (0.8, 0.0), m)
            for k, (o, m) in enumerate(zip(obs[:4], (Bounce8(), RandomWalk(), TurnEvery(2), TurnEvery(7))))]
    world = World(world.bounds, static_map=world.static_map, moving_obstacles=tuple(obs), robots=world.robots,
                  name="all")
    fc = H.ObstacleForecast(world, world.grid(), robot_radius=0.2)
    track = obstacle_track(world, 120, rng)
    start = initial_obstacle_state(world)
    path = np.concatenate([(start.positions - start.velocities * world.dt)[None], track])
    depth = 4
    tighter = 0
    for t in range(1, len(path) - depth):
        loose = fc.coverage(path[t], path[t - 1], depth)
        fc.at_step(t - 1)   # path[t]: the obstacles after their move of step t - 1
        coverage = fc.coverage(path[t], path[t - 1], depth)
        tighter += int(sum(c.sum() for c in loose) > sum(c.sum() for c in coverage))
        assert all(not (c & ~lc).any() for c, lc in zip(coverage, loose))
        for k in range(1, depth + 1):
            a, b = path[t + k - 1], path[t + k]
            swept = H.paint(coverage[0].shape, fc.sweep_ranges(a, b, fc.keep_lo, fc.keep_hi)[0])
            assert not (swept & ~coverage[k - 1]).any(), (t, k)
        fc = H.ObstacleForecast(world, world.grid(), robot_radius=0.2)   # no step known: any-heading
    assert tighter > len(path) // 2   # turn-every is forecast as a bouncer between its turns


def test_dead_end_cells_are_the_cells_peeled_with_one_way_on():
    """A 1-cell nook, a 3-cell dead-end corridor and a loop: the nook and the corridor are dead
    ends, the loop and the open room are not (8-connected moves without corner cutting)."""
    rows = ["#########",
            "#.......#",
            "#.......#",
            "#.###.#.#",
            "#.#.#.#.#",
            "#.....#.#",
            "#######.#",
            "#######.#",
            "#########"]
    blocked = np.array([[c == "#" for c in r] for r in rows])[::-1]   # row 0 of the list is the top
    dead = H.dead_end_cells(static_moves(blocked, 8))
    cells = {(int(x), int(y)) for y, x in zip(*np.nonzero(dead))}
    # (3, 4): a nook above the loop's floor; (7, 1..5): the corridor down the right side
    assert cells == {(3, 4), (7, 1), (7, 2), (7, 3), (7, 4), (7, 5)}
    assert not H.dead_end_cells(static_moves(np.zeros((5, 5), bool), 8)).any()


def _pockets_by_search(blocked: np.ndarray, reach: int) -> set[tuple[int, int]]:
    """The definition of :func:`pocket_cells` searched plainly: for every free cell m, close
    the 3 x 3 around it and flood (8-connected moves without corner cutting) from every free
    cell within ``reach``; a cell that reaches no cell more than ``reach`` from m (Chebyshev)
    nor the grid's outside beyond that is in a pocket."""
    h, w = blocked.shape
    free = ~blocked
    moves = static_moves(blocked, 8)
    out = set()
    for my, mx in zip(*np.nonzero(free)):
        closed = np.zeros_like(blocked)
        closed[max(my - 1, 0):my + 2, max(mx - 1, 0):mx + 2] = True
        seen: set[tuple[int, int]] = set()
        for sy in range(max(my - reach, 0), min(my + reach + 1, h)):
            for sx in range(max(mx - reach, 0), min(mx + reach + 1, w)):
                if not free[sy, sx] or closed[sy, sx] or (sx, sy) in seen:
                    continue
                part, stack, escapes = {(sx, sy)}, [(sx, sy)], False
                while stack:
                    x, y = stack.pop()
                    if max(abs(x - mx), abs(y - my)) >= reach:
                        escapes = True      # on the window's edge: the part goes on beyond
                    for a in range(1, 9):
                        if not moves[y, x, a]:
                            continue
                        nx, ny = x + int(GRID_MOVES[a, 0]), y + int(GRID_MOVES[a, 1])
                        if closed[ny, nx] or (nx, ny) in part or max(abs(nx - mx), abs(ny - my)) > reach:
                            continue
                        part.add((nx, ny))
                        stack.append((nx, ny))
                seen |= part
                if not escapes:
                    out |= part
    return out


def test_pocket_cells_are_the_cells_one_obstacle_shuts_in():
    """A 2 x 3 nook with a 2-cell mouth at the map's edge is a pocket (an obstacle in the mouth
    shuts it); the open room beside it is not. On random maps the labelled windows give
    exactly the cells a plain search of the definition finds."""
    rows = ["##########",
            "#........#",
            "#........#",
            "#........#",
            "#....#####",
            "#.......##",
            "#.......##",
            "#....#..##",
            "##########"]
    blocked = np.array([[c == "#" for c in r] for r in rows])[::-1]
    pockets = H.pocket_cells(static_moves(blocked, 8), reach=4)
    cells = {(int(x), int(y)) for y, x in zip(*np.nonzero(pockets))}
    assert {(x, y) for x in (6, 7) for y in (1, 2, 3)} <= cells      # the nook
    assert not pockets[5:8, 3:7].any()                               # the middle of the room above
    assert not H.pocket_cells(static_moves(np.zeros((12, 12), bool), 8), reach=4).any()
    rng = np.random.default_rng(7)
    for density in (0.15, 0.25, 0.35):
        blocked = rng.random((14, 17)) < density
        found = H.pocket_cells(static_moves(blocked, 8), reach=3, batch=37)
        assert {(int(x), int(y)) for y, x in zip(*np.nonzero(found))} == _pockets_by_search(blocked, 3), density


def _walled_in_world() -> World:
    """A bounce obstacle heading north in a 1-cell gap of a vertical wall (cells above and
    below it blocked): it can never move. A robot east of the wall has its goal in the cell
    east of the obstacle."""
    blocked = np.zeros((7, 9), bool)
    blocked[:, 4] = True
    blocked[3, 4] = False
    ob = MovingObstacle("stuck", Rect((-0.5, -0.5), (0.5, 0.5)), (4.5, 3.5), (0.0, 1.0), Bounce())
    robots = (Robot("a", (7.5, 0.5), (5.5, 3.5), 0.0, S2),)
    return World(RectBounds(9, 7), static_map=StaticMap(blocked, 1.0), moving_obstacles=(ob,), robots=robots,
                 name="walled-in")


def test_a_bouncer_that_stood_still_is_forecast_to_stay():
    """Standing still means every flip of its heading was blocked, and a bounce obstacle tries the
    same four each step: D_1 ... D_4 are its own cell (they were every cell within its speed)."""
    from swarmpath.world.moving import advance_obstacles, initial_obstacle_state

    world = _walled_in_world()
    state = initial_obstacle_state(world)
    rng = np.random.default_rng(0)
    for _ in range(6):
        nxt = advance_obstacles(world, state, rng)
        assert np.array_equal(nxt.positions, state.positions)
        state = nxt
    fc = H.ObstacleForecast(world, world.grid())
    p = state.positions
    for cover in fc.coverage(p, p, 4):
        assert np.argwhere(cover).tolist() == [[3, 4]]
    # turn-every stands as a bouncer does until its next turn (period 4, seen after step 5: the
    # moves of steps 6 and 7 are steady, that of step 8 may head anywhere), then may leave the gap
    turner = World(world.bounds, static_map=world.static_map, robots=world.robots, name="walled-in-turner",
                   moving_obstacles=(dataclasses.replace(world.moving_obstacles[0], motion=TurnEvery(4)),))
    fc = H.ObstacleForecast(turner, turner.grid())
    fc.at_step(5)
    cover = fc.coverage(p, p, 4)
    assert [np.argwhere(c).tolist() for c in cover[:2]] == [[[3, 4]], [[3, 4]]]
    assert cover[2].sum() > 1 and cover[2][3, 3] and cover[2][3, 5]


@pytest.mark.parametrize("controller", ["pibt", "cat-swarm"])
def test_a_robot_reaches_its_goal_beside_a_walled_in_bouncer(controller):
    """The goal beside the walled-in bouncer was always in its forecast reach: the robot waited
    beside it for ever. Now it arrives, and the checker finds no contact."""
    from swarmpath.registry import CONTROLLERS
    from swarmpath.testing import validate_trajectory

    world = _walled_in_world()
    traj = Simulator(world, CONTROLLERS.get(controller)(), None, seed=0, max_steps=100).run()
    assert validate_trajectory(world, traj) == []
    assert traj.status == "all_reached"


def test_waypoint_obstacles_are_forecast_along_their_route():
    """A waypoints obstacle (speed 0.8: it turns at corners mid-step) is replayed from its start:
    every sweep it makes k steps later lies in D_k, and D_k is then the sweep itself, far fewer
    cells than the reach boxes it had before. Seen where its replay says it is not (a run
    started elsewhere), it stays any-heading."""
    from swarmpath.world.moving import Waypoints, advance_obstacles, initial_obstacle_state

    blocked = np.zeros((12, 12), bool)
    blocked[5:7, 5:7] = True
    route = Waypoints(((9.5, 2.5), (9.5, 9.5), (2.5, 9.5), (2.5, 2.5)), True)
    ob = MovingObstacle("w", Rect((-0.4, -0.4), (0.4, 0.4)), (2.5, 2.5), (0.8, 0.0), route)
    world = World(RectBounds(12, 12), static_map=StaticMap(blocked), moving_obstacles=(ob,),
                  robots=(Robot("a", (0.5, 0.5), (11.5, 11.5), 0.2, S2),), name="route")
    state = initial_obstacle_state(world)
    rng = np.random.default_rng(0)
    path = [state.positions.copy(), state.positions.copy()]   # path[t]: after the move of step t - 1
    for _ in range(60):
        state = advance_obstacles(world, state, rng)
        path.append(state.positions.copy())
    path = np.array(path)
    depth = 5
    for t in range(2, len(path) - depth):
        fc = H.ObstacleForecast(world, world.grid(), robot_radius=0.2)
        loose = fc.coverage(path[t], path[t - 1], depth)
        fc.at_step(t - 1, path[t])
        coverage = fc.coverage(path[t], path[t - 1], depth)
        for k in range(1, depth + 1):
            a, b = path[t + k - 1], path[t + k]
            swept = H.paint(coverage[0].shape, fc.sweep_ranges(a, b, fc.keep_lo, fc.keep_hi)[0])
            assert not (swept & ~coverage[k - 1]).any(), (t, k)
            assert np.array_equal(swept, coverage[k - 1]), (t, k)
        assert sum(c.sum() for c in coverage) < sum(c.sum() for c in loose) / 2
        elsewhere = H.ObstacleForecast(world, world.grid(), robot_radius=0.2)
        elsewhere.at_step(t - 1, path[t] + 0.5)
        assert not elsewhere.script


def _simulated_obstacles(seed: int, steps: int, cell_sized: bool = False):
    """A cluttered world's obstacles of every forecast class but teleport (a redraw jumps
    anywhere off the robots' cells), run ``steps`` steps by the simulator's own models:
    (world, positions (steps + 2, m, 2), the first being one step before the start). With
    ``cell_sized`` every obstacle is a 1 x 1 box."""
    from swarmpath.world.moving import advance_obstacles, initial_obstacle_state

    world, _, _, rng = world_with_obstacles(seed, size=20)
    obs = tuple(o for o in world.moving_obstacles if o.motion.forecast != "teleport")
    if cell_sized:
        obs = tuple(dataclasses.replace(o, shape=Rect((-0.5, -0.5), (0.5, 0.5))) for o in obs)
    world = World(world.bounds, static_map=world.static_map, moving_obstacles=obs, robots=world.robots,
                  name=f"disc{seed}")
    state = initial_obstacle_state(world)
    path = [state.positions - state.velocities * world.dt, state.positions]
    for _ in range(steps):
        state = advance_obstacles(world, state, rng)
        path.append(state.positions)
    return world, np.array(path)


@pytest.mark.parametrize("seed", range(8))
def test_every_cell_of_the_two_step_tier_keeps_a_way_on_the_checker_clears(seed):
    """The claim of :func:`~swarmpath.control.hazards.safe_tier` against the checker: a robot
    that ends this step on a cell of the two-step tier (S_1) is not hit in the next step
    wherever the obstacles go, and then has a move, made among the obstacles where that step
    left them, into S_2 that the checker clears. Before the diagonals past an obstacle's next
    cell were left out, a diagonal that crossed it counted as that way on. The obstacles are
    1 x 1 boxes, on and off the grid (bounce8 steps diagonals of length 1), the robots points:
    the claim holds for footprints at least a cell wide (:func:`~swarmpath.control.hazards.
    moves_past`)."""
    from swarmpath.sim.collisions import robot_moving_contacts

    world, path = _simulated_obstacles(seed, 80, cell_sized=True)
    grid = world.grid()
    h, w = grid.blocked.shape
    moves = static_moves(grid.blocked)
    fc = H.ObstacleForecast(world, grid)
    checked = 0
    for t in range(1, len(path) - 1):
        fc.at_step(t - 1, path[t])
        covered = fc.coverage(path[t], path[t - 1], 2)
        first, then = H.safe_tier(covered, moves, 2)
        cells = np.argwhere(first & ~grid.blocked)[:, ::-1]
        if not len(cells):
            continue
        centres = cells + 0.5
        radii = np.zeros(len(cells))
        assert robot_moving_contacts(world, centres, centres, path[t], path[t + 1], radii) == [], t
        way_on = np.zeros(len(cells), bool)
        for a, move in enumerate(GRID_MOVES):
            ends = cells + move
            inside = np.all((ends >= 0) & (ends < [w, h]), axis=1)
            ok = inside & moves[cells[:, 1], cells[:, 0], a]
            ok[ok] &= then[ends[ok, 1], ends[ok, 0]]
            hit = {i for i, _, _ in robot_moving_contacts(world, centres[ok], centres[ok] + move, path[t + 1],
                                                          path[t + 1], radii[ok])}
            way_on[np.flatnonzero(ok)[[i for i in range(int(ok.sum())) if i not in hit]]] = True
        assert way_on.all(), (t, cells[~way_on][:3].tolist())
        checked += len(cells)
    assert checked > 1000


@pytest.mark.parametrize("radius", [0.0, 0.3, 0.5])
@pytest.mark.parametrize("seed", range(3))
def test_robots_on_uncovered_cells_are_never_hit_by_the_checker(seed, radius):
    """The cover rule against the independent checker, for point and disc robots: a robot
    resting on an uncovered cell's centre (D_1) meets no obstacle in the next step, and a move
    between two uncovered 8-adjacent centres that :meth:`crossings` clears meets none where
    the obstacles stand. Disc robots count cells by their centres, so they lose far fewer
    cells than a square-overlap rule would take from them; point robots lose at most the
    cells of the sweeps' bounding boxes."""
    from swarmpath.sim.collisions import robot_moving_contacts

    world, path = _simulated_obstacles(seed, 60)
    h, w = world.grid().blocked.shape
    fc = H.ObstacleForecast(world, world.grid(), robot_radius=radius)
    cells = np.argwhere(np.ones((h, w), bool))[:, ::-1]
    centres = cells + 0.5
    radii = np.full(len(cells), radius)
    lost = squares = hits = 0
    for t in range(1, len(path) - 1):
        fc.at_step(t - 1, path[t])
        danger = fc.danger(path[t], path[t - 1])
        clear = ~danger[cells[:, 1], cells[:, 0]]
        rest = robot_moving_contacts(world, centres[clear], centres[clear], path[t], path[t + 1], radii[clear])
        assert rest == [], (t, rest[:3])
        hits += len(robot_moving_contacts(world, centres, centres, path[t], path[t + 1], radii))
        lost += int(danger.sum())
        p = path[t].reshape(-1, 2)
        cand, possible, extra = fc.next_positions(p, path[t - 1])
        j, s = np.nonzero(possible)
        q = cand[j, s]
        squares += int(H.paint(danger.shape, H.box_cell_ranges(np.minimum(p[j], q) + fc.keep_lo[j] - extra[j, None],
                                                                np.maximum(p[j], q) + fc.keep_hi[j] + extra[j, None],
                                                                1.0)).sum())
        for move in GRID_MOVES[1:]:
            ends = cells + move
            inside = np.all((ends >= 0) & (ends < [w, h]), axis=1)
            ok = clear & inside
            ok[inside] &= ~danger[ends[inside, 1], ends[inside, 0]]
            ok[ok] &= ~fc.crossings(centres[ok], (centres[ok] + move)[:, None, :], path[t])[:, 0]
            moved = robot_moving_contacts(world, centres[ok], centres[ok] + move, path[t], path[t], radii[ok])
            assert moved == [], (t, move, moved[:3])
    assert hits > 0                       # obstacles do sweep over cells: the check can fail
    if radius > 0:
        assert lost < 0.6 * squares       # centre cover: far fewer cells lost than by squares
    else:
        assert lost <= squares            # the swept region, no more than its bounding boxes


@pytest.mark.parametrize("radius", [0.0, 0.3, 0.5])
def test_sweep_hits_is_the_checkers_phase_one_for_robots_off_centre(radius):
    """:meth:`ObstacleForecast.sweep_hits` at points anywhere (exact goals off the cell centres)
    flags every point the obstacles' actual next move hits (by the checker) and is exact for
    the obstacles whose next position is certain (a straight run)."""
    from swarmpath.sim.collisions import robot_moving_contacts

    world, path = _simulated_obstacles(7, 60)
    h, w = world.grid().blocked.shape
    rng = np.random.default_rng(1)
    points = rng.uniform(0, [w, h], (400, 2))
    radii = np.full(len(points), radius)
    fc = H.ObstacleForecast(world, world.grid(), robot_radius=radius)
    flagged = hit = 0
    for t in range(1, len(path) - 1):
        fc.at_step(t - 1, path[t])
        may = fc.sweep_hits(points, path[t], path[t - 1])
        actual = {i for i, _, _ in robot_moving_contacts(world, points, points, path[t], path[t + 1], radii)}
        assert all(may[i] for i in actual), t
        flagged += int(may.sum())
        hit += len(actual)
    assert hit > 0
    assert flagged < 12 * hit             # the worst case of a walker's 9 moves, not a blanket


@pytest.mark.parametrize("radius", [0.0, 0.3, 0.5])
def test_crossings_is_the_checkers_phase_two(radius):
    """:meth:`ObstacleForecast.crossings` against the checker's phase 2 (robots move among the
    obstacles where they stand) for moves from random points: the same answer for every move
    of a disc robot and for point robots among boxes; for point robots among discs it may
    also forbid moves through the bounding box's corners, never allow one that meets the
    disc. (Seed 7 of the 64 x 64 world with discs of radius 0.3: a robot resting on its goal
    in the corner of an obstacle's box grown by the radius, clear of the obstacle, was denied
    every move, the obstacle's next step hit it.)"""
    from swarmpath.sim.collisions import robot_moving_contacts

    world, path = _simulated_obstacles(5, 1)
    fc = H.ObstacleForecast(world, world.grid(), robot_radius=radius)
    rng = np.random.default_rng(2)
    here = path[1].reshape(-1, 2)
    starts = here[rng.integers(len(here), size=3000)] + rng.uniform(-1.6, 1.6, (3000, 2))
    ends = starts + GRID_MOVES[rng.integers(0, 9, size=3000)]
    said = fc.crossings(starts, ends[:, None, :], here)[:, 0]
    hit = np.zeros(len(starts), bool)
    for i, _, _ in robot_moving_contacts(world, starts, ends, here, here, np.full(len(starts), radius)):
        hit[i] = True
    boxes = np.array([not isinstance(o.shape, Circle) for o in world.moving_obstacles])
    assert hit.sum() > 100 and (~hit).sum() > 100
    assert not (hit & ~said).any()
    if radius > 0 or boxes.all():
        assert np.array_equal(said, hit)
    else:
        assert (said & ~hit).any()
