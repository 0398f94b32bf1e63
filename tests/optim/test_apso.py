"""Zhan et al.'s adaptive PSO (``apso``): the ESE kernels against hand-computed values, then behaviour."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.optim import APSO, SPSO
from swarmpath.optim.apso import (
    CONVERGENCE,
    EXPLOITATION,
    EXPLORATION,
    JUMPING_OUT,
    adapt_acceleration,
    adaptive_inertia,
    classify_state,
    elitist_learning_candidate,
    evolutionary_factor,
    state_memberships,
)
from swarmpath.optim.functions import get_function


def test_evolutionary_factor_by_hand():
    # particles at 0, 1 and 3 on a line: mean distances 2, 1.5, 2.5
    x = np.array([[0.0], [1.0], [3.0]])
    assert evolutionary_factor(x, x[0]) == pytest.approx(0.5)
    assert evolutionary_factor(x, x[1]) == pytest.approx(0.0)
    assert evolutionary_factor(x, x[2]) == pytest.approx(1.0)
    # a global best away from every particle: d_g = (1 + 2 + 4) / 2 = 3.5 -> clipped to 1
    assert evolutionary_factor(x, np.array([-1.0])) == 1.0
    # all particles equally spread (a regular triangle): no information, factor 0
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, np.sqrt(3) / 2]])
    assert evolutionary_factor(tri, tri[0]) == 0.0


def test_memberships_eq_11():
    assert state_memberships(0.5) == pytest.approx((0.5, 0.5, 0.0, 0.0))
    assert state_memberships(0.25) == pytest.approx((0.0, 0.5, 0.25, 0.0))
    assert state_memberships(0.75) == pytest.approx((0.5, 0.0, 0.0, 0.25))
    assert state_memberships(0.05) == pytest.approx((0.0, 0.0, 1.0, 0.0))
    assert state_memberships(0.95) == pytest.approx((0.0, 0.0, 0.0, 1.0))
    assert state_memberships(0.65) == pytest.approx((1.0, 0.0, 0.0, 0.0))


@pytest.mark.parametrize(
    ("f", "previous", "expected"),
    [
        (0.05, JUMPING_OUT, CONVERGENCE),        # one membership: no choice
        (0.95, CONVERGENCE, JUMPING_OUT),
        (0.5, EXPLORATION, EXPLORATION),         # overlap S1/S2: stay where the swarm was
        (0.5, EXPLOITATION, EXPLOITATION),
        (0.5, CONVERGENCE, EXPLOITATION),        # ... or take the next state on the cycle
        (0.5, JUMPING_OUT, EXPLORATION),
        (0.25, CONVERGENCE, CONVERGENCE),        # overlap S2/S3
        (0.25, EXPLORATION, EXPLOITATION),
        (0.75, EXPLORATION, EXPLORATION),        # overlap S1/S4
        (0.75, CONVERGENCE, JUMPING_OUT),
    ],
)
def test_classification_follows_the_state_cycle(f, previous, expected):
    assert classify_state(f, previous) == expected


def test_inertia_eq_10_spans_0_4_to_0_9():
    assert adaptive_inertia(0.0) == pytest.approx(0.4)
    assert adaptive_inertia(1.0) == pytest.approx(1 / (1 + 1.5 * np.exp(-2.6)))
    assert 0.89 < adaptive_inertia(1.0) < 0.9
    assert np.all(np.diff([adaptive_inertia(f) for f in np.linspace(0, 1, 11)]) > 0)


def test_acceleration_table_1():
    assert adapt_acceleration(2.0, 2.0, EXPLORATION, 0.1) == pytest.approx((2.1, 1.9))
    assert adapt_acceleration(2.0, 2.0, EXPLOITATION, 0.1) == pytest.approx((2.05, 1.95))
    assert adapt_acceleration(2.0, 2.0, JUMPING_OUT, 0.1) == pytest.approx((1.9, 2.1))
    # convergence raises both: the sum is brought back to 4
    assert adapt_acceleration(2.0, 2.0, CONVERGENCE, 0.1) == pytest.approx((2.0, 2.0))
    assert adapt_acceleration(1.6, 1.6, CONVERGENCE, 0.1) == pytest.approx((1.65, 1.65))
    # clamped to [1.5, 2.5]
    assert adapt_acceleration(2.48, 1.52, EXPLORATION, 0.1) == pytest.approx((4 * 2.5 / 4.0, 4 * 1.5 / 4.0))


def test_elitist_learning_moves_one_dimension_inside_the_box():
    rng = np.random.default_rng(0)
    lower, upper = np.full(5, -1.0), np.full(5, 1.0)
    gbest = np.array([0.9, 0.0, 0.0, 0.0, -0.9])
    for _ in range(200):
        cand = elitist_learning_candidate(gbest, lower, upper, 1.0, rng)
        assert np.count_nonzero(cand != gbest) <= 1
        assert np.all(cand >= lower) and np.all(cand <= upper)


def _finals(optimizer, name, seeds=range(10)) -> np.ndarray:
    # 30 particles, 30,000 evaluations (the 30 x 1000 budget), 30-D, the paper's box
    problem = get_function(name).problem(30)
    return np.array([
        optimizer.minimize(problem, iterations=10**6, particles=30, rng=s, max_evaluations=30_000).f for s in seeds
    ])


@pytest.mark.slow
def test_apso_beats_the_papers_spso_at_equal_evaluations():
    assert np.median(_finals(APSO(), "sphere")) < 1e-10 < np.median(_finals(SPSO(), "sphere"))
    assert np.median(_finals(APSO(), "rastrigin")) < 0.5 * np.median(_finals(SPSO(), "rastrigin"))
    # Ackley is bimodal for APSO: a run either finds the optimum or settles in a local minimum
    # near f = 1; most runs find it, SPSO's stop around 5e-3
    solved = np.sum(_finals(APSO(), "ackley") < 1e-5)
    assert solved >= 5 and solved > np.sum(_finals(SPSO(), "ackley") < 1e-5)


@pytest.mark.slow
def test_elitist_learning_lets_the_swarm_leave_rastrigins_local_minima():
    with_els = np.median(_finals(APSO(), "rastrigin"))
    assert with_els < 0.5 * np.median(_finals(APSO(elitist_learning=False), "rastrigin"))


def test_sigma_schedule_follows_iterations_or_the_evaluation_budget():
    from swarmpath.optim._budget import Evaluator
    from swarmpath.optim.apso import run_progress

    problem = get_function("sphere").problem(2)
    free, capped = Evaluator(problem, None), Evaluator(problem, 400)
    for evaluator in (free, capped):
        evaluator(np.zeros((100, 2)))
    assert run_progress(10, 40, free) == pytest.approx(0.25)
    assert run_progress(10, 10**6, capped) == pytest.approx(0.25)   # 100 of 400 evaluations
    assert run_progress(30, 40, capped) == pytest.approx(0.75)      # whichever is further
    assert run_progress(50, 40, free) == 1.0
