"""Batched single-node scenes: the vectorized projection and the block-diagonal solver batch
against the single-node path, point by point."""

import numpy as np
import pytest

from lcpfric import ConvergenceError, InputError, SingleNode, steady_state
from lcpfric.batch import batched_W_hat, projection_steady_states, projection_W_hat
from lcpfric.exact import exact_W_hat

from support import need
from support import CASES, fitted_order

RNG = np.random.default_rng(7)
# the suite's cases, the edges (no load, tangency P̂1 = 1, no separation, stick) and random
# points on both sides of P̂1 = 1
P1 = np.concatenate(
    [[c[0] for c in CASES.values()], [0.0, 1.0, 2.0, 0.9, 3.0], RNG.uniform(0.0, 4.0, 8)]
)
Q1 = np.concatenate(
    [[c[1] for c in CASES.values()], [1.0, 1.5, 0.0, 0.4, 0.2], RNG.uniform(0.0, 5.0, 8)]
)
PHI = np.concatenate(
    [
        [c[2] for c in CASES.values()],
        [2.0, 1.0, 0.5, 0.6 * np.pi, 0.0],
        RNG.uniform(-np.pi, np.pi, 8),
    ]
)


def one_by_one(method, steps, placement):
    return np.array(
        [
            steady_state(SingleNode.normalized(p, q, f), method, steps, placement=placement).W_hat
            for p, q, f in zip(P1, Q1, PHI)
        ]
    )


@pytest.mark.parametrize("placement", ["uniform", "contact"])
def test_projection_batch_equals_single_node_projection(placement):
    res = projection_steady_states(P1, Q1, PHI, 600, placement)
    ref = one_by_one("projection", 600, placement)
    np.testing.assert_allclose(res.W_hat, ref, rtol=0, atol=1e-13)
    assert res.converged.all() and res.steps_requested == 600 and res.steps_used >= 600
    cycles = [
        steady_state(SingleNode.normalized(p, q, f), "projection", 600, placement=placement).cycles
        for p, q, f in zip(P1, Q1, PHI)
    ]
    np.testing.assert_array_equal(res.cycles, cycles)


@pytest.mark.parametrize("method", ["clarabel", "osqp"])
def test_solver_batch_equals_projection_batch(method):
    need(method)
    W = batched_W_hat(P1, Q1, PHI, method, 300)
    np.testing.assert_allclose(W, projection_W_hat(P1, Q1, PHI, 300), rtol=0, atol=1e-12)


def test_projection_batch_is_second_order():
    P1s, Q1s, phis = np.array([1.5, 0.5]), np.array([2.0, 2.0]), np.array([0.6, 0.6]) * np.pi
    steps = [250, 500, 1000, 2000]
    exact = exact_W_hat(P1s, Q1s, phis)
    errors = np.array([np.abs(projection_W_hat(P1s, Q1s, phis, s) - exact) / exact for s in steps])
    for e in errors.T:
        assert fitted_order(steps, e) > 1.5, e
    assert errors[-1].max() < 5e-6


def test_shapes_and_scalars():
    W = projection_W_hat(np.array([[0.5], [1.5]]), np.array([1.0, 2.0, 3.0]), 0.3, 100)
    assert W.shape == (2, 3)
    w = projection_W_hat(1.5, 2.0, 0.3, 100)
    assert isinstance(w, float) and w == W[1, 1]
    assert projection_W_hat(0.5, 0.0, 0.0, 100) == 0.0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"P1": -1.0}, "P1"),
        ({"Q1": [1.0, 2.0], "P1": [1.0, 2.0, 3.0]}, "broadcast"),
        ({"steps_per_cycle": 2}, "steps_per_cycle"),
        ({"placement": "random"}, "placement"),
        ({"tol": 0.0}, "tol"),
        ({"phi": np.nan}, "phi"),
        ({"P1": []}, "at least one"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"P1": 0.5, "Q1": 2.0, "phi": 0.0, "steps_per_cycle": 50, **kwargs}
    with pytest.raises(InputError, match=match):
        projection_W_hat(**args)


def test_nonconvergence_is_reported():
    with pytest.raises(ConvergenceError, match="no periodic steady state"):
        projection_W_hat([0.5, 1.5], 2.0, 0.3, 100, max_cycles=1)
    info = projection_steady_states(
        [0.5, 1.5], 2.0, 0.3, 100, max_cycles=1, on_nonconvergence="ignore"
    )
    # a point that did not converge is NaN, never a value taken for converged
    assert not info.converged.any() and np.all(np.isnan(info.W_hat))
    assert np.all(info.cycles == 1) and info.method == "projection"
    assert info.unconverged == 2


def test_batched_needs_a_solver_backend():
    with pytest.raises(InputError, match="projection_steady_states"):
        batched_W_hat(0.5, 2.0, 0.0, "projection", 50)
