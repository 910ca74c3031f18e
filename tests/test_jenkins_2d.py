"""The d = 2 displacement-driven Jenkins element's exact steady cycle (lcpfric.exact.driven2d):
along one axis it is the d = 1 event solver's cycle; a circular motion has the closed-form
uniform rotation; the energy balance; the sampled radial-return march converges to it at order 1;
bad input named."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lcpfric.errors import ConvergenceError, InputError
from lcpfric.exact.driven import driven_cycle
from lcpfric.exact.driven2d import driven_cycle_2d
from lcpfric.harmonic import jenkins_march
from lcpfric.model import Fourier, Harmonic
from lcpfric.model.jenkins import JenkinsElement
from lcpfric.results import State

KT, MU = 2.0, 0.5
X = Fourier(0.3, (2.0, 0.7), (0.4, 1.1))
Y = Fourier(-0.2, (1.3, 0.9), (1.4, 0.3))
N_VARY = Fourier(1.0, (0.6, 0.3), (0.2, 2.0))
N_SEP = Fourier(1.0, (1.4, 0.3), (0.2, 2.0))  # separates once per cycle


def scaled(load: Fourier, c: float) -> Fourier:
    return Fourier(c * load.mean, tuple(c * a for a in load.amplitudes), load.phases, load.omega)


@pytest.mark.parametrize("normal", [N_VARY, N_SEP, Fourier(1.0, (1.5,), (0.3,))])
def test_one_axis_is_the_d1_cycle(normal):
    el = JenkinsElement(kt=KT, mu=MU, N0=1.0)
    ref = driven_cycle(el, X, normal=normal, harmonics=3)
    for x, y, comp in ((X, 0.0, 0), (0.0, X, 1)):
        cyc = driven_cycle_2d(x, y, normal, KT, MU, harmonics=3)
        assert cyc.W == pytest.approx(ref.W, rel=1e-10, abs=1e-12)
        np.testing.assert_allclose(cyc.force_cos[comp], ref.force_cos, atol=1e-10)
        np.testing.assert_allclose(cyc.force_sin[comp], ref.force_sin, atol=1e-10)
        assert np.abs(cyc.force_cos[1 - comp]).max() < 1e-12
    # along the diagonal: T_x = T_y = T/√2, the same W
    c = 1.0 / math.sqrt(2.0)
    diag = driven_cycle_2d(scaled(X, c), scaled(X, c), normal, KT, MU, harmonics=3)
    assert diag.W == pytest.approx(ref.W, rel=1e-10)
    for i in (0, 1):
        np.testing.assert_allclose(diag.force_cos[i], c * ref.force_cos, atol=1e-10)
        np.testing.assert_allclose(diag.force_sin[i], c * ref.force_sin, atol=1e-10)


@pytest.mark.parametrize("a, N, kt, mu", [(2.0, 1.0, 1.0, 1.0), (0.37, 3.0, 20.0, 0.3)])
def test_circular_motion_uniform_rotation(a, N, kt, mu):
    # T = kt (X - S), |T| = μN, S' ∥ T, S on a circle of radius r_s with X - S ⊥ S (tangent):
    # a² = r_s² + (μN/kt)²; W = μN · 2π r_s. The slider lags X; T (from S to X, tangent to the
    # slip circle) leads X by β: T·X = F a cos β = kt (a² - S·X) = F²/kt
    F = mu * N
    r_s = math.sqrt(a * a - (F / kt) ** 2)
    cyc = driven_cycle_2d(Harmonic(0.0, a, math.pi / 2), Harmonic(0.0, a, 0.0), N, kt, mu)
    assert cyc.converged and cyc.change < 1e-10
    assert cyc.W == pytest.approx(2.0 * math.pi * F * r_s, rel=1e-9)
    assert np.all(cyc.state == State.FORWARD)
    np.testing.assert_allclose(np.hypot(*cyc.T), F, rtol=1e-10)
    np.testing.assert_allclose(np.hypot(*cyc.slider), r_s, rtol=1e-9)
    # the lag: S·(X - S) = 0 (the slip circle's tangent through X)
    dot = np.sum(cyc.slider * (cyc.x - cyc.slider), axis=0)
    assert np.abs(dot).max() < 1e-9 * a * a
    # first harmonic: T = F (cos(ωt + β), sin(ωt + β)), cos β = μN/(kt a)
    cos_b, sin_b = F / (kt * a), math.sqrt(1.0 - (F / (kt * a)) ** 2)
    (Ax, Bx), (Ay, By) = cyc.first_harmonic
    np.testing.assert_allclose([Ax, Bx, Ay, By], F * np.array([cos_b, -sin_b, sin_b, cos_b]),
                               rtol=1e-9)  # fmt: skip


def test_small_circle_sticks_where_started():
    cyc = driven_cycle_2d(Harmonic(0, 0.1, math.pi / 2), Harmonic(0, 0.1, 0), 1.0, 1.0, 1.0,
                          start=(0.2, -0.3))  # fmt: skip
    assert cyc.W == 0.0 and cyc.cycles == 1
    assert np.all(cyc.state == State.STICK)
    np.testing.assert_allclose(cyc.slider[:, 0], (0.2, -0.3))


@pytest.mark.parametrize("normal", [N_VARY, N_SEP])
def test_energy_balance_and_friction_law(normal):
    cyc = driven_cycle_2d(X, Y, normal, KT, MU, harmonics=2, samples=512)
    # ∮ T·dX = W (the stored energy returns): from T's harmonics up to X's degree
    work = 0.0
    for i, ld in enumerate((X, Y)):
        for k, (amp, ph) in enumerate(zip(ld.amplitudes, ld.phases), start=1):
            c, s = amp * math.sin(ph), amp * math.cos(ph)  # ld = c cos kθ + s sin kθ
            work += math.pi * k * (s * cyc.force_cos[i, k] - c * cyc.force_sin[i, k])
    assert work == pytest.approx(cyc.W, rel=1e-9)
    assert np.all(np.hypot(*cyc.T) <= MU * cyc.N * (1 + 1e-9) + 1e-12)
    assert cyc.converged and cyc.cycles <= 5
    if normal is N_SEP:
        assert np.any(cyc.state == State.SEPARATION)
        assert np.all(cyc.T[:, cyc.state == State.SEPARATION] == 0.0)


def march_errors(ns, cyc, normal):
    th = 2.0 * np.pi * np.arange(ns) / ns
    res = jenkins_march(np.array([X(th), Y(th)])[None], normal(th)[None], KT, MU)
    T = res.force[0]
    a1 = 2.0 / ns * (T * np.cos(th)).sum(-1)
    b1 = 2.0 / ns * (T * np.sin(th)).sum(-1)
    eF = max(np.abs(a1 - cyc.force_cos[:, 1]).max(), np.abs(b1 - cyc.force_sin[:, 1]).max())
    return abs(res.dissipation[0] - cyc.W), eF


def test_march_converges_at_first_order():
    cyc = driven_cycle_2d(X, Y, N_VARY, KT, MU)
    e = np.array([march_errors(ns, cyc, N_VARY) for ns in (256, 512, 1024, 2048)])
    orders = np.log2(e[:-1] / e[1:])
    assert np.all((orders > 0.85) & (orders < 1.2)), orders


def test_bad_input_named():
    h = Harmonic(0.0, 1.0, 0.0)
    cases = [
        (dict(kt=-1.0), "kt"),
        (dict(mu=0.0), "mu"),
        (dict(mu=float("nan")), "mu"),
        (dict(harmonics=0), "harmonics"),
        (dict(samples=2), "samples"),
        (dict(start=(1.0,)), "start"),
        (dict(x="1"), "x"),
        (dict(normal=Fourier(-1.0, (0.5,), (0.0,))), "normal"),
        (dict(y=Harmonic(0.0, 1.0, 0.0, omega=1.5)), "y"),
        (dict(max_cycles=0), "max_cycles"),
    ]
    for change, name in cases:
        kw = dict(x=h, y=h, normal=1.0, kt=1.0, mu=1.0) | change
        with pytest.raises(InputError) as info:
            driven_cycle_2d(**kw)
        assert info.value.parameter == name, (change, info.value)
    with pytest.raises(ConvergenceError, match="within 1 cycles"):
        driven_cycle_2d(Harmonic(0, 2, math.pi / 2), Harmonic(0, 2, 0), 1.0, 1.0, 1.0,
                        max_cycles=1)  # fmt: skip


@pytest.mark.slow
def test_random_elements_converge():
    rng = np.random.default_rng(7)
    for _ in range(20):
        m = 3
        x = Fourier(rng.normal(), tuple(rng.uniform(0, 2, m)), tuple(rng.uniform(0, 6.3, m)))
        y = Fourier(rng.normal(), tuple(rng.uniform(0, 2, m)), tuple(rng.uniform(0, 6.3, m)))
        N = Fourier(1.0, tuple(rng.uniform(0, 0.8, 2)), tuple(rng.uniform(0, 6.3, 2)))
        cyc = driven_cycle_2d(x, y, N, rng.uniform(0.5, 5), rng.uniform(0.1, 1), harmonics=3)
        assert cyc.converged and cyc.W >= 0.0
