"""Matrix-free systems: a compliance known only by its products (here a Toeplitz compliance
applied by FFT, :func:`scipy.linalg.matmul_toeplitz`), solved by the active-set backend's
compliance form with conjugate gradients, against the same system given as a matrix."""

import numpy as np
import pytest

from support import need
from scipy.linalg import matmul_toeplitz, toeplitz
from scipy.sparse.linalg import LinearOperator, aslinearoperator

import lcpfric
from lcpfric.errors import InputError, SolverError
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings


def kernel(n, length=3.0):
    """First column of an SPD Toeplitz compliance: exp(-|i - j| / length) (a positive
    definite kernel in 1-D) plus the identity."""
    c = np.exp(-np.arange(n) / length)
    c[0] += 1.0
    return c


def fft_operator(c):
    n = c.size
    return LinearOperator((n, n), matvec=lambda x: matmul_toeplitz(c, x), dtype=float)


def loads(n, seed=0, sep=True):
    rng = np.random.default_rng(seed)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    Q1, phi = rng.uniform(0.5, 2.0, n), rng.uniform(0, 2 * np.pi, n)
    return (
        tuple(Harmonic(0.0, Q1[i], phi[i]) for i in range(n)),
        IndependentSprings(tuple(Harmonic(1.0, P1[i]) for i in range(n))),
    )


def pair(n=30, sep=True, seed=0):
    """The same system matrix-free (FFT products) and with its stiffness K = C⁻¹."""
    c = kernel(n)
    Q, normal = loads(n, seed, sep)
    free = ContactSystem(None, np.ones(n), Q, normal, compliance=fft_operator(c))
    K = np.linalg.inv(toeplitz(c))
    dense = ContactSystem(0.5 * (K + K.T), np.ones(n), Q, normal)
    return free, dense


@pytest.mark.slow
@pytest.mark.parametrize("sep", [True, False], ids=["separation", "contact"])
@pytest.mark.parametrize("events", [False, True])
def test_matrix_free_equals_the_matrix(sep, events):
    """Cycle by cycle the same increments: W of each of the first cycles, and the last one."""
    free, dense = pair(sep=sep)
    run = dict(tol=1e-12, locate_events=events, max_cycles=3, on_nonconvergence="ignore")
    a = lcpfric.steady_state(free, "active-set", 150, **run)
    b = lcpfric.steady_state(dense, "active-set", 150, **run)
    np.testing.assert_allclose(a.W_cycles, b.W_cycles, rtol=1e-10)
    np.testing.assert_allclose(a.v, b.v, atol=1e-9 * np.ptp(b.v))
    stats = a.solver_stats
    assert stats["products"] > 0 and stats["cg_iterations"] > 0
    assert stats["max_residual"] < 1e-10
    assert events == (stats["events"] > 0)


def test_small_matrix_free_with_convex_backends_and_start():
    """Up to 2000 unknowns the other methods form C from its products; a start u0 is turned
    into forces by conjugate gradients."""
    need("osqp")
    free, dense = pair(n=12)
    a = lcpfric.steady_state(free, "osqp", 150, tol=1e-12)
    b = lcpfric.steady_state(dense, "osqp", 150, tol=1e-12)
    assert a.W == pytest.approx(b.W, rel=1e-10)
    # a start admissible at t = 0 (the driver checks it): forces inside the cone, varied
    Q0, b = dense.tangential(0.0), dense.normal.reactions(0.0)
    u0 = dense.solve(np.linspace(-0.6, 0.7, 12) * b - Q0)
    a = lcpfric.steady_state(
        free, "active-set", 150, tol=1e-12, u0=u0, max_cycles=1, on_nonconvergence="ignore"
    )
    b = lcpfric.steady_state(
        dense, "active-set", 150, tol=1e-12, u0=u0, max_cycles=1, on_nonconvergence="ignore"
    )
    assert a.W == pytest.approx(b.W, rel=1e-10)
    np.testing.assert_allclose(free.stiffness_times(u0), dense.stiffness @ u0, atol=1e-12)


def test_matrix_free_errors():
    n = 10
    Q, normal = loads(n)
    with pytest.raises(InputError, match="compliance="):
        ContactSystem(None, np.ones(n), Q, normal)
    with pytest.raises(InputError, match="must be 10 x 10"):
        ContactSystem(None, np.ones(n), Q, normal, compliance=np.eye(11))
    A = np.eye(n)
    A[0, 1] = 0.5
    with pytest.raises(InputError, match="symmetric"):
        ContactSystem(None, np.ones(n), Q, normal, compliance=A)
    with pytest.raises(InputError, match="positive definite"):
        ContactSystem(None, np.ones(n), Q, normal, compliance=-np.eye(n))
    nan = LinearOperator((n, n), matvec=lambda x: np.full(n, np.nan), dtype=float)
    with pytest.raises(InputError, match="finite"):
        ContactSystem(None, np.ones(n), Q, normal, compliance=nan)
    free, _ = pair(n=8)
    with pytest.raises(InputError, match="block"):
        lcpfric.steady_state(free, "active-set", 50, block="dense")
    with pytest.raises(SolverError) as err:
        lcpfric.steady_state(free, "active-set", 50, cg_max_iter=1)
    assert err.value.status == "cg_max_iter"
    # d = 2 matrix-free: refused by name
    rng = np.random.default_rng(1)
    Q2 = tuple(
        Harmonic(0.0, q, p) for q, p in zip(rng.uniform(0.5, 2, 2 * n), rng.uniform(0, 6, 2 * n))
    )
    d2 = ContactSystem(
        None, np.ones(n), Q2, normal, dims=2, compliance=aslinearoperator(np.eye(2 * n))
    )
    with pytest.raises(InputError, match="d = 1 only"):
        lcpfric.steady_state(d2, "active-set", 50)


def test_large_matrix_free_refused_by_matrix_methods():
    """Beyond 2000 unknowns no method forms C: the matrix methods refuse before any work,
    naming active-set."""
    need("osqp")
    n = 2001
    c = kernel(n)
    normal = IndependentSprings(tuple(Harmonic(1.0, 0.5) for _ in range(n)))
    free = ContactSystem(
        None,
        np.ones(n),
        tuple(Harmonic(0.0, 1.0) for _ in range(n)),
        normal,
        compliance=fft_operator(c),
    )
    for method in ("explicit", "osqp"):
        with pytest.raises(InputError, match="active-set"):
            lcpfric.steady_state(free, method, 20)
