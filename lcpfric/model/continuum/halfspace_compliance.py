"""The tangential compliance of a :class:`~.halfspace.HalfSpace` by its products on the grid:
node-major forces to and from the FFT's padded layout, the products ``C F``, and the compliance
operator with ``C⁻¹ B`` that makes the model a system (:meth:`~.halfspace.HalfSpace.springs`).

The products are :class:`~.influence.Convolution`'s (zero-padded FFT; no matrix is formed).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...linalg.cg import cg

if TYPE_CHECKING:
    from scipy.sparse.linalg import LinearOperator

__all__ = ["pad", "nodes", "apply", "compliance", "compliance_springs"]


def pad(model, F):
    """Node-major forces ``(n, d)`` or flat in the FFT's padded layout
    (:meth:`~.influence.Convolution.view`)."""
    N, d = model.N, model.dims
    buf = model.op.empty()
    model.op.view(buf)[:N, :N] = np.asarray(F, dtype=float).reshape(N, N, d)
    return buf


def nodes(model, buf):
    """A padded array's nodes, node-major ``(n, d)`` (a view)."""
    N, d = model.N, model.dims
    return model.op.view(buf)[:N, :N].reshape(N * N, d)


def apply(model, op, kind, F, factor):
    """The product ``kind`` (:meth:`~.influence.Convolution.padded`) of node-major forces
    ``(n, d)`` or flat, times ``factor``, by ``op`` (the model's operator, or a
    :class:`~.influence.Counted` one): ``(n, d)``."""
    return nodes(model, op.padded(kind, pad(model, F), factor))


def compliance(model, op, F) -> np.ndarray:
    """``C F``: relative tangential displacements ``(n, d)`` from forces ``(n, d)`` or flat."""
    return apply(model, op, "tangential", F, 1.0 / model.h**2)


def compliance_springs(model) -> tuple[LinearOperator, np.ndarray, np.ndarray]:
    """``(compliance operator, C⁻¹ B, diag C)`` of a half-space with the body held fixed (the
    model's :meth:`~.halfspace.HalfSpace.springs`, which documents them)."""
    from scipy.sparse.linalg import LinearOperator

    n, d = model.nodes, model.dims
    m = n * d

    def product(x):
        return compliance(model, model.op, x).reshape(-1)

    op = LinearOperator((m, m), matvec=product, rmatvec=product, dtype=float)
    h2 = model.h**2
    stats = {"cg": 0}
    W = np.empty((m, d))
    for j in range(d):
        e = np.zeros((n, d))
        e[:, j] = 1.0
        x, _ = cg(
            op.matvec,
            e.ravel(),
            np.zeros(m),
            None,
            lambda r: apply(model, model.op, "precondition", r, h2).reshape(-1),
            1e-13 * float(np.max(np.abs(e))) * model.c,
            stats,
        )
        W[:, j] = x
    return op, (W[:, 0] if d == 1 else W), np.full(m, model.c)
