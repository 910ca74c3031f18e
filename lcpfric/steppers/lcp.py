"""Linear complementarity problems with a P-matrix, by principal pivoting.

The rate problem of the explicit stepper (which nodes slip after an event, and how fast) is
``λ >= 0, Mλ + q >= 0, λ·(Mλ + q) = 0`` with M = D S D a P-matrix (S a Schur complement of the
positive definite stiffness, D the slip signs): it has exactly one solution.
"""

from __future__ import annotations

import numpy as np

from ..errors import SolverError

__all__ = ["solve_lcp"]


def solve_lcp(M: np.ndarray, q: np.ndarray, basis=None, max_pivots: int | None = None):
    """Solve ``z >= 0, w = M z + q >= 0, z·w = 0`` for a P-matrix M by Murty's least-index
    principal pivoting. ``basis`` (bool array) is a warm start: the indices expected with z > 0.

    Returns
    -------
    z : ndarray
    """
    n = q.size
    B = np.zeros(n, dtype=bool) if basis is None else np.array(basis, dtype=bool)
    max_pivots = max_pivots or 50 * (n + 1) ** 2
    scale = max(1.0, float(np.max(np.abs(q))) if n else 1.0)
    for _ in range(max_pivots):
        z = np.zeros(n)
        if B.any():
            z[B] = np.linalg.solve(M[np.ix_(B, B)], -q[B])
        w = q + M @ z
        tol = 1e-12 * scale
        bad = (B & (z < -tol)) | (~B & (w < -tol))
        if not bad.any():
            return np.maximum(z, 0.0)
        i = int(np.argmax(bad))
        B[i] = ~B[i]
    raise SolverError(
        "explicit stepper: the slip-rate LCP did not settle (is K positive definite?)",
        backend="explicit",
        status="lcp_max_pivots",
    )
