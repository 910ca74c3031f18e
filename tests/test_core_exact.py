"""The exact solution: Eqs. (11)/(12), symmetries, shakedown, extreme inputs."""

import math

import numpy as np
import pytest

import lcpfric
from lcpfric.analysis.analytic import jang_barber
from lcpfric.exact import BACKWARD, FORWARD, SEPARATION, STICK, exact_cycle, exact_W_hat
from lcpfric.analysis.shakedown import shakedown, shakedown_margin


def test_jang_barber_regimes_values():
    # hand-checked values of the corrected Eq. (11) and Eq. (12)
    assert jang_barber(0.5, 2.0) == pytest.approx(4 * 1 * 1.75 / 3.75, rel=1e-15)
    assert jang_barber(2.0, 2.5) == pytest.approx(0.5 * 9 / (2 * 4.5), rel=1e-15)
    assert jang_barber(0.5, 0.9) == 0.0
    assert jang_barber(3.0, 1.0) == 0.0
    # continuous across P̂1 = 1
    assert jang_barber(1 - 1e-12, 3.0) == pytest.approx(jang_barber(1 + 1e-12, 3.0), rel=1e-10)


def test_exact_matches_jang_barber_on_grid_all_regimes():
    g = np.concatenate([np.linspace(0, 10, 81), [0.999999, 1.0, 1.000001]])
    P1, Q1 = np.meshgrid(g, g)
    W = exact_W_hat(P1, Q1, 0.0)
    J = jang_barber(P1, Q1)
    pos = J > 0
    # all four régimes are on the grid
    assert np.any((P1 < 1) & (Q1 < 1)) and np.any((P1 < 1) & (Q1 > 1) & pos)
    assert np.any((P1 > 1) & (Q1 < P1)) and np.any((P1 > 1) & (Q1 > P1) & pos)
    rel = np.abs(W[pos] - J[pos]) / J[pos]
    # 1e-12 relative, except where the problem itself is ill-conditioned: next to the boundary
    # of a zero régime Ŵ ∝ (distance to it), so double precision gives ~eps/distance there.
    dist = np.where(P1 < 1, np.abs(Q1 - 1), np.abs(Q1 - P1))[pos]
    assert np.all(rel <= 1e-12 + 1e-15 * (1 + Q1[pos]) / dist)
    assert np.max(rel[dist > 1e-2]) < 1e-12
    assert np.max(np.abs(W[~pos])) < 1e-14


def test_period_pi_in_phi():
    rng = np.random.default_rng(1)
    P1 = rng.uniform(0, 6, 400)
    Q1 = rng.uniform(0, 6, 400)
    phi = rng.uniform(0, np.pi, 400)
    a = exact_W_hat(P1, Q1, phi)
    b = exact_W_hat(P1, Q1, phi + np.pi)
    c = exact_W_hat(P1, Q1, phi - 3 * np.pi)
    assert np.max(np.abs(a - b) / np.maximum(a, 1)) < 1e-12
    assert np.max(np.abs(a - c) / np.maximum(a, 1)) < 1e-12


def _boundary_Q1(P1, phi):
    """Q̂1 on the shakedown boundary (margin = 0) by bisection; margin decreases with Q̂1."""
    lo, hi = 0.0, 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if shakedown_margin(P1, mid, phi) >= 0 else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("phi", np.linspace(0, np.pi, 9))
@pytest.mark.parametrize("P1", [0.0, 0.3, 0.8])
def test_zero_inside_shakedown_positive_just_outside(P1, phi):
    q = _boundary_Q1(P1, phi)
    assert 0 < q <= 1.0 + 1e-12
    inside, outside = q * (1 - 1e-3), q * (1 + 1e-3)
    assert shakedown(P1, inside, phi).shakedown and not shakedown(P1, outside, phi).shakedown
    assert exact_W_hat(P1, inside, phi) == 0.0
    assert exact_W_hat(P1, outside, phi) > 0.0
    for method in ("explicit", "projection"):
        node = lcpfric.SingleNode.normalized(P1, inside, phi)
        assert lcpfric.steady_state(node, method, 400).W_hat == pytest.approx(0.0, abs=1e-13)


def test_shakedown_shift_is_valid():
    for P1, Q1, phi in [(0.5, 0.7, 0.3 * np.pi), (0.2, 0.9, 1.0), (0.0, 1.0, 0.0)]:
        res = shakedown(P1, Q1, phi)
        assert res.shakedown
        t = np.linspace(0, 2 * np.pi, 20001)
        Ph, Qh = 1 + P1 * np.sin(t), Q1 * np.sin(t + phi)
        assert np.all(np.abs(Qh - res.shift) <= Ph + 1e-12)
    res = shakedown(1.5, 0.1, 0.5)  # separation: never shakes down
    assert not res.shakedown and res.shift is None


def test_shakedown_general_loads_agrees_with_closed_form():
    node = lcpfric.SingleNode(k11=2.0, f=0.4, P0=3.0, P1=1.2, Q1=0.8, phi=0.7)
    closed = shakedown(*node.normalized_parameters())
    general_node = lcpfric.SingleNode(
        k11=2.0,
        f=0.4,
        normal_load=lcpfric.Fourier(3.0, (1.2, 0.0), (0.0, 0.0)),
        tangential_load=lcpfric.Fourier(0.0, (0.8, 0.0), (0.7, 0.0)),
    )
    general = shakedown(general_node)
    assert general.shakedown == closed.shakedown
    assert general.margin == pytest.approx(closed.margin, abs=1e-9)


