"""The displacement-driven Jenkins element's exact steady cycle (issue 39, item 1, d = 1): its map
onto the paper's single node, the event solver for trigonometric motions and normal loads
(lcpfric.exact.driven) against the exact single node (lcpfric.exact.jenkins_node) and against an
independent fine-sample return map (tests/support/jenkins_reference.py) at its measured order,
the starts, periodicity, and bad input."""

import math

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import ConvergenceError, InputError
from lcpfric.exact.driven import driven_cycle
from lcpfric.exact.jenkins_node import jenkins_cycle
from lcpfric.exact.trig import TrigPoly, periodic_sign_changes
from lcpfric.model import Fourier, Harmonic
from lcpfric.model.jenkins import JenkinsElement
from lcpfric.results import State
from support import fitted_order
from support.jenkins_reference import return_map_cycle

TWO_PI = 2 * math.pi


def _random_cases(n, seed):
    """Elements with constant, varying, touching (N1 = N0) and separating normal loads, amplitudes
    from a third to a hundred times the slip limit, and starts anywhere."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        N0 = rng.uniform(0.5, 2.0)
        ratio = rng.choice([0.0, rng.uniform(0.0, 0.95), 1.0, rng.uniform(1.02, 3.0)])
        el = JenkinsElement(rng.uniform(0.5, 2), rng.uniform(0.1, 1), N0, ratio * N0,
                            rng.uniform(-4, 4))  # fmt: skip
        a = el.slip_limit * 10 ** rng.uniform(-0.5, 2.0)
        yield el, a, rng.uniform(-1, 1) * a


def _difference(c1, c2, el, a):
    """The largest difference of W (over μ max N a) and of the force's harmonics and amplitude
    (over μ max N)."""
    scale = el.mu * (el.N0 + el.N1)
    return max(
        abs(c1.W - c2.W) / (scale * a),
        np.max(np.abs(c1.force_cos - c2.force_cos)) / scale,
        np.max(np.abs(c1.force_sin - c2.force_sin)) / scale,
        abs(c1.force_amplitude - c2.force_amplitude) / scale,
    )


def test_the_element_is_the_single_node():
    """k11 = kt, f = μ, P = N0 + N1 cos(ωt + φ), Q = -kt x; the node's F is -T and v is w."""
    el = JenkinsElement(kt=2.0, mu=0.3, N0=5.0, N1=2.0, phi=0.7)
    node = el.single_node(3.0, omega=2.0, x0=0.4)
    assert (node.k11, node.f, node.P0, node.P1) == (2.0, 0.3, 5.0, 2.0)
    t = np.linspace(0, node.period, 7)
    x = 0.4 + 3.0 * np.cos(2.0 * t)
    np.testing.assert_allclose(node.tangential_load(t), -2.0 * x, atol=1e-14)
    np.testing.assert_allclose(node.normal_load(t), 5.0 + 2.0 * np.cos(2.0 * t + 0.7), atol=1e-14)
    res = lcpfric.steady_state(node, "exact", steps_per_cycle=64)
    cyc = jenkins_cycle(el, 3.0, omega=2.0, x0=0.4, samples=64)
    assert cyc.W == pytest.approx(res.W, rel=1e-14)
    # the uniform samples of the cycle are the driver's instants (the events are added)
    uniform = np.isin(cyc.t, res.t)
    np.testing.assert_allclose(cyc.t[uniform], res.t, atol=1e-15)
    np.testing.assert_allclose(cyc.T[uniform], -res.F, atol=1e-13)
    np.testing.assert_allclose(cyc.w[uniform], res.v, atol=1e-13)
    np.testing.assert_array_equal(cyc.state[uniform], res.state)


def test_event_solver_agrees_with_the_exact_single_node():
    """300 random elements, amplitudes and starts (stick, slip, touching and separation): the two
    exact paths agree to 1e-12 (measured 1.2e-14 on 3000)."""
    worst = max(
        _difference(
            driven_cycle(el, el.motion(a), start=s, harmonics=3),
            jenkins_cycle(el, a, start=s, harmonics=3),
            el,
            a,
        )
        for el, a, s in _random_cases(300, seed=0)
    )
    assert worst < 1e-12


