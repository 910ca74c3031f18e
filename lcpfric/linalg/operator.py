"""The compliance of a matrix-free system, known by its products: the block of the active-set
stepper's compliance form (:mod:`~lcpfric.steppers.active_set`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import SolverError
from .blocks import not_spd

if TYPE_CHECKING:
    from scipy.sparse.linalg import LinearOperator

__all__ = ["OperatorBlock"]


class OperatorBlock:
    """The compliance C of a matrix-free system, known by its products (a LinearOperator).

    The active-set backend then works in the compliance form, where the unknowns of a pattern
    are the forces of the sticking nodes S and each iteration solves ``C_SS x = b``, here by
    conjugate gradients (C_SS is symmetric positive definite), one product with C per CG
    iteration. The products of every iteration are kept over all rows, so that the slips
    ``C x`` of the other nodes come with the solution, without one more product.

    Parameters
    ----------
    C : (m, m) LinearOperator
        The compliance, symmetric positive definite, known by ``matvec`` and ``matmat``.
    max_iter : int
        Cap on the CG iterations of one :meth:`solve`, >= 0.

    Attributes
    ----------
    C, max_iter
        The parameters, as given.
    m : int
        Unknowns of C.
    stats : dict
        ``products`` (with C) and ``cg_iterations``, so far.
    """

    def __init__(self, C: LinearOperator, max_iter: int) -> None:
        self.C = C
        self.m = C.shape[0]
        self.max_iter = max_iter
        self.stats = {"products": 0, "cg_iterations": 0}

    def apply(self, x: np.ndarray) -> np.ndarray:
        """``C x``, counted in ``stats["products"]``.

        Parameters
        ----------
        x : (m,) ndarray
            The vector.

        Returns
        -------
        (m,) ndarray
            ``C x``, as floats.
        """
        self.stats["products"] += 1
        return np.asarray(self.C.matvec(x), dtype=float).reshape(self.m)

    def apply_many(self, X: np.ndarray) -> np.ndarray:
        """``C X`` for the columns of X, each counted in ``stats["products"]``.

        Parameters
        ----------
        X : (m, k) ndarray
            The vectors, as columns.

        Returns
        -------
        (m, k) ndarray
            ``C X``, as floats.
        """
        self.stats["products"] += X.shape[1]
        return np.asarray(self.C.matmat(X), dtype=float).reshape(self.m, X.shape[1])

    def solve(self, S: np.ndarray, b: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
        """``(x, C x̂)`` by conjugate gradients on ``C_SS x = b``.

        From x = 0 until ``max |b - C_SS x| <= tol``; ``x̂`` is x on S and zero elsewhere, and
        ``C x̂`` is over all m rows.

        Parameters
        ----------
        S : (s,) int ndarray
            The unknowns of the sticking nodes.
        b : (s,) ndarray
            The right-hand side.
        tol : float
            The largest residual entry accepted (absolute, in the units of b).

        Returns
        -------
        x : (s,) ndarray
            The solution on S.
        Cx : (m,) ndarray
            ``C x̂`` over all m rows.

        Raises
        ------
        lcpfric.errors.SolverError
            ``status="cg_max_iter"`` when ``max_iter`` iterations do not reach tol (the
            residual reached is in the message), ``"not_spd"`` for a direction of
            non-positive curvature.
        """
        m = self.m
        x = np.zeros(S.size)
        Cx = np.zeros(m)
        r = b.copy()
        p = r.copy()
        rr = float(r @ r)
        full = np.zeros(m)
        for it in range(self.max_iter + 1):
            if float(np.max(np.abs(r), initial=0.0)) <= tol:
                self.stats["cg_iterations"] += it
                return x, Cx
            if it == self.max_iter:
                break
            full[S] = p
            q = self.apply(full)
            qS = q[S]
            curv = float(p @ qS)
            if not curv > 0.0:
                raise not_spd("C_SS (the compliance of the sticking nodes)")
            alpha = rr / curv
            x += alpha * p
            Cx += alpha * q
            r -= alpha * qS
            rr, rr_old = float(r @ r), rr
            p *= rr / rr_old
            p += r
        self.stats["cg_iterations"] += self.max_iter
        raise SolverError(
            f"active-set: conjugate gradients on the sticking nodes did not reach "
            f"{tol:.3g} in {self.max_iter} iterations (residual "
            f"{float(np.max(np.abs(r))):.3g}); raise cg_max_iter",
            backend="active-set",
            status="cg_max_iter",
        )
