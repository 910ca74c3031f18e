"""``K_FF`` of a sparse K: LAPACK's banded Cholesky for a small bandwidth (after reverse
Cuthill-McKee), SuperLU otherwise (:mod:`lcpfric.linalg.blocks`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg import lapack

from .block import Block, not_spd

if TYPE_CHECKING:
    import scipy.sparse as sp
    from numpy.typing import ArrayLike

__all__ = ["BandedBlock", "SparseBlock", "banded_order"]


class BandedBlock(Block):
    """``K_FF`` of a sparse K of small bandwidth, by LAPACK's banded Cholesky.

    ``perm`` is K's reverse Cuthill-McKee order (the identity when K is already banded); the
    band of ``K_FF`` in that order is gathered from K's band (a principal submatrix of a band
    matrix, taken in the same order, has at most the same bandwidth). The factor of ``K_FF``
    is reused while F (and the segments solved) are unchanged.

    :func:`make_block` finds ``perm`` and ``width``. The set starts empty: call :meth:`set`
    before :meth:`solve`.

    Parameters
    ----------
    K : (m, m) scipy sparse matrix or ndarray
        The stiffness, symmetric positive definite.
    perm : (m,) int ndarray
        The order in which K has bandwidth ``width`` (a permutation of ``0..m-1``).
    width : int
        The bandwidth of K in that order, >= 0.

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
    perm, width
        The parameters, as given.
    """

    def __init__(self, K: sp.spmatrix | np.ndarray, perm: np.ndarray, width: int) -> None:
        super().__init__(K)
        import scipy.sparse as sp

        self.perm = perm
        self.natural = bool(np.array_equal(perm, np.arange(perm.size)))
        self.rank = np.empty_like(perm)
        self.rank[perm] = np.arange(perm.size)
        self.width = width
        Kp = sp.csr_matrix(K)[perm][:, perm]
        m, w = perm.size, width
        band = np.zeros((w + 1, m))  # LAPACK upper band storage: band[w + i - j, j] = K[i, j]
        for d in range(w + 1):
            band[w - d, d:] = Kp.diagonal(d)
        self.band = band
        self.factor = self.sel = None
        self.pos = np.empty(0, dtype=np.intp)

    def set(self, free: np.ndarray) -> None:
        """Make ``free`` the current set: its positions in band order and its segments.

        The segments are the maximal runs whose consecutive positions are at most w apart;
        two segments are not coupled by K, so each can be solved alone.

        Nothing is factored here: :meth:`solve` factors what it needs.

        Parameters
        ----------
        free : (f,) int ndarray
            The unknowns of the new set F, sorted (kept, not copied).
        """
        if np.array_equal(free, self.index):
            return
        self.index = free
        pos = free if self.natural else np.sort(self.rank[free])
        self.pos = pos
        cut = np.flatnonzero(np.diff(pos) > self.width) + 1
        self.starts = np.concatenate([[0], cut]).astype(np.intp)
        self.stops = np.concatenate([cut, [pos.size]]).astype(np.intp)

    def solve(
        self, r: np.ndarray, support: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(unknowns, x)`` with ``K_FF x_F = r_F``, on the segments that ``support`` needs.

        Computed on the segments that hold an unknown of ``support`` (all when None): r must
        be negligible on the others, where the solution is zero (and not returned).

        Parameters
        ----------
        r : (m,) ndarray
            The right-hand side (only its entries on F are read).
        support : (s,) int ndarray, optional
            The unknowns of F where r is not negligible (None: all). When they, or the
            segments that hold them, make more than half of F, all of F is solved.

        Returns
        -------
        unknowns : int ndarray
            The unknowns solved for, in band order.
        x : ndarray
            The solution on them.

        Raises
        ------
        lcpfric.errors.SolverError
            ``status="not_spd"``: ``K_FF`` is not positive definite (found when it is
            factored).
        """
        pos = self.pos
        if pos.size == 0:
            return pos, np.zeros(0)
        if support is None or 2 * len(support) > pos.size:
            sel = pos
        else:
            at = np.searchsorted(pos, self.rank[support])
            seg = np.unique(np.searchsorted(self.starts, at, side="right") - 1)
            lengths = self.stops[seg] - self.starts[seg]
            if 2 * lengths.sum() > pos.size:
                sel = pos
            else:
                offs = np.repeat(
                    self.starts[seg] - np.concatenate([[0], np.cumsum(lengths)[:-1]]), lengths
                )
                sel = pos[np.arange(lengths.sum()) + offs]
        if self.factor is None or not np.array_equal(sel, self.sel):
            self._factor(sel)
        unknowns = sel if self.natural else self.perm[sel]
        y, info = lapack.dpbtrs(self.factor, r[unknowns], lower=0)
        return unknowns, y

    def _factor(self, sel: np.ndarray) -> None:
        """Banded Cholesky of ``K`` on the band positions ``sel`` (sorted)."""
        w = self.width
        f = sel.size
        band = np.zeros((w + 1, f))
        for d in range(1, w + 1):
            if d >= f:
                break
            gap = sel[d:] - sel[: f - d]  # distance in band order of the pair (i, i + d)
            ok = gap <= w
            vals = np.zeros(f - d)
            vals[ok] = self.band[w - gap[ok], sel[d:][ok]]
            band[w - d, d:] = vals
        band[w] = self.band[w, sel]
        c, info = lapack.dpbtrf(band, lower=0)
        if info != 0:
            raise not_spd("K_FF")
        self.factor, self.sel = c, sel
        self.stats["factorizations"] += 1