@pytest.mark.parametrize("ratio", [1e-6, 0.5, 1.0 + 1e-6, 2.0, 1e3, 1e6])
@pytest.mark.parametrize(
    ("N1", "phi"),
    [(0.0, 0.0), (1.0, math.pi), (1.0, 1.0), (1.0 + 1e-12, math.pi), (0.5, -math.pi / 2),
     (2.0, 1e-9)],
)  # fmt: skip
def test_the_two_paths_at_the_extremes(N1, phi, ratio):
    """Touching N = 0 (at t = 0 with φ = π), grazing separation, amplitudes from 1e-6 to 1e6 slip
    limits: the two exact paths agree to 1e-12. (Regressions: a touch at t = 0 was taken for a
    whole cycle of separation; at 1e6 slip limits a start 5e-13 of a off the orbit was taken for
    periodic.)"""
    el = JenkinsElement(1.0, 1.0, 1.0, N1, phi)
    a = ratio * el.slip_limit
    for start in (None, 0.3 * a):
        one = driven_cycle(el, el.motion(a), start=start, harmonics=2)
        two = jenkins_cycle(el, a, start=start, harmonics=2)
        assert _difference(one, two, el, a) < 1e-12


@pytest.mark.slow
def test_event_solver_agrees_with_the_exact_single_node_many():
    worst = max(
        _difference(
            driven_cycle(el, el.motion(a), start=s, harmonics=3),
            jenkins_cycle(el, a, start=s, harmonics=3),
            el,
            a,
        )
        for el, a, s in _random_cases(3000, seed=1)
    )
    assert worst < 1e-12


@pytest.mark.parametrize("start", [-0.3, 0.0, 0.1, 0.3])
def test_a_shakedown_keeps_the_start(start):
    """Below the slip limit the slider ends where the start's first cycle leaves it:
    clip(w0, max lo, min hi) = clip(w0, a - Fs/kt, Fs/kt - a); W = 0, k_eq = kt."""
    el = JenkinsElement(kt=1.0, mu=1.0, N0=1.0)
    a = 0.8
    want = min(max(start, a - 1.0), 1.0 - a)
    for cyc in (jenkins_cycle(el, a, start=start), driven_cycle(el, el.motion(a), start=start)):
        assert cyc.W == 0.0
        assert {s[2] for s in cyc.segments} == {State.STICK}
        assert cyc.w[0] == pytest.approx(want, abs=1e-15)
        assert cyc.force_cos[0] == pytest.approx(-want, abs=1e-15)  # mean force kt (0 - w)
        assert cyc.first_harmonic == pytest.approx((a, 0.0), abs=1e-15)
        assert cyc.force_amplitude == pytest.approx(a + abs(want), abs=1e-15)


def test_multi_harmonic_cycle_against_the_return_map():
    """Three harmonics of x, two of N (with separation): the fine-sample return map converges to
    the exact cycle at second order (error x n² bounded; fitted order measured 1.9 to 2.1)."""
    el = JenkinsElement(kt=1.3, mu=0.6, N0=1.0)
    x = Fourier(0.1, (2.0, 0.7, 0.3), (0.4, 1.1, -0.5), 1.0)
    for normal in (Fourier(1.0, (0.4, 0.3), (0.2, 2.0), 1.0),
                   Fourier(1.0, (1.4, 0.5), (0.2, 2.0), 1.0)):  # fmt: skip
        cyc = driven_cycle(el, x, normal=normal, harmonics=3, start=0.3)
        if normal.amplitudes[0] > 1:
            assert State.SEPARATION in {s[2] for s in cyc.segments}
        steps = [1000, 2000, 4000, 8000, 16000]
        errors = []
        for n in steps:
            ref = return_map_cycle(el.kt, el.mu, x, normal, TWO_PI, n, start=0.3, harmonics=3)
            errors.append(
                max(
                    abs(ref["W"] - cyc.W),
                    np.max(np.abs(ref["force_cos"] - cyc.force_cos)),
                    np.max(np.abs(ref["force_sin"] - cyc.force_sin)),
                )
            )
        assert max(e * n * n for e, n in zip(errors, steps)) < 100.0
        assert fitted_order(steps, errors) > 1.7
        assert errors[-1] < 1e-6


