"""ORCA's linear programs (swarmpath.control.orca.lp and the C loop): hand-computed values,
agreement with scipy.optimize.linprog on random instances, and C == Python bit for bit."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog

from swarmpath.control.orca import kernels, lp
from swarmpath.control.orca.halfplanes import halfplane_below


def lines(*rows):
    """Half-planes n . v <= b from rows (nx, ny, b); n is normalised here."""
    n = np.array([r[:2] for r in rows], float)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return halfplane_below(n, np.array([r[2] for r in rows], float))


# ------------------------------------------------------------------------------ by hand
def test_no_lines_keeps_the_preferred_velocity_or_clips_it_to_the_disc():
    empty = np.zeros((0, 2))
    fail, v = lp.solve_lp2(empty, empty, 2.0, [1.0, 1.0])
    assert fail == 0 and np.array_equal(v, [1.0, 1.0])
    fail, v = lp.solve_lp2(empty, empty, 2.0, [3.0, 4.0])
    np.testing.assert_allclose(v, [1.2, 1.6])


def test_one_and_two_lines():
    p, d = lines((1, 0, 1.0))
    fail, v = lp.solve_lp2(p, d, 5.0, [3.0, 0.5])
    assert fail == 1
    np.testing.assert_allclose(v, [1.0, 0.5])
    p, d = lines((1, 0, 1.0), (0, 1, 1.0))
    _, v = lp.solve_lp2(p, d, 5.0, [3.0, 3.0])
    np.testing.assert_allclose(v, [1.0, 1.0])
    # the corner lies outside the disc of radius 1: the best point is on the circle
    _, v = lp.solve_lp2(*lines((1, 1, 1.0)), 1.0, [3.0, 3.0])
    np.testing.assert_allclose(v, [np.sqrt(0.5), np.sqrt(0.5)])


def test_a_line_beyond_the_speed_disc_is_infeasible():
    fail, _ = lp.solve_lp2(*lines((-1, 0, -3.0)), 2.0, [0.0, 0.0])      # v_x >= 3, |v| <= 2
    assert fail == 0


def test_lp3_splits_the_violation_of_two_opposite_soft_lines():
    p, d = lines((-1, 0, -1.0), (1, 0, -3.0))          # v_x >= 1 and v_x <= -3: 4 apart
    v, status = lp.solve_orca_lp(p, d, 0, 5.0, [0.0, 2.0])
    assert status == 1
    np.testing.assert_allclose(v[0], -1.0, atol=1e-12)
    np.testing.assert_allclose(lp.violation(p, d, v), [2.0, 2.0], atol=1e-12)


def test_lp3_keeps_hard_lines():
    p, d = lines((1, 0, -2.0), (-1, 0, -1.0))          # hard v_x <= -2, soft v_x >= 1
    v, status = lp.solve_orca_lp(p, d, 1, 5.0, [1.0, 0.0])
    assert status == 1
    assert v[0] <= -2.0 + 1e-12
    np.testing.assert_allclose(lp.violation(p, d, v)[1], 3.0, atol=1e-12)


def test_firm_lines_relax_only_when_they_themselves_conflict():
    # hard v_x <= 0.5; firm v_x >= 3 (beyond the disc of 2): firm joins the soft lines
    p, d = lines((1, 0, 0.5), (-1, 0, -3.0), (0, 1, 0.0))
    v, status = lp.solve_orca_lp(p, d, 1, 2.0, [1.0, 1.0], n_firm=2)
    assert status == 2
    assert v[0] <= 0.5 + 1e-12 and np.hypot(*v) <= 2.0 + 1e-12
    # hard lines that exclude the whole disc: stand still
    p, d = lines((-1, 0, -3.0))
    v, status = lp.solve_orca_lp(p, d, 1, 2.0, [1.0, 1.0])
    assert status == 3 and np.array_equal(v, [0.0, 0.0])


# ------------------------------------------------------------------------------ against linprog
def polygon_rows(radius: float, sides: int, outer: bool) -> tuple[np.ndarray, np.ndarray]:
    """The disc of ``radius`` as ``sides`` half-planes: inscribed (inside the disc) or
    circumscribed (containing it)."""
    a = 2 * np.pi * (np.arange(sides) + 0.5) / sides
    n = np.stack([np.cos(a), np.sin(a)], axis=1)
    b = radius if outer else radius * np.cos(np.pi / sides)
    return n, np.full(sides, b)


def as_rows(points, directions):
    """Half-planes n . v <= b of lines (left of the direction permitted)."""
    n = np.stack([directions[:, 1], -directions[:, 0]], axis=1)
    return n, np.einsum("ij,ij->i", n, points)


instance = st.tuples(st.integers(1, 8), st.integers(0, 10_000), st.floats(0.5, 3.0))


def random_lines(k: int, seed: int, spread: float = 1.0):
    rng = np.random.default_rng(seed)
    ang = rng.uniform(0, 2 * np.pi, k)
    d = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    p = rng.normal(0, spread, (k, 2))
    return p, d, rng


@settings(max_examples=60, deadline=None)
@given(instance)
def test_lp2_optimum_matches_linprog(args):
    """Direction optimisation is a linear program over lines and disc: its value lies
    between linprog's over the inscribed and the circumscribed 256-gon; closest-point mode
    returns a projection (no feasible point improves it, checked by linprog)."""
    k, seed, radius = args
    p, d, rng = random_lines(k, seed)
    opt = rng.normal(0, 1, 2)
    opt /= np.linalg.norm(opt)
    n_l, b_l = as_rows(p, d)
    inner = [np.vstack([n_l, polygon_rows(radius, 256, False)[0]]), np.concatenate([b_l, polygon_rows(radius, 256, False)[1]])]
    outer = [np.vstack([n_l, polygon_rows(radius, 256, True)[0]]), np.concatenate([b_l, polygon_rows(radius, 256, True)[1]])]
    res_in = linprog(-opt, A_ub=inner[0], b_ub=inner[1], bounds=[(None, None)] * 2)
    res_out = linprog(-opt, A_ub=outer[0], b_ub=outer[1], bounds=[(None, None)] * 2)
    fail, v = lp.solve_lp2(p, d, radius, opt, direction_opt=True)
    if res_in.status == 0:
        assert fail == k, "feasible for the inscribed polygon, so feasible for the disc"
    if res_out.status == 2:
        assert fail < k, "infeasible for the circumscribed polygon, so infeasible for the disc"
    if fail == k:
        assert np.all(lp.violation(p, d, v) <= 1e-9) and np.hypot(*v) <= radius + 1e-9
        assert res_out.status == 0
        value = float(opt @ v)
        assert value <= -res_out.fun + 1e-7
        if res_in.status == 0:
            assert value >= -res_in.fun - 1e-7
        # closest-point mode: v* is the projection of `pref` iff max (pref - v*) . (x - v*) <= 0
        pref = rng.normal(0, 2, 2)
        fail2, w = lp.solve_lp2(p, d, radius, pref)
        assert fail2 == k
        g = pref - w
        res = linprog(-g, A_ub=outer[0], b_ub=outer[1], bounds=[(None, None)] * 2)
        # a point of the circumscribed polygon (within delta of the disc) that the lines
        # also permit lies within delta + sqrt(2 R delta) of the lines-and-disc region
        delta = radius * (1 / np.cos(np.pi / 256) - 1)
        slack = (delta + np.sqrt(2 * radius * delta)) * np.linalg.norm(g)
        assert -res.fun - g @ w <= slack + 1e-7


@settings(max_examples=60, deadline=None)
@given(instance)
def test_lp3_minimises_the_largest_violation_as_linprog_does(args):
    """min t s.t. soft lines violated by at most t, hard lines kept, v in the disc: LP3's
    largest violation lies between linprog's optima over the circumscribed and inscribed
    polygons (hard lines here all permit v = 0, as ORCA's static lines do)."""
    k, seed, radius = args
    p, d, rng = random_lines(k + 2, seed, spread=2.0)
    n_hard = int(rng.integers(0, 3))
    n_rows, b_rows = as_rows(p, d)
    b_rows[:n_hard] = np.abs(b_rows[:n_hard])             # v = 0 satisfies the hard lines
    p[:n_hard] = n_rows[:n_hard] * b_rows[:n_hard, None]
    v, status = lp.solve_orca_lp(p, d, n_hard, radius, rng.normal(0, 1, 2))
    viol = lp.violation(p, d, v)
    assert np.all(viol[:n_hard] <= 1e-9)
    worst = max(0.0, float(viol[n_hard:].max(initial=0.0)))
    bounds = []
    for outer in (True, False):
        pn, pb = polygon_rows(radius, 256, outer)
        # variables (vx, vy, t): soft n.v - t <= b, hard n.v <= b, polygon, t >= 0
        a_soft = np.hstack([n_rows[n_hard:], -np.ones((len(n_rows) - n_hard, 1))])
        a_hard = np.hstack([n_rows[:n_hard], np.zeros((n_hard, 1))])
        a_poly = np.hstack([pn, np.zeros((len(pn), 1))])
        res = linprog([0, 0, 1], A_ub=np.vstack([a_soft, a_hard, a_poly]),
                      b_ub=np.concatenate([b_rows[n_hard:], b_rows[:n_hard], pb]),
                      bounds=[(None, None), (None, None), (0, None)])
        assert res.status == 0
        bounds.append(res.fun)
    if status == 0:
        assert worst <= 1e-9
    else:
        assert bounds[0] - 1e-7 <= worst <= bounds[1] + 1e-6


# ------------------------------------------------------------------------------ C == Python
@pytest.mark.parametrize("seed", range(4))
def test_c_loop_is_bit_identical_to_the_python_reference(seed):
    if kernels._orcalp is None:
        pytest.skip("the C extension is not built")
    rng = np.random.default_rng(seed)
    n, k = 400, 12
    ang = rng.uniform(0, 2 * np.pi, (n, k))
    packed = np.concatenate([rng.normal(0, 1, (n, k, 2)), np.stack([np.cos(ang), np.sin(ang)], -1)], -1)
    n_lines = rng.integers(0, k + 1, n)
    n_hard = np.minimum(rng.integers(0, 3, n), n_lines)
    n_firm = np.minimum(n_lines, n_hard + rng.integers(0, 3, n))
    pref = rng.normal(0, 2, (n, 2))
    radius = rng.uniform(0.5, 2, n)
    a, sa = kernels.solve_lines(packed, n_lines, n_hard, n_firm, pref, radius)
    b, sb = kernels.solve_lines(packed, n_lines, n_hard, n_firm, pref, radius, use_c=False)
    assert np.array_equal(a, b) and np.array_equal(sa, sb)
    assert set(np.unique(sa)) >= {0, 1}


def test_pack_lines_orders_tiers_and_counts():
    owner = np.array([1, 0, 1, 1, 0])
    tier = np.array([2, 0, 0, 1, 2])
    pts = np.arange(10, dtype=float).reshape(5, 2)
    dirs = np.tile([1.0, 0.0], (5, 1))
    packed, n_lines, n_hard, n_firm = kernels.pack_lines(owner, pts, dirs, tier, 3)
    assert n_lines.tolist() == [2, 3, 0] and n_hard.tolist() == [1, 1, 0] and n_firm.tolist() == [1, 2, 0]
    assert packed[1, :3, 0].tolist() == [4.0, 6.0, 0.0]          # hard, firm, soft
    assert packed[0, :2, 0].tolist() == [2.0, 8.0]
