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
rooting (lowest index).

Each pattern is a fresh LU of ``(K T)_BB`` (``O(|B|³)``, no rank-one updates: stiff systems
are small in practice), whose column-scaled condition number is checked: beyond
``1 / (1e6 eps)`` the pattern is an error naming it (the springs left outside the clusters,
or couplings of many scales in one cluster, are then what limits the digits).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SolverError
from ..results import State
from .events import EventSolver
from .pattern import Pattern
from .triples import value

__all__ = [
    "spring_form",
    "Clusters",
    "ClusterPattern",
    "ClusterEventSolver",
    "CLUSTER_RATIO",
    "STIFF",
]

STICK, FORWARD, BACKWARD = int(State.STICK), int(State.FORWARD), int(State.BACKWARD)
_EPS = float(np.finfo(float).eps)
CLUSTER_RATIO = 1e3  # a spring this much stiffer than the largest grounding ties a cluster
STIFF = 1e-10  # eps cond(K) above which exact works in cluster coordinates
_COND_LIMIT = 1.0 / (1e6 * _EPS)  # column-scaled condition of a pattern's matrix: beyond, error


def spring_form(K: np.ndarray):
    """``(g, S)``: groundings (exactly rounded row sums) and springs ``S_ij = -K_ij`` (zero
    diagonal) of a symmetric K, ``K = diag(g) + Σ_{i<j} S_ij (e_i - e_j)(e_i - e_j)ᵀ``."""
    g = np.array([math.fsum(row) for row in K.tolist()])
    S = -np.array(K, dtype=float)
    np.fill_diagonal(S, 0.0)
    return g, S


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
        self.KT0 = M = self.cl.KT(self.root)
        self.kappa = max(1.0, _scaled_condition(M))
        self.rel = max(self.rel, 100.0 * _EPS * self.kappa)
        self.residual = max(self.residual, 1e3 * _EPS * self.kappa)
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
        import scipy.linalg as sla

        return sla.lu_solve(sla.lu_factor(self.cl.KT(self.cl.canonical)), rhs)

    def force_change(self, r):
        """A change r of the start state as the largest change of a node's force relative to
        its force scale."""
        return float(np.max(np.abs(self.KT0 @ r) / self.fscale, initial=0.0))

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
        import scipy.linalg as sla

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
            self.Jt = self.cl.reroot(self.Jt, old, root)
        x = self.cl.reroot(np.asarray(x, dtype=float), self.cl.canonical, root)
        M = self.cl.KT(root)
        B = ~stuck
        Bi = np.nonzero(B)[0]
        sign = np.where(status == FORWARD, -1.0, np.where(status == BACKWARD, 1.0, 0.0))
        Fp = sign[:, None] * self.bt
        X = np.zeros((n, 3))
        X[stuck, 0] = x[stuck]
        if Bi.size:
            A = M[np.ix_(Bi, Bi)]
            cond = _scaled_condition(A)
            if cond > _COND_LIMIT:
                raise SolverError(
                    f"exact: the pattern's equations in cluster coordinates have condition "
                    f"number {cond:.3g} (columns scaled) at θ = {theta:.17g}: the answer "
                    f"could not keep 1e-6 of its digits; springs of many scales in one "
                    f"cluster, or stiff entries that are not springs (K_ij > 0), limit it",
                    backend="exact",
                    status="ill_conditioned",
                )
            rhs = Fp[Bi] - self.Qt[Bi]
            rhs[:, 0] -= M[np.ix_(Bi, np.nonzero(stuck)[0])] @ x[stuck]
            lu = sla.lu_factor(A)
            X[Bi] = sla.lu_solve(lu, rhs)
            # the tangent's G = A⁻¹ (the cycle's first pattern is set before tracking starts)
            self.G[: Bi.size, : Bi.size] = sla.lu_solve(lu, np.eye(Bi.size))
        m = Bi.size
        self.m, self.Bidx[:m] = m, Bi
        self.pos[:] = -1
        self.pos[Bi] = np.arange(m)
        self.Kt = M
        F = self.Qt + M @ X
        if Bi.size:
            res = float(np.max(np.abs(F[Bi] - Fp[Bi])) / np.max(self.fscale))
            if res > self.residual:
                raise SolverError(
                    f"exact: equilibrium residual {res:.3g} of the pattern at θ = {theta:.17g} "
                    f"in cluster coordinates",
                    backend="exact",
                    status="residual",
                )
            F[Bi] = Fp[Bi]
        self.stats["refactorizations"] += 1
        self.root, self.X = root, X
        self.status, self.U, self.Ft, self.sign = status.copy(), self.cl.to_u(X, root), F, sign
        self.B = B
        self.dirty[:] = True
        self.touched[:] = True
        self._any_dirty = True


def _scaled_condition(A: np.ndarray) -> float:
    """2-norm condition number of A with its columns scaled to unit largest entry."""
    if A.size == 0:
        return 1.0
    c = np.max(np.abs(A), axis=0)
    c[c == 0.0] = 1.0
    s = np.linalg.svd(A / c, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else np.inf


class ClusterEventSolver(ClusterPattern, EventSolver):
    """:class:`~lcpfric.exact.events.EventSolver` in cluster coordinates (stiff systems)."""
