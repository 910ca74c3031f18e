"""Coupled systems' first pieces (issue 38): the coupling block and its well-posedness
(lcpfric.model.coupling), the safe state of a coupled system (a linear program), and the
methods' refusal until they solve coupled systems."""

import itertools

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError
from lcpfric.model import ContactSystem, IndependentSprings
from lcpfric.model.coupling import check_coupling
from lcpfric.model.loads import Harmonic


def _system(K, B, f, P0, P1, psi, Q1, phi):
    n = len(f)
    return ContactSystem(
        np.atleast_2d(K),
        np.asarray(f, float),
        tuple(Harmonic(0.0, Q1[i], phi[i]) for i in range(n)),
        IndependentSprings(tuple(Harmonic(P0[i], P1[i], psi[i]) for i in range(n))),
        coupling=None if B is None else np.atleast_2d(B),
    )


def _brute_well_posed(K, B, f):
    """Every principal minor of K + diag(s f) B, every s, formed directly."""
    n = len(f)
    for s in itertools.product((1.0, -1.0), repeat=n):
        A = K + np.diag(np.array(s) * f) @ B
        for k in range(1, n + 1):
            for S in itertools.combinations(range(n), k):
                if np.linalg.det(A[np.ix_(S, S)]) <= 1e-12:
                    return False
    return True


def test_one_node_is_klarbrings_condition():
    K, f = np.array([[2.0]]), np.array([0.5])
    check_coupling([[3.9]], K, f)  # f |k21| = 1.95 < k11 = 2
    check_coupling([[-3.9]], K, f)
    for k21 in (4.1, -4.1):
        with pytest.raises(InputError, match=r"coupling.*Klarbring.*node\(s\) \[0\]"):
            check_coupling([[k21]], K, f)


@pytest.mark.parametrize("seed", range(12))
def test_the_check_agrees_with_every_minor_formed_directly(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 5))
    A = rng.standard_normal((n, n))
    K = A @ A.T / n + 0.5 * np.eye(n)
    B = rng.standard_normal((n, n)) * rng.uniform(0.2, 3.0)
    f = rng.uniform(0.2, 1.0, n)
    if _brute_well_posed(K, B, f):
        np.testing.assert_array_equal(check_coupling(B, K, f), B)
    else:
        with pytest.raises(InputError, match="not well posed"):
            check_coupling(B, K, f)


def test_bad_coupling_blocks_are_refused_by_name():
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    args = ([0.5, 0.5], [1, 1], [0.2, 0.2], [0, 0], [0.3, 0.3], [0, 1])
    with pytest.raises(InputError, match="coupling.*2 x 2"):
        _system(K, np.zeros((3, 3)), *args)
    with pytest.raises(InputError, match="coupling"):
        _system(K, [[np.nan, 0], [0, 0]], *args)
    d2 = lcpfric.chain(2, P1=0.5, Q1=0.4, phi=0.3, dims=2)
    with pytest.raises(InputError, match="coupling.*d = 1"):
        ContactSystem(
            d2.stiffness, d2.friction, d2.tangential_loads, d2.normal, 2, coupling=0.1 * np.eye(2)
        )


@pytest.mark.parametrize("method", ["projection"])
def test_a_method_that_does_not_solve_a_coupled_system_says_so(method):
    s = _system([[2.0, -1], [-1, 2]], [[0.3, 0], [0, -0.2]], [0.5, 0.5], [1, 1], [0.2, 0.2],
                [0, 0], [0.3, 0.3], [0, 1])  # fmt: skip
    with pytest.raises(InputError, match="coupling.*does not solve coupled.*'exact' or 'explicit'"):
        lcpfric.steady_state(s, method, 100)
    assert lcpfric.steady_state(s, "exact", 100).W >= 0


@pytest.mark.parametrize("Q1", [[0.4, 0.6, 0.3], [0.4, 1.9, 0.3]])
def test_the_linear_program_with_b_zero_is_the_uncoupled_closed_form(Q1):
    s = lcpfric.chain(3, k_coupling=3.0, P1=np.array([0.3, 0.5, 0.2]), Q1=np.array(Q1),
                      phi=np.array([0.2, 2.0, 4.0]))  # fmt: skip
    from lcpfric.analysis.safe_state import _coupled

    coupled = ContactSystem(s.stiffness, s.friction, s.tangential_loads, s.normal,
                            coupling=np.zeros((3, 3)))  # fmt: skip
    assert coupled.coupling is None  # B = 0 is the uncoupled system
    object.__setattr__(coupled, "coupling", np.zeros((3, 3)))  # the linear program on it
    a = lcpfric.shakedown(s)
    ok, margin, state, margins = _coupled(coupled, 4096)
    assert ok == a.shakedown
    assert margin == pytest.approx(a.margin, rel=1e-10)


@pytest.mark.parametrize("seed", range(10))
def test_one_coupled_node_against_its_closed_form(seed):
    """One node: N = P + k21 v, F = Q + k11 v; safe constants v lie between
    max -(Q + f P)/(k11 + f k21) and min (f P - Q)/(k11 - f k21) (a play's ends)."""
    rng = np.random.default_rng(seed)
    k11, f = 2.0, 0.6
    k21 = rng.uniform(-0.9, 0.9) * k11 / f
    P1, psi, Q1, phi = (
        rng.uniform(0, 0.9),
        rng.uniform(0, 6),
        rng.uniform(0, 1.2),
        rng.uniform(0, 6),
    )
    s = _system([[k11]], [[k21]], [f], [1.0], [P1], [psi], [Q1], [phi])
    t = np.linspace(0, 2 * np.pi, 200001)
    P, Q = 1.0 + P1 * np.sin(t + psi), Q1 * np.sin(t + phi)
    lo, hi = np.max(-(Q + f * P) / (k11 + f * k21)), np.min((f * P - Q) / (k11 - f * k21))
    sd = lcpfric.shakedown(s)
    if abs(hi - lo) > 1e-6:
        assert sd.shakedown == (hi > lo)
    if sd.shakedown:
        assert lo - 1e-9 <= sd.state[0] <= hi + 1e-9


def test_a_coupled_safe_state_is_safe():
    K = np.array([[3.0, -1.0, 0], [-1.0, 3.0, -1.0], [0, -1.0, 3.0]])
    B = np.array([[0.8, 0.3, 0.0], [-0.2, -0.9, 0.4], [0.0, 0.5, 0.6]])
    s = _system(K, B, [0.5, 0.6, 0.4], [1, 1, 1], [0.3, 0.4, 0.2], [0, 1, 2], [0.2, 0.3, 0.15],
                [0.5, 2.0, 4.0])  # fmt: skip
    sd = lcpfric.shakedown(s)
    assert sd.shakedown and sd.margin > 0
    t = np.linspace(0.0, s.period, 20001)
    v = sd.state
    F = s.tangential(t) + K @ v
    N = s.normal.loads_at(t) + B @ v
    assert np.all(np.abs(F) <= s.friction * N + 1e-12)
    loud = _system(K, B, [0.5, 0.6, 0.4], [1, 1, 1], [0.3, 0.4, 0.2], [0, 1, 2], [0.2, 2.5, 0.15],
                   [0.5, 2.0, 4.0])  # fmt: skip
    sd = lcpfric.shakedown(loud)
    assert not sd.shakedown and sd.margin < 0 and sd.state is None
