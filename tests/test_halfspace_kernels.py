"""The half-space's compiled kernels (lcpfric.model.continuum.halfspace_kernels, numba) against
plain computations on small arrays, the pruned FFT products against the dense influence
matrices, and a steady state against its value before the kernels."""

import math

import numpy as np
import pytest

import lcpfric
from lcpfric.model import Harmonic
from lcpfric.model.continuum import HalfSpace
from lcpfric.model.continuum import halfspace_kernels as kern
from lcpfric.model.continuum.influence import Convolution
from lcpfric.steppers.slip_memory import SlipMemory

RNG = np.random.default_rng(37)


@pytest.mark.parametrize("M", [6, 7])
def test_cerruti_product_is_A_z_plus_B_conj_z_of_minus_k(M):
    Z = RNG.standard_normal((M, M)) + 1j * RNG.standard_normal((M, M))
    A = RNG.standard_normal((M, M)) + 0j
    B = RNG.standard_normal((M, M)) + 1j * RNG.standard_normal((M, M))
    want = np.empty_like(Z)
    for i in range(M):
        for j in range(M):
            want[i, j] = A[i, j] * Z[i, j] + B[i, j] * np.conj(Z[-i % M, -j % M])
    got = Z.copy()
    kern.cerruti_product(got, A, B)
    assert np.allclose(got, want, rtol=0, atol=1e-14)


@pytest.mark.parametrize("d, ks", [(1, 0.0), (2, 0.0), (2, 0.7)])
def test_natural_map_residual(d, ks):
    n, c = 9, 0.8
    F, CF, s0 = (RNG.standard_normal((n, d)) for _ in range(3))
    delta, Qv = RNG.standard_normal(d), RNG.standard_normal(d)
    b = RNG.random(n)
    contact = np.arange(n) % 4 != 0
    ds, z, zn, slip, worst, merit, eq = kern.natural(F, CF, delta, s0, c, b, contact, Qv, ks)
    ds_ = CF + delta - s0
    z_ = F - ds_ / c
    zn_ = np.array([math.hypot(*row) for row in z_])
    slip_ = contact & (zn_ > b)
    proj = np.where(contact[:, None], z_, 0.0)
    proj[slip_] *= (b / zn_)[slip_, None]
    R = F - proj
    eq_ = F.sum(axis=0) - ks * delta + Qv
    assert np.allclose(ds, ds_, rtol=1e-15, atol=0) and np.allclose(z, z_, rtol=1e-14, atol=0)
    assert np.allclose(zn, zn_, rtol=1e-15, atol=0) and np.array_equal(slip, slip_)
    assert worst == pytest.approx(np.abs(R).max(), rel=1e-14)
    assert np.allclose(eq, eq_, rtol=1e-14, atol=1e-15)
    assert merit == pytest.approx((R * R).sum() + eq_ @ eq_, rel=1e-13)


def test_slip_memory_update_is_r_p_pT_R():
    n, c = 6, 0.3
    R = RNG.standard_normal((n, 2, 2))
    dv = RNG.standard_normal((n, 2))
    dv[2] = 0.0
    b = RNG.random(n)
    want = R.copy()
    for i in range(n):
        m = math.hypot(*dv[i])
        if m > 0.0:
            p = np.array([-dv[i, 1], dv[i, 0]]) / m
            want[i] = (c * b[i] / (c * b[i] + m)) * np.outer(p, p) @ R[i]
    SlipMemory(c, n).update(R, dv.ravel(), b)
    assert np.allclose(R, want, rtol=1e-13, atol=1e-15)
    per_node = RNG.random(n) + 0.1
    R1, R2 = RNG.standard_normal((2, n, 2, 2))
    R2[:] = R1
    SlipMemory(per_node, n).update(R1, dv.ravel(), b)
    for i in range(n):
        SlipMemory(per_node[i], 1).update(R2[i : i + 1], dv[i], b[i : i + 1])
    assert np.array_equal(R1, R2)