def test_energy_identities():
    """W = ∮ T dw (the slips) = ∮ T dx (trapezoid on a fine series, second order), and for a
    harmonic motion W = -π a B1 exactly."""
    el = JenkinsElement(kt=1.0, mu=0.8, N0=1.0, N1=1.5, phi=0.9)
    cyc = driven_cycle(el, el.motion(2.5), samples=200000)
    loop = float(np.sum(0.5 * (cyc.T[1:] + cyc.T[:-1]) * np.diff(cyc.x)))
    assert loop == pytest.approx(cyc.W, rel=1e-8)
    assert -math.pi * 2.5 * cyc.first_harmonic[1] == pytest.approx(cyc.W, rel=1e-13)


def test_periodicity_is_confirmed():
    """A start away from the orbit takes more than one cycle; the cycle's start then repeats; one
    cycle allowed is not enough and says so."""
    el = JenkinsElement(kt=1.0, mu=1.0, N0=1.0, N1=0.4, phi=1.0)
    x = Fourier(0.0, (3.0, 1.0), (0.5, 0.2), 1.0)
    start = float(x(0.0))  # T(0) = 0: inside the interval at t = 0, off the orbit
    cyc = driven_cycle(el, x, start=start)
    assert cyc.converged and cyc.cycles >= 2 and cyc.change <= 1e-12
    assert cyc.w[0] == pytest.approx(cyc.w[-1], abs=1e-13)
    assert cyc.w[0] != pytest.approx(start, abs=1e-3)
    with pytest.raises(ConvergenceError, match="max_cycles"):
        driven_cycle(el, x, start=start, max_cycles=1)


def test_the_series_and_states():
    el = JenkinsElement(kt=1.0, mu=1.0, N0=1.0, N1=2.0, phi=0.0)
    cyc = jenkins_cycle(el, 3.0, samples=100)
    assert cyc.t[0] == 0.0 and cyc.t[-1] == pytest.approx(TWO_PI)
    assert np.all(np.diff(cyc.t) > 0)
    assert np.all(np.isin(cyc.events, cyc.t))
    assert np.all(np.abs(cyc.T) <= el.mu * cyc.N + 1e-12)
    sep = cyc.state == State.SEPARATION
    assert sep.any() and np.all(cyc.T[sep] == 0.0) and np.all(cyc.N[sep] == 0.0)
    fwd, bwd = cyc.state == State.FORWARD, cyc.state == State.BACKWARD
    np.testing.assert_allclose(cyc.T[fwd], el.mu * cyc.N[fwd], atol=1e-14)
    np.testing.assert_allclose(cyc.T[bwd], -el.mu * cyc.N[bwd], atol=1e-14)
    np.testing.assert_allclose(cyc.T, el.kt * (cyc.x - cyc.w), atol=1e-13)


def test_normal_spring_and_normal_displacement():
    """kn and un1 give N1 = kn un1; a normal displacement u_n(t) with kn is N0 + kn u_n."""
    a = JenkinsElement(1.0, 0.5, 2.0, kn=4.0, un1=0.3, phi=0.4)
    b = JenkinsElement(1.0, 0.5, 2.0, N1=1.2, phi=0.4)
    assert a.N1 == pytest.approx(1.2)
    assert jenkins_cycle(a, 3.0).W == pytest.approx(jenkins_cycle(b, 3.0).W, rel=1e-15)
    un = Fourier(0.05, (0.3, 0.1), (0.4 + math.pi / 2, 1.0), 1.0)
    N = Fourier(2.0 + 4.0 * 0.05, (1.2, 0.4), (0.4 + math.pi / 2, 1.0), 1.0)
    c1 = driven_cycle(a, a.motion(3.0), normal=un, harmonics=2)
    c2 = driven_cycle(b, b.motion(3.0), normal=N, harmonics=2)
    assert c1.W == pytest.approx(c2.W, rel=1e-14)
    np.testing.assert_allclose(c1.force_cos, c2.force_cos, atol=1e-14)


