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
from scipy.linalg import lapack

from ..errors import SolverError

__all__ = ["DenseBlock", "BandedBlock", "SparseBlock", "make_block", "not_spd"]

#: largest bandwidth (after reordering) for which the banded Cholesky is used: beyond it the
#: band holds more than a sparse factor would
MAX_BANDWIDTH = 64
#: rank of the dense block's low-rank correction at which it is folded into its inverse
FOLD_RANK = 48


def not_spd(what: str) -> SolverError:
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

    def product(self, cols: np.ndarray, y: np.ndarray) -> np.ndarray:
        """``K x`` for the x that is ``y`` on the unknowns ``cols`` and zero elsewhere."""
        return columns_product(self.K, cols, y)


class DenseBlock(_Block):
    """``K_FF⁻¹`` of a dense K, kept as the inverse ``G0 = K_BB⁻¹`` of a base set B and a
    low-rank correction for the unknowns that joined (J) and left (R) since.

    With ``X = G0 K_BJ`` and ``S = K_JJ - K_JB X``, ``H = K_AA⁻¹`` on ``A = B ∪ J`` is applied
    as ``y = G0 r_B``, ``v = S⁻¹ (Xᵀ r_B - r_J)``, ``H r = (y + X v, -v)``; leaving unknowns
    are removed with ``K_FF⁻¹ = H_FF - H_FR H_RR⁻¹ H_RF``. A solve then costs one product with
    G0 and O(|B| (|J| + |R|)); a change of the set, one product with G0 per joining unknown.
    When ``|J| + |R|`` reaches :data:`FOLD_RANK` the correction is folded into G0 (one
    matrix-matrix product of rank ``|J| + |R|``), and when a quarter of the set changes at
    once G0 is rebuilt from a Cholesky factorization (LAPACK ``potrf``/``potri``). The rows
    ``K_B`` of the base set are kept beside G0, so that a product of K with a vector on the
    free set (:meth:`product`, after every solve) reads ``|F| m`` numbers, not ``m²``."""

    def __init__(self, K):
        super().__init__(np.ascontiguousarray(K, dtype=float))
        self.base = np.empty(0, dtype=np.intp)  # B, in G0's order
        self.G0 = np.zeros((0, 0))
        self.rows = np.zeros((0, self.m))  # K[B]: the products with the free set read these
        self._solved = None  # the unknowns the last solve returned
        self._where = np.full(self.m, -1, dtype=np.intp)  # position in B, or -1
        self._correction(np.empty(0, dtype=np.intp), np.empty(0, dtype=np.intp))

    def set(self, free: np.ndarray) -> None:
        """Make ``free`` (sorted unknowns) the current set."""
        if np.array_equal(free, self.index):
            return
        inside = np.zeros(self.m, dtype=bool)
        inside[free] = True
        left = np.flatnonzero(~inside[self.base])       # positions in B
        joined = free[self._where[free] < 0]             # unknowns not in B
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
        self.G0 = _spd_inverse(self.rows[:, free], "K_FF") if free.size else np.zeros((0, 0))
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
            KJ = K[joined]                                   # (j, m), rows
            KJB = KJ[:, B]
            if fresh:
                XT[fresh] = KJB[fresh] @ G0
            S = KJ[:, joined] - KJB @ XT.T
            Sinv = _spd_inverse(0.5 * (S + S.T), "the Schur complement of the joining unknowns")
        else:
            XT, Sinv = np.zeros((0, B.size)), np.zeros((0, 0))
        self.joined, self.XT, self.Sinv, self.left = joined, XT, Sinv, left
        self.rank = left.size + joined.size
        if left.size:
            # H[:, R]ᵀ: rows of H = K_AA⁻¹ at the leaving positions
            XRS = XT[:, left].T @ Sinv                       # (k, j)
            HRT = np.hstack([G0[left] + XRS @ XT, -XRS])     # (k, |B| + j)
            self.HRT = HRT
            HRR = HRT[:, left]
            self.M = _spd_inverse(0.5 * (HRR + HRR.T), "H_RR")
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

    def solve(self, r: np.ndarray, support=None):
        """``(unknowns, x)``: the solution of ``K_FF x_F = r_F`` on the unknowns of F
        (``support``, the unknowns where r is not negligible, is not used: a dense K couples
        everything)."""
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
        """``K x`` for x equal to ``y`` on ``cols``: for the unknowns of the last solve, from
        the rows of the base set kept in ``rows`` (a product over the free set costs
        ``|F| m``, not ``m²``, and gathers nothing); otherwise as any block."""
        solved = self._solved
        if solved is None or cols is not solved[0]:
            return columns_product(self.K, cols, y)
        keep, nb = solved[1], self.base.size
        yB = np.zeros(nb)
        yB[keep[:nb]] = y[:nb - self.left.size]
        out = yB @ self.rows
        if self.joined.size:
            out += y[nb - self.left.size:] @ self.K[self.joined]
        return out


def columns_product(K, cols: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``K x`` for the x that is ``y`` on the unknowns ``cols`` and zero elsewhere: from those
    columns (rows: K is symmetric) when they are few, else with the whole K."""
    m = K.shape[0]
    if 8 * cols.size < m:
        return K[:, cols] @ y if hasattr(K, "tocsc") else y @ K[cols]
    x = np.zeros(m)
    x[cols] = y
    return K @ x


def _spd_inverse(A: np.ndarray, what: str) -> np.ndarray:
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
            raise not_spd("K_FF")
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
            raise not_spd(f"K_FF ({exc})") from None
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