def test_the_newton_steps_vector_kernels():
    flat = np.zeros(20, dtype=complex)
    idx = np.array([3, 7, 11, 12, 19])
    x = RNG.standard_normal(5) + 1j * RNG.standard_normal(5)
    w = RNG.random(5)
    kern.embed(flat, idx, x, w)
    assert np.array_equal(flat[idx], x * w) and np.count_nonzero(flat) == 5
    kern.embed(flat, idx, x, np.empty(0))
    assert np.array_equal(flat[idx], x)
    ns = 2
    tau = np.exp(1j * RNG.random(3))
    scale, diag = RNG.random(3), RNG.random(3)
    got = kern.restrict2(flat, idx, ns, tau, scale, x, diag)
    t = (np.conj(tau) * flat[idx[ns:]]).real * scale
    assert np.allclose(got[:ns], flat[idx[:ns]]) and np.allclose(
        got[ns:], tau * t + diag * x[ns:], rtol=1e-15
    )
    Winv = np.linalg.inv(np.array([[3.0, 0.2], [0.2, 2.5]]))
    r = RNG.standard_normal(5) + 1j * RNG.standard_normal(5)
    lam = Winv @ np.array([r.sum().real, r.sum().imag])
    bt = np.concatenate([np.full(ns, complex(*lam)), tau * (tau.real * lam[0] + tau.imag * lam[1])])
    assert np.allclose(kern.project2(r, ns, tau, Winv), r - bt, rtol=1e-14, atol=1e-15)
    total = RNG.standard_normal((3, 3)) + 0j
    last = RNG.standard_normal((5, 5)) + 0j
    want = total + 0.3 * last[:3, :3]
    kern.add_corner(total, 0.3, last)
    assert np.allclose(total, want, rtol=1e-15)


def test_pattern_residual_of_the_d1_newton_loop():
    n, c, ks, tolF, eps = 11, 0.7, 0.4, 1e-9, np.finfo(float).eps
    F, CF, s0 = (RNG.standard_normal((n, 1)) for _ in range(3))
    delta, Qv, b = RNG.standard_normal(1), RNG.standard_normal(1), RNG.random(n)
    contact = np.arange(n) % 3 != 0
    ds, z, lo, hi, zn, worst, eq = kern.pattern_residual(
        F, CF, delta, s0, c, b, ks, Qv, tolF, eps, contact
    )
    ds_ = delta + CF - s0
    z_ = (F - ds_ / c)[:, 0]
    band = tolF + 64 * eps * (b + np.abs(F[:, 0]))
    assert np.array_equal(ds, ds_) and np.array_equal(z, z_) and np.array_equal(zn, np.abs(z_))
    assert np.array_equal(lo, -b - band) and np.array_equal(hi, b + band)
    assert worst == np.max(np.abs(F[:, 0] - np.clip(z_, -b, b))[contact])
    assert eq == pytest.approx(F.sum() - ks * delta + Qv, rel=1e-14)


def test_newton2_setup_is_the_plain_computation():
    n, c = 12, 0.6
    F, z, ds = (RNG.standard_normal((n, 2)) for _ in range(3))
    zn = np.hypot(z[:, 0], z[:, 1])
    b = 0.5 * zn * RNG.random(n) + 0.3 * RNG.random(n)
    contact = np.arange(n) % 5 != 0
    slip = contact & (zn > b)
    cpos = RNG.permutation(40)[:n]
    nodes, ns, known, tau, tdiag, idx, rhs, weights, sxx, sxy, syy, ksum = kern.newton2_setup(
        F, z, zn, ds, b, contact, slip, cpos, c
    )
    stick, L = np.flatnonzero(contact & ~slip), np.flatnonzero(slip)
    assert ns == stick.size and np.array_equal(nodes, np.r_[stick, L])
    Fc, zc = F[:, 0] + 1j * F[:, 1], z[:, 0] + 1j * z[:, 1]
    e = zc[L] / zn[L]
    known_ = np.where(contact, 0.0, -Fc)
    known_[L] = e * (b[L] - (np.conj(e) * Fc[L]).real)
    beta = b[L] / zn[L]
    tdiag_ = c * (1 - beta) / beta
    assert np.allclose(known, known_, rtol=1e-15, atol=0) and np.allclose(tau, 1j * e, rtol=1e-15)
    assert np.allclose(tdiag, tdiag_, rtol=1e-15) and np.array_equal(idx, cpos[nodes])
    rhs_ = np.r_[
        -(ds[stick, 0] + 1j * ds[stick, 1]), 1j * e * (-c / beta) * (-1j * np.conj(e) * Fc[L]).real
    ]
    assert np.allclose(rhs, rhs_, rtol=1e-14, atol=1e-15)
    assert np.allclose(weights, np.r_[np.ones(ns), np.sqrt(c / (c + tdiag_))], rtol=1e-15)
    t = 1j * e
    assert np.allclose([sxx, sxy, syy], [t.real @ t.real, t.real @ t.imag, t.imag @ t.imag])
    assert ksum == pytest.approx(known_.sum(), rel=1e-14)
    u = RNG.standard_normal(nodes.size) + 0j
    want = known.copy()
    want[nodes] += u
    assert np.array_equal(kern.add_at(known, nodes, u), want)


