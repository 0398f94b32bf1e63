"""Every registered optimiser: determinism, budget, improvement over random search, bad input.

Parametrised over the registry, so an optimiser registered later is tested the moment it exists.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.optim import OptimizeResult, Problem, minimize
from swarmpath.optim.functions import sphere, zdt_problem
from swarmpath.registry import OPTIMIZERS

NAMES = OPTIMIZERS.names()
PSO_FAMILY = {"pso", "spso", "amopso1", "amopso2", "amopso3", "amopso4", "mopso"}

#: A hyperparameter value each built-in optimiser must reject.
BAD_HYPER = {
    "pso": {"c1": -1.0},
    "spso": {"w_min": 0.95},
    "apso": {"c1": 3.0},
    "amopso1": {"w_min": 0.95},
    "amopso2": {"z": -1.0},
    "amopso3": {"velocity_clamp": 0.0},
    "amopso4": {"w_max": 2.0},
    "mopso": {"archive_size": 0},
    "cso": {"smp": 1},
    "afsa": {"try_number": 0},
}


class Counting:
    """A vectorised sphere that counts the points it evaluates."""

    def __init__(self) -> None:
        self.points = 0

    def __call__(self, X):
        self.points += X.shape[0]
        return sphere(X)


def sphere_problem(dim: int = 10, counter: Counting | None = None) -> Problem:
    return Problem(counter or sphere, -100.0, 100.0, dim=dim, name="sphere")


def test_registry_has_the_design_names():
    assert set(NAMES) >= {"pso", "spso", "apso", "amopso1", "amopso2", "amopso3", "amopso4", "mopso", "cso", "afsa"}


@pytest.mark.parametrize("name", NAMES)
def test_same_seed_same_result(name):
    opt = OPTIMIZERS.get(name)()
    a = opt.minimize(sphere_problem(), iterations=20, particles=10, rng=7)
    b = OPTIMIZERS.get(name)().minimize(sphere_problem(), iterations=20, particles=10, rng=7)
    c = opt.minimize(sphere_problem(), iterations=20, particles=10, rng=8)
    assert isinstance(a, OptimizeResult)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.history, b.history)
    assert a.f == b.f and a.n_evaluations == b.n_evaluations
    assert a.seed == 7 and a.algorithm == name
    assert not np.array_equal(a.x, c.x)
    # a Generator gives the same run as the seed it was made from
    g = opt.minimize(sphere_problem(), iterations=20, particles=10, rng=np.random.default_rng(99))
    h = opt.minimize(sphere_problem(), iterations=20, particles=10, rng=np.random.default_rng(99))
    np.testing.assert_array_equal(g.x, h.x)
    assert g.seed is None


@pytest.mark.parametrize("name", NAMES)
def test_result_is_consistent_and_frozen(name):
    res = OPTIMIZERS.get(name)().minimize(sphere_problem(), iterations=15, particles=8, rng=1)
    assert res.x.shape == (10,)
    assert res.f == pytest.approx(sphere(res.x))
    assert res.history.shape == (res.n_iterations,)
    assert np.all(np.diff(res.history) <= 0)  # best-so-far never gets worse
    assert res.history[-1] == pytest.approx(res.f)
    assert res.stop_reason == "iterations" and res.n_iterations == 15
    assert np.all(res.x >= -100) and np.all(res.x <= 100)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.f = 0.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        res.x[0] = 1.0


@pytest.mark.parametrize("name", NAMES)
def test_evaluation_budget_is_counted_and_respected(name):
    counter = Counting()
    res = OPTIMIZERS.get(name)().minimize(sphere_problem(counter=counter), iterations=12, particles=10, rng=2)
    assert res.n_evaluations == counter.points
    if name in PSO_FAMILY:
        assert res.n_evaluations == 12 * 10
    capped = Counting()
    res = OPTIMIZERS.get(name)().minimize(
        sphere_problem(counter=capped), iterations=10_000, particles=10, rng=2, max_evaluations=255
    )
    assert capped.points == res.n_evaluations <= 255
    assert res.stop_reason == "max_evaluations"
    assert res.n_evaluations > 255 - 10 * 10  # it used most of the budget


@pytest.mark.parametrize("name", NAMES)
def test_improves_over_random_search_at_equal_evaluations(name):
    dim, particles, iterations = 10, 20, 250
    ours, random_search = [], []
    for seed in range(5):
        # CSO and AFSA evaluate more than one point per cat/fish and iteration: the cap makes
        # every optimiser spend the same 5000 evaluations
        res = OPTIMIZERS.get(name)().minimize(
            sphere_problem(dim), iterations=iterations, particles=particles, rng=seed,
            max_evaluations=particles * iterations,
        )
        ours.append(res.f)
        rng = np.random.default_rng(1000 + seed)
        random_search.append(sphere(rng.uniform(-100, 100, size=(res.n_evaluations, dim))).min())
    assert np.median(ours) < 0.5 * np.median(random_search)


@pytest.mark.parametrize("name", NAMES)
def test_initial_swarm_is_used(name):
    best = np.full((1, 10), 0.0)
    start = np.vstack([best, np.full((2, 10), 50.0)])
    res = OPTIMIZERS.get(name)().minimize(sphere_problem(), iterations=3, particles=10, rng=0, initial=start)
    assert res.f <= 1e-20  # the seeded optimum is never lost


@pytest.mark.parametrize("name", NAMES)
def test_bad_run_arguments_raise_config_error(name):
    opt = OPTIMIZERS.get(name)()
    p = sphere_problem()
    cases = [
        dict(iterations=0, particles=10),
        dict(iterations=5, particles=1),
        dict(iterations=5, particles=2.5),
        dict(iterations=5, particles=10, max_evaluations=5),
        dict(iterations=5, particles=10, initial=np.zeros((11, 10))),
        dict(iterations=5, particles=10, initial=np.zeros((2, 3))),
        dict(iterations=5, particles=10, initial=np.full((1, 10), 500.0)),
        dict(iterations=5, particles=10, rng=-1),
    ]
    for kwargs in cases:
        with pytest.raises(ConfigError):
            opt.minimize(p, **kwargs)
    with pytest.raises(ConfigError, match=f"^{name}: particles"):
        opt.minimize(p, iterations=5, particles=1)
    with pytest.raises(ConfigError):
        opt.minimize("sphere", iterations=5, particles=10)  # type: ignore[arg-type]


@pytest.mark.parametrize("name", NAMES)
def test_bad_hyperparameters_raise_config_error(name):
    assert name in BAD_HYPER, f"add a bad hyperparameter for {name!r} to BAD_HYPER"
    opt = OPTIMIZERS.get(name)(**BAD_HYPER[name])
    key = next(iter(BAD_HYPER[name]))
    with pytest.raises(ConfigError, match=f"{name}: {key}"):
        opt.minimize(sphere_problem(), iterations=5, particles=10, rng=0)
    with pytest.raises(ConfigError, match="unknown hyperparameter 'colour'"):
        minimize(sphere_problem(), name, iterations=5, particles=10, colour=3)


@pytest.mark.parametrize("name", NAMES)
def test_objective_count_is_checked(name):
    opt = OPTIMIZERS.get(name)()
    if opt.multi_objective:
        res = opt.minimize(zdt_problem("zdt1", 5), iterations=5, particles=10, rng=0)
        assert res.pareto_f is not None and res.pareto_f.shape[1] == 2
    else:
        with pytest.raises(ConfigError, match="mopso"):
            opt.minimize(zdt_problem("zdt1", 5), iterations=5, particles=10, rng=0)


def test_nan_objective_never_becomes_the_best():
    def half_nan(X):
        f = sphere(X)
        return np.where(X[:, 0] > 0, np.nan, f)

    p = Problem(half_nan, -10.0, 10.0, dim=3)
    for name in NAMES:
        res = OPTIMIZERS.get(name)().minimize(p, iterations=10, particles=10, rng=0)
        assert np.isfinite(res.f), name
        assert res.x[0] <= 0, name




def test_public_conformance_check_catches_a_broken_optimizer():
    from swarmpath.optim.base import RunOutput
    from swarmpath.optim.conformance import check_optimizer
    from swarmpath.optim.pso import PSO

    @dataclasses.dataclass(frozen=True)
    class Liar(PSO):
        def _run(self, problem, evaluate, *, iterations, particles, rng, initial):
            x = np.random.default_rng().uniform(problem.lower, problem.upper)  # ignores the seed
            return RunOutput(x, 0.0, np.zeros(iterations), iterations, "iterations", np.zeros(1))

    problems = check_optimizer(Liar)
    assert any("same seed" in p for p in problems)
    assert any("not the objective" in p for p in problems)
    assert any("evaluations" in p for p in problems)


def test_all_nan_objective_is_an_outcome_not_a_crash():
    p = Problem(lambda X: np.full(X.shape[0], np.nan), -1.0, 1.0, dim=3)
    for name in NAMES:
        res = OPTIMIZERS.get(name)().minimize(p, iterations=5, particles=6, rng=0)
        assert res.f == np.inf and res.x.shape == (3,), name
