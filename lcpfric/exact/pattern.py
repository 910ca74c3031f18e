"""The exact solver's stick/slip patterns: the closed form of a pattern (the triples of u and F,
``G = K_BB⁻¹`` by a fresh factorization or by rank-one updates as single nodes change state) and
the dissipation of its slipping segments (:mod:`lcpfric.exact.discrete`, "Between events")."""

from __future__ import annotations

import math

import numpy as np

from ..errors import SolverError
from ..results import State
from .tangent import Tangent
from .triples import REL, TWO_PI, multiplier, rate_of, value

__all__ = ["Pattern"]

STICK, FORWARD, BACKWARD, SEPARATION = (
    int(State.STICK),
    int(State.FORWARD),
    int(State.BACKWARD),
    int(State.SEPARATION),
)
_RESIDUAL = 1e-10  # equilibrium residual of a fresh pattern above which it is an error
_EPS = float(np.finfo(float).eps)


class Pattern(Tangent):
    """A stick/slip pattern's closed form (all quantities in scaled units): ``G = K_BB⁻¹`` of
    the nodes that are not stuck, updated by bordering and rank-one downdates as single nodes
    change state, and the trig triples of u and F it gives."""

    def __init__(self, K, f, Qt, Pt, samples, max_events, kappa=1.0):
        from . import kernels, loop  # numba: imported by a discrete solve only

        self.kernels, self.loop = kernels, loop
        self.ints = np.zeros(kernels.N_INTS, dtype=np.int64)
        self.fl = np.zeros(kernels.N_FL)
        self.ints[kernels.FLIPS_OK] = not self.structured
        self.ints[kernels.MAX_EVENTS] = max_events
        self.K = self.Kt = K = np.ascontiguousarray(K, dtype=float)
        self.KT = K if np.array_equal(K, K.T) else np.ascontiguousarray(K.T)
        self.n = n = f.size
        # K's columns, compressed, when it is mostly zeros (a chain): K z on the rows it reaches
        if np.count_nonzero(K) <= 0.25 * n * n:
            import scipy.sparse as sp

            C = sp.csc_matrix(K)
            self.csc = (C.indptr.astype(np.intp), C.indices.astype(np.intp), C.data)
        else:
            self.csc = (np.zeros(0, np.intp), np.zeros(0, np.intp), np.zeros(0))
        # what round-off through K_BB⁻¹ allows: relative tolerances grow with cond(K)
        self.kappa = kappa
        self.rel = max(REL, 100.0 * _EPS * kappa)
        self.residual = max(_RESIDUAL, 1e3 * _EPS * kappa)
        self.Kmul = multiplier(K)
        self.G = np.zeros((n, n))
        self.Bidx = np.zeros(n, dtype=np.intp)
        self.pos = np.full(n, -1, dtype=np.intp)
        self.U = self.Ft = self.status = None
        self.Jt = None
        self.trow = np.zeros(n)
        self._noJ = np.zeros((1, 1))
        self.flipped = np.zeros(n, dtype=bool)
        self.a_seg = np.zeros(n)
        self.t_all = np.full(2 * n, np.inf)
        self.dirty = np.ones(n, dtype=bool)
        self._any_dirty = True
        self.touched = np.ones(n, dtype=bool)
        ii, ff, bb = np.zeros(n + 1, np.intp), np.zeros(n + 1), np.zeros(n, dtype=bool)
        self.wk = (ii, ii[:n].copy(), ii[:n].copy(), ff, ff[:n].copy(), ff[:n].copy())
        self.wk += (ff[:n].copy(), ff[:n].copy(), bb)
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
        ev = self.normal_events
        self.normal = (
            np.array([e[0] for e in ev], dtype=float),
            np.array([e[1] for e in ev], dtype=np.intp),
            np.array([e[2] for e in ev], dtype=np.intp),
        )
        self.samples = samples
        self.stats = {
            "lcp_solves": 0,
            "degenerate": 0,
            "refactorizations": 0,
        }

    # -- the compiled kernels' state (lcpfric.exact.kernels) ---------------------------------
    def _slot(name, store="ints", kind=int):  # noqa: N805 - a property factory
        def get(self):
            return kind(getattr(self, store)[getattr(self.kernels, name)])

        def put(self, value):
            getattr(self, store)[getattr(self.kernels, name)] = value

        return property(get, put)

    m = _slot("M")
    _since = _slot("SINCE")
    _any_dirty = _slot("ANY_DIRTY", kind=bool)
    track = _slot("TRACK", kind=bool)
    erased = _slot("ERASED", kind=bool)
    W = _slot("W", "fl", float)
    rel = _slot("RELTOL", "fl", float)
    del _slot

    def kernel_stats(self):
        """The counters the kernels keep: changes of state (``flips``), the free set's size
        summed over them (its mean: the floor), the deepest dip not treated as an event."""
        k = self.kernels
        return {
            "flips": int(self.ints[k.FLIPS]),
            "free_set_sum": int(self.ints[k.FREE_SUM]),
            "skipped_depth": float(self.fl[k.SKIPPED]),
        }

    def bundles(self):
        """The state as the kernels take it: (lin, tri, flg, tan, wk)."""
        lin = (self.K, self.KT, *self.csc, self.G, self.Bidx, self.pos)
        tri = (self.U, self.Ft, self.bt, self.sign, self.status, self.B, self.a_seg)
        J = self._noJ if self.Jt is None else self.Jt
        tan = (J, self.Kt, self.state_triples(), self.trow, self.dbt)
        return lin, tri, (self.dirty, self.touched, self.flipped), tan, self.wk

    def raise_code(self, code):
        """The error a kernel's code < 0 stands for."""
        if code == self.kernels.NOT_SPD:
            j, s = int(self.ints[self.kernels.ERR_NODE]), float(self.fl[self.kernels.ERR_VALUE])
            raise SolverError(
                f"exact: K_BB lost positive definiteness adding node {j} (pivot {s:.3g})",
                backend="exact",
                status="not_spd",
            )

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

        A pattern that differs from the current one in a few nodes is reached by single
        changes of state (:meth:`flip`, O(n²) at most for dense K, less where K is sparse);
        otherwise, or every max(64, |B|) changes, it is recomputed from a fresh factorization
        of K_BB from the displacements ``u`` (default: the current ones at theta) and its
        equilibrium residual checked."""
        if not refresh and u is None:
            code = self.loop.set_flips(status, theta, *self.bundles(), self.ints, self.fl)
            self.raise_code(code)
            if code == self.loop.DONE:
                return
        self.full(status, self.u_at(theta) if u is None else u, theta)

    def settle(self, rows, theta):
        """Add the dissipation of ``rows`` from their segment starts to theta; restart there."""
        rows = np.asarray(rows, dtype=np.intp)
        self.kernels.settle(rows, rows.size, theta, self.bundles()[1], self.fl)

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
        self.status = np.array(status, dtype=np.int8)
        self.U, self.Ft, self.sign = U, np.ascontiguousarray(F), sign
        self.B = B
        self.dirty[:] = True
        self.touched[:] = True
        self._any_dirty = True

    def flip(self, j, new, theta):
        """Change node j's state at theta (:func:`lcpfric.exact.kernels.flip`: G by bordering
        or a rank-one downdate, U and F on the rows they change)."""
        code = self.kernels.flip(j, new, theta, *self.bundles(), self.ints, self.fl)
        self.raise_code(code)

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
