"""The paper's equations as pure functions, checked against values computed by hand."""
from __future__ import annotations

import math

import numpy as np
import pytest

from swarmpath.optim.afsa import afsa_move_towards, afsa_neighbours, afsa_random_within
from swarmpath.optim.amopso import (
    amopso_acceleration,
    amopso_inertia_eq15,
    amopso_inertia_eq16,
    amopso_l_factor,
    amopso_random_factors,
    log_progress,
)
from swarmpath.optim.cso import cso_seek_candidates, cso_selection_probabilities, cso_trace_velocity, roulette
from swarmpath.optim.mopso import (
    check_weights,
    coello_mutation,
    crowding_tournament,
    normalised_cost,
    pareto_pbest_update,
    weighted_sum,
)
from swarmpath.optim.pareto import (
    crowding_distance,
    dominates,
    hypervolume_2d,
    non_dominated,
    truncate_by_crowding,
    unique_rows,
)
from swarmpath.optim.pso import clamp_velocity, linear_inertia_eq32, pso_position_update, pso_velocity_update
from swarmpath.errors import ConfigError

E1 = math.exp(-1.0)


# ---- SPSO (eq. 9-12, 32) ---------------------------------------------------------------------


def test_velocity_update_eq9_10_by_hand():
    v = np.array([[1.0, -2.0]])
    x = np.array([[0.0, 0.0]])
    pbest = np.array([[1.0, 1.0]])
    gbest = np.array([2.0, -1.0])
    out = pso_velocity_update(v, x, pbest, gbest, 0.5, 2.0, 1.0, np.array([[0.5, 0.25]]), np.array([[1.0, 0.5]]))
    # 0.5*[1,-2] + 2*[0.5,0.25]*[1,1] + 1*[1,0.5]*[2,-1] = [0.5,-1] + [1,0.5] + [2,-0.5]
    np.testing.assert_allclose(out, [[3.5, -1.0]])


def test_velocity_update_per_particle_coefficients():
    v = np.zeros((2, 1))
    x = np.zeros((2, 1))
    out = pso_velocity_update(v, x, np.ones((2, 1)), np.zeros(1), 0.0, np.array([[1.0], [3.0]]), 0.0, np.ones((2, 1)), np.ones((2, 1)))
    np.testing.assert_allclose(out, [[1.0], [3.0]])


def test_linear_inertia_eq32():
    assert linear_inertia_eq32(0, 120) == pytest.approx(0.9)
    assert linear_inertia_eq32(60, 120) == pytest.approx(0.65)
    assert linear_inertia_eq32(120, 120) == pytest.approx(0.4)


def test_position_update_absorbs_at_the_walls():
    x = np.array([[0.0, 9.0], [0.0, 0.0]])
    v = np.array([[3.0, 4.0], [-12.0, 1.0]])
    lo, hi = np.full(2, -10.0), np.full(2, 10.0)
    nx, nv = pso_position_update(x, v, lo, hi)
    np.testing.assert_allclose(nx, [[3.0, 10.0], [-10.0, 1.0]])
    np.testing.assert_allclose(nv, [[3.0, 0.0], [0.0, 1.0]])


def test_clamp_velocity():
    np.testing.assert_allclose(clamp_velocity(np.array([[5.0, -5.0, 0.5]]), np.array([1.0, 2.0, 1.0])), [[1.0, -2.0, 0.5]])


# ---- AMOPSO (eq. 15-24) ----------------------------------------------------------------------


def test_l_factor_by_hand():
    # M = 2, sample std = 1, Y = (-1, 0, 1), L = exp(-|Y|)
    np.testing.assert_allclose(amopso_l_factor(np.array([1.0, 2.0, 3.0])), [E1, 1.0, E1])
    # outliers on both sides get small L, the typical particle L = 1
    L = amopso_l_factor(np.array([0.0, 10.0, 10.0, 10.0, 20.0]))
    assert L[0] == pytest.approx(L[-1]) and L[0] < L[1] == pytest.approx(1.0)


@pytest.mark.parametrize("pbest", [[2.0, 2.0, 2.0], [5.0], [1.0, np.inf, 3.0]])
def test_l_factor_guard_v_zero(pbest):
    np.testing.assert_array_equal(amopso_l_factor(np.array(pbest)), np.ones(len(pbest)))


