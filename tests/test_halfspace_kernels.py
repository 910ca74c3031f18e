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
