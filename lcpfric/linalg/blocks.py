r"""Solves with the principal block ``K_FF`` of the stiffness on a set F that changes by a few
unknowns at a time: the linear algebra of the active-set stepper
(:mod:`~lcpfric.steppers.active_set`).

At every iteration the active-set method solves ``K_FF x = r`` for the free unknowns F (those
of the slipping and the separated nodes; a sticking node's displacement is fixed). Between two
iterations, and between two time steps, F changes by the few nodes that start or stop slipping.
Each block keeps what makes the next solve cheap, and is chosen from the form of K:

``DenseBlock``   dense K: the inverse ``G0`` of a base set and a low-rank (Woodbury)
                 correction for the unknowns that joined or left since, so that a change of
                 the set costs one product with G0 per joining unknown and a solve one product
                 with G0; the correction is folded into G0 by one matrix-matrix product when
                 its rank grows, and G0 rebuilt from a Cholesky factorization (LAPACK
                 ``potrf``/``potri``) when more than a quarter of F changes at once.
``BandedBlock``  sparse K of small bandwidth w (a chain has w = d; any K is first reordered by
                 reverse Cuthill-McKee): LAPACK's banded Cholesky (``pbtrf``/``pbtrs``) of
                 ``K_FF``, ``O(|F| w²)`` per change of F, reused while F is unchanged.
``SparseBlock``  any other sparse K: SuperLU (:func:`scipy.sparse.linalg.splu`) of ``K_FF``,
                 reused while F is unchanged.

None of them forms K⁻¹ of the whole system: a stiff K (stiffness ratios of 1e12) keeps its
digits in K itself, and the caller measures the residual of every solve on K (the forces) and
refines the answer (iterative refinement) until it is at round-off. A block that finds ``K_FF``
not positive definite raises :class:`~lcpfric.errors.SolverError` (``status="not_spd"``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .block import FOLD_RANK, MAX_BANDWIDTH, Block, not_spd
from .dense import DenseBlock
from .sparse import BandedBlock, SparseBlock, banded_order

if TYPE_CHECKING:
    import numpy as np
    import scipy.sparse as sp

__all__ = [
    "DenseBlock",
    "BandedBlock",
    "SparseBlock",
    "make_block",
    "not_spd",
    "Block",
    "MAX_BANDWIDTH",
    "FOLD_RANK",
]


def make_block(
    K: np.ndarray | sp.spmatrix, kind: str = "auto"
) -> DenseBlock | BandedBlock | SparseBlock:
    """The block for K: ``"dense"``, ``"banded"``, ``"sparse"`` or ``"auto"``.

    ``"auto"`` is dense for a dense K; for a sparse K, banded when its bandwidth after reverse
    Cuthill-McKee is at most :data:`MAX_BANDWIDTH`, else SuperLU.

    Parameters
    ----------
    K : (m, m) ndarray or scipy sparse matrix
        The stiffness, symmetric positive definite (not checked here: a block finds out).
    kind : str
        ``"auto"`` (default), ``"dense"`` (:class:`DenseBlock`), ``"banded"``
        (:class:`BandedBlock`, whatever the bandwidth) or ``"sparse"`` (:class:`SparseBlock`;
        also for any other value).

    Returns
    -------
    DenseBlock or BandedBlock or SparseBlock
        The block, its set empty.
    """
    import scipy.sparse as sp

    if not sp.issparse(K):
        if kind in ("auto", "dense"):
            return DenseBlock(K)
        K = sp.csc_matrix(K)
    elif kind == "dense":
        return DenseBlock(K.toarray())
    if kind in ("auto", "banded"):
        perm, width = banded_order(K)
        if kind == "banded" or width <= MAX_BANDWIDTH:
            return BandedBlock(K, perm, width)
    return SparseBlock(K)