def test_the_d2_newton_steps_start_and_its_residual():
    N, M, ns = 3, 6, 2
    known = RNG.standard_normal(N * N) + 1j * RNG.standard_normal(N * N)
    idx = np.array([0, 7, 8, 13, 14])
    u0 = RNG.standard_normal(5) + 1j * RNG.standard_normal(5)
    buf = np.zeros((M, M), dtype=complex)
    kern.start2(buf, known, N, idx, u0)
    want = np.zeros((M, M), dtype=complex)
    want[:N, :N] = known.reshape(N, N)
    want.reshape(-1)[idx] += u0
    assert np.array_equal(buf, want)
    first = RNG.standard_normal((M, M)) + 1j * RNG.standard_normal((M, M))
    tau = np.exp(1j * RNG.random(3))
    rhs = RNG.standard_normal(5) + 1j * RNG.standard_normal(5)
    tdiag = RNG.random(3)
    res, total = kern.residual2(first, buf, N, idx, ns, tau, rhs, tdiag, u0)
    res_ = rhs - kern.restrict2(first.reshape(-1), idx, ns, tau, np.empty(0), u0[:0], tdiag[:0])
    res_[ns:] -= tdiag * u0[ns:]
    assert np.array_equal(res, res_) and np.array_equal(total, first[:N, :N])
    assert not buf[:N, :N].any() and np.array_equal(buf[N:], want[N:])


@pytest.mark.parametrize("precondition", [True, False])
def test_the_normal_problems_iteration_kernels(precondition):
    from lcpfric.model.continuum import normal_kernels as nk

    N, P, area = 8, 2.0, 0.3
    g0, u, At, zz0 = (RNG.standard_normal((N, N)) for _ in range(4))
    p = np.maximum(RNG.standard_normal((N, N)), 0.0)
    t = RNG.standard_normal((N, N))
    S = p > 0
    zz = np.empty((N, N))
    g = nk.gaps(g0, u, p, zz)
    g_ = g0 + u
    g_ -= g_[S].mean()
    assert np.allclose(g, g_, rtol=0, atol=1e-15) and np.array_equal(zz, np.where(S, g, 0.0))
    z = (zz0[S] - zz0[S].mean()) if precondition else g[S]
    t_ = t.copy()
    t_[S] = z + (g[S] @ z / 0.7) * t[S]
    t_[~S] = 0.0
    G = nk.direction(g, zz0, p, t, 0.7, False, precondition)
    assert G == pytest.approx(g[S] @ z, rel=1e-13) and np.allclose(t, t_, rtol=1e-13, atol=1e-15)
    # the step: p's update, the clipping, the entering elements and the load; then a step
    # that keeps the contact (u follows by linearity)
    for p, t in ((p, t), (1.0 + RNG.random((N, N)), 1e-3 * RNG.standard_normal((N, N)))):
        S = p > 0
        At = t * (2.0 + RNG.random((N, N)))  # a positive curvature along t
        p_, u_ = p.copy(), u.copy()
        tau = (g[S] @ t[S]) / ((At - At[S].mean())[S] @ t[S])
        p_[S] -= tau * t[S]
        clipped = p_ < 0.0
        p_[clipped] = 0.0
        enter = (p_ == 0.0) & (g < 0.0)
        p_[enter] -= tau * g[enter]
        factor = P / (area * p_.sum())
        p_ *= factor
        status, change, restart, fresh = nk.update(At, g, p_old := p.copy(), t, u, P, area)
        assert status == 1 and np.allclose(p_old, p_, rtol=1e-12, atol=1e-14)
        assert restart == enter.any() and fresh == (enter.any() or clipped.any())
        assert change == pytest.approx(area * np.abs(p_ - p).sum() / P, rel=1e-12)
        if not fresh:
            assert np.allclose(u, (u_ - tau * At) * factor, rtol=1e-12)
        else:
            assert np.array_equal(u, u_)


