"""The exact solver's stick/slip patterns: the closed form of a pattern (the triples of u and F,
``G = K_BB⁻¹`` by a fresh factorization or by rank-one updates as single nodes change state) and
the dissipation of its slipping segments (:mod:`lcpfric.exact.discrete`, "Between events")."""

from __future__ import annotations

import math

import numpy as np

from ..errors import SolverError
from ..results import State
from .tangent import Tangent
from .triples import REL, TWO_PI, multiplier, rate_of, segment_dissipation, value

__all__ = ["Pattern"]

STICK, FORWARD, BACKWARD, SEPARATION = (
    int(State.STICK),
    int(State.FORWARD),
    int(State.BACKWARD),
    int(State.SEPARATION),
)
_RESIDUAL = 1e-10  # equilibrium residual of a fresh pattern above which it is an error
_EPS = float(np.finfo(float).eps)
_SMALL = 256  # G blocks up to this size are updated whole (cheaper than indexing)


class Pattern(Tangent):
    """A stick/slip pattern's closed form (all quantities in scaled units): ``G = K_BB⁻¹`` of
    the nodes that are not stuck, updated by bordering and rank-one downdates as single nodes
    change state, and the trig triples of u and F it gives."""

    def __init__(self, K, f, Qt, Pt, samples, max_events, kappa=1.0):
        from . import kernels  # numba: imported by a discrete solve only (lcpfric.exact.kernels)

        self.kernels = kernels
        self.K = self.Kt = K
        # what round-off through K_BB⁻¹ allows: relative tolerances grow with cond(K)
        self.kappa = kappa
        self.rel = max(REL, 100.0 * _EPS * kappa)
        self.residual = max(_RESIDUAL, 1e3 * _EPS * kappa)
        self.n = n = f.size
        self.Kmul = multiplier(K)
        self.G = np.zeros((n, n))
        self.Bidx = np.zeros(n, dtype=np.intp)
        self.pos = np.full(n, -1, dtype=np.intp)
        self.m = 0
        self._since = 0
        self.U = self.Ft = self.status = None
        self.track = False
        self.Jt = None
        self.theta_row = None
        self.flipped = np.zeros(n, dtype=bool)
        self.W = 0.0
        self.a_seg = np.zeros(n)
        self.t_all = np.full(2 * n, np.inf)
        self.dirty = np.ones(n, dtype=bool)
        self._any_dirty = True
        self.touched = np.ones(n, dtype=bool)
        self.f = f
        self.Qt = Qt  # (n, 3)
        self.Pt = Pt  # (n, 3)
        self.bt = f[:, None] * Pt  # friction limit in contact
        self.dQt, self.dbt, self.dPt = rate_of(Qt), rate_of(self.bt), rate_of(Pt)
        self.max_events = max_events
        # force scale per node (for tolerances) and the system's displacement-rate scale
        self.fscale = (
            np.abs(Qt[:, 0])
            + np.hypot(Qt[:, 1], Qt[:, 2])
            + np.abs(self.bt[:, 0])
            + np.hypot(self.bt[:, 1], self.bt[:, 2])
        )
        fmax = float(np.max(self.fscale))
        self.fscale = np.maximum(self.fscale, 1e-300)
        kmin = float(np.min(np.diag(K)))
        self.rscale = max(fmax / kmin, 1e-300)
        self.rate_scale = np.full(n, self.rscale)  # per node: slip-rate tolerances
        # the displacement the tangential amplitudes make (what moves u; a mean Q0 is taken out)
        self.qscale = max(float(np.max(np.hypot(Qt[:, 1], Qt[:, 2]))) / kmin, 1e-300)
        # contact arcs: P_i < 0 on (sep_i, rec_i) (mod 2π); always / never in contact
        c0, R = Pt[:, 0], np.hypot(Pt[:, 1], Pt[:, 2])
        self.never = c0 + R <= 0.0
        self.always = c0 - R >= 0.0
        self.normal_events = self.normal_event_list()
        self.samples = samples
        self.stats = {
            "lcp_solves": 0,
            "degenerate": 0,
            "refactorizations": 0,
            "skipped_depth": 0.0,
            "flips": 0,
            "free_set_sum": 0,  # the free set's size summed over the flips (its mean: the floor)
        }

    # -- normal events -----------------------------------------------------------------------
    def normal_event_list(self):
        """Sorted (angle in [0, 2π), node, kind) of separations (kind 0) and re-contacts (1)."""
        ev = []
        Pt = self.Pt
        for i in np.nonzero(~self.never & ~self.always)[0]:
            c0, cs, cc = Pt[i]
            R = math.hypot(cs, cc)
            psi = math.atan2(cc, cs)
            h = 2.0 * math.asin(math.sqrt(min((R - c0) / (2.0 * R), 1.0)))
            ev.append((math.fmod(1.5 * math.pi - h - psi + 4 * math.pi, TWO_PI), int(i), 0))
            ev.append((math.fmod(1.5 * math.pi + h - psi + 4 * math.pi, TWO_PI), int(i), 1))
        ev.sort()
        return ev

    def in_contact(self, theta):
        P = value(self.Pt, theta)
        return np.where(self.never, False, np.where(self.always, True, P > 0.0))

    # -- the pattern's closed form -----------------------------------------------------------
    def u_at(self, theta):
        """Displacements at theta (stuck nodes hold theirs)."""
        return value(self.U, theta)

    def set_pattern(self, status, theta, refresh=False, u=None):
        """Triples of u and F for the pattern ``status`` at theta.

        A pattern that differs from the current one in a few nodes is reached by rank-one
        updates (:meth:`_flip`, O(n²) at most for dense K, less where K is sparse); otherwise,
        or every max(64, |B|) updates, it is recomputed from a fresh factorization of K_BB from
        the displacements ``u`` (default: the current ones at theta) and its equilibrium residual
        checked."""
        if not refresh and u is None and self._since < max(64, self.m):
            changed = np.nonzero(self.status != status)[0]
            if changed.size <= 4:
                for j in changed:
                    self.flip(int(j), int(status[j]), theta)
                return
        self.full(status, self.u_at(theta) if u is None else u, theta)

    def settle(self, rows, theta):
        """Add the dissipation of ``rows`` from their segment starts to theta; restart there."""
        sign = self.sign[rows]
        slip = rows[sign != 0.0]
        if slip.size:
            a = self.a_seg[slip]
            self.W += segment_dissipation(self.bt[slip], self.U[slip], -self.sign[slip], a, theta)
        self.a_seg[rows] = theta

    def full(self, status, u, theta):
        import scipy.linalg as sla

        K, n = self.K, self.n
        if self.U is not None:
            self.settle(np.arange(n), theta)
            if self.track:
                for j in (self.B & (status == STICK)).nonzero()[0]:
                    self.tangent_stick(int(j), theta)
            self.flipped |= self.status != status
        self.a_seg[:] = theta
        B = status != STICK
        Bidx = np.nonzero(B)[0]
        m = Bidx.size
        self.m = m
        self.Bidx[:m] = Bidx
        self.pos[:] = -1
        self.pos[Bidx] = np.arange(m)
        self.G[:m, :m] = 0.0
        if m:
            self.G[:m, :m] = sla.cho_solve(sla.cho_factor(K[np.ix_(Bidx, Bidx)]), np.eye(m))
        self.stats["refactorizations"] += 1
        self._since = 0
        sign = np.where(status == FORWARD, -1.0, np.where(status == BACKWARD, 1.0, 0.0))
        Fp = sign[:, None] * self.bt  # prescribed forces (0 when separated)
        uS = np.where(B, 0.0, u)
        U = np.zeros((n, 3))
        U[:, 0] = uS
        if m:
            KuS = self.Kmul(uS)
            rhs = Fp[Bidx] - self.Qt[Bidx]
            rhs[:, 0] -= KuS[Bidx]
            U[Bidx] = self.G[:m, :m] @ rhs
        F = self.prescribed(self.Qt + self.Kmul(U), Fp, Bidx, theta, "(is K well conditioned?)")
        self.status, self.U, self.Ft, self.sign = status.copy(), U, F, sign
        self.B = B
        self.dirty[:] = True
        self.touched[:] = True
        self._any_dirty = True

    def flip(self, j, new, theta):
        """Change node j's state by rank-one updates of G = K_BB⁻¹, U and F, on the rows they
        change (all of them for dense K; the slipping cluster around j for a sparse one)."""
        old = int(self.status[j])
        if old == new:
            return
        self.stats["flips"] += 1
        self.stats["free_set_sum"] += self.m
        sgn = -1.0 if new == FORWARD else (1.0 if new == BACKWARD else 0.0)
        if old == STICK:  # j joins B with a prescribed force
            sup, zs = self.add(j)  # u response (over B) to a unit force at j
            delta = sgn * self.bt[j] - self.Ft[j]
        else:
            p = self.pos[j]
            m = self.m
            col = self.G[:m, p]
            nz = np.nonzero(col)[0]
            sup, zs = self.Bidx[nz], col[nz].copy()
            if new == STICK:  # j leaves B: u_j keeps its value at theta
                if self.track:
                    self.tangent_stick(j, theta)
                du = -self.U[j].copy()
                du[0] += float(value(self.U[j], theta))
                delta = du / col[p]
                self.remove(j)
            else:  # prescribed force changes (slip <-> separation)
                delta = sgn * self.bt[j] - self.Ft[j]
        if 4 * sup.size > self.n:
            z = np.zeros(self.n)
            z[sup] = zs
            Kz = self.Kmul(z)
        else:
            Kz = self.K[:, sup] @ zs
        mask = Kz != 0.0
        mask[sup] = True
        rows = mask.nonzero()[0]
        self.settle(rows, theta)
        self.U[sup] += np.multiply.outer(zs, delta)
        self.Ft[rows] += np.multiply.outer(Kz[rows], delta)
        self.status[j] = new
        self.flipped[j] = True
        self.sign[j] = sgn
        self.B[j] = new != STICK
        if new == STICK:
            self.U[j] = (float(value(self.U[j], theta)), 0.0, 0.0)
        # the nodes of B carry their prescribed forces exactly (K z = e_j only to round-off)
        rb = rows[self.B[rows]]
        self.Ft[rb] = self.sign[rb, None] * self.bt[rb]
        self.dirty[rows] = True
        self.touched[rows] = True
        self._any_dirty = True
        self._since += 1

    def add(self, j):
        """Border G with node j; returns the support (nodes) and values of G's new column."""
        m = self.m
        Bi = self.Bidx[:m]
        kb = self.K[j, Bi]
        nzk = np.nonzero(kb)[0]
        G = self.G
        g = G[:m, nzk] @ kb[nzk] if nzk.size < m else G[:m, :m] @ kb
        s = self.K[j, j] - kb @ g
        if not s > 0:
            raise SolverError(
                f"exact: K_BB lost positive definiteness adding node {j} (pivot {s:.3g})",
                backend="exact",
                status="not_spd",
            )
        sup = g.nonzero()[0]
        if m <= _SMALL or 4 * sup.size > m:
            self.kernels.rank_one(G, m, g, g / s, 1)
        elif sup.size:
            self.kernels.rank_one_on(G, sup, g[sup], g[sup] / s, 1)
        G[:m, m] = G[m, :m] = -g / s
        G[m, m] = 1.0 / s
        self.Bidx[m] = j
        self.pos[j] = m
        self.m = m + 1
        cols = np.append(sup, m)
        return self.Bidx[cols], G[cols, m].copy()

    def remove(self, j):
        """Downdate G = K_BB⁻¹ for B without node j (the last node takes its place)."""
        m, p = self.m, self.pos[j]
        G = self.G
        col = G[:m, p].copy()
        sup = col.nonzero()[0]
        if m <= _SMALL or 4 * sup.size > m:
            self.kernels.rank_one(G, m, col, col / col[p], -1)
        else:
            self.kernels.rank_one_on(G, sup, col[sup], col[sup] / col[p], -1)
        last = m - 1
        if p != last:
            G[p, :last] = G[last, :last]
            G[:last, p] = G[:last, last]
            G[p, p] = G[last, last]
            k = self.Bidx[last]
            self.Bidx[p] = k
            self.pos[k] = p
        G[last, :m] = 0.0
        G[:m, last] = 0.0
        self.pos[j] = -1
        self.m = last

    structured = False  # cluster coordinates (lcpfric.exact.clusters) when True

    def prescribed(self, F, Fp, Bidx, theta, note):
        """F with the nodes of B on their prescribed forces Fp, once their equilibrium
        residual is checked (an error beyond ``self.residual``, ``note`` saying where)."""
        if Bidx.size:
            res = float(np.max(np.abs(F[Bidx] - Fp[Bidx])) / np.max(self.fscale))
            if res > self.residual:
                raise SolverError(
                    f"exact: equilibrium residual {res:.3g} of the pattern at "
                    f"θ = {theta:.17g} {note}",
                    backend="exact",
                    status="residual",
                )
            F[Bidx] = Fp[Bidx]
        return F

    def forces_at(self, theta, u):
        """F at theta from the state u (the current pattern's state)."""
        return value(self.Qt, theta) + self.Kmul(u)

    def state_for_forces(self, rhs):
        """The state of the displacements ``K⁻¹ rhs`` (u itself here)."""
        return self.cho_solve(rhs)

    def cho_solve(self, rhs):
        import scipy.linalg as sla

        if not hasattr(self, "_cho"):
            self._cho = sla.cho_factor(self.K)
        return sla.cho_solve(self._cho, rhs)
