r"""Solves with the principal block ``K_FF`` of the stiffness on a set F that changes by a few
unknowns at a time: the linear algebra of the active-set backend
(:mod:`~lcpfric.backends.active_set`).

At every iteration the active-set method solves ``K_FF x = r`` for the free unknowns F (those
of the slipping and the separated nodes; a sticking node's displacement is fixed). Between two
iterations, and between two time steps, F changes by the few nodes that start or stop slipping.
Each block keeps what makes the next solve cheap, and is chosen from the form of K:

``DenseBlock``   dense K: the inverse ``G = K_FF⁻¹``, kept by block bordering (nodes join F)
                 and block Schur downdates (nodes leave F), one pass over G per change of the
                 set, O(|F|² k) for k changes; rebuilt from a Cholesky factorization (LAPACK
                 ``potrf``/``potri``) when more than a quarter of F changes.
``BandedBlock``  sparse K of small bandwidth w (a chain has w = d; any K is first reordered by
                 reverse Cuthill-McKee): LAPACK's banded Cholesky (``pbtrf``/``pbtrs``) of
                 ``K_FF``, O(|F| w²) per change of F, reused while F is unchanged.
``SparseBlock``  any other sparse K: SuperLU (:func:`scipy.sparse.linalg.splu`) of ``K_FF``,
                 reused while F is unchanged.

None of them forms K⁻¹ of the whole system: a stiff K (stiffness ratios of 1e12) keeps its
digits in K itself, and the caller measures the residual of every solve on K (the forces) and
refines the answer (iterative refinement) until it is at round-off. A block that finds ``K_FF``
not positive definite raises :class:`~lcpfric.errors.SolverError` (``status="not_spd"``).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
from scipy.linalg import lapack

from ..errors import SolverError

__all__ = ["DenseBlock", "BandedBlock", "SparseBlock", "make_block"]

#: largest bandwidth (after reordering) for which the banded Cholesky is used: beyond it the
#: band holds more than a sparse factor would
MAX_BANDWIDTH = 64


def _not_spd(what: str) -> SolverError:
    return SolverError(f"active-set: {what} is not positive definite (K must be SPD)",
                       backend="active-set", status="not_spd")


class _Block:
    """Common part: the current set (sorted unknowns) and the counters."""

    def __init__(self, K):
        self.K = K
        self.m = K.shape[0]
        self.index = np.empty(0, dtype=np.intp)
        self.stats = {"factorizations": 0, "updates": 0}

    @property
    def size(self) -> int:
        return int(self.index.size)

    def matvec(self, x: np.ndarray) -> np.ndarray:
        """``K x``."""
        return self.K @ x


class DenseBlock(_Block):
    """``K_FF⁻¹`` of a dense K, updated by blocks of joining and leaving unknowns.

    ``G`` holds the inverse in the order of ``index`` (sorted on a rebuild, new unknowns
    appended on an update: the order is internal, :meth:`solve` takes and returns full-size
    vectors)."""

    def __init__(self, K):
        super().__init__(np.ascontiguousarray(K, dtype=float))
        self.G = np.zeros((0, 0))
        self.order = np.empty(0, dtype=np.intp)  # G's row order (the unknowns)

    def set(self, free: np.ndarray) -> None:
        """Make ``free`` (sorted unknowns) the current set."""
        if np.array_equal(free, self.index):
            return
        inside = np.zeros(self.m, dtype=bool)
        inside[free] = True
        keep = inside[self.order]
        was = np.zeros(self.m, dtype=bool)
        was[self.order] = True
        join = free[~was[free]]
        changes = int((~keep).sum()) + join.size
        if self.order.size == 0 or 4 * changes > free.size or changes > 256:
            self._rebuild(free)
        else:
            if not keep.all():
                self._leave(keep)
            if join.size:
                self._join(join)
            self.stats["updates"] += 1
        self.index = free

    def _rebuild(self, free: np.ndarray) -> None:
        self.order = free.copy()
        if free.size == 0:
            self.G = np.zeros((0, 0))
            return
        A = self.K[np.ix_(free, free)]
        c, info = lapack.dpotrf(A, lower=False, clean=True, overwrite_a=True)
        if info != 0:
            raise _not_spd("K_FF")
        G, info = lapack.dpotri(c, lower=False, overwrite_c=True)
        if info != 0:
            raise _not_spd("K_FF")
        iu = np.tril_indices(free.size, -1)
        G[iu] = G.T[iu]
        self.G = G
        self.stats["factorizations"] += 1

    def _leave(self, keep: np.ndarray) -> None:
        """Downdate: the inverse of the kept block is ``G_kk - G_kr G_rr⁻¹ G_rk``."""
        G = self.G
        k, r = np.flatnonzero(keep), np.flatnonzero(~keep)
        Gkr = G[np.ix_(k, r)]
        Grr = G[np.ix_(r, r)]
        try:
            X = sla.solve(Grr, Gkr.T, assume_a="pos", check_finite=False)
        except (np.linalg.LinAlgError, sla.LinAlgError):
            raise _not_spd("the block of leaving unknowns") from None
        Gk = G[np.ix_(k, k)]
        Gk -= Gkr @ X
        self.G = Gk
        self.order = self.order[k]

    def _join(self, join: np.ndarray) -> None:
        """Bordering: with ``X = G K_oj`` and the Schur complement ``S = K_jj - K_jo X``,
        ``[[G + X S⁻¹ Xᵀ, -X S⁻¹], [-S⁻¹ Xᵀ, S⁻¹]]``."""
        o = self.order
        K = self.K
        Koj = K[np.ix_(o, join)]
        X = self.G @ Koj
        S = K[np.ix_(join, join)] - Koj.T @ X
        S = 0.5 * (S + S.T)
        c, info = lapack.dpotrf(S, lower=False, clean=True)
        if info != 0:
            raise _not_spd("the Schur complement of the joining unknowns")
        Si, info = lapack.dpotri(c, lower=False)
        iu = np.tril_indices(join.size, -1)
        Si[iu] = Si.T[iu]
        XS = X @ Si
        s, j = o.size, join.size
        G = np.empty((s + j, s + j))
        G[:s, :s] = self.G
        G[:s, :s] += XS @ X.T
        G[:s, s:] = -XS
        G[s:, :s] = -XS.T
        G[s:, s:] = Si
        self.G = G
        self.order = np.concatenate([o, join])

    def solve(self, r: np.ndarray, support=None):
        """``(unknowns, x)``: the solution of ``K_FF x_F = r_F`` on the unknowns of F
        (``support``, the unknowns where r is not negligible, is not used: a dense K couples
        everything)."""
        return self.order, self.G @ r[self.order]


class BandedBlock(_Block):
    """``K_FF`` of a sparse K of small bandwidth, by LAPACK's banded Cholesky.

    ``perm`` is K's reverse Cuthill-McKee order (the identity when K is already banded); the
    band of ``K_FF`` in that order is gathered from K's band (a principal submatrix of a band
    matrix, taken in the same order, has at most the same bandwidth)."""

    def __init__(self, K, perm: np.ndarray, width: int):
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
        """Make ``free`` the current set: its positions in band order and its segments
        (maximal runs whose consecutive positions are at most w apart; two segments are not
        coupled by K, so each can be solved alone)."""
        if np.array_equal(free, self.index):
            return
        self.index = free
        pos = free if self.natural else np.sort(self.rank[free])
        self.pos = pos
        cut = np.flatnonzero(np.diff(pos) > self.width) + 1
        self.starts = np.concatenate([[0], cut]).astype(np.intp)
        self.stops = np.concatenate([cut, [pos.size]]).astype(np.intp)

    def solve(self, r: np.ndarray, support=None):
        """``(unknowns, x)`` with ``K_FF x_F = r_F``, computed on the segments that hold an
        unknown of ``support`` (all when None): r must be negligible on the others, where the
        solution is zero (and not returned)."""
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
                offs = np.repeat(self.starts[seg] - np.concatenate([[0], np.cumsum(lengths)[:-1]]),
                                 lengths)
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
            gap = sel[d:] - sel[:f - d]  # distance in band order of the pair (i, i + d)
            ok = gap <= w
            vals = np.zeros(f - d)
            vals[ok] = self.band[w - gap[ok], sel[d:][ok]]
            band[w - d, d:] = vals
        band[w] = self.band[w, sel]
        c, info = lapack.dpbtrf(band, lower=0)
        if info != 0:
            raise _not_spd("K_FF")
        self.factor, self.sel = c, sel
        self.stats["factorizations"] += 1


class SparseBlock(_Block):
    """``K_FF`` of a general sparse K, by SuperLU, refactored when the set changes."""

    def __init__(self, K):
        import scipy.sparse as sp

        super().__init__(sp.csc_matrix(K))
        self.lu = None

    def set(self, free: np.ndarray) -> None:
        import scipy.sparse.linalg as spl

        if self.lu is not None and np.array_equal(free, self.index):
            return
        self.index = free
        if free.size == 0:
            self.lu = None
            return
        A = self.K[free][:, free].tocsc()
        try:
            self.lu = spl.splu(A, permc_spec="MMD_AT_PLUS_A",
                               options={"SymmetricMode": True})
        except RuntimeError as exc:
            raise _not_spd(f"K_FF ({exc})") from None
        self.stats["factorizations"] += 1

    def solve(self, r: np.ndarray, support=None):
        if self.lu is None:
            return self.index, np.zeros(0)
        return self.index, self.lu.solve(r[self.index])


def make_block(K, kind: str = "auto"):
    """The block for K: ``"dense"``, ``"banded"``, ``"sparse"`` or ``"auto"`` (dense for a
    dense K; for a sparse K, banded when its bandwidth after reverse Cuthill-McKee is at most
    :data:`MAX_BANDWIDTH`, else SuperLU)."""
    import scipy.sparse as sp

    if not sp.issparse(K):
        if kind in ("auto", "dense"):
            return DenseBlock(K)
        K = sp.csc_matrix(K)
    elif kind == "dense":
        return DenseBlock(K.toarray())
    if kind in ("auto", "banded"):
        perm, width = _banded_order(K)
        if kind == "banded" or width <= MAX_BANDWIDTH:
            return BandedBlock(K, perm, width)
    return SparseBlock(K)


def _banded_order(K) -> tuple[np.ndarray, int]:
    """The natural order if it has the smallest bandwidth, else reverse Cuthill-McKee's, and
    the bandwidth in that order."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    coo = sp.coo_matrix(K)
    natural = int(np.max(np.abs(coo.row - coo.col), initial=0))
    if natural <= 1:
        return np.arange(K.shape[0]), natural
    perm = np.asarray(reverse_cuthill_mckee(sp.csr_matrix(K), symmetric_mode=True),
                      dtype=np.intp)
    rank = np.empty_like(perm)
    rank[perm] = np.arange(perm.size)
    width = int(np.max(np.abs(rank[coo.row] - rank[coo.col]), initial=0))
    if width >= natural:
        return np.arange(K.shape[0]), natural
    return perm, width
