"""Benchmark functions: known optima, hand-computed values, agreement with pymoo and opfunu."""
from __future__ import annotations

import math

import numpy as np
import pytest

from swarmpath.errors import ConfigError, UnknownNameError
from swarmpath.optim import functions as fn
from swarmpath.optim.pareto import hypervolume_2d
from swarmpath.registry import FUNCTIONS

PAPER_RANGES = {  # Table 2 of the paper
    "sphere": 100.0,
    "quadric": 100.0,
    "quartic-noise": 1.28,
    "rastrigin": 5.12,
    "ackley": 32.0,
    "griewank": 600.0,
}


def test_registry_holds_the_design_names():
    assert set(FUNCTIONS.names()) >= {"sphere", "quadric", "quartic-noise", "rastrigin", "ackley", "griewank", "rosenbrock"}


@pytest.mark.parametrize("name", sorted(PAPER_RANGES))
def test_default_bounds_are_the_papers_ranges(name):
    p = FUNCTIONS.get(name).problem(30)
    assert p.dim == 30
    assert np.all(p.lower == -PAPER_RANGES[name]) and np.all(p.upper == PAPER_RANGES[name])


@pytest.mark.parametrize("name", ["sphere", "quadric", "rastrigin", "ackley", "griewank", "rosenbrock"])
@pytest.mark.parametrize("dim", [2, 30])
def test_known_optimum(name, dim):
    b = FUNCTIONS.get(name)
    x = b.optimum_x(dim)
    assert b(x[None, :])[0] == pytest.approx(b.optimum_f, abs=1e-12)
    # and it is a minimum: small perturbations are worse
    rng = np.random.default_rng(0)
    around = x + rng.normal(scale=1e-3, size=(20, dim))
    assert np.all(b(around) > b(x[None, :])[0])


def test_values_at_hand_computed_points():
    x = np.array([1.0, 2.0, 3.0])
    assert fn.sphere(x) == 14.0
    assert fn.quadric(x) == 1 + 9 + 36  # partial sums 1, 3, 6
    assert fn.quartic(x) == 1 * 1 + 2 * 16 + 3 * 81
    assert fn.rastrigin(x) == pytest.approx(14.0)  # cos(2 pi k) = 1 at integers
    assert fn.rastrigin(np.array([0.5])) == pytest.approx(0.25 + 10 + 10)
    assert fn.rosenbrock(np.array([0.0, 0.0])) == 1.0
    assert fn.rosenbrock(np.array([1.0, 2.0])) == 100.0
    one = np.ones(2)
    expected = -20 * math.exp(-0.2) - math.exp(math.cos(2 * math.pi)) + 20 + math.e
    assert fn.ackley(one) == pytest.approx(expected)
    assert fn.griewank(np.array([math.pi])) == pytest.approx(math.pi**2 / 4000 + 2.0)


def test_vectorised_over_leading_axes():
    rng = np.random.default_rng(1)
    X = rng.uniform(-5, 5, size=(4, 6, 10))
    for name in ["sphere", "quadric", "rastrigin", "ackley", "griewank", "rosenbrock"]:
        f = FUNCTIONS.get(name).func
        out = f(X)
        assert out.shape == (4, 6)
        assert out[2, 3] == pytest.approx(f(X[2, 3]))


def test_quadric_matches_a_plain_double_loop():
    rng = np.random.default_rng(2)
    X = rng.uniform(-100, 100, size=(20, 30))
    naive = [sum(sum(x[j] for j in range(i + 1)) ** 2 for i in range(30)) for x in X]
    np.testing.assert_allclose(fn.quadric(X), naive, rtol=1e-12)


@pytest.mark.parametrize("name", ["ackley", "griewank", "rastrigin", "rosenbrock", "sphere"])
def test_agrees_with_pymoo_at_random_points(name):
    from pymoo.problems import get_problem

    rng = np.random.default_rng(3)
    dim = 30
    X = rng.uniform(-5, 5, size=(50, dim))
    reference = get_problem(name, n_var=dim).evaluate(X).ravel()
    ours = FUNCTIONS.get(name).func(X - 0.5) if name == "sphere" else FUNCTIONS.get(name).func(X)
    # pymoo's sphere is centred at 0.5: sum (x - 0.5)^2
    np.testing.assert_allclose(ours, reference, rtol=1e-12, atol=1e-12)