class SparseBlock(Block):
    """``K_FF`` of a general sparse K, by SuperLU, refactored when the set changes.

    The set starts empty: call :meth:`set` before :meth:`solve`.

    Parameters
    ----------
    K : (m, m) scipy sparse matrix or array_like
        The stiffness, symmetric positive definite (converted to CSC).

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

    def __init__(self, K: sp.spmatrix | ArrayLike) -> None:
        import scipy.sparse as sp

        super().__init__(sp.csc_matrix(K))
        self.lu = None

    def set(self, free: np.ndarray) -> None:
        """Make ``free`` the current set and factor ``K_FF`` (SuperLU), unless it is unchanged.

        Parameters
        ----------
        free : (f,) int ndarray
            The unknowns of the new set F, sorted (kept, not copied).

        Raises
        ------
        lcpfric.errors.SolverError
            ``status="not_spd"``: SuperLU finds ``K_FF`` singular.
        """
        import scipy.sparse.linalg as spl

        if self.lu is not None and np.array_equal(free, self.index):
            return
        self.index = free
        if free.size == 0:
            self.lu = None
            return
        A = self.K[free][:, free].tocsc()
        try:
            self.lu = spl.splu(A, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        except RuntimeError as exc:
            raise not_spd(f"K_FF ({exc})") from None
        self.stats["factorizations"] += 1

    def solve(
        self, r: np.ndarray, support: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(unknowns, x)`` with ``K_FF x_F = r_F``, from the factor of :meth:`set`.

        Parameters
        ----------
        r : (m,) ndarray
            The right-hand side (only its entries on F are read).
        support : ndarray, optional
            Not used (the whole set is solved).

        Returns
        -------
        unknowns : (f,) int ndarray
            The unknowns of F, sorted (:attr:`index`).
        x : (f,) ndarray
            The solution on them.
        """
        if self.lu is None:
            return self.index, np.zeros(0)
        return self.index, self.lu.solve(r[self.index])


def banded_order(K) -> tuple[np.ndarray, int]:
    """The natural order if it has the smallest bandwidth, else reverse Cuthill-McKee's, and
    the bandwidth in that order."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    coo = sp.coo_matrix(K)
    natural = int(np.max(np.abs(coo.row - coo.col), initial=0))
    if natural <= 1:
        return np.arange(K.shape[0]), natural
    perm = np.asarray(reverse_cuthill_mckee(sp.csr_matrix(K), symmetric_mode=True), dtype=np.intp)
    rank = np.empty_like(perm)
    rank[perm] = np.arange(perm.size)
    width = int(np.max(np.abs(rank[coo.row] - rank[coo.col]), initial=0))
    if width >= natural:
        return np.arange(K.shape[0]), natural
    return perm, width
