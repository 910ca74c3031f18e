"""The harmonic-balance AFT of Jenkins elements (lcpfric.harmonic, issue 39 item 2): the Fourier
conventions, the Jacobian against central differences with stick, slip and separation, the
notes' closed forms at the measured order, the small-amplitude shakedown, the d = 1 return
map's exactness for piecewise-linear input against an independent event-driven reference,
d = 2 along one axis as d = 1 and its measured order, the steady cycle, the residual's layout,
and bad input."""

import numpy as np
import pytest
import scipy.sparse

from lcpfric import memory
from lcpfric.errors import ConvergenceError, ConvergenceWarning, InputError
from lcpfric.harmonic import fourier_basis, jenkins_aft, jenkins_march, jenkins_residual
from support import fitted_order
from support.jenkins_events import reference_cycle

STICK, FORWARD, BACKWARD, SEPARATION = 0, 1, 2, 3


def closed_forms(a, kt, slip_force):
    """The notes' Jenkins element, x = a cos τ, constant N: (k_eq, ω c_eq, W)."""
    tau = np.arccos(1.0 - 2.0 * slip_force / (kt * a))
    k_eq = kt / np.pi * (tau - np.sin(2.0 * tau) / 2.0)
    wc_eq = 4.0 * slip_force / (np.pi * a) * (1.0 - slip_force / (kt * a))
    return k_eq, wc_eq, 4.0 * slip_force * (a - slip_force / kt)


# -- the Fourier conventions ---------------------------------------------------------------------
def test_fourier_conventions():
    rng = np.random.default_rng(0)
    b = fourier_basis(3, 16)
    c = rng.normal(size=7)
    tau = b.angles
    x = c[0] + sum(c[2 * h - 1] * np.cos(h * tau) + c[2 * h] * np.sin(h * tau) for h in (1, 2, 3))
    assert np.allclose(b.to_samples(c), x, rtol=0, atol=1e-14)
    assert np.allclose(b.D @ b.E, np.eye(7), rtol=0, atol=1e-14)
    assert np.allclose(b.to_coefficients(x), c, rtol=0, atol=1e-14)
    assert np.allclose(tau, 2 * np.pi * np.arange(16) / 16)
    with pytest.raises(InputError) as err:
        fourier_basis(3, 6)
    assert err.value.parameter == "samples" and "2H" in str(err.value)


# -- the Jacobian --------------------------------------------------------------------------------
def _case(d, normal, seed, n=24, H=4):
    rng = np.random.default_rng(seed)
    K = 2 * H + 1
    X = rng.normal(size=(n, d, K)) / np.arange(1, K + 1) ** 0.5
    Nc = rng.normal(size=(n, K)) * 0.6
    Nc[:, 0] = 0.3
    kw = dict(normal_load=Nc) if normal == "load" else dict(normal_displacement=Nc, kn=2.0)
    if normal == "displacement":
        kw["preload"] = 0.2
    return X, Nc, kw


def _vector(r, normal):
    f = r.tangential_force.reshape(r.tangential_force.shape[0], -1)
    return f if normal == "load" else np.concatenate([f, r.normal_force], axis=1)


