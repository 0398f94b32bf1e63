"""Problem validation, the minimize() front door and run_benchmark (the optimize command's JSON)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from swarmpath.errors import ConfigError, UnknownNameError
from swarmpath.optim import PSO, Problem, benchmark_results, make_optimizer, minimize, run_benchmark
from swarmpath.optim.functions import sphere

DESIGN_KEYS = {"algorithm", "function", "dim", "runs", "min", "mean", "std", "best_per_run"}


def test_problem_from_a_plain_callable():
    p = Problem(lambda X: X.sum(axis=1), [-1, -2], [1, 2])
    assert p.dim == 2 and p.n_objectives == 1
    np.testing.assert_array_equal(p.lower, [-1, -2])
    np.testing.assert_allclose(p.evaluate(np.ones((3, 2))), [2, 2, 2])
    # (n, 1) output is accepted for one objective
    q = Problem(lambda X: X[:, :1], -1, 1, dim=4)
    assert q.evaluate(np.zeros((5, 4))).shape == (5,)
    with pytest.raises(ValueError):
        p.lower[0] = 3.0  # bounds are read-only


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(lower=[0, 0], upper=[1]), "bounds|shape"),
        (dict(lower=[1, 0], upper=[0, 1]), r"lower\[0\]"),
        (dict(lower=0, upper=1), "dim"),
        (dict(lower=[0, -np.inf], upper=[1, 1]), "finite"),
        (dict(lower=[0], upper=[1], n_objectives=0), "n_objectives"),
        (dict(lower=0, upper=1, dim=0), "dim"),
    ],
)
def test_bad_problems(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        Problem(sphere, **kwargs)


def test_wrong_objective_shapes_are_reported():
    p = Problem(lambda X: X, -1, 1, dim=3, name="oops")
    with pytest.raises(ConfigError, match="'oops'.*shape"):
        p.evaluate(np.zeros((4, 3)))
    two = Problem(lambda X: X[:, :2], -1, 1, n_objectives=3, dim=3)
    with pytest.raises(ConfigError, match=r"\(4, 3\)"):
        two.evaluate(np.zeros((4, 3)))
    with pytest.raises(ConfigError, match=r"\(n, 3\)"):
        p.evaluate(np.zeros((4, 2)))


def test_nan_becomes_inf():
    p = Problem(lambda X: np.full(X.shape[0], np.nan), -1, 1, dim=2)
    assert np.all(np.isinf(p.evaluate(np.zeros((2, 2)))))


def test_minimize_front_door():
    p = Problem(sphere, -5.0, 5.0, dim=3)
    res = minimize(p, "pso", iterations=200, particles=20, seed=1)
    assert res.f < 1e-3 and res.algorithm == "pso" and res.seed == 1
    assert res.params["c1"] == pytest.approx(1.49618) and minimize(p, "spso", iterations=5, particles=5).params["c1"] == 2.0
    again = minimize(p, PSO(c1=1.5, c2=1.5), iterations=200, particles=20, seed=1)
    assert again.params["c1"] == 1.5
    tuned = minimize(p, "pso", iterations=200, particles=20, seed=1, c1=1.5, c2=1.5)
    np.testing.assert_array_equal(again.x, tuned.x)
    with pytest.raises(ConfigError, match="constructor"):
        minimize(p, PSO(), iterations=5, particles=5, c1=1.0)
    with pytest.raises(UnknownNameError, match="choose from"):
        minimize(p, "sso", iterations=5, particles=5)
    with pytest.raises(ConfigError, match="unknown hyperparameter 'variant'"):
        make_optimizer("amopso1", variant=3)  # the variant of a registered AMOPSO is fixed


def test_run_benchmark_json_object():
    calls = []
    doc = run_benchmark("pso", "sphere", 10, 10, 50, 3, 1, progress=lambda done, total: calls.append((done, total)))
    assert DESIGN_KEYS <= set(doc)
    assert json.loads(json.dumps(doc)) == doc
    assert (doc["algorithm"], doc["function"], doc["dim"], doc["runs"]) == ("pso", "sphere", 10, 3)
    best = np.array(doc["best_per_run"])
    assert len(best) == 3
    assert doc["min"] == best.min() and doc["mean"] == pytest.approx(best.mean())
    assert doc["std"] == pytest.approx(best.std())
    assert doc["evaluations"] == 3 * 10 * 50
    assert calls == [(1, 3), (2, 3), (3, 3)]
    # same seed, same numbers; run r does not depend on how many runs there are
    again = run_benchmark("pso", "sphere", 10, 10, 50, 2, 1)
    assert again["best_per_run"] == doc["best_per_run"][:2]
    other = run_benchmark("pso", "sphere", 10, 10, 50, 2, 2)
    assert other["best_per_run"] != again["best_per_run"]


def test_paired_runs_share_the_initial_swarm():
    a = benchmark_results("pso", "sphere", 10, 8, 1, 3, 5)
    b = benchmark_results("amopso3", "sphere", 10, 8, 1, 3, 5)
    assert [r.f for r in a] == [r.f for r in b]


def test_noisy_function_is_reproducible():
    a = run_benchmark("amopso4", "quartic-noise", 10, 8, 30, 2, 3)
    b = run_benchmark("amopso4", "quartic-noise", 10, 8, 30, 2, 3)
    assert a["best_per_run"] == b["best_per_run"]


@pytest.mark.parametrize(
    "args, error, match",
    [
        (("pso", "nope", 10, 10, 5, 1, 0), UnknownNameError, "unknown function 'nope'"),
        (("psx", "sphere", 10, 10, 5, 1, 0), UnknownNameError, "unknown optimizer 'psx'"),
        (("pso", "sphere", 0, 10, 5, 1, 0), ConfigError, "dim"),
        (("pso", "sphere", 10, 1, 5, 1, 0), ConfigError, "particles"),
        (("pso", "sphere", 10, 10, 0, 1, 0), ConfigError, "iterations"),
        (("pso", "sphere", 10, 10, 5, 0, 0), ConfigError, "runs"),
        (("pso", "sphere", 10, 10, 5, 1, -3), ConfigError, "seed"),
    ],
)
def test_run_benchmark_bad_input(args, error, match):
    with pytest.raises(error, match=match) as info:
        run_benchmark(*args)
    assert "\n" not in str(info.value)