def test_log_progress():
    assert log_progress(0, 100) == 0.0
    assert log_progress(9, 100) == pytest.approx(0.5)
    assert log_progress(99, 100) == pytest.approx(1.0)
    assert log_progress(500, 100) == 1.0  # clipped
    assert log_progress(0, 1) == 1.0  # degenerate base


def test_inertia_eq15_by_hand():
    # ratio max/gbest = 1 -> exp(-1); log_100(10) = 0.5: w = 0.4 + 0.5 * e^-1 * 0.5
    assert amopso_inertia_eq15(np.array([2.0, 2.0]), 2.0, 9, 100) == pytest.approx(0.4 + 0.25 * E1)
    # ratio 2: exp(-4); T = Tmax - 1: log factor 1
    assert amopso_inertia_eq15(np.array([1.0, 2.0]), 1.0, 99, 100) == pytest.approx(0.4 + 0.5 * math.exp(-4))
    # T = 0: log(1) = 0 -> w_min
    assert amopso_inertia_eq15(np.array([1.0, 2.0]), 1.0, 0, 100) == pytest.approx(0.4)
    # negative costs: the ratio is squared
    assert amopso_inertia_eq15(np.array([-2.0, -2.0]), -2.0, 9, 100) == pytest.approx(0.4 + 0.25 * E1)


def test_inertia_eq15_guards_gbest_zero():
    assert amopso_inertia_eq15(np.array([0.0, 0.0]), 0.0, 9, 100) == pytest.approx(0.4 + 0.25 * E1)
    assert amopso_inertia_eq15(np.array([0.0, 3.0]), 0.0, 9, 100) == pytest.approx(0.4)
    w = amopso_inertia_eq15(np.array([1e-300, 1e300]), 1e-300, 50, 100)
    assert w == pytest.approx(0.4)


def test_inertia_eq16_by_hand():
    np.testing.assert_allclose(amopso_inertia_eq16(np.array([1.0, 0.5]), 9, 100), [0.65, 0.525])
    np.testing.assert_allclose(amopso_inertia_eq16(np.array([1.0, 0.5]), 0, 100), [0.4, 0.4])
    np.testing.assert_allclose(amopso_inertia_eq16(np.array([1.0]), 99, 100), [0.9])


def test_acceleration_eq17_to_22_by_hand():
    L = np.array([1.0, 0.5])
    c1, c2 = amopso_acceleration(L, 50, 100, "eq17-18")
    np.testing.assert_allclose(c1, [2.0, 1.75])
    np.testing.assert_allclose(c2, [2.0, 1.75])
    c1, c2 = amopso_acceleration(L, 50, 100, "eq19-20")
    np.testing.assert_allclose(c1, [1.0, 1.25])
    np.testing.assert_allclose(c2, [1.0, 1.25])
    c1, c2 = amopso_acceleration(L, 50, 100, "eq21-22")
    np.testing.assert_allclose(c1, [1.0, 1.25])
    np.testing.assert_allclose(c2, [2.0, 1.75])
    # the range of section 5.1: 0.5 <= c <= 2.5
    for rule in ["eq17-18", "eq19-20", "eq21-22"]:
        for c in amopso_acceleration(np.array([1.0, 0.0]), 100, 100, rule):
            assert np.all((c >= 0.5) & (c <= 2.5))
    with pytest.raises(ValueError):
        amopso_acceleration(L, 1, 2, "eq99")


def test_random_factors_eq23_24():
    L = np.array([1.0, 0.0, 0.5])
    r1, r2 = amopso_random_factors(L, 50, 100, np.random.default_rng(3), 4)
    raw = np.random.default_rng(3).random((2, 3, 4))
    np.testing.assert_allclose(r1, raw[0] * (L * 0.5)[:, None])
    np.testing.assert_allclose(r2, raw[1] * (L * 0.5)[:, None])
    assert np.all(r1[1] == 0) and np.all(r1[0] < 0.5)


# ---- Pareto machinery (eq. 14) ----------------------------------------------------------------


