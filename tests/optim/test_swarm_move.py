"""The one-pass C move equals the numpy reference kernels bit for bit, for every coefficient shape."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmpath.optim.pso import Coefficients, clamp_velocity, pso_position_update, pso_velocity_update, swarm_move


def reference(x, v, pbest, leaders, coefficients, v_max, lower, upper):
    w, c1, c2, r1, r2 = coefficients
    v = clamp_velocity(pso_velocity_update(v, x, pbest, leaders, w, c1, c2, r1, r2), v_max)
    return pso_position_update(x, v, lower, upper)


def swarm(seed: int, n: int, d: int, shared: bool, per_particle_leader: bool):
    rng = np.random.default_rng(seed)
    lower, upper = -rng.uniform(1, 10, d), rng.uniform(1, 10, d)
    x = rng.uniform(lower, upper, (n, d))
    v = rng.normal(0, 5, (n, d))       # large: many components are clamped and hit the walls
    pbest = rng.uniform(lower, upper, (n, d))
    leaders = rng.uniform(lower, upper, (n, d) if per_particle_leader else d)
    r = rng.random((2, n, d))
    if shared:
        coeffs = Coefficients(float(rng.uniform(0, 1)), 2.0, 1.49618, r[0], r[1])
    else:
        coeffs = Coefficients(rng.uniform(0, 1, (n, 1)), rng.uniform(0, 3, (n, 1)), rng.uniform(0, 3, (n, 1)), r[0], r[1])
    v_max = 0.2 * (upper - lower)
    return x, v, pbest, leaders, coeffs, v_max, lower, upper


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(1, 40),
    d=st.integers(1, 12),
    shared=st.booleans(),
    per_particle_leader=st.booleans(),
)
def test_c_move_equals_the_numpy_kernels(seed, n, d, shared, per_particle_leader):
    args = swarm(seed, n, d, shared, per_particle_leader)
    want_x, want_v = reference(*[a.copy() if isinstance(a, np.ndarray) else a for a in args])
    x_before = args[0].copy()
    got_x, got_v = swarm_move(*args)
    np.testing.assert_array_equal(got_x, want_x)
    np.testing.assert_array_equal(got_v, want_v)
    np.testing.assert_array_equal(args[0], x_before)  # the caller's positions are not overwritten
    assert np.all(got_x >= args[6]) and np.all(got_x <= args[7])


def test_walls_stop_the_particle():
    x, v = np.array([[0.9, 0.0]]), np.array([[0.5, 0.1]])
    coeffs = Coefficients(1.0, 0.0, 0.0, np.zeros((1, 2)), np.zeros((1, 2)))
    nx, nv = swarm_move(x, v, x.copy(), x[0].copy(), coeffs, np.ones(2), -np.ones(2), np.ones(2))
    np.testing.assert_array_equal(nx, [[1.0, 0.1]])
    np.testing.assert_array_equal(nv, [[0.0, 0.1]])


def test_per_component_coefficients_use_the_numpy_path():
    args = swarm(3, 5, 4, True, False)
    x, v, pbest, leaders, (w, c1, c2, r1, r2), v_max, lower, upper = args
    odd = Coefficients(np.full((5, 4), 0.5), c1, c2, r1, r2)
    want = reference(x.copy(), v.copy(), pbest, leaders, odd, v_max, lower, upper)
    got = swarm_move(x, v, pbest, leaders, odd, v_max, lower, upper)
    np.testing.assert_array_equal(got[0], want[0])
    np.testing.assert_array_equal(got[1], want[1])


def test_bad_shapes_are_rejected_by_the_extension():
    from swarmpath.optim import _swarmstep

    x = np.zeros((3, 2))
    with pytest.raises(ValueError, match="leaders"):
        _swarmstep.step(x, x.copy(), x, np.zeros(5), np.ones(1), np.ones(1), np.ones(1), x, x,
                        np.ones(2), -np.ones(2), np.ones(2))
    with pytest.raises(TypeError, match="float64"):
        _swarmstep.step(x.astype(np.float32), x.copy(), x, np.zeros(2), np.ones(1), np.ones(1), np.ones(1),
                        x, x, np.ones(2), -np.ones(2), np.ones(2))
