"""The exact solver's compiled kernels (lcpfric.exact.kernels, numba): bit-identical to the numpy
expressions they replace, imported by a discrete solve only."""

import subprocess
import sys

import numpy as np
import pytest

from lcpfric.exact import kernels


@pytest.mark.parametrize("sign", [1, -1])
def test_rank_one_is_the_numpy_update_bit_for_bit(sign):
    rng = np.random.default_rng(3)
    G = rng.standard_normal((40, 40))
    x, s = rng.standard_normal(31), 1.0 + rng.random()
    want = G.copy()
    if sign > 0:
        want[:31, :31] += np.multiply.outer(x, x / s)
    else:
        want[:31, :31] -= np.multiply.outer(x, x / s)
    kernels.rank_one(G, 31, x, x / s, sign)
    assert np.array_equal(G, want)


@pytest.mark.parametrize("sign", [1, -1])
def test_rank_one_on_a_support_is_the_numpy_update_bit_for_bit(sign):
    rng = np.random.default_rng(4)
    G = rng.standard_normal((50, 50))
    idx = np.array([2, 7, 11, 30, 49])
    x, y = rng.standard_normal(50), rng.standard_normal(50)
    want = G.copy()
    if sign > 0:
        want[np.ix_(idx, idx)] += np.multiply.outer(x[idx], y[idx])
    else:
        want[np.ix_(idx, idx)] -= np.multiply.outer(x[idx], y[idx])
    kernels.rank_one_on(G, idx, idx.size, x, y, float(sign))
    assert np.array_equal(G, want)


def _imports_numba(code):
    out = subprocess.run(
        [sys.executable, "-c", code + "\nimport sys; print('numba' in sys.modules)"],
        capture_output=True,
        text=True,
        check=True,
    )
    return out.stdout.strip().splitlines()[-1] == "True"


def test_numba_is_imported_by_a_discrete_exact_solve_only():
    """``import lcpfric`` and the single node's closed form do not pay numba's import."""
    assert not _imports_numba("import lcpfric")
    assert not _imports_numba(
        "import lcpfric\n"
        "lcpfric.steady_state(lcpfric.SingleNode.normalized(P1=1.5, Q1=2.0, phi=1.0))"
    )
    assert _imports_numba(
        "import lcpfric\nlcpfric.steady_state(lcpfric.chain(3, P1=0.5, Q1=1.2, phi=0.4), 'exact')"
    )


# -- the event loop's closed forms, against independent computations ---------------------------
def test_entry_angle_is_where_the_triple_first_falls_below_minus_tol():
    """The first angle >= θ where c0 + cs sin + cc cos < -tol, against a fine grid."""
    rng = np.random.default_rng(5)
    grid = np.linspace(0.0, 2 * np.pi, 400001)
    for _ in range(200):
        c0, cs, cc = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
        theta, tol = rng.uniform(0, 2 * np.pi), 1e-3
        t, ratio = kernels.entry(c0, cs, cc, theta, tol)
        x = theta + grid
        below = c0 + cs * np.sin(x) + cc * np.cos(x) < -tol
        if np.hypot(cs, cc) - c0 <= tol:  # never below: no entry, the shallow depth reported
            assert np.isinf(t) and ratio <= 1.0
            continue
        assert ratio == 0.0
        # the entry of the arc below zero (the arc's start, or θ itself inside its first half)
        first = x[np.argmax(below)]
        assert theta <= t <= first + 1e-4


def test_segment_dissipation_is_the_integral():
    from scipy.integrate import quad

    rng = np.random.default_rng(6)
    for _ in range(20):
        b, u = rng.standard_normal(3), rng.standard_normal(3)
        a, e = np.sort(rng.uniform(0, 2 * np.pi, 2))

        def integrand(t):
            return (b[0] + b[1] * np.sin(t) + b[2] * np.cos(t)) * (
                u[1] * np.cos(t) - u[2] * np.sin(t)
            )

        want = quad(integrand, a, e, epsabs=1e-14, epsrel=1e-13)[0]
        assert kernels.segment(b, u, a, e) == pytest.approx(want, abs=1e-12)


def _solver(n=12, seed=7, sparse=False):
    from lcpfric.exact.events import EventSolver

    rng = np.random.default_rng(seed)
    if sparse:
        K = 3.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    else:
        A = rng.standard_normal((n, n)) / np.sqrt(n)
        K = A @ A.T + np.eye(n)
    Qt = np.column_stack([np.zeros(n), rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)])
    Pt = np.column_stack([np.ones(n), 0.3 * rng.uniform(-1, 1, n), 0.3 * rng.uniform(-1, 1, n)])
    return EventSolver(K, np.full(n, 0.3), Qt, Pt, 16, 10_000), rng


@pytest.mark.parametrize("sparse", [False, True])
def test_changes_of_state_agree_with_a_fresh_factorization(sparse):
    """A sequence of single changes of state (bordering, downdates, K z on the stuck rows
    only) gives the G, U and F a fresh factorization of the same pattern gives."""
    s, rng = _solver(sparse=sparse)
    n = s.n
    status = np.zeros(n, dtype=np.int8)
    s.full(status, rng.standard_normal(n) * 0.1, 0.3)
    theta = 0.3
    for _ in range(40):
        j, new = int(rng.integers(n)), int(rng.integers(4))
        theta += 0.01
        s.flip(j, new, theta)
    u = s.u_at(theta)
    U, Ft, m = s.U.copy(), s.Ft.copy(), s.m
    G = s.G[:m, :m].copy()
    Bidx = s.Bidx[:m].copy()
    s.full(s.status.copy(), u, theta)
    order = np.argsort(Bidx)
    assert np.allclose(G[np.ix_(order, order)], s.G[:m, :m], atol=1e-12)
    assert np.allclose(U, s.U, atol=1e-12)
    assert np.allclose(Ft, s.Ft, atol=1e-12)


def test_sparse_and_dense_products_give_one_answer():
    """K z through K's compressed columns (a chain) or its dense rows: the same W."""
    import lcpfric
    from lcpfric.exact import pattern

    system = lcpfric.chain(30, k_coupling=10.0, P1=0.6, Q1=1.5, phi=0.7)
    W_sparse = lcpfric.steady_state(system, "exact").W
    original = pattern.Pattern.__init__

    def dense_only(self, *args, **kwargs):
        original(self, *args, **kwargs)
        self.csc = (np.zeros(0, np.intp), np.zeros(0, np.intp), np.zeros(0))

    pattern.Pattern.__init__ = dense_only
    try:
        W_dense = lcpfric.steady_state(system, "exact").W
    finally:
        pattern.Pattern.__init__ = original
    assert W_dense == pytest.approx(W_sparse, rel=1e-13)


def test_the_loops_cache_is_keyed_by_the_kernels_file_too():
    """numba keys a cached function by its own file only; the loop links the kernels of
    another file, so a change there must not load a stale loop (lcpfric.exact.loop)."""
    import os

    from lcpfric.exact import loop

    index = getattr(getattr(loop.run, "_cache", None), "_cache_file", None)
    if index is None:
        pytest.skip("this numba lays out its cache otherwise (the loop is not cached)")
    st = os.stat(kernels.__file__)
    assert index._source_stamp[1] == (st.st_mtime, st.st_size)