@pytest.mark.parametrize("P1", [1e-6, 1e-3, 1.0, 1e3, 1e6])
@pytest.mark.parametrize("Q1", [1e-6, 1e-3, 1.0, 1e3, 1e6])
def test_extreme_inputs_finite_and_correct(P1, Q1):
    ref = jang_barber(P1, Q1)
    scale = 1 + math.sqrt(P1 * Q1)
    for phi in (0.0, np.pi):
        W = exact_W_hat(P1, Q1, phi)
        assert math.isfinite(W)
        assert abs(W - ref) <= 1e-12 * max(ref, 0) + 1e-15 * scale
    for phi in (1e-9, np.pi / 2, np.pi - 1e-9):
        W = exact_W_hat(P1, Q1, phi)
        assert math.isfinite(W) and W >= 0


def test_zero_amplitudes_give_zero():
    assert exact_W_hat(0.0, 0.0, 0.3) == 0.0
    assert exact_W_hat(3.0, 0.0, 0.3) == 0.0
    assert exact_W_hat(0.0, 3.0, 0.3) == pytest.approx(4 * (3 - 1) * 3 / 9, rel=1e-12)


@pytest.mark.parametrize(
    "P1,Q1,phi", [(0.5, 2.0, 0.6 * np.pi), (1.5, 2.0, 0.6 * np.pi), (5.0, 5.0, 0.5 * np.pi)]
)
def test_exact_cycle_satisfies_coulomb_and_energy(P1, Q1, phi):
    cyc = exact_cycle(P1, Q1, phi)
    th = np.linspace(0, 2 * np.pi, 200001)
    w = cyc.w(th)
    st = cyc.state(th)
    L = np.maximum(1 + P1 * np.sin(th), 0)
    F = Q1 * np.sin(th + phi) + w
    assert np.all(np.abs(F) <= L + 1e-12)
    assert set(np.unique(st)) <= {STICK, FORWARD, BACKWARD, SEPARATION}
    # slip states push w in their direction; stick keeps w
    dw = np.diff(w)
    mid = st[1:]
    assert np.all(dw[mid == FORWARD] >= -1e-12) and np.all(dw[mid == BACKWARD] <= 1e-12)
    # periodic, continuous (no jump larger than the local motion), and ∮ L|dw| = Q̂1 Ŵ
    assert abs(w[0] - w[-1]) < 1e-12
    J = np.sum(0.5 * (L[1:] + L[:-1]) * np.abs(dw))
    assert J / Q1 == pytest.approx(cyc.W_hat, rel=1e-6)
    # the energy identity W = ∮ u dQ for a periodic cycle (F = Q + K u)
    dQ = np.diff(Q1 * np.sin(th + phi))
    assert np.sum(0.5 * (w[1:] + w[:-1]) * dQ) / Q1 == pytest.approx(cyc.W_hat, rel=1e-6)


def test_scalar_and_vectorized_event_loops_agree():
    from lcpfric.exact.scalar import run_scalar
    from lcpfric.exact.vectorized import run_vectorized

    rng = np.random.default_rng(7)
    n = 3000
    P1 = np.concatenate([rng.uniform(0, 3, n), rng.choice([0.0, 0.5, 1.0, 2.0], 200)])
    Q1 = np.concatenate([rng.uniform(0, 3, n), rng.choice([0.5, 1.0, 2.0], 200)])  # Q̂1 > 0
    phi = np.concatenate([rng.uniform(0, 2 * np.pi, n), rng.choice([0.0, np.pi / 2, np.pi], 200)])
    W = run_vectorized(P1, Q1, phi)
    Ws = np.array([run_scalar(p, q, f)[0] for p, q, f in zip(P1, Q1, phi)])
    assert np.max(np.abs(W - Ws) / np.maximum(np.abs(Ws), 1.0)) < 1e-13
    # the segments of the scalar loop integrate to its Ŵ (checked in detail below)
    assert np.all(np.isfinite(W))


def test_period_pi_in_phi_dense_grid_across_separation_onset():
    # Re-contact with the lower bound's phase in [3π/2, 2π) (P̂1 just above 1, small Q̂1) once
    # escaped the tests: a dense grid across P̂1 = 1 checks the φ + π symmetry there.
    P1, Q1, phi = np.meshgrid(
        np.linspace(0.9, 2.0, 45),
        np.linspace(0.05, 2.0, 40),
        np.linspace(0, np.pi, 37),
        indexing="ij",
    )
    a = exact_W_hat(P1, Q1, phi)
    b = exact_W_hat(P1, Q1, phi + np.pi)
    assert np.max(np.abs(a - b)) < 1e-12
    # and against the explicit stepper at the worst points of the old bug
    for p, q, f in [(1.2, 0.8, 0.75 * np.pi), (1.1, 0.5, 0.9 * np.pi), (1.35, 1.2, 0.6 * np.pi)]:
        ex = exact_W_hat(p, q, f)
        num = lcpfric.steady_state(lcpfric.SingleNode.normalized(p, q, f), "explicit", 20000)
        assert num.W_hat == pytest.approx(ex, rel=1e-6, abs=1e-9)
