"""``exact`` on coupled systems (N = P + B u): against the independent event-driven reference
(:mod:`support.coupled_reference`), the one-node play operator, the uncoupled limit, and the
errors."""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError
from lcpfric.exact.triples import harmonic_triples
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings

from support.coupled_reference import Reference


def system(K, B, f, P0, P1, psi, Q0, Q1, phi):
    n = len(f)
    return ContactSystem(
        np.asarray(K, float),
        np.asarray(f, float),
        tuple(Harmonic(Q0[i], Q1[i], phi[i], 1.0) for i in range(n)),
        IndependentSprings(tuple(Harmonic(P0[i], P1[i], psi[i], 1.0) for i in range(n))),
        coupling=None if B is None else np.asarray(B, float),
    )


def random_system(n, rng, c=0.5):
    A = rng.standard_normal((n, n))
    K = A @ A.T + n * np.eye(n)
    f = rng.uniform(0.3, 0.8, n)
    B = c * rng.standard_normal((n, n)) * np.sqrt(np.diag(K))[:, None]
    return system(
        K, B, f, rng.uniform(3, 5, n), rng.uniform(0, 1.5, n), rng.uniform(0, 6.28, n),
        rng.uniform(-0.5, 0.5, n), rng.uniform(1, 3, n), rng.uniform(0, 6.28, n),
    )  # fmt: skip


def reference(s):
    Qt = harmonic_triples(s.tangential_loads, 1.0, "Q")
    Pt = harmonic_triples(s.normal.loads, 1.0, "P")
    return Reference(s.dense_stiffness(), s.coupling, s.friction, Qt, Pt)


# (seed draw index, n): systems of the validation sample that slip in their steady state
CASES = [(2, 3), (11, 2), (14, 5), (20, 1), (28, 4)]


@pytest.mark.parametrize(("index", "n"), CASES)
def test_exact_matches_the_independent_reference(index, n):
    rng = np.random.default_rng(1)
    for trial in range(index + 1):
        s = random_system(1 + trial % 5, rng)
    assert s.n == n
    res = lcpfric.steady_state(s, method="exact", steps_per_cycle=64)
    assert res.W > 0
    W_ref = reference(s).steady(res.v[0])[0]
    # the same start: exact's own start (its first sample), W within 1e-10
    assert abs(res.W - W_ref) <= 1e-10 * max(1.0, res.W)
    assert res.solver_stats["remaining"] <= 1e-12


def test_start_given_is_followed():
    rng = np.random.default_rng(1)
    for trial in range(3):
        s = random_system(1 + trial % 5, rng)
    from lcpfric.analysis.starts import start_from_ratios

    for r in ([0.9, -0.5, 0.2], [-0.8, 0.8, -0.1]):
        u0 = start_from_ratios(s, r)
        res = lcpfric.steady_state(s, method="exact", steps_per_cycle=64, u0=u0)
        W_ref = reference(s).steady(u0)[0]
        assert abs(res.W - W_ref) <= 1e-10
        assert np.allclose(res.v[0], res.v[-1], atol=1e-9)


def test_one_node_play_operator():
    """One coupled node: v sweeps [lo(θ), hi(θ)] like a play operator; W in the steady cycle
    by quadrature of f N |dv| along the two slipping arcs (the notes' closed form)."""
    from scipy.integrate import quad
    from scipy.optimize import brentq, minimize_scalar

    k, b, f, P0, P1, Q1, phi = 2.0, 0.8, 0.5, 3.0, 1.0, 2.5, 0.7
    s = system([[k]], [[b]], [f], [P0], [P1], [0.0], [0.0], [Q1], [phi])
    res = lcpfric.steady_state(s, method="exact", steps_per_cycle=64)
    P = lambda t: P0 + P1 * np.sin(t)  # noqa: E731
    Q = lambda t: Q1 * np.sin(t + phi)  # noqa: E731
    lo = lambda t: (-f * P(t) - Q(t)) / (k + f * b)  # noqa: E731
    hi = lambda t: (f * P(t) - Q(t)) / (k - f * b)  # noqa: E731
    lo_max = -minimize_scalar(lambda t: -lo(t), bounds=(0, 2 * np.pi), method="bounded",
                              options={"xatol": 1e-12}).fun  # fmt: skip
    hi_min = minimize_scalar(hi, bounds=(0, 2 * np.pi), method="bounded",
                             options={"xatol": 1e-12}).fun  # fmt: skip
    assert lo_max > hi_min  # it slips

    dP = lambda t: P1 * np.cos(t)  # noqa: E731
    dQ = lambda t: Q1 * np.cos(t + phi)  # noqa: E731
    dlo = lambda t: (-f * dP(t) - dQ(t)) / (k + f * b)  # noqa: E731
    dhi = lambda t: (f * dP(t) - dQ(t)) / (k - f * b)  # noqa: E731

    def arc(edge, rate, level, sign):
        # v follows the edge from where it passes the level (v's value since the other arc)
        # up to the edge's extreme (sign +1: the lower edge's maximum): ∫ f N |dv|
        t = np.linspace(0, 2 * np.pi, 20001)
        m = t[np.argmax(sign * edge(t))]
        m = minimize_scalar(lambda x: -sign * edge(x), bounds=(m - 0.01, m + 0.01),
                            method="bounded", options={"xatol": 1e-14}).x  # fmt: skip
        back = np.linspace(m - 2 * np.pi, m, 20001)
        j = np.nonzero(sign * (edge(back) - level) < 0)[0][-1]
        a = brentq(lambda x: edge(x) - level, back[j], back[j + 1], xtol=1e-15)
        return quad(lambda x: f * (P(x) + b * edge(x)) * abs(rate(x)), a, m, epsabs=1e-14)[0]

    W = arc(lo, dlo, hi_min, +1) + arc(hi, dhi, lo_max, -1)
    assert res.W == pytest.approx(W, rel=1e-11)