@pytest.mark.parametrize("d", [1, 2])
def test_an_increments_finish_projects_and_zeroes_the_sticking_slips(d):
    n = 10
    F, ds, s0, CF, CFp = (RNG.standard_normal((n, d)) for _ in range(5))
    Fp, b = RNG.standard_normal(n * d), RNG.random(n)
    contact, slip = np.arange(n) % 4 != 0, np.arange(n) % 3 == 0
    F0, ds0 = F.copy(), ds.copy()
    F_end, v, dF, dCF = kern.finish(F, ds, s0, b, contact, slip, Fp, CF, CFp)
    assert np.array_equal(F_end, F0.ravel()) and np.array_equal(dF, F0.ravel() - Fp)
    assert np.array_equal(dCF, CF - CFp)
    norm = np.hypot(F0[:, 0], F0[:, 1]) if d == 2 else np.abs(F0[:, 0])
    proj = F0 * np.where(norm > b, b / np.where(norm > 0, norm, 1), 1.0)[:, None]
    assert np.allclose(F, proj, rtol=1e-15, atol=0) and np.all(np.abs(F) <= b[:, None])
    ds0[contact & ~slip] = 0.0
    assert np.array_equal(ds, ds0) and np.array_equal(v, (s0 + ds0).ravel())


@pytest.mark.parametrize("dims, nu", [(1, 0.0), (2, 0.3), (2, 0.0)])
def test_pruned_products_equal_the_dense_influence_matrices(dims, nu):
    N = 9
    op = Convolution(N, 0.1, 1.0, nu, dims)
    q = RNG.standard_normal((N, N)) if dims == 1 else RNG.standard_normal((2, N, N))
    xx = op.dense("xx")
    if dims == 1:
        want = (xx @ q.ravel()).reshape(N, N)
    else:
        yy, xy = op.dense("yy"), op.dense("xy") if nu else 0.0 * xx
        want = np.stack(
            [
                (xx @ q[0].ravel() + xy @ q[1].ravel()).reshape(N, N),
                (xy @ q[0].ravel() + yy @ q[1].ravel()).reshape(N, N),
            ]
        )
    got = op.tangential(q)
    assert np.abs(got - want).max() <= 1e-14 * np.abs(want).max()
    p = RNG.random((N, N))  # the normal product, pruned too
    want = (op.dense("n") @ p.ravel()).reshape(N, N)
    assert np.abs(op.normal(p) - want).max() <= 1e-14 * np.abs(want).max()


@pytest.mark.parametrize("dims, nu", [(1, 0.0), (2, 0.3)])
def test_the_public_fft_fallback_gives_the_same_products(dims, nu, monkeypatch):
    """Where scipy's pocketfft bindings are missing or disagree (:func:`influence._agrees`),
    the same pruned transforms through scipy.fft's public functions."""
    from lcpfric.model.continuum import influence

    N = 9
    q = RNG.standard_normal((N, N)) if dims == 1 else RNG.standard_normal((2, N, N))
    first = Convolution(N, 0.1, 1.0, nu, dims).tangential(q)
    assert influence._agrees(influence._backend(), influence._Public())
    monkeypatch.setattr(influence, "_FFT", influence._Public())
    again = Convolution(N, 0.1, 1.0, nu, dims).tangential(q)
    assert np.abs(again - first).max() <= 1e-14 * np.abs(first).max()


@pytest.mark.parametrize(
    "dims, nu, tol, W",
    [
        # the values before the compiled kernels and the pruned products (a 12-element sphere,
        # 40 steps); d = 2 to the cycle tolerance 1e-12, whose W the default 1e-10 reaches only
        # to about 2e-11 (the cycle at which it stops moves with the round-off)
        (1, 0.0, 1e-10, 0.005005855731960353),
        (2, 0.3, 1e-12, 0.005703655382586268),
    ],
)
def test_a_steady_state_is_its_value_before_the_kernels(dims, nu, tol, W):
    model = HalfSpace.sphere(
        10.0,
        200e3,
        nu,
        0.5,
        Harmonic(100.0, 50.0, 0.0, 2 * math.pi),
        Harmonic(0.0, 20.0, 0.5 * math.pi, 2 * math.pi),
        grid=12,
        dims=dims,
    )
    r = lcpfric.steady_state(model, steps_per_cycle=40, tol=tol, max_cycles=60)
    assert r.W == pytest.approx(W, rel=1e-12)
