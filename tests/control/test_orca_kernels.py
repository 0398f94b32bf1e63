"""The C kernels of one ORCA step (swarmpath.control.orca._orcalp, wrapped in kernels.py)
against their numpy references, bit for bit on random inputs: the nearest neighbours
(cKDTree), the robot-robot half-planes, the packing of lines, the pairwise move check of
``ORCASolver._robot_pairs`` and ``tidy_moves``; and whole runs of the ``orca`` controller
with and without the extension give the same trajectories."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from swarmpath.control.orca import ORCAController, ORCAParams, ORCASolver, core, kernels
from swarmpath.control.orca.halfplanes import orca_halfplanes_robots
from swarmpath.sim.simulator import Simulator
from swarmpath.world import RectBounds, Robot, World
from swarmpath.world.generators import antipodal, rooms_with_doors, with_obstacles

pytestmark = pytest.mark.skipif(kernels._orcalp is None, reason="the C extension is not built")


@pytest.fixture
def numpy_only(monkeypatch):
    """Run the numpy references: the kernels report the extension as missing."""
    monkeypatch.setattr(kernels, "_orcalp", None)


def reference_knn(pos: np.ndarray, k: int, upper: float) -> np.ndarray:
    dist, idx = cKDTree(pos).query(pos, k=k, distance_upper_bound=upper)
    dist, idx = dist.reshape(len(pos), k), idx.reshape(len(pos), k)
    return np.where(np.isfinite(dist) & (idx < len(pos)), idx, -1)


def random_positions(rng: np.random.Generator, n: int, kind: int) -> np.ndarray:
    """Scattered, on a lattice (many ties and duplicates), clustered far from the origin,
    or on a circle (mirror-image ties)."""
    if kind == 0:
        return rng.uniform(-20, 20, (n, 2))
    if kind == 1:
        return rng.integers(-6, 6, (n, 2)) * float(rng.choice([1.0, 0.5, 0.3]))
    if kind == 2:
        return rng.normal(0, 3, (n, 2)) + rng.uniform(-1e3, 1e3)
    a = 2 * np.pi * np.arange(n) / n
    r = n / (2 * np.pi) + rng.uniform(0, 3)
    return np.stack([7 + r * np.cos(a), 7 + r * np.sin(a)], axis=1)


# ------------------------------------------------------------------------------ neighbours
@pytest.mark.parametrize("seed", range(4))
def test_nearest_equals_ckdtree_where_distances_are_distinct(seed):
    rng = np.random.default_rng(seed)
    ties = 0
    for trial in range(200):
        n = int(rng.integers(1, 250))
        pos = random_positions(rng, n, trial % 4)
        k = min(int(rng.integers(1, 20)), n)
        upper = float(rng.choice([8.0, 0.7, 2.5, 1.0, 0.3, 3.0000000001, 1e6, np.inf]))
        idx, tied = kernels.nearest(pos, k, upper)
        ref = reference_knn(pos, k, upper)
        assert np.array_equal(idx[~tied], ref[~tied]), (trial, n, k, upper)
        # a tied row holds the same distances, in some order cKDTree may not share
        for row in np.flatnonzero(tied)[:5]:
            d_c = np.sort([np.sum((pos[row] - pos[j]) ** 2) for j in idx[row] if j >= 0])
            d_ref = np.sort([np.sum((pos[row] - pos[j]) ** 2) for j in ref[row] if j >= 0])
            assert np.array_equal(d_c, d_ref)
        ties += int(tied.sum())
    assert ties > 0          # the lattices and circles do have ties


def test_nearest_excludes_the_upper_distance_itself_as_ckdtree_does():
    pos = np.array([[0.0, 0.0], [0.7, 0.0], [0.0, 0.7], [0.49, 0.49], [0.3, 0.2]])
    idx, tied = kernels.nearest(pos, 5, 0.7)
    ref = reference_knn(pos, 5, 0.7)
    assert np.array_equal(idx[~tied], ref[~tied])
    assert 1 not in idx[0] and 2 not in idx[0]


@pytest.mark.parametrize("max_neighbours", [1, 3, 10, 70])
def test_solver_neighbours_equal_the_ckdtree_reference(max_neighbours, monkeypatch):
    """Ties included: those robots are asked of cKDTree, so the pairs come out identical.
    Beyond MAX_GRID_NEIGHBOURS the reference itself runs."""
    rng = np.random.default_rng(max_neighbours)
    solver = ORCASolver(ORCAParams(max_neighbours=max_neighbours, neighbour_distance=4.0))
    for trial in range(60):
        pos = random_positions(rng, int(rng.integers(2, 200)), trial % 4).astype(float)
        i, j = solver.neighbours(pos)
        with monkeypatch.context() as m:
            m.setattr(kernels, "_orcalp", None)
            ri, rj = solver.neighbours(pos)
        assert i.dtype == ri.dtype == j.dtype == rj.dtype == np.int64
        assert np.array_equal(i, ri) and np.array_equal(j, rj)


# ------------------------------------------------------------------------------ half-planes
def random_pairs(rng: np.random.Generator, n: int, e: int):
    """Robots (some point robots, some standing still, some touching or coincident) and e
    random (i, j) pairs of distinct robots."""
    pos = rng.uniform(0, 6, (n, 2))
    pos[: n // 10] = pos[n // 10: 2 * (n // 10)]                           # coincident
    pos[2 * (n // 10): 3 * (n // 10)] = pos[:n // 10] + rng.normal(0, 0.1, (n // 10, 2))   # in contact
    vel = rng.normal(0, 0.6, (n, 2))
    vel[rng.random(n) < 0.2] = 0.0
    vel[3 * (n // 10): 4 * (n // 10)] = vel[:n // 10]                       # w = 0 cases
    radii = rng.choice([0.0, 0.2, 0.3, 0.45], n)
    i = rng.integers(0, n, e)
    j = (i + rng.integers(1, n, e)) % n
    return pos, vel, radii, i.astype(np.int64), j.astype(np.int64)


@pytest.mark.parametrize("seed", range(6))
def test_robot_halfplanes_are_the_numpy_lines_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    n, e = 300, 4000
    pos, vel, radii, i, j = random_pairs(rng, n, e)
    fixed = rng.random(n) < 0.3
    resp = np.where(fixed, 1.0, 0.5)
    resolution = float(rng.choice([1.0, 0.5]))
    margin, tau, dt = 0.02, float(rng.choice([4.0, 2.0, 0.5])), float(rng.choice([1.0, 0.25]))
    points, directions = kernels.robot_halfplanes(pos, vel, radii, resp, i, j, np.sqrt(2.0) * resolution, margin,
                                                  tau, dt)
    both = (radii[i] == 0) & (radii[j] == 0)
    combined = np.where(both, np.sqrt(2.0) * resolution, radii[i] + radii[j]) + margin
    ref_p, ref_d = orca_halfplanes_robots(pos[j] - pos[i], vel[i] - vel[j], vel[i], combined, tau, dt, resp[j])
    assert np.array_equal(points, ref_p) and np.array_equal(directions, ref_d)
    # every branch was exercised: in contact, on the cut-off circle, on both legs
    dist = np.linalg.norm(pos[j] - pos[i], axis=1)
    assert (dist <= combined).any() and (dist > combined).any()


@pytest.mark.parametrize("fixed_share", [None, 0.3])
def test_solver_lines_are_the_numpy_lines(fixed_share, monkeypatch):
    world = antipodal(60)
    solver = ORCASolver()
    solver.reset(world)
    rng = np.random.default_rng(7)
    pos = world.starts + rng.normal(0, 3.0, world.starts.shape)
    vel = rng.normal(0, 0.4, pos.shape)
    fixed = None if fixed_share is None else rng.random(len(pos)) < fixed_share
    got = solver.lines(pos, vel, None, fixed)
    monkeypatch.setattr(kernels, "_orcalp", None)
    ref = solver.lines(pos, vel, None, fixed)
    for a, b in zip(got, ref):
        assert a.dtype == b.dtype and np.array_equal(a, b)


# ------------------------------------------------------------------------------ packing
@pytest.mark.parametrize("seed", range(4))
def test_pack_lines_in_c_equals_the_lexsort(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    e = int(rng.integers(0, 600))
    owner = rng.integers(0, n, e)
    tier = rng.integers(0, 3, e)
    pts, dirs = rng.normal(0, 1, (e, 2)), rng.normal(0, 1, (e, 2))
    got = kernels.pack_lines(owner, pts, dirs, tier, n)
    ref = kernels.pack_lines(owner, pts, dirs, tier, n, use_c=False)
    for a, b in zip(got, ref):
        assert a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b)


def test_pack_lines_rejects_bad_tiers():
    with pytest.raises(ValueError):
        kernels.pack_lines(np.array([0]), np.zeros((1, 2)), np.zeros((1, 2)), np.array([3]), 1)


# ------------------------------------------------------------------------------ pairwise check
def solver_for(radii: np.ndarray, resolution: float = 1.0) -> ORCASolver:
    """A solver reset on a world whose robots have these radii (starts far apart; the tests
    pass their own positions)."""
    n = len(radii)
    side = 4.0 * n + 4
    robots = tuple(Robot(f"r{k}", (2.0 + 4 * k, 2.0), (2.0 + 4 * k, side - 2.0), float(radii[k]), 1.0)
                   for k in range(n))
    solver = ORCASolver()
    solver.reset(World(RectBounds(side, side), robots=robots, resolution=resolution))
    return solver


@pytest.mark.parametrize("seed", range(6))
def test_robot_pairs_lower_the_same_levels_as_the_numpy_loop(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    for trial in range(25):
        n = int(rng.integers(2, 120))
        kind = trial % 3
        if kind == 0:           # discs in a crowd
            radii = rng.choice([0.2, 0.3, 0.4], n)
            p0 = rng.uniform(0, np.sqrt(n) * 1.2, (n, 2))
            ang = rng.uniform(0, 2 * np.pi, n)
            d = rng.uniform(0, 0.8, n)[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=1)
        else:                   # point robots on cell centres making grid moves (mixed with discs)
            radii = np.zeros(n) if kind == 1 else rng.choice([0.0, 0.3], n)
            p0 = rng.integers(0, int(np.sqrt(n)) + 2, (n, 2)) + 0.5
            d = rng.integers(-1, 2, (n, 2)).astype(float) * rng.choice([1.0, 0.5], (n, 1))
        d[rng.random(n) < 0.15] = 0.0
        solver = solver_for(radii)
        level = rng.integers(0, len(core.SCALES), n).astype(np.int64)
        level[rng.random(n) < 0.5] = 0
        threatened = rng.random(n) < 0.2
        got = solver._robot_pairs(p0, d, level, threatened)
        with monkeypatch.context() as m:
            m.setattr(kernels, "_orcalp", None)
            ref = solver._robot_pairs(p0, d, level, threatened)
        assert got.dtype == np.int64 and np.array_equal(got, ref), (seed, trial)


# ------------------------------------------------------------------------------ tidy moves
@pytest.mark.parametrize("seed", range(3))
def test_tidy_moves_in_c_equals_numpy(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    n = 500
    pos = rng.uniform(0, 10, (n, 2))
    goals = pos + rng.normal(0, 0.6, (n, 2))
    p1 = pos + rng.normal(0, 0.6, (n, 2))
    p1[:50] = goals[:50] + rng.normal(0, 1e-6, (50, 2))     # within the snap
    p1[50:100] = pos[50:100] + rng.normal(0, 1e-13, (50, 2))  # dust
    p1[100:120] = pos[100:120]
    step_len = rng.choice([0.5, 1.0, 0.0], n)
    got = core.tidy_moves(pos, p1, goals, step_len, 1e-6)
    monkeypatch.setattr(kernels, "_orcalp", None)
    ref = core.tidy_moves(pos, p1, goals, step_len, 1e-6)
    assert np.array_equal(got, ref)


# ------------------------------------------------------------------------------ whole runs
def run_positions(world: World, max_steps: int | None = None) -> np.ndarray:
    return Simulator(world, ORCAController(), None, seed=0, max_steps=max_steps).run().positions


def test_antipodal_runs_are_identical_without_the_extension(monkeypatch):
    world = antipodal(24)
    got = run_positions(world)
    monkeypatch.setattr(kernels, "_orcalp", None)
    assert np.array_equal(got, run_positions(world))


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["redraw", "waypoints", "random-walk"])
def test_runs_among_moving_obstacles_and_walls_are_identical_without_the_extension(kind, monkeypatch):
    world = with_obstacles(rooms_with_doors(), kind, 3, 1)
    got = run_positions(world, 60)
    monkeypatch.setattr(kernels, "_orcalp", None)
    assert np.array_equal(got, run_positions(world, 60))


@pytest.mark.slow
def test_a_crowd_of_100_is_identical_without_the_extension(monkeypatch):
    world = antipodal(100)
    got = run_positions(world)
    monkeypatch.setattr(kernels, "_orcalp", None)
    assert np.array_equal(got, run_positions(world))
