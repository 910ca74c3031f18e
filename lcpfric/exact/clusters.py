"""The exact solver on stiff systems: springs, rigid clusters and cluster coordinates.

Why the plain form loses digits
-------------------------------
On a system whose nodes are tied by couplings k_c much stiffer than their grounding k_g (a
nearly rigid chain, a stiff bolt), the displacements of the nodes of a cluster differ by the
stretches of its couplings, O(F / k_c), while they themselves are O(F / k_g). Held as float64
displacements, a stretch is known to ``eps |u|`` only, so a coupling's force ``k_c (u_i - u_j)``
carries an error ``eps k_c / k_g`` relative to the forces, and the Schur complements of
``K_BB`` (:mod:`lcpfric.exact.pattern`) cancel to the same accuracy: W drifts like
``eps cond(K)`` (5e-5 at k_c / k_g = 1e12, ``benchmarks/validation/stiff_chains.py``).

The form used here
------------------
K is read as a spring network: ``K = diag(g) + Σ_{i<j} s_ij (e_i - e_j)(e_i - e_j)ᵀ`` with the
springs ``s_ij = -K_ij`` and the groundings ``g_i = Σ_j K_ij``, the row sums, computed exactly
rounded (:func:`math.fsum`) from the entries as stored: the decomposition is exact for the K
given. Springs stiffer than ``CLUSTER_RATIO`` times the largest grounding tie their nodes into
*clusters*. Each cluster is held in *cluster coordinates* x: its root node's displacement
``c`` and, for every other node, its offset from the root ``w_i = u_i - c`` (so ``u = T x``
with T unit triangular, 0/1 entries). The offsets are small numbers held to their own
relative precision, and the stiff springs act on them alone (their Laplacian annihilates a
cluster's rigid motion), so ``K T`` has the groundings of a cluster in its root column and the
stiff springs in the offset columns, each column of its own scale: the pattern's equations
``(K T)_BB x_B = F_B - Q_B - (K T)_BS x_S`` are well conditioned once the columns are scaled,
and Gaussian elimination with partial pivoting (invariant to column scaling) keeps the digits.

Each pattern is rooted where stuck nodes hold a cluster still: the root of a cluster is its
lowest-index stuck node (its lowest-index node when none is stuck), so a stuck node holds
``x_i`` exactly (the root its c, the others their offsets) and a sliding node's offset is
solved for. Re-rooting (``w' = w - w_ρ'``, ``c' = c + w_ρ'``) moves a whole cluster by the
rounding of ``c'`` at most: no stretch changes. The cycle map works on x in the canonical
rooting (lowest index), with the tangent carried in it (rows re-rooted with the pattern);
periodicity is judged coordinate by coordinate (:meth:`ClusterPattern.state_change`).

A cluster that slides whole has no stuck node to hold it: its root's equation is replaced by
the cluster's equilibrium, its rows summed (``Eᵀ K_soft T``, where the stiff springs cancel
exactly), which is what determines its rigid motion. Rows are not scaled: a pivot row of
another scale would mix its round-off into the offsets of a stiff cluster.

Each pattern is a fresh LU of ``(K T)_BB`` (``O(|B|³)``, no rank-one updates: stiff systems
are small in practice), whose column-scaled condition number is checked: beyond
``DIGITS / eps`` (fewer than 8 digits left) the system is refused before any work, or a
pattern mid-cycle raises, naming it (springs left outside the clusters, couplings of many
scales in one cluster, or stiff entries that are not springs are then what limits the digits).
The groundings are what float64 holds of K: beside a coupling k_c a grounding is known to
``eps k_c``, and W is exact for the K as stored.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError, SolverError
from ..results import State
from .events import EventSolver
from .pattern import Pattern
from .triples import value

__all__ = [
    "spring_form",
    "Clusters",
    "ClusterPattern",
    "ClusterEventSolver",
    "stiff_hint",
    "ScaledLU",
    "CLUSTER_RATIO",
    "DIGITS",
    "STIFF",
]

STICK, FORWARD, BACKWARD = int(State.STICK), int(State.FORWARD), int(State.BACKWARD)
_EPS = float(np.finfo(float).eps)
CLUSTER_RATIO = 1e3  # a spring this much stiffer than the largest grounding ties a cluster
STIFF = 1e-10  # eps cond(K) above which exact works in cluster coordinates
DIGITS = 1e-8  # eps times a pattern's scaled condition number beyond which exact refuses
_COND_LIMIT = DIGITS / _EPS


def spring_form(K: np.ndarray):
    """``(g, S)``: groundings (exactly rounded row sums) and springs ``S_ij = -K_ij`` (zero
    diagonal) of a symmetric K, ``K = diag(g) + Σ_{i<j} S_ij (e_i - e_j)(e_i - e_j)ᵀ``."""
    g = np.array([math.fsum(row) for row in K.tolist()])
    S = -np.array(K, dtype=float)
    np.fill_diagonal(S, 0.0)
    return g, S


def stiff_hint(system) -> str:
    """For an error message: how stiffly K ties nodes into clusters and which method answers
    that ("" when it does not, or for systems too large to look at)."""
    try:
        if system is None or system.matrix_free or system.m > 3000:
            return ""
        g, S = spring_form(np.asarray(system.dense_stiffness(), dtype=float))
    except Exception:  # a hint, never a second error
        return ""
    gmax = float(np.max(np.abs(g)))
    ratio = float(np.max(S)) / gmax if gmax > 0 else np.inf
    if not ratio > CLUSTER_RATIO:
        return ""
    return (
        f"; springs up to {ratio:.2g} times the largest grounding tie nodes into nearly "
        f"rigid clusters, whose slips this method decides node by node: 'exact' solves such "
        f"systems in cluster coordinates (d = 1, harmonic loads)"
    )


class Clusters:
    """The clusters of a stiffness K (d = 1) and ``K T`` for any rooting.

    Attributes
    ----------
    label : (n,) int array
        The cluster of each node.
    stiff : (n, n) bool array
        The springs that tie clusters (symmetric).
    soft, lap : (n, n) arrays
        ``K = soft + lap``: ``lap`` the stiff springs' Laplacian (rows sum to zero within a
        cluster), ``soft`` the groundings and the other springs.
    """

    def __init__(self, K: np.ndarray, ratio: float = CLUSTER_RATIO):
        from scipy.sparse.csgraph import connected_components

        n = K.shape[0]
        g, S = spring_form(K)
        gmax = float(np.max(np.abs(g)))
        stiff = S > ratio * gmax if gmax > 0 else S > 0
        self.count, self.label = connected_components(stiff, directed=False)
        self.stiff = stiff
        lap = np.where(stiff, -S, 0.0)
        np.fill_diagonal(lap, np.where(stiff, S, 0.0).sum(axis=1))
        soft = np.where(stiff, 0.0, -S)
        np.fill_diagonal(soft, g + np.where(stiff | np.eye(n, dtype=bool), 0.0, S).sum(axis=1))
        self.soft, self.lap, self.n = soft, lap, n
        # the soft part's columns summed over each cluster: K 1_cluster, exactly from g
        E = np.zeros((n, self.count))
        E[np.arange(n), self.label] = 1.0
        self.soft_sum = soft @ E
        self.E = E
        self.sizes = E.sum(axis=0)
        self.Esoft = E.T @ soft  # a cluster's rows summed: the stiff springs cancel exactly
        self.EsoftE = self.Esoft @ E
        self.canonical = self.roots(np.zeros(n, dtype=bool))

    def roots(self, stuck: np.ndarray) -> np.ndarray:
        """Root node of every node's cluster: the lowest-index stuck node, else the lowest."""
        n = self.n
        key = np.where(stuck, 0, n) + np.arange(n)  # stuck first, then by index
        best = np.full(self.count, 2 * n)
        np.minimum.at(best, self.label, key)
        return (best % n)[self.label] if n else best[self.label]

    def KT(self, root: np.ndarray) -> np.ndarray:
        """``K T`` for the rooting ``root`` (x -> K u with u = T x)."""
        M = self.soft + self.lap
        r = np.unique(root)
        M[:, r] = self.soft_sum[:, self.label[r]]
        return M

    def summed(self, M: np.ndarray, root: np.ndarray, rows: np.ndarray):
        """M with the rows of the roots ``rows`` replaced by their clusters' rows summed
        (``Eᵀ K_soft T``: the equilibrium of a cluster as a whole, its stiff springs cancelled
        exactly), and the summing operator's labels."""
        M2 = M.copy()
        if rows.size:
            c = self.label[rows]
            r = np.unique(root)
            M2[rows] = self.Esoft[c]
            M2[np.ix_(rows, r)] = self.EsoftE[np.ix_(c, self.label[r])]
        return M2

    @staticmethod
    def to_u(X: np.ndarray, root: np.ndarray) -> np.ndarray:
        """u = T x (rows of X: nodes; any trailing axes)."""
        idx = np.arange(root.size)
        U = X[root] + X
        U[root == idx] = X[root == idx]
        return U

    @staticmethod
    def reroot(x: np.ndarray, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """x (values, one per node) in the rooting ``new`` from the rooting ``old``."""
        moved = old != new
        if not moved.any():
            return x.copy()
        y = x.copy()
        d = x[new[moved]]  # offset of each moved node's new root under the old rooting
        y[moved] = x[moved] - d
        r_old, r_new = old[moved], new[moved]
        y[r_old] = -x[r_new]
        y[r_new] = x[r_old] + x[r_new]
        return y


class ClusterPattern(Pattern):
    """:class:`~lcpfric.exact.pattern.Pattern` in cluster coordinates (module docstring).

    The state passed in and out (``u`` of :meth:`u_at`, :meth:`full`, the cycle map) is x in
    the canonical rooting; ``self.U`` and ``self.Ft`` stay the triples of u and F."""

    structured = True

    def __init__(self, K, f, Qt, Pt, samples, max_events, kappa=1.0):
        self.cl = Clusters(K)
        self.root = self.cl.canonical
        self.X = None
        super().__init__(K, f, Qt, Pt, samples, max_events, 1.0)
        M = self.cl.KT(self.root)
        r = np.unique(self.root)
        whole = r[self.cl.sizes[self.cl.label[r]] > 1]
        self.kappa = max(1.0, ScaledLU(self.cl.summed(M, self.root, whole)).cond)
        if self.kappa > _COND_LIMIT:
            raise InputError(
                "stiffness",
                f"cond(K) = {kappa:.3g}, and {self.cl.count} cluster(s) of stiff springs leave "
                f"a scaled condition number {self.kappa:.3g}: exact's W could not be "
                f"guaranteed to {DIGITS:g} (springs of many scales in one cluster, or stiff "
                f"entries that are not springs, K_ij > 0)",
            )
        self.rel = max(self.rel, 100.0 * _EPS * self.kappa)
        self.residual = max(self.residual, 1e3 * _EPS * self.kappa)
        # the displacement the tangential amplitudes make on the clusters' groundings
        ground = float(np.min(np.diag(self.cl.EsoftE)))
        if ground > 0:
            self.qscale = max(float(np.max(np.hypot(Qt[:, 1], Qt[:, 2]))) / ground, 1e-300)
        # slip rates per node: a stretch rate of a stiff spring, or a stiff node's own rate
        self.rate_scale = np.maximum(self.fscale / np.diag(K), 1e-300)
        self.stats["clusters"] = int(self.cl.count)
        self.stats["condition_scaled"] = self.kappa

    # -- state: x in the canonical rooting ---------------------------------------------------
    def u_at(self, theta):
        return self.cl.reroot(value(self.X, theta), self.root, self.cl.canonical)

    def cho_solve(self, rhs):
        """u = K⁻¹ rhs through cluster coordinates (canonical rooting)."""
        return self.cl.to_u(self.state_for_forces(rhs), self.cl.canonical)

    def state_for_forces(self, rhs):
        """x (canonical) with ``K T x = rhs``, each cluster's rows summed into its root's."""
        root = self.cl.canonical
        r = np.unique(root)
        whole = r[self.cl.sizes[self.cl.label[r]] > 1]
        rhs = np.array(rhs, dtype=float)
        total = np.zeros((self.cl.count,) + rhs.shape[1:])
        np.add.at(total, self.cl.label, rhs)
        rhs[whole] = total[self.cl.label[whole]]
        return ScaledLU(self.cl.summed(self.cl.KT(root), root, whole)).solve(rhs)

    def state_change(self, r, x, ptp):
        """A change r of the start state x (canonical), relative coordinate by coordinate
        beyond its round-off (``100 eps κ |x_i|``): a root against its node's range over the
        cycle ``ptp``, an offset (and a root at rest) against the stretch its node's forces
        make on its stiff springs (``fscale / K_ii``)."""
        roots = self.cl.canonical == np.arange(self.n)
        scale = np.where(roots, np.maximum(ptp, self.rate_scale), self.rate_scale)
        excess = np.maximum(np.abs(r) - 100.0 * _EPS * self.kappa * np.abs(x), 0.0)
        return float(np.max(excess / scale, initial=0.0))

    def forces_at(self, theta, u):
        return value(self.Ft, theta)

    # -- the tangent in cluster coordinates --------------------------------------------------
    def state_triples(self):
        return self.X

    def start_tangent(self):
        J = self.cl.reroot(np.eye(self.n), self.cl.canonical, self.root)
        J[self.status != STICK] = 0.0
        return J

    def jacobian(self):
        return self.cl.reroot(super().jacobian(), self.root, self.cl.canonical)

    def transform(self):
        """(T, T⁻¹) of the canonical rooting, u = T x (integer entries, exact)."""
        T = self.cl.to_u(np.eye(self.n), self.cl.canonical)
        return T, np.rint(np.linalg.inv(T))

    # -- patterns ----------------------------------------------------------------------------
    def set_pattern(self, status, theta, refresh=False, u=None):
        self.full(status, self.u_at(theta) if u is None else u, theta)

    def flip(self, j, new, theta):
        status = self.status.copy()
        status[j] = new
        self.full(status, self.u_at(theta), theta)

    def full(self, status, x, theta):

        n = self.n
        if self.U is not None:
            self.settle(np.arange(n), theta)
            self.flipped |= self.status != status
        self.a_seg[:] = theta
        stuck = status == STICK
        root = self.cl.roots(stuck)
        if self.track and self.U is not None:
            # rows of the nodes that stick now, and of the roots given up while sliding, in
            # the old pattern; then every row in the new rooting
            old = self.root
            gone = np.unique(old[old != root])
            for j in np.nonzero(self.B & (stuck | np.isin(np.arange(n), gone)))[0]:
                self.tangent_stick(int(j), theta)
            self.resolve_trow()
            self.Jt = self.cl.reroot(self.Jt, old, root)
        x = self.cl.reroot(np.asarray(x, dtype=float), self.cl.canonical, root)
        M = self.cl.KT(root)
        B = ~stuck
        Bi = np.nonzero(B)[0]
        sign = np.where(status == FORWARD, -1.0, np.where(status == BACKWARD, 1.0, 0.0))
        Fp = sign[:, None] * self.bt
        X = np.zeros((n, 3))
        X[stuck, 0] = x[stuck]
        # a cluster that slides whole: its root's equation is the cluster's equilibrium
        r = np.unique(root)
        whole = r[~stuck[r] & (self.cl.sizes[self.cl.label[r]] > 1)]
        M2 = self.cl.summed(M, root, whole)
        if Bi.size:
            lu = ScaledLU(M2[np.ix_(Bi, Bi)])
            cond = lu.cond
            if cond > _COND_LIMIT:
                raise SolverError(
                    f"exact: the pattern's equations in cluster coordinates have condition "
                    f"number {cond:.3g} (columns scaled) at θ = {theta:.17g}: the answer "
                    f"could not be guaranteed to {DIGITS:g}; springs of many scales in one "
                    f"cluster, or stiff entries that are not springs (K_ij > 0), limit it",
                    backend="exact",
                    status="ill_conditioned",
                )
            net = Fp - self.Qt
            if whole.size:
                total = np.zeros((self.cl.count, 3))
                np.add.at(total, self.cl.label, net)
                net[whole] = total[self.cl.label[whole]]
            rhs = net[Bi]
            rhs[:, 0] -= M2[np.ix_(Bi, np.nonzero(stuck)[0])] @ x[stuck]
            X[Bi] = lu.solve(rhs)
            # the tangent's G = A⁻¹ (the cycle's first pattern is set before tracking starts)
            self.G[: Bi.size, : Bi.size] = lu.solve(np.eye(Bi.size))
        m = Bi.size
        self.m, self.Bidx[:m] = m, Bi
        self.pos[:] = -1
        self.pos[Bi] = np.arange(m)
        self.Kt = M2
        F = self.prescribed(self.Qt + M @ X, Fp, Bi, theta, "in cluster coordinates")
        self.stats["refactorizations"] += 1
        self.root, self.X = root, X
        self.status, self.U, self.Ft, self.sign = status.copy(), self.cl.to_u(X, root), F, sign
        self.B = B
        self.dirty[:] = True
        self.touched[:] = True
        self._any_dirty = True


class ScaledLU:
    """LU of ``A`` with its columns equilibrated (powers of two, exact), and the 1-norm
    condition number of the scaled matrix (LAPACK's estimate from the factors, O(m²))."""

    def __init__(self, A: np.ndarray):
        import scipy.linalg as sla
        from scipy.linalg.lapack import dgecon

        # rows are not scaled: a pivot row of another scale would mix its round-off into
        # the offsets of a stiff cluster (partial pivoting picks stiff rows for them as is)
        r = np.ones(A.shape[0])
        c = _pow2(np.max(np.abs(A), axis=0))
        As = A / c[None, :]
        self.r, self.c = r, c
        self.lu = sla.lu_factor(As, check_finite=False)
        rcond, info = dgecon(self.lu[0], float(np.max(np.sum(np.abs(As), axis=0))), norm="1")
        self.cond = 1.0 / rcond if info == 0 and rcond > 0 else np.inf

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A⁻¹ b (b: (m,) or (m, k))."""
        import scipy.linalg as sla

        x = sla.lu_solve(self.lu, b / (self.r if b.ndim == 1 else self.r[:, None]))
        return x / (self.c if b.ndim == 1 else self.c[:, None])


def _pow2(v: np.ndarray) -> np.ndarray:
    """The power of two nearest each positive entry (1 for zeros)."""
    out = np.ones_like(v)
    pos = v > 0
    out[pos] = np.exp2(np.round(np.log2(v[pos])))
    return out


class ClusterEventSolver(ClusterPattern, EventSolver):
    """:class:`~lcpfric.exact.events.EventSolver` in cluster coordinates (stiff systems)."""
