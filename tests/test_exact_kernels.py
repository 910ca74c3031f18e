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
    x, y = rng.standard_normal(5), rng.standard_normal(5)
    want = G.copy()
    if sign > 0:
        want[np.ix_(idx, idx)] += np.multiply.outer(x, y)
    else:
        want[np.ix_(idx, idx)] -= np.multiply.outer(x, y)
    kernels.rank_one_on(G, idx, x, y, sign)
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