def test_agrees_with_opfunu_at_random_points(monkeypatch):
    from opfunu.name_based import Ackley01, Griewank, Quartic

    rng = np.random.default_rng(4)
    X = rng.uniform(-1.28, 1.28, size=(20, 30))
    for cls, ours in [(Ackley01, fn.ackley), (Griewank, fn.griewank)]:
        ref = cls(ndim=30)
        np.testing.assert_allclose([ref.evaluate(x) for x in X], ours(X), rtol=1e-12)
    # opfunu's Quartic adds np.random.rand() from numpy's global state: pin it to 0.25
    monkeypatch.setattr(np.random, "rand", lambda: 0.25)
    q = Quartic(ndim=30)
    np.testing.assert_allclose([q.evaluate(x) for x in X], fn.quartic(X) + 0.25, rtol=1e-12)


def test_quartic_noise_is_seeded_and_uniform():
    X = np.zeros((2000, 30))
    a = fn.QUARTIC_NOISE(X, rng=5)
    b = fn.QUARTIC_NOISE(X, rng=5)
    c = fn.QUARTIC_NOISE(X, rng=6)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert a.min() >= 0.0 and a.max() < 1.0
    assert a.mean() == pytest.approx(0.5, abs=0.03)
    # a problem built with a generator draws fresh noise at each evaluation, reproducibly
    p1 = fn.QUARTIC_NOISE.problem(30, rng=np.random.default_rng(9))
    p2 = fn.QUARTIC_NOISE.problem(30, rng=np.random.default_rng(9))
    first, second = p1.evaluate(X[:5]), p1.evaluate(X[:5])
    assert not np.array_equal(first, second)
    np.testing.assert_array_equal(first, p2.evaluate(X[:5]))


def test_bad_dimension_and_unknown_names():
    with pytest.raises(ConfigError, match="dim"):
        FUNCTIONS.get("rosenbrock").problem(1)
    with pytest.raises(ConfigError, match="dim"):
        FUNCTIONS.get("sphere").problem(0)
    with pytest.raises(UnknownNameError, match="sphere"):
        fn.get_function("spere")
    with pytest.raises(UnknownNameError):
        fn.zdt_problem("zdt9")


def test_zdt_agree_with_pymoo():
    from pymoo.problems.multi.zdt import ZDT1, ZDT2

    X = np.random.default_rng(5).random((40, 30))
    np.testing.assert_allclose(fn.zdt1(X), ZDT1(n_var=30).evaluate(X), rtol=1e-12)
    np.testing.assert_allclose(fn.zdt2(X), ZDT2(n_var=30).evaluate(X), rtol=1e-12)
    p = fn.zdt_problem("zdt1")
    assert (p.dim, p.n_objectives) == (30, 2)
    assert np.all(p.lower == 0) and np.all(p.upper == 1)


@pytest.mark.parametrize("name", ["zdt1", "zdt2"])
def test_true_front_hypervolume_is_the_limit_of_dense_fronts(name):
    exact = fn.zdt_front_hypervolume(name)
    assert exact == pytest.approx({"zdt1": 0.876667, "zdt2": 0.543333}[name], abs=1e-6)
    dense = hypervolume_2d(fn.zdt_front(name, 20001), (1.1, 1.1))
    assert dense < exact
    assert dense == pytest.approx(exact, abs=1e-4)
    # points on the front have g = 1, i.e. x_2..x_n = 0
    f1 = np.linspace(0, 1, 11)
    X = np.zeros((11, 30))
    X[:, 0] = f1
    np.testing.assert_allclose(fn.zdt1(X) if name == "zdt1" else fn.zdt2(X), fn.zdt_front(name, 11))
