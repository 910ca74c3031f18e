"""``K_FF`` of a dense K: the inverse of a base set and a low-rank (Woodbury) correction for the
unknowns that joined or left since (:mod:`lcpfric.linalg.blocks`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg import lapack

from .block import FOLD_RANK, Block, columns_product, not_spd

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["DenseBlock", "spd_inverse"]


class DenseBlock(Block):
    """``K_FF⁻¹`` of a dense K, as the inverse of a base set and a low-rank correction.

    ``K_FF⁻¹`` is kept as the inverse ``G0 = K_BB⁻¹`` of a base set B and a low-rank
    correction for the unknowns that joined (J) and left (R) since.

    With ``X = G0 K_BJ`` and ``S = K_JJ - K_JB X``, ``H = K_AA⁻¹`` on ``A = B ∪ J`` is applied
    as ``y = G0 r_B``, ``v = S⁻¹ (Xᵀ r_B - r_J)``, ``H r = (y + X v, -v)``; leaving unknowns
    are removed with ``K_FF⁻¹ = H_FF - H_FR H_RR⁻¹ H_RF``. A solve then costs one product with
    G0 and ``O(|B| (|J| + |R|))``; a change of the set, one product with G0 per joining
    unknown. When ``|J| + |R|`` reaches :data:`FOLD_RANK` the correction is folded into G0
    (one matrix-matrix product of rank ``|J| + |R|``), and when a quarter of the set changes
    at once G0 is rebuilt from a Cholesky factorization (LAPACK ``potrf``/``potri``). The rows
    ``K_B`` of the base set are kept beside G0, so that a product of K with a vector on the
    free set (:meth:`product`, after every solve) reads ``|F| m`` numbers, not ``m²``.

    The set starts empty: call :meth:`set` before :meth:`solve`.

    Parameters
    ----------
    K : (m, m) array_like
        The stiffness, symmetric positive definite (copied to a C-contiguous float array).

    Attributes
    ----------
    K : (m, m) ndarray or scipy sparse matrix
        The stiffness (as the block holds it).
    m : int
        Unknowns of K.
    index : (f,) int ndarray
        The current set F, as last given to :meth:`set`.
    stats : dict
        ``factorizations`` and ``updates`` so far.
    """

    def __init__(self, K: ArrayLike) -> None:
        super().__init__(np.ascontiguousarray(K, dtype=float))
        self.base = np.empty(0, dtype=np.intp)  # B, in G0's order
        self.G0 = np.zeros((0, 0))
        self.rows = np.zeros((0, self.m))  # K[B]: the products with the free set read these
        self._solved = None  # the unknowns the last solve returned
        self._where = np.full(self.m, -1, dtype=np.intp)  # position in B, or -1
        self._correction(np.empty(0, dtype=np.intp), np.empty(0, dtype=np.intp))

    def set(self, free: np.ndarray) -> None:
        """Make ``free`` (sorted unknowns) the current set.

        Updates the low-rank correction, folds it into G0, or rebuilds G0, by how much of
        the set changed (see the class docstring); nothing when the set is unchanged.

        Parameters
        ----------
        free : (f,) int ndarray
            The unknowns of the new set F, sorted (kept, not copied).

        Raises
        ------
        lcpfric.errors.SolverError
            ``status="not_spd"``: ``K_FF`` (or a Schur complement of the update) is not
            positive definite.
        """
        if np.array_equal(free, self.index):
            return
        inside = np.zeros(self.m, dtype=bool)
        inside[free] = True
        left = np.flatnonzero(~inside[self.base])  # positions in B
        joined = free[self._where[free] < 0]  # unknowns not in B
        rank = left.size + joined.size
        if self.base.size == 0 or 4 * (rank - self.rank) > max(free.size, 1):
            self._rebuild(free)
        elif rank > max(FOLD_RANK, self.base.size // 16):
            self._correction(left, joined)
            self._fold(free)
        else:
            self._correction(left, joined)
            self.stats["updates"] += 1
        self.index = free

    @property
    def order(self) -> np.ndarray:
        """The unknowns of the current set in the order :meth:`solve` returns them."""
        keep = np.ones(self.base.size, dtype=bool)
        keep[self.left] = False
        return np.concatenate([self.base[keep], self.joined])

    def _rebuild(self, free: np.ndarray) -> None:
        self._where[self.base] = -1
        self.base = free.copy()
        self._where[free] = np.arange(free.size)
        self.rows = self.K[free]
        self.G0 = spd_inverse(self.rows[:, free], "K_FF") if free.size else np.zeros((0, 0))
        self._correction(np.empty(0, dtype=np.intp), np.empty(0, dtype=np.intp))
        self.stats["factorizations"] += 1

    def _correction(self, left: np.ndarray, joined: np.ndarray) -> None:
        """The low-rank terms for the leaving positions ``left`` and the joining ``joined``.

        Everything is kept by rows (``XT = Xᵀ``, ``HRT = H[:, R]ᵀ``) and gathered by rows of
        the symmetric K and G0: a column gather of a large array touches one cache line per
        element, a row gather streams."""
        K, B, G0 = self.K, self.base, self.G0
        old = getattr(self, "joined", np.empty(0, dtype=np.intp))
        if joined.size:
            # Xᵀ = K_JB G0, reusing the rows of unknowns that had joined already
            XT = np.empty((joined.size, B.size))
            known = {int(u): c for c, u in enumerate(old)}
            fresh = [c for c, u in enumerate(joined) if int(u) not in known]
            for c, u in enumerate(joined):
                if int(u) in known:
                    XT[c] = self.XT[known[int(u)]]
            KJ = K[joined]  # (j, m), rows
            KJB = KJ[:, B]
            if fresh:
                XT[fresh] = KJB[fresh] @ G0
            S = KJ[:, joined] - KJB @ XT.T
            Sinv = spd_inverse(0.5 * (S + S.T), "the Schur complement of the joining unknowns")
        else:
            XT, Sinv = np.zeros((0, B.size)), np.zeros((0, 0))
        self.joined, self.XT, self.Sinv, self.left = joined, XT, Sinv, left
        self.rank = left.size + joined.size
        if left.size:
            # H[:, R]ᵀ: rows of H = K_AA⁻¹ at the leaving positions
            XRS = XT[:, left].T @ Sinv  # (k, j)
            HRT = np.hstack([G0[left] + XRS @ XT, -XRS])  # (k, |B| + j)
            self.HRT = HRT
            HRR = HRT[:, left]
            self.M = spd_inverse(0.5 * (HRR + HRR.T), "H_RR")
        else:
            self.HRT, self.M = np.zeros((0, B.size + joined.size)), np.zeros((0, 0))

    def _apply(self, rB: np.ndarray, rJ: np.ndarray) -> np.ndarray:
        """``H (r_B, r_J)`` with ``H = K_AA⁻¹``, then the leaving positions removed."""
        y = self.G0 @ rB
        if self.joined.size:
            v = self.Sinv @ (self.XT @ rB - rJ)
            z = np.concatenate([y + v @ self.XT, -v])
        else:
            z = y
        if self.left.size:
            z -= (self.M @ z[self.left]) @ self.HRT
        return z

    def _fold(self, free: np.ndarray) -> None:
        """Fold the correction into a new G0 for the current set: with Bk the kept base
        positions, ``P = [X_Bk; -I]`` and ``Hk`` the kept rows of ``H[:, R]``,

            G0_new = [[G0_BkBk, 0], [0, 0]] + P S⁻¹ Pᵀ - Hk M Hkᵀ,

        one gather of G0 and one matrix-matrix product of rank ``|J| + |R|``."""
        B, XT, Sinv, left, joined = self.base, self.XT, self.Sinv, self.left, self.joined
        s, j = B.size, joined.size
        keep = np.ones(s + j, dtype=bool)
        keep[left] = False
        kb = np.flatnonzero(keep[:s])
        t = kb.size
        G = np.zeros((t + j, t + j))
        G[:t, :t] = self.G0[np.ix_(kb, kb)] if left.size else self.G0
        lhs, rhs = [], []
        if j:
            P = np.vstack([XT[:, kb].T, -np.eye(j)])
            lhs.append(P @ Sinv)
            rhs.append(P)
        if left.size:
            Hk = self.HRT[:, keep].T
            lhs.append(-(Hk @ self.M))
            rhs.append(Hk)
        if lhs:
            G += np.hstack(lhs) @ np.hstack(rhs).T
        self._where[B] = -1
        self.base = np.concatenate([B[kb], joined])
        self._where[self.base] = np.arange(self.base.size)
        self.G0 = G
        self.rows = self.K[self.base]
        self._correction(np.empty(0, dtype=np.intp), np.empty(0, dtype=np.intp))
        self.stats["updates"] += 1

    def solve(
        self, r: np.ndarray, support: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(unknowns, x)``: the solution of ``K_FF x_F = r_F`` on the unknowns of F.

        Parameters
        ----------
        r : (m,) ndarray
            The right-hand side (only its entries on F are read).
        support : ndarray, optional
            The unknowns where r is not negligible; not used: a dense K couples everything.

        Returns
        -------
        unknowns : (f,) int ndarray
            The unknowns of F, in the order of :attr:`order` (not necessarily sorted).
        x : (f,) ndarray
            The solution on them.
        """
        if self.base.size + self.joined.size == 0:
            return self.base, np.zeros(0)
        rB = r[self.base]
        if self.left.size:
            rB[self.left] = 0.0
        z = self._apply(rB, r[self.joined])
        keep = np.ones(z.size, dtype=bool)
        keep[self.left] = False
        unknowns = np.concatenate([self.base, self.joined])[keep]
        self._solved = (unknowns, keep)
        return unknowns, z[keep]

    def product(self, cols: np.ndarray, y: np.ndarray) -> np.ndarray:
        """``K x`` for x equal to ``y`` on ``cols`` and zero elsewhere.

        For the unknowns of the last solve (the very array :meth:`solve` returned), from the
        rows of the base set kept in ``rows`` (a product over the free set costs ``|F| m``,
        not ``m²``, and gathers nothing); otherwise as any block.

        Parameters
        ----------
        cols : (c,) int ndarray
            The unknowns where x is nonzero.
        y : (c,) ndarray
            x on them.

        Returns
        -------
        (m,) ndarray
            ``K x``.
        """
        solved = self._solved
        if solved is None or cols is not solved[0]:
            return columns_product(self.K, cols, y)
        keep, nb = solved[1], self.base.size
        yB = np.zeros(nb)
        yB[keep[:nb]] = y[: nb - self.left.size]
        out = yB @ self.rows
        if self.joined.size:
            out += y[nb - self.left.size :] @ self.K[self.joined]
        return out


def spd_inverse(A: np.ndarray, what: str) -> np.ndarray:
    """The inverse of a symmetric positive definite A (Cholesky, LAPACK potrf/potri)."""
    if A.size == 0:
        return np.zeros((0, 0))
    c, info = lapack.dpotrf(A, lower=False, clean=True)
    if info != 0:
        raise not_spd(what)
    G, info = lapack.dpotri(c, lower=False, overwrite_c=True)
    if info != 0:
        raise not_spd(what)
    iu = np.tril_indices(A.shape[0], -1)
    G[iu] = G.T[iu]
    return G
