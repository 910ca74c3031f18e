"""The checks of a :class:`~lcpfric.model.system.ContactSystem`'s operators: the stiffness K
(finite, m x m, symmetric, positive definite), a compliance C given with it (K⁻¹), and the
compliance operator of a matrix-free system (finite, symmetric, positive products).

Each returns the operator as the system keeps it, or raises :class:`~lcpfric.errors.InputError`
naming ``stiffness`` or ``compliance``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError

if TYPE_CHECKING:
    from scipy.sparse.linalg import LinearOperator

__all__ = ["check_stiffness", "check_inverse", "check_compliance_operator", "admissible_start"]


def check_stiffness(K, m: int):
    """K must be a finite, symmetric, positive definite m x m matrix (dense, or sparse: checked
    in full up to m = 2000, beyond that only its shape).

    Parameters
    ----------
    K : (m, m) array_like or scipy.sparse matrix
        The stiffness as given.
    m : int
        The tangential unknowns, n·d.

    Returns
    -------
    ndarray or scipy.sparse.csc_matrix
        K as the system keeps it (CSC for a sparse K).

    Raises
    ------
    InputError
        K not finite, not m x m, not symmetric or not positive definite (named ``stiffness``).
    """
    import scipy.sparse as sp

    if sp.issparse(K):
        K = sp.csc_matrix(K, dtype=float)
        dense = K.toarray() if m <= 2000 else None
    else:
        K = _checks.finite_array("stiffness", K)
        K = np.atleast_2d(K)
        dense = K
    if K.shape != (m, m):
        raise InputError("stiffness", f"must be {m} x {m} (n·d), got {K.shape}")
    if dense is not None:
        if not np.all(np.isfinite(dense)):
            raise InputError("stiffness", "every entry must be finite")
        if not np.allclose(dense, dense.T, rtol=1e-12, atol=0.0):
            raise InputError("stiffness", "must be symmetric")
        try:
            np.linalg.cholesky(dense)
        except np.linalg.LinAlgError:
            raise InputError("stiffness", "must be positive definite") from None
    return K


def check_inverse(K, C, m: int) -> np.ndarray:
    """A supplied C must be K⁻¹: ``max |K C x - x| <= 1e-8 max |x|``.

    On the unit vectors up to m = 2000, on 8 random vectors beyond.

    Parameters
    ----------
    K : (m, m) ndarray or scipy.sparse matrix
        The stiffness, checked (:func:`check_stiffness`).
    C : (m, m) array_like or scipy.sparse matrix
        The compliance as given.
    m : int
        The tangential unknowns, n·d.

    Returns
    -------
    ndarray
        C as a dense array.

    Raises
    ------
    InputError
        C not a finite m x m matrix, or not K⁻¹ (named ``compliance``).
    """
    C = np.asarray(C.toarray() if hasattr(C, "toarray") else C, dtype=float)
    if C.shape != (m, m) or not np.all(np.isfinite(C)):
        raise InputError("compliance", f"must be a finite {m} x {m} matrix, got shape {C.shape}")
    X = np.eye(m) if m <= 2000 else np.random.default_rng(0).standard_normal((m, 8))
    err = float(np.max(np.abs(K @ (C @ X) - X)))
    if not err <= 1e-8:
        raise InputError(
            "compliance",
            f"must be the inverse of the stiffness: "
            f"max |K C x - x| = {err:.3g} > 1e-8 on unit vectors",
        )
    return C


def check_compliance_operator(compliance, m: int) -> LinearOperator:
    """A matrix-free system: C a finite, symmetric, positive m x m operator (probed with two
    random vectors: ``|xᵀCy - yᵀCx| <= 1e-8 |x| |Cy|`` and ``xᵀCx > 0``).

    Parameters
    ----------
    compliance : (m, m) array_like, LinearOperator or None
        The compliance as given (anything :func:`~scipy.sparse.linalg.aslinearoperator`
        accepts).
    m : int
        The tangential unknowns, n·d.

    Returns
    -------
    LinearOperator
        C as an operator.

    Raises
    ------
    InputError
        No compliance (named ``stiffness``: the system has neither), or one that is not a
        finite, symmetric, positive m x m operator (named ``compliance``).
    """
    from scipy.sparse.linalg import aslinearoperator

    if compliance is None:
        raise InputError(
            "stiffness",
            "is None: a matrix-free system needs compliance= "
            "(a LinearOperator with C x); give one of the two",
        )
    try:
        op = aslinearoperator(compliance)
    except (TypeError, ValueError) as exc:
        raise InputError("compliance", f"must be a matrix or a LinearOperator ({exc})") from None
    if op.shape != (m, m):
        raise InputError("compliance", f"must be {m} x {m} (n·d), got {op.shape}")
    rng = np.random.default_rng(12345)
    x, y = rng.standard_normal(m), rng.standard_normal(m)
    Cx = np.asarray(op.matvec(x), dtype=float).ravel()
    Cy = np.asarray(op.matvec(y), dtype=float).ravel()
    if Cx.shape != (m,) or not (np.all(np.isfinite(Cx)) and np.all(np.isfinite(Cy))):
        raise InputError("compliance", f"products C x must be finite vectors of {m}")
    scale = float(np.linalg.norm(x) * max(np.linalg.norm(Cx), np.linalg.norm(Cy)))
    if not abs(x @ Cy - y @ Cx) <= 1e-8 * scale:
        raise InputError(
            "compliance",
            "must be symmetric: xᵀCy differs from yᵀCx by "
            f"{abs(x @ Cy - y @ Cx):.3g} (relative > 1e-8)",
        )
    if not (x @ Cx > 0 and y @ Cy > 0):
        raise InputError("compliance", "must be positive definite: xᵀCx <= 0 for a random x")
    return op


def admissible_start(system, u0) -> np.ndarray:
    """``u0`` as m finite displacements that the friction law admits at t = 0:
    ``||F_i(0)|| <= f_i N_i(0)`` for every node in contact, ``F = Q(0) + K u0``, to round-off
    (1e-12 of the force scale, and 1e-13 of the terms K u0 sums); a node out of contact at
    t = 0 carries no force, and its displacement is not part of the state. Else
    :class:`InputError` naming the nodes that violate it."""
    u0 = _checks.finite_array("u0", u0).ravel()
    if u0.size != system.m:
        raise InputError("u0", f"needs {system.m} displacements (n·d), got {u0.size}")
    F = (system.tangential(0.0) + system.stiffness_times(u0)).reshape(system.n, system.dims)
    force = np.sqrt(np.sum(F * F, axis=1))
    coupling = getattr(system, "coupling", None)
    if coupling is None:
        limit = system.friction * system.normal.reactions(0.0)
    else:  # N = P(0) + B u0 must be a compression at every node (no separation modelled)
        N = np.asarray(system.normal.loads_at(0.0), dtype=float) + coupling @ u0
        if np.any(N <= 0):
            i = int(np.argmin(N))
            raise InputError(
                "u0",
                f"is not an admissible start: node {i}'s normal reaction P(0) + (B u0) = "
                f"{N[i]:.6g} is not a compression (a coupled node must stay in contact)",
            )
        limit = system.friction * N
    scale = float(np.max(np.abs(F), initial=0.0)) + float(np.max(limit, initial=0.0))
    # round-off: of the loads, and of K u0's sums (a stiff K sums large terms to a small force)
    slack = 1e-12 * scale
    if system.stiffness is not None:
        terms = (abs(system.stiffness) @ np.abs(u0)).reshape(system.n, system.dims)
        slack = slack + 1e-13 * np.sqrt(np.sum(terms * terms, axis=1))
    bad = np.nonzero((limit > 0) & (force > limit + slack))[0]
    if bad.size:
        show = ", ".join(f"{i} (|F| = {force[i]:.6g} > f N = {limit[i]:.6g})" for i in bad[:5])
        more = f" and {bad.size - 5} more" if bad.size > 5 else ""
        raise InputError(
            "u0",
            f"is not an admissible start: at t = 0 the friction law is violated at node(s) "
            f"{show}{more}; give displacements with |Q(0) + K u0| <= f N(0) at every node in "
            f"contact",
        )
    return u0