@pytest.mark.parametrize("d", [1, 2])
@pytest.mark.parametrize("normal", ["load", "displacement"])
def test_jacobian_matches_central_differences(d, normal):
    """Random 4-harmonic inputs with stick, slip and separation; no event within the step of a
    sample (the perturbed cycles keep every sample's state), so the differences see one piece."""
    X, Nc, kw = _case(d, normal, seed=11 + d)
    opts = dict(kt=1.3, mu=0.4, tol=1e-15 if d == 1 else 1e-14)
    r = jenkins_aft(X, 128, **opts, **kw)
    assert {STICK, SEPARATION} <= set(np.unique(r.state)) and (r.state == FORWARD).any()
    n, _, K = X.shape
    m = (d + (normal == "displacement")) * K
    assert r.jacobian.shape == (n, m, m)
    h = 1e-6 if d == 1 else 1e-5
    fd = np.zeros_like(r.jacobian)
    for j in range(m):
        for sign in (1.0, -1.0):
            Xp, Np = X.copy(), Nc.copy()
            if j < d * K:
                Xp[:, j // K, j % K] += sign * h
            else:
                Np[:, j - d * K] += sign * h
            kwp = dict(kw, **{"normal_load" if normal == "load" else "normal_displacement": Np})
            rp = jenkins_aft(Xp, 128, **opts, **kwp, jacobian=False)
            assert np.array_equal(rp.state, r.state)  # no event within the step
            fd[:, :, j] += sign * _vector(rp, normal) / (2 * h)
    scale = np.abs(fd).max(axis=(1, 2))
    rel = np.abs(fd - r.jacobian).max(axis=(1, 2)) / scale
    assert rel.max() < 1e-6, rel.max()


@pytest.mark.parametrize("d", [1, 2])
def test_jacobian_of_a_shaken_down_element(d):
    """Elements that stick in their steady cycle after slips before it: the slider is the limit
    of the sample it touches (its normal part follows x and N there), not a constant."""
    rng = np.random.default_rng(21)
    n, K = 12, 7
    X = rng.normal(size=(n, d, K)) * 0.05
    U = rng.normal(size=(n, K)) * 0.02
    slider = rng.choice([-1.0, 1.0], size=(n, d)) * rng.uniform(1, 3, (n, d))  # far outside
    opts = dict(normal_displacement=U, kn=2.0, preload=1.0, slider=slider, tol=1e-15)
    r = jenkins_aft(X, 64, 1.0, 0.3, **opts)
    assert (r.state == STICK).all() and (r.slider != slider).all(axis=1).all()
    m = (d + 1) * K
    h, fd = 1e-6, np.zeros((n, m, m))
    for j in range(m):
        for sign in (1.0, -1.0):
            Xp, Up = X.copy(), U.copy()
            if j < d * K:
                Xp[:, j // K, j % K] += sign * h
            else:
                Up[:, j - d * K] += sign * h
            rp = jenkins_aft(Xp, 64, 1.0, 0.3, **dict(opts, normal_displacement=Up), jacobian=False)
            fd[:, :, j] += sign * _vector(rp, "displacement") / (2 * h)
    assert np.abs(fd - r.jacobian).max() < 1e-6 * np.abs(fd).max()
    assert np.abs(r.jacobian - np.eye(m)[None] * np.r_[np.ones(d * K), np.zeros(K)]).max() > 0.1


# -- the notes' closed forms ---------------------------------------------------------------------
KT, MU, N0 = 1.0, 0.5, 1.0
FS = MU * N0


@pytest.mark.parametrize("ratio", [1.5, 6.0, 200.0])
def test_constant_load_approaches_the_closed_forms_at_second_order(ratio):
    """x = a cos τ: k_eq = a1/a and ω c_eq = -b1/a (the in-phase and quadrature first
    harmonics of T) approach the notes' forms at order 2 in the samples (measured 1.9 to 2.2:
    the trapezoidal DFT across the slip onset's kink); W is exact whenever the turning points are
    samples, and otherwise is ``4 Fs (A_s - Fs/kt)`` with A_s the samples' half-range, exactly:
    order 2, under ``4 Fs a (1 - cos(π/Ns))``."""
    a = ratio * FS / KT
    k_eq, wc_eq, W = closed_forms(a, KT, FS)
    steps = [64, 128, 256, 512, 1024, 2048]
    err_k, err_c = [], []
    for ns in steps:
        r = jenkins_aft([[0.0, a, 0.0]], ns, KT, MU, normal_load=N0, jacobian=False)
        a1, b1 = r.tangential_force[0, 0, 1:3]
        err_k.append(abs(a1 / a - k_eq) / KT)
        err_c.append(abs(-b1 / a - wc_eq) / KT)
        assert r.dissipation[0] == pytest.approx(W, rel=1e-12)  # turning points sampled
        # a phase that puts no sample on a turning point
        phi = 0.3
        r = jenkins_aft(
            [[0.0, a * np.cos(phi), -a * np.sin(phi)]], ns, KT, MU, normal_load=N0, jacobian=False
        )
        x = r.basis.to_samples([0.0, a * np.cos(phi), -a * np.sin(phi)])
        half_range = 0.5 * (x.max() - x.min())
        assert r.dissipation[0] == pytest.approx(4 * FS * (half_range - FS / KT), rel=1e-12)
        assert 0 < W - r.dissipation[0] <= 4 * FS * a * (1 - np.cos(np.pi / ns)) * (1 + 1e-9)
    assert fitted_order(steps, err_k) > 1.7 and fitted_order(steps, err_c) > 1.7
    assert max(err_k[-1], err_c[-1]) < 5e-6


def test_small_amplitude_sticks_where_its_history_left_it():
    """a + |s0| < μN/kt: the element sticks from the start, T = kt (x - s0): k_eq = kt,
    c_eq = 0, W = 0, the mean force -kt s0; a slider beyond the limit is carried to it once
    and then sticks (shakedown); the Jacobian is kt I (the slider is history)."""
    a = 0.4 * FS / KT
    for s0 in (0.0, 0.3 * FS / KT, -0.5 * FS / KT):
        r = jenkins_aft([[0.0, a, 0.0]], 64, KT, MU, normal_load=N0, slider=s0)
        c0, a1, b1 = r.tangential_force[0, 0, :3]
        assert a1 / a == pytest.approx(KT, rel=1e-13) and abs(b1) < 1e-15
        assert c0 == pytest.approx(-KT * s0, abs=1e-15)
        assert r.dissipation[0] == 0.0 and (r.state == STICK).all() and r.periods[0] == 1
        assert np.allclose(r.jacobian[0], KT * np.eye(3), rtol=0, atol=1e-14)
    r = jenkins_aft([[0.0, a, 0.0]], 64, KT, MU, normal_load=N0, slider=5.0)
    assert r.dissipation[0] == 0.0 and abs(r.tangential_force[0, 0, 2]) < 1e-15
    # carried down to the limit at the displacement's minimum, then stuck there
    assert r.slider[0, 0] == pytest.approx(-a + FS / KT) and r.periods[0] == 2


# -- the d = 1 return map is exact for piecewise-linear input ------------------------------------
def _random_polygons(seed, count):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        ns = int(rng.integers(5, 60))
        tau = 2 * np.pi * np.arange(ns) / ns
        x = rng.normal() * np.cos(tau + rng.uniform(0, 6)) * rng.uniform(0.2, 3)
        x = x + rng.normal(size=ns) * rng.uniform(0, 1)
        N = rng.uniform(-0.5, 1.5) + rng.uniform(0, 1.5) * np.sin(tau + rng.uniform(0, 6))
        yield x, N, rng.uniform(0.5, 2), rng.uniform(0.1, 0.8), rng.normal()


def test_d1_is_exact_for_piecewise_linear_input_against_an_event_driven_reference():
    """200 random polygons (varying N, separation, re-contact, random starts): the forces at the
    samples, the states and W of the event-driven reference, to rounding."""
    seen = set()
    for x, N, kt, mu, s0 in _random_polygons(3, 200):
        ref = reference_cycle(x, N, kt, mu, slider=s0)
        c = jenkins_march(x[None], N[None], kt, mu, slider=s0)
        scale = kt * np.abs(x).max()
        assert np.abs(c.force[0, 0] - ref["force"]).max() <= 1e-13 * scale
        assert abs(c.dissipation[0] - ref["W"]) <= 1e-13 * scale * np.abs(x).max()
        assert np.array_equal(c.state[0], ref["state"])
        assert c.periods[0] <= 2 and c.converged[0]
        seen |= set(ref["state"].tolist())
        if (N <= 0).any() and (N > 0).any():
            seen.add("re-contact")
    assert seen == {STICK, FORWARD, BACKWARD, SEPARATION, "re-contact"}


def test_d1_subdividing_the_polygon_changes_nothing_but_d2_converges_at_first_order():
    """The same polygon sampled 7 times finer: in d = 1 the forces at the original samples and W
    are the same to rounding (the return map is exact on each interval); in d = 2 (radial
    return) they are not, and the error falls like 1/Ns (measured order 0.9 to 0.96 from 128
    to 1024 samples, 0.8 from 32)."""
    b = fourier_basis(3, 48)
    rng = np.random.default_rng(4)
    X = rng.normal(size=(6, 2, 7))
    Nc = rng.normal(size=(6, 7)) * 0.5
    Nc[:, 0] = 0.6

    def subdivided(xs, Ns, m):
        t = np.arange(xs.shape[-1] * m) / m
        i0 = np.floor(t).astype(int)
        i1, f = (i0 + 1) % xs.shape[-1], t - i0
        return xs[..., i0] * (1 - f) + xs[..., i1] * f, Ns[..., i0] * (1 - f) + Ns[..., i1] * f

    # the polygon of the clipped normal load (separation included) is the input of the claim
    x, N = b.to_samples(X[:, 0]), np.maximum(b.to_samples(Nc), 0.0)
    assert (N == 0).any()
    one = jenkins_march(x, N, 1.0, 0.5)
    xs, Ns = subdivided(x, N, 7)
    fine = jenkins_march(xs, Ns, 1.0, 0.5)
    assert np.abs(fine.force[..., ::7] - one.force).max() < 1e-13
    assert np.allclose(fine.dissipation, one.dissipation, rtol=1e-13, atol=0)
    # d = 2: the error against the same polygon subdivided 32 times, as Ns grows
    errors, steps = [], [128, 256, 512]
    for ns in steps:
        b = fourier_basis(3, ns)
        x, N = b.to_samples(X[:1]), np.maximum(b.to_samples(Nc[:1]), 0.0)
        coarse = jenkins_march(x, N, 1.0, 0.5, tol=1e-14)
        ref = jenkins_march(*subdivided(x, N, 32), 1.0, 0.5, tol=1e-14)
        errors.append(np.abs(ref.force[..., ::32] - coarse.force).max())
    assert 0.8 < fitted_order(steps, errors) < 1.2


def test_d2_along_one_axis_is_d1():
    rng = np.random.default_rng(8)
    X1 = rng.normal(size=(30, 9))
    Nc = rng.normal(size=(30, 9)) * 0.5
    Nc[:, 0] = 0.4
    e = np.array([np.cos(0.7), np.sin(0.7)])
    one = jenkins_aft(X1, 64, 1.2, 0.3, normal_displacement=Nc, kn=1.5)
    two = jenkins_aft(
        e[None, :, None] * X1[:, None, :], 64, 1.2, 0.3, normal_displacement=Nc, kn=1.5
    )
    assert np.abs(two.tangential_force - e[None, :, None] * one.tangential_force).max() < 1e-13
    assert np.allclose(two.dissipation, one.dissipation, rtol=1e-12, atol=1e-14)
    slip = np.isin(one.state, (FORWARD, BACKWARD))
    assert np.array_equal(two.state, np.where(slip, FORWARD, one.state))
    K = 9
    J2 = two.jacobian
    along = sum(e[i] * e[j] * J2[:, i * K : (i + 1) * K, j * K : (j + 1) * K] for i in range(2)
                for j in range(2))  # fmt: skip
    assert np.abs(along - one.jacobian[:, :K, :K]).max() < 1e-12
    normal = sum(e[i] * J2[:, i * K : (i + 1) * K, 2 * K :] for i in range(2))
    assert np.abs(normal - one.jacobian[:, :K, K:]).max() < 1e-12
    assert np.array_equal(J2[:, 2 * K :, 2 * K :], one.jacobian[:, K:, K:])
    assert not J2[:, 2 * K :, : 2 * K].any()


# -- the steady cycle ----------------------------------------------------------------------------
def test_d1_is_steady_after_one_period_and_the_cap_is_reported():
    rng = np.random.default_rng(2)
    X = rng.normal(size=(2000, 11))
    Nc = rng.normal(size=(2000, 11)) * 0.5
    Nc[:, 0] = 0.5
    r = jenkins_aft(X, 256, 1.0, 0.4, normal_load=Nc, jacobian=False, tol=0.0)
    assert r.converged.all() and r.periods.max() == 2
    X2 = rng.normal(size=(50, 2, 5))
    with pytest.raises(ConvergenceError) as err:
        jenkins_aft(X2, 32, 1.0, 0.4, normal_load=1.0, max_periods=1)
    assert "50 of 50 elements" in str(err.value) and "max_periods=1" in str(err.value)
    with pytest.warns(ConvergenceWarning, match="max_periods=1"):
        r = jenkins_aft(X2, 32, 1.0, 0.4, normal_load=1.0, max_periods=1, on_nonconvergence="warn")
    assert not r.converged.any()
    r = jenkins_aft(X2, 32, 1.0, 0.4, normal_load=1.0)
    assert r.converged.all() and r.periods.max() > 2


def test_d2_newton_steps_reach_the_plain_periods_fixed_point():
    """The d = 2 period map with Newton steps from the second period: few periods, the same
    steady slider as plain periods (to the tolerance) where those need many."""
    from lcpfric.harmonic.march import march_d2

    rng = np.random.default_rng(1)
    n, ns, H = 3000, 128, 3
    b = fourier_basis(H, ns)
    X = rng.normal(size=(n, 2, 2 * H + 1))
    X[:, :, 1:] /= np.repeat(np.arange(1, H + 1), 2)
    X *= np.exp(rng.uniform(-1, 4, n))[:, None, None]
    x = np.ascontiguousarray(np.moveaxis(b.to_samples(X), 2, 0))
    r = np.full((ns, n), 0.5)
    plain = march_d2(x, r, np.zeros((n, 2)), 2000, 1e-12, accelerate=False)
    fast = march_d2(x, r, np.zeros((n, 2)), 2000, 1e-12)
    assert plain[2].max() >= 30 and fast[2].max() <= 8
    # plain periods stop within tol of their own start, the fixed point is further: 1e-10
    span = np.abs(x).max(axis=(0, 2)) + 0.5
    assert (np.abs(fast[1] - plain[1]).max(axis=1) <= 1e-10 * span).all()


# -- the residual's layout -----------------------------------------------------------------------
def test_residual_layout_and_block_diagonal_jacobian():
    rng = np.random.default_rng(6)
    n, H, K = 5, 2, 5
    Q = rng.normal(size=(n, 3, K))
    Q[:, 2, 0] = 0.2
    f, J = jenkins_residual(Q.ravel(), H, 16, 1.0, 0.3, directions=2, kn=2.0, preload=0.5)
    r = jenkins_aft(Q[:, :2], 16, 1.0, 0.3, normal_displacement=Q[:, 2], kn=2.0, preload=0.5)
    expect = np.concatenate([r.tangential_force, r.normal_force[:, None]], axis=1)
    assert np.array_equal(f, expect.ravel())
    assert scipy.sparse.issparse(J) and J.shape == (n * 3 * K, n * 3 * K)
    assert np.array_equal(J.toarray(), scipy.linalg.block_diag(*r.jacobian))
    f1, B = jenkins_residual(Q[:, 0].ravel(), H, 16, 1.0, 0.3, normal_load=1.0, blocks=True)
    r1 = jenkins_aft(Q[:, 0], 16, 1.0, 0.3, normal_load=1.0)
    assert np.array_equal(f1, r1.tangential_force.ravel()) and np.array_equal(B, r1.jacobian)


# -- bad input -----------------------------------------------------------------------------------
GOOD = dict(tangential=[[0.0, 1.0, 0.0]], samples=8, kt=1.0, mu=0.3, normal_load=1.0)


@pytest.mark.parametrize(
    "change, parameter",
    [
        (dict(kt=0.0), "kt"),
        (dict(kt=-1.0), "kt"),
        (dict(mu=-0.1), "mu"),
        (dict(mu=float("nan")), "mu"),
        (dict(tangential=[[0.0, float("nan"), 0.0]]), "tangential"),
        (dict(tangential=[[0.0, 1.0]]), "tangential"),
        (dict(tangential=np.zeros((1, 3, 3))), "tangential"),
        (dict(samples=2), "samples"),
        (dict(samples=8.5), "samples"),
        (dict(normal_load=float("inf")), "normal_load"),
        (dict(normal_load=[[1.0, 0.0]]), "normal_load"),
        (dict(normal_load=None, normal_displacement=0.1, kn=-1.0), "kn"),
        (dict(normal_load=None, normal_displacement=0.1), "kn"),
        (dict(normal_displacement=0.1, kn=1.0), "normal_load"),
        (dict(slider=[1.0, 2.0]), "slider"),
        (dict(max_periods=0), "max_periods"),
        (dict(tol=-1.0), "tol"),
        (dict(on_nonconvergence="maybe"), "on_nonconvergence"),
    ],
)
def test_bad_input_names_the_parameter(change, parameter):
    args = dict(GOOD, **change)
    with pytest.raises(InputError) as err:
        jenkins_aft(args.pop("tangential"), args.pop("samples"), args.pop("kt"), args.pop("mu"),
                    **args)  # fmt: skip
    assert err.value.parameter == parameter


def test_memory_is_checked_before_any_work():
    with memory.limit(1e5, "--max-memory"), pytest.raises(InputError) as err:
        jenkins_aft(np.zeros((1000, 11)), 256, 1.0, 0.3, normal_load=1.0)
    assert err.value.parameter == "tangential" and "--max-memory" in str(err.value)