def test_dominates_eq14():
    assert dominates([1, 2], [1, 3]) is True
    assert dominates([1, 2], [1, 2]) is False
    assert dominates([1, 2], [2, 1]) is False
    assert dominates([2, 3], [1, 2]) is False
    np.testing.assert_array_equal(dominates([1, 1], [[2, 2], [1, 1], [0, 5]]), [True, False, False])


def test_non_dominated_keeps_duplicates_and_unique_rows_drops_them():
    F = np.array([[1, 2], [2, 1], [2, 2], [1, 2]], dtype=float)
    np.testing.assert_array_equal(non_dominated(F), [True, True, False, True])
    np.testing.assert_array_equal(unique_rows(F), [0, 1, 2])
    assert non_dominated(np.empty((0, 2))).shape == (0,)


def test_crowding_distance_by_hand():
    F = np.array([[0, 4], [1, 2], [2, 1], [4, 0]], dtype=float)
    cd = crowding_distance(F)
    assert np.isinf(cd[0]) and np.isinf(cd[3])
    # point (1,2): f1 neighbours 0 and 2 -> 2/4; f2 neighbours 1 and 4 -> 3/4
    assert cd[1] == pytest.approx(1.25)
    assert cd[2] == pytest.approx(1.25)
    assert np.all(np.isinf(crowding_distance(F[:2])))


def test_truncate_by_crowding_keeps_extremes_and_spread():
    f1 = np.concatenate([np.linspace(0, 1, 11), [0.51, 0.52, 0.49]])
    F = np.stack([f1, 1 - f1], axis=1)
    keep = truncate_by_crowding(F, 11)
    assert len(keep) == 11
    kept = np.sort(F[keep, 0])
    assert kept[0] == 0 and kept[-1] == 1
    # the crowded cluster around 0.5 lost its extra members
    assert np.sum((kept > 0.45) & (kept < 0.55)) <= 2


def test_hypervolume_2d_by_hand_and_against_pymoo():
    F = np.array([[1, 3], [2, 2], [3, 1], [3, 3], [5, 0]], dtype=float)
    # rectangles (2-1)*(4-3) + (3-2)*(4-2) + (4-3)*(4-1); (3,3) is dominated, (5,0) outside
    assert hypervolume_2d(F, (4, 4)) == pytest.approx(6.0)
    assert hypervolume_2d(np.empty((0, 2)), (4, 4)) == 0.0
    from pymoo.indicators.hv import HV

    rng = np.random.default_rng(0)
    for _ in range(5):
        P = rng.random((60, 2))
        assert hypervolume_2d(P, (1.1, 1.1)) == pytest.approx(HV(ref_point=np.array([1.1, 1.1]))(P), rel=1e-12)


# ---- MOPSO helpers ----------------------------------------------------------------------------


def test_weighted_sum_eq13_and_weight_checks():
    np.testing.assert_allclose(weighted_sum([[1.0, 2.0], [4.0, 0.0]], [0.25, 0.75]), [1.75, 1.0])
    check_weights("mopso", [0.3, 0.7], 2)
    with pytest.raises(ConfigError, match="sum to 1"):
        check_weights("mopso", [0.5, 0.6], 2)
    with pytest.raises(ConfigError, match="2 entries"):
        check_weights("mopso", [1.0], 2)
    with pytest.raises(ConfigError, match=r"\[0, 1\]"):
        check_weights("mopso", [1.5, -0.5], 2)


def test_pbest_update_rule():
    old = np.array([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]])
    new = np.array([[0.5, 0.5], [2.0, 2.0], [0.0, 3.0]])
    picks = np.array([pareto_pbest_update(old, new, np.random.default_rng(s)) for s in range(200)])
    assert picks[:, 0].all()  # new dominates
    assert not picks[:, 1].any()  # old dominates
    assert 0.35 < picks[:, 2].mean() < 0.65  # neither: a coin flip


def test_crowding_tournament_prefers_less_crowded():
    cd = np.array([0.1, 5.0, 0.2])
    picks = crowding_tournament(cd, 3000, np.random.default_rng(0))
    counts = np.bincount(picks, minlength=3)
    assert counts[1] > counts[2] > counts[0]
    assert np.all(crowding_tournament(np.array([1.0]), 5, np.random.default_rng(0)) == 0)


