"""The compliance of a matrix-free system, known by its products: the block of the active-set
stepper's compliance form (:mod:`~lcpfric.steppers.active_set`)."""

from __future__ import annotations

import numpy as np

from ..errors import SolverError
from .blocks import not_spd

__all__ = ["OperatorBlock"]


class OperatorBlock:
    """The compliance C of a matrix-free system, known by its products (a LinearOperator):
    the active-set backend then works in the compliance form, where the unknowns of a pattern
    are the forces of the sticking nodes S and each iteration solves ``C_SS x = b``, here by
    conjugate gradients (C_SS is symmetric positive definite), one product with C per CG
    iteration. The products of every iteration are kept over all rows, so that the slips
    ``C x`` of the other nodes come with the solution, without one more product.

    ``stats``: ``products`` (with C) and ``cg_iterations``."""

    def __init__(self, C, max_iter: int):
        self.C = C
        self.m = C.shape[0]
        self.max_iter = max_iter
        self.stats = {"products": 0, "cg_iterations": 0}

    def apply(self, x: np.ndarray) -> np.ndarray:
        """``C x``."""
        self.stats["products"] += 1
        return np.asarray(self.C.matvec(x), dtype=float).reshape(self.m)

    def apply_many(self, X: np.ndarray) -> np.ndarray:
        """``C X`` for the columns of X."""
        self.stats["products"] += X.shape[1]
        return np.asarray(self.C.matmat(X), dtype=float).reshape(self.m, X.shape[1])

    def solve(self, S: np.ndarray, b: np.ndarray, tol: float):
        """``(x, C x̂)``: conjugate gradients on ``C_SS x = b`` from x = 0 until ``max |b - C_SS
        x| <= tol``; ``x̂`` is x on S and zero elsewhere, and ``C x̂`` is over all m rows.
        SolverError ``status="cg_max_iter"`` when ``max_iter`` iterations do not reach tol
        (the residual reached is in the message), ``"not_spd"`` for a direction of
        non-positive curvature."""
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
        raise SolverError(f"active-set: conjugate gradients on the sticking nodes did not reach "
                          f"{tol:.3g} in {self.max_iter} iterations (residual "
                          f"{float(np.max(np.abs(r))):.3g}); raise cg_max_iter",
                          backend="active-set", status="cg_max_iter")