def test_uncoupled_limit_is_bit_for_bit():
    rng = np.random.default_rng(3)
    s = random_system(3, rng)
    plain = ContactSystem(s.stiffness, s.friction, s.tangential_loads, s.normal)
    zero = ContactSystem(plain.stiffness, plain.friction, plain.tangential_loads, plain.normal,
                         coupling=np.zeros((3, 3)))  # fmt: skip
    a = lcpfric.steady_state(plain, method="exact")
    b = lcpfric.steady_state(zero, method="exact")
    assert a.W == b.W
    assert np.array_equal(a.v, b.v)


def test_separation_is_an_error_naming_node_and_instant():
    # a strong coupling that drives node 0's normal reaction to zero when it slips
    s = system([[2.0]], [[-1.9]], [0.5], [1.0], [0.0], [0.0], [0.0], [3.0], [0.0])
    with pytest.raises(InputError, match=r"node 0.*reaches zero at θ = ") as exc:
        lcpfric.steady_state(s, method="exact")
    assert exc.value.parameter == "normal_loads"


def test_other_methods_refuse_coupled_systems_by_name():
    s = system([[2.0]], [[0.5]], [0.5], [3.0], [1.0], [0.0], [0.0], [2.0], [0.0])
    from lcpfric.model.coupling import COUPLED_METHODS

    other = next(m for m in ("active-set", "projection", "clarabel") if m not in COUPLED_METHODS)
    with pytest.raises(InputError, match=f"'{other}' does not solve coupled") as exc:
        lcpfric.steady_state(s, method=other)
    assert exc.value.parameter == "coupling"


def test_inadmissible_start_names_the_normal_reaction():
    s = system([[2.0]], [[1.0]], [0.5], [1.0], [0.0], [0.0], [0.0], [0.5], [0.0])
    with pytest.raises(InputError, match="not a compression") as exc:
        lcpfric.steady_state(s, method="exact", u0=[-2.0])
    assert exc.value.parameter == "u0"


@pytest.mark.parametrize(("k21", "Q0"), [(0.5, 0.0), (-0.8, 0.4)])
def test_klarbrings_node_is_its_one_node_system(k21, Q0):
    node = lcpfric.SingleNode(k11=2.0, f=0.5, P0=3.0, P1=1.0, Q1=2.5, phi=0.7, Q0=Q0, k21=k21)
    s = system([[2.0]], [[k21]], [0.5], [3.0], [1.0], [0.0], [Q0], [2.5], [0.7])
    a, b = lcpfric.steady_state(node, "exact"), lcpfric.steady_state(s, "exact")
    assert a.W == pytest.approx(b.W, rel=1e-13)
    assert np.allclose(a.v, b.v[:, 0], atol=1e-13) and np.allclose(a.N, b.N[:, 0], atol=1e-13)
    assert a.W_hat == pytest.approx(a.W / node.normalization().W, rel=1e-13)
    assert lcpfric.steady_state(node, "explicit", 1600).W == pytest.approx(a.W, rel=1e-5)
    from lcpfric.model.coupling import COUPLED_METHODS

    other = next(m for m in ("active-set", "projection", "clarabel") if m not in COUPLED_METHODS)
    with pytest.raises(InputError, match=f"'{other}' does not solve coupled"):
        lcpfric.steady_state(node, other)


def test_klarbrings_condition_for_one_node():
    with pytest.raises(InputError, match="Klarbring") as exc:
        lcpfric.SingleNode(k11=2.0, f=0.5, P0=3.0, k21=4.0)
    assert exc.value.parameter == "k21"


def test_single_node_from_a_start_keeps_its_units():
    """The exact single node from a start (its one-node system) gives the closed form's W and
    series in the node's units (a start once returned W in the system's units)."""
    node = lcpfric.SingleNode(k11=2.0, f=0.5, P0=3.0, P1=1.0, Q1=2.5, phi=0.0)
    a = lcpfric.steady_state(node, "exact")
    b = lcpfric.steady_state(node, "exact", u0=[0.0])
    assert b.W == pytest.approx(a.W, rel=1e-12) and b.W_hat == pytest.approx(a.W_hat, rel=1e-12)
    assert np.allclose(a.v, b.v, atol=1e-12) and np.allclose(a.F, b.F, atol=1e-12)