def test_coello_mutation():
    rng = np.random.default_rng(1)
    x = np.full((50, 4), 0.5)
    lo, hi = np.zeros(4), np.ones(4)
    same = coello_mutation(x, 60, 100, 0.5, lo, hi, rng)
    assert same is x  # after t_max * rate there is no mutation
    early = coello_mutation(x, 0, 100, 0.5, lo, hi, rng)  # p = 1: every particle, one coordinate
    changed = early != x
    assert np.all(changed.sum(axis=1) == 1)
    assert np.all((early >= 0) & (early <= 1))


def test_normalised_cost():
    archive = np.array([[0.0, 10.0], [2.0, 0.0]])
    np.testing.assert_allclose(normalised_cost(np.array([[1.0, 5.0], [2.0, 10.0]]), archive), [0.5, 1.0])


# ---- CSO ---------------------------------------------------------------------------------------


def test_cso_selection_probabilities_by_hand():
    np.testing.assert_allclose(cso_selection_probabilities(np.array([[1.0, 2.0, 3.0]])), [[2 / 3, 1 / 3, 0.0]])
    np.testing.assert_allclose(cso_selection_probabilities(np.array([[4.0, 4.0, 4.0, 4.0]])), [[0.25] * 4])
    p = cso_selection_probabilities(np.array([[1.0, np.inf, 3.0], [np.inf, np.inf, np.inf]]))
    np.testing.assert_allclose(p, [[1.0, 0.0, 0.0], [1 / 3, 1 / 3, 1 / 3]])


def test_cso_seek_candidates():
    x = np.array([[1.0, 2.0, 3.0, 4.0, 5.0], [-1.0, -2.0, -3.0, -4.0, -5.0]])
    lo, hi = np.full(5, -100.0), np.full(5, 100.0)
    c = cso_seek_candidates(x, lo, hi, smp=6, srd=0.2, cdc=0.4, spc=True, rng=np.random.default_rng(0))
    assert c.shape == (2, 6, 5)
    np.testing.assert_array_equal(c[:, 0], x)  # SPC: the present position is a candidate
    ratio = c[:, 1:] / x[:, None, :]
    changed = ~np.isclose(ratio, 1.0)
    assert np.all(changed.sum(axis=-1) == 2)  # round(0.4 * 5) dimensions per copy
    assert np.allclose(np.abs(ratio[changed] - 1.0), 0.2)  # +- SRD of the present value
    clipped = cso_seek_candidates(np.array([[99.0]]), np.array([-100.0]), np.array([100.0]), smp=20, srd=0.2,
                                  cdc=1.0, spc=False, rng=np.random.default_rng(1))
    assert clipped.max() <= 100.0


def test_roulette_and_trace_velocity():
    picks = roulette(np.tile([[0.0, 1.0, 0.0]], (50, 1)), np.random.default_rng(0))
    assert np.all(picks == 1)
    v = cso_trace_velocity(np.array([[1.0, 1.0]]), np.array([[0.0, 0.0]]), np.array([2.0, -2.0]), 0.5, 1.5, np.array([[1.0, 0.5]]))
    np.testing.assert_allclose(v, [[0.5 + 3.0, 0.5 - 1.5]])


# ---- AFSA --------------------------------------------------------------------------------------


def test_afsa_kernels():
    U = np.array([[0.0, 0.0]])
    np.testing.assert_allclose(afsa_move_towards(U, np.array([[3.0, 4.0]]), 1.0, np.array([0.5])), [[0.3, 0.4]])
    np.testing.assert_allclose(afsa_move_towards(U, U, 1.0, np.array([0.5])), U)
    N = afsa_neighbours(np.array([[0.0, 0.0], [0.3, 0.4], [1.0, 1.0]]), 0.6)
    np.testing.assert_array_equal(N, [[False, True, False], [True, False, False], [False, False, False]])
    P = afsa_random_within(np.zeros((500, 3)), 0.2, np.random.default_rng(0))
    assert np.linalg.norm(P, axis=1).max() <= 0.2 + 1e-12