def test_no_friction_carries_no_force():
    el = JenkinsElement(1.0, 0.0, 1.0)
    cyc = driven_cycle(el, el.motion(2.0))
    assert cyc.W == 0.0 and cyc.force_amplitude == 0.0 and np.all(cyc.T == 0.0)
    with pytest.raises(InputError, match="^mu: "):
        el.single_node(2.0)


def test_frequencies_of_the_loads():
    """A normal load at twice the motion's frequency is a harmonic of it; a ratio that is not
    whole is refused by name."""
    el = JenkinsElement(1.0, 1.0, 1.0)
    x = Harmonic(0.0, 3.0, 0.0, 1.0)
    cyc = driven_cycle(el, x, normal=Harmonic(1.0, 0.5, 0.0, 2.0))
    assert cyc.omega == 1.0 and cyc.W > 0
    with pytest.raises(InputError, match="^normal: "):
        driven_cycle(el, x, normal=Harmonic(1.0, 0.5, 0.0, 1.5))


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        (dict(kt=0.0, mu=1.0, N0=1.0), "kt"),
        (dict(kt=-1.0, mu=1.0, N0=1.0), "kt"),
        (dict(kt=1.0, mu=-0.1, N0=1.0), "mu"),
        (dict(kt=1.0, mu=float("nan"), N0=1.0), "mu"),
        (dict(kt=1.0, mu=1.0, N0=0.0), "N0"),
        (dict(kt=1.0, mu=1.0, N0=1.0, N1=-1.0), "N1"),
        (dict(kt=1.0, mu=1.0, N0=1.0, phi=float("inf")), "phi"),
        (dict(kt=1.0, mu=1.0, N0=1.0, kn=0.0, un1=1.0), "kn"),
        (dict(kt=1.0, mu=1.0, N0=1.0, un1=1.0), "un1"),
        (dict(kt=1.0, mu=1.0, N0=1.0, N1=0.5, kn=1.0, un1=1.0), "un1"),
    ],
)
def test_bad_elements_are_refused_by_name(kwargs, name):
    with pytest.raises(InputError, match=f"^{name}: "):
        JenkinsElement(**kwargs)


def test_bad_motions_are_refused_by_name():
    el = JenkinsElement(1.0, 1.0, 1.0)
    for amplitude in (0.0, -1.0, float("nan")):
        with pytest.raises(InputError, match="^amplitude: "):
            el.motion(amplitude)
        with pytest.raises(InputError, match="^amplitude: "):
            jenkins_cycle(el, amplitude)
    with pytest.raises(InputError, match="^motion: "):
        driven_cycle(el, 3.0)
    with pytest.raises(InputError, match="^harmonics: "):
        driven_cycle(el, el.motion(1.0), harmonics=0)
    with pytest.raises(InputError, match="^start: "):
        driven_cycle(el, el.motion(1.0), start=float("nan"))
    with pytest.raises(InputError, match="^normal: "):
        driven_cycle(el, el.motion(1.0), normal=Fourier(-1.0, (0.5,), (0.0,), 1.0))


def test_every_sign_change_of_a_trigonometric_polynomial():
    """60 random trigonometric polynomials of degree 1 to 6: the roots found are every sign change a
    fine grid shows, refined to round-off."""
    rng = np.random.default_rng(3)
    grid = np.linspace(0, TWO_PI, 100001)
    for _ in range(60):
        h = int(rng.integers(1, 7))
        f = TrigPoly(rng.normal(size=h + 1) * 0.5, rng.normal(size=h + 1))
        roots, dirs = periodic_sign_changes(f)
        v = f(grid)
        seen = np.count_nonzero(np.sign(v[1:]) != np.sign(v[:-1]))
        assert roots.size == seen
        scale = np.sum(np.abs(f.cos)) + np.sum(np.abs(f.sin))
        assert np.all(np.abs(f(roots)) <= 1e-14 * scale)
        assert np.all(np.sign(f.derivative()(roots)) == dirs)
