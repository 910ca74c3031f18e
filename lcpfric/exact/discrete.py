"""The exact periodic steady state of a discrete system (d = 1), event by event.

The system is ``F = Q(θ) + K u``, ``|F_i| <= f_i N_i(θ)``, ``N_i = max(P_i(θ), 0)``, θ = ωt, with
every load harmonic at the one frequency ω (each node its own mean, amplitude and phase for P and
for Q) and K symmetric positive definite, dense or sparse.

Between events: closed form
---------------------------
Write every load as a *trig triple* ``x(θ) = c0 + cs sin θ + cc cos θ``. Within a fixed pattern
(each node stuck, slipping forward with ``F_i = -f_i P_i``, slipping backward with
``F_i = +f_i P_i``, or separated with ``F_i = 0``) the stuck nodes S keep their displacements
and the others B carry known forces, so::

    u_B(θ) = K_BB⁻¹ (F_B(θ) - Q_B(θ) - K_BS u_S),     F(θ) = Q(θ) + K u(θ)

are trig triples too. Every event is where one of them crosses zero:

* a stuck node reaches a friction limit: ``f_i P_i ∓ F_i = 0``;
* a slip rate vanishes: ``±du_i/dθ = 0``;
* a node separates or re-enters contact: ``P_i = 0``.

``c0 + R sin(θ + ψ) = 0`` is solved in closed form (:func:`next_entry`), and the dissipation
of a segment, ``Σ_slip ∫ f_i P_i |du_i|``, is integrated in closed form
(:func:`segment_dissipation`).

At an event: the rate problem
-----------------------------
Which nodes slip after an event is decided by the slip-rate complementarity problem, a P-matrix
LCP (:func:`lcpfric.steppers.rates.slip_rates`, the explicit stepper's too, with the
load rates at the event). The common case, one node changing state, is first tried as a guess
(the node that reached its limit slips, the node whose rate vanished sticks) and accepted when
the rates of the new pattern satisfy the LCP's conditions at the event; that is the LCP's unique
solution, at O(n²) instead of O(|B|³). Degenerate instants, where the first-order rates leave a
tie (a node touching its limit with zero margin rate), are resolved by the LCP with the load
rates a little after the event; an instant that still does not settle raises
:class:`~lcpfric.errors.SolverError` naming the nodes and their states, never a hang.

The inverse ``G = K_BB⁻¹`` is updated by bordering when a node joins B and by a rank-one
downdate when it leaves (O(|B|²) each), and refactorized after max(32, |B|) updates or whenever
the equilibrium residual of the new pattern exceeds 1e-10 of the force scale.

Tolerances
----------
A margin or rate is *meaningfully* negative when its minimum is below ``-rel`` of its node's
force (or the system's rate) scale, ``rel = max(1e-13, 100 eps cond(K))``: round-off through
``K_BB⁻¹`` grows with the conditioning. Shallower dips, a node touching its limit without
slipping, are not events; the deepest one skipped is reported (``skipped_depth``), and the
dissipation it could hide is below that depth times the largest compliance times the largest
friction limit. A fresh pattern whose equilibrium residual exceeds ``max(1e-10, 1e3 eps cond(K))``
raises :class:`~lcpfric.errors.SolverError`.

Cycles
------
The first cycle starts at θ = 0 from an admissible state (forces ``clip(Q(0), -f N, f N)``).
The cycle map ``u(0) -> u(2π)`` is then solved by Newton's method with its exact Jacobian,
propagated along the cycle: a node that sticks holds ``u_j = U_j(θ)``, which depends on the
stuck displacements through ``-(G K_BS)_j`` and, when it is stopped by another node reaching
its limit (not by its own slip rate vanishing), on that event's angle, whose sensitivity is
``-(∂g/∂u_S) / g'`` for the margin g that triggered it. With the sequence of events settled
the convergence is quadratic; where a node sits on the threshold of slipping (a tiny slip that
appears in one cycle and not the next) the cycle map has a kink there and the convergence is
linear (``benchmarks/exact_discrete.py`` reports the cycles). A node that never changes state
keeps its start displacement (the steady state is not unique in it, the dissipation is).
Cycles stop when the start displacements of two successive cycles agree to ``tol`` of the
largest displacement range over the cycle (what the slips are measured against; at least
the displacement ``max |Q1| / min K_ii`` the tangential amplitudes make; a mean
tangential load Q0 is taken out beforehand, as it only shifts u by ``-K⁻¹ Q0``), or to the
round-off ``100 eps cond(K) max(|u|, max f N / min K_ii)``, if larger; with uncoupled normal
reactions the steady dissipation is unique (Barber, Klarbring and Ciavarella), so the start
does not change it. When the first cycle already repeats (every node's history erased by
separation) no Jacobian is computed. Where Newton's step makes no progress (less than 10 % off
the change), it is halved from the best start so far, down to 1/8, then one plain cycle-map
step is taken. The number of cycles and of Newton steps is reported.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError, SolverError
from ..results import State
from ..steppers.rates import slip_rates

__all__ = ["DiscreteCycle", "harmonic_triples", "next_entry", "segment_dissipation",
           "exact_system_cycle"]

STICK, FORWARD, BACKWARD, SEPARATION = (int(State.STICK), int(State.FORWARD),
                                        int(State.BACKWARD), int(State.SEPARATION))
TWO_PI = 2.0 * math.pi
_REL = 1e-13             # a dip below this fraction of its scale is an event
_SAME = 64 * np.finfo(float).eps * TWO_PI   # events closer than this happen together
_ETAS = (1e-9, 1e-7, 1e-5, 1e-3)   # load-rate look-ahead for degenerate instants
_RESIDUAL = 1e-10        # equilibrium residual of a fresh pattern above which it is an error
_EPS = float(np.finfo(float).eps)
_SMALL = 256             # G blocks up to this size are updated whole (cheaper than indexing)


# ---------------------------------------------------------------------------------------------
# trig triples
def harmonic_triples(loads, omega: float, parameter: str) -> np.ndarray:
    """(n, 3) triples ``(c0, cs, cc)`` of harmonic loads at the angular frequency ``omega``.

    ``mean + a sin(ωt + ψ) = mean + a cos ψ sin θ + a sin ψ cos θ``. A load with a harmonic of
    another frequency raises :class:`InputError` naming ``parameter``.
    """
    from ..model.loads import Fourier

    out = np.zeros((len(loads), 3))
    for i, load in enumerate(loads):
        if not isinstance(load, Fourier):
            raise InputError(parameter, f"'exact' needs harmonic loads (Harmonic or a one-term "
                                        f"Fourier); load {i} is {type(load).__name__}: use "
                                        f"'explicit' or a solver backend")
        amps = [a for a in load.amplitudes[1:] if a]
        if amps:
            raise InputError(parameter, f"'exact' needs harmonic loads of one frequency; load "
                                        f"{i} has higher harmonics: use 'explicit' or a solver "
                                        f"backend")
        a = load.amplitudes[0] if load.amplitudes else 0.0
        if a and not math.isclose(load.omega, omega, rel_tol=1e-12):
            raise InputError(parameter, f"'exact' needs one frequency; load {i} has ω = "
                                        f"{load.omega}, others {omega}")
        p = load.phases[0] if load.phases else 0.0
        out[i] = (load.mean, a * math.cos(p), a * math.sin(p)) if a else (load.mean, 0.0, 0.0)
    return out


def _value(T, theta):
    """Triples T (..., 3) at the angle(s) theta (broadcast on the leading axis)."""
    s, c = np.sin(theta), np.cos(theta)
    return T[..., 0] + T[..., 1] * s + T[..., 2] * c


def _rate(T):
    """d/dθ of triples: ``cs cos θ - cc sin θ`` -> (0, -cc, cs)."""
    D = np.empty_like(T)
    D[..., 0] = 0.0
    D[..., 1] = -T[..., 2]
    D[..., 2] = T[..., 1]
    return D


def next_entry(T: np.ndarray, theta: float, tol, skipped: bool = False):
    """Per row of T, the first angle >= ``theta`` where ``g = c0 + cs sin + cc cos`` enters the
    arc where it is below ``-tol`` (inf when it never is).

    ``g = c0 + R sin(x)``, ``x = θ + ψ``, is negative on the arc centred at ``x = 3π/2`` of
    half-width ``h = 2 asin(sqrt(depth / 2R))``, depth = R - c0 (written so that a shallow arc
    keeps its digits). A dip shallower than ``tol`` (a touch) is not an entry. When θ is in the
    first half of the arc (g falling or at its minimum) the entry is ``theta`` itself; in the
    second half g is rising back and, unless it is still below ``-tol``, the next entry is one
    period on; c0 <= -R (negative everywhere) enters at theta. With ``skipped``, also returns
    the deepest dip not treated as an entry, as a fraction of ``tol`` times ``_REL`` (the
    scale-relative depth).
    """
    c0, cs, cc = T[:, 0], T[:, 1], T[:, 2]
    R = np.hypot(cs, cc)
    depth = R - c0
    with np.errstate(divide="ignore", invalid="ignore"):
        h = 2.0 * np.arcsin(np.sqrt(np.minimum(depth / (2.0 * R), 1.0)))
        x = theta + np.arctan2(cc, cs)
        d = np.mod(x - (1.5 * math.pi - h), TWO_PI)      # angle past the entry
        now = (d < 2.0 * h) & ((d <= h) | (c0 + R * np.sin(x) < -tol))
        out = np.where(now | (depth >= 2.0 * R), theta, theta + (TWO_PI - d))
        shallow = depth <= tol
        out[shallow] = np.inf
        if skipped:
            skip = float(np.max(depth[shallow] / tol[shallow], initial=0.0)) * _REL \
                if np.ndim(tol) else float(np.max(depth[shallow], initial=0.0) / tol) * _REL
    return (out, skip) if skipped else out


def segment_dissipation(b: np.ndarray, U: np.ndarray, sign: np.ndarray, a, e: float) -> float:
    """``Σ_i sign_i ∫_{a_i}^e b_i(θ) du_i/dθ dθ`` for triples b (bounds) and U (displacements):
    the dissipation of slipping nodes from their angles ``a`` (scalar or per row) to ``e``, in
    closed form.

    With ``b = b0 + bs S + bc C`` and ``du = us C - uc S``::

        ∫ b du = b0 (us ΔS + uc ΔC) + (bs us - bc uc) Δ(S²)/2 + (bc us - bs uc) Δθ/2
                 + (bc us + bs uc) Δ(sin 2θ)/4

    each difference written with half-angles (``ΔS = 2 cos m sin h``, ...) to keep the digits of
    short segments.
    """
    if b.shape[0] == 0:
        return 0.0
    a = np.asarray(a, dtype=float)
    m, h = 0.5 * (a + e), 0.5 * (e - a)
    sh = np.sin(h)
    dS = 2.0 * np.cos(m) * sh
    dC = -2.0 * np.sin(m) * sh
    dS2 = dS * (np.sin(a) + math.sin(e)) * 0.5
    d2 = 2.0 * np.cos(2.0 * m) * np.sin(2.0 * h)
    b0, bs, bc = b[:, 0], b[:, 1], b[:, 2]
    us, uc = U[:, 1], U[:, 2]
    per = (b0 * (us * dS + uc * dC) + (bs * us - bc * uc) * dS2 + (bc * us - bs * uc) * h
           + (bc * us + bs * uc) * (0.25 * d2))
    return float(sign @ per)


def _multiplier(K):
    """``x -> K @ x``, through a sparse copy of K when it is mostly zeros (a chain)."""
    n = K.shape[0]
    if n >= 400 and np.count_nonzero(K) <= 0.05 * n * n:
        import scipy.sparse as sp

        Ks = sp.csr_matrix(K)
        return Ks.__matmul__
    return K.__matmul__


# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DiscreteCycle:
    """The exact steady cycle of a discrete system.

    Attributes
    ----------
    W : float
        Dissipation per cycle (model units).
    W_cycles : ndarray
        W of every cycle run (the last is the steady one).
    cycles : int
        Cycles run until the start of a cycle repeated (to ``tol``).
    change : float
        The relative change of the start displacements over the last cycle.
    events : int
        Events in the steady cycle.
    omega : float
        The loads' angular frequency (θ = ωt).
    theta, u, F, N, state : ndarray
        The steady cycle sampled at the angles ``theta`` (rows), one column per node.
    stats : dict
        ``events_per_cycle``, ``lcp_solves`` (fallbacks to the full rate LCP), ``degenerate``
        (instants resolved by look-ahead), ``refactorizations``, ``skipped_depth`` (the deepest
        dip not treated as an event, relative to its scale), ``seconds``.
    """

    W: float
    W_cycles: np.ndarray
    cycles: int
    change: float
    events: int
    omega: float
    theta: np.ndarray
    u: np.ndarray
    F: np.ndarray
    N: np.ndarray
    state: np.ndarray
    stats: dict = field(default_factory=dict)


class _Solver:
    """Event-by-event integration of one system (all quantities in scaled units)."""

    def __init__(self, K, f, Qt, Pt, samples, max_events, kappa=1.0):
        self.K = K
        # what round-off through K_BB⁻¹ allows: relative tolerances grow with cond(K)
        self.kappa = kappa
        self.rel = max(_REL, 100.0 * _EPS * kappa)
        self.residual = max(_RESIDUAL, 1e3 * _EPS * kappa)
        self.n = n = f.size
        self.Kmul = _multiplier(K)
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
        self.Qt = Qt                       # (n, 3)
        self.Pt = Pt                       # (n, 3)
        self.bt = f[:, None] * Pt          # friction limit in contact
        self.dQt, self.dbt, self.dPt = _rate(Qt), _rate(self.bt), _rate(Pt)
        self.max_events = max_events
        # force scale per node (for tolerances) and the system's displacement-rate scale
        self.fscale = (np.abs(Qt[:, 0]) + np.hypot(Qt[:, 1], Qt[:, 2])
                       + np.abs(self.bt[:, 0]) + np.hypot(self.bt[:, 1], self.bt[:, 2]))
        fmax = float(np.max(self.fscale))
        self.fscale = np.maximum(self.fscale, 1e-300)
        kmin = float(np.min(np.diag(K)))
        self.rscale = max(fmax / kmin, 1e-300)
        # the displacement the tangential amplitudes make (what moves u; a mean Q0 is taken out)
        self.qscale = max(float(np.max(np.hypot(Qt[:, 1], Qt[:, 2]))) / kmin, 1e-300)
        # contact arcs: P_i < 0 on (sep_i, rec_i) (mod 2π); always / never in contact
        c0, R = Pt[:, 0], np.hypot(Pt[:, 1], Pt[:, 2])
        self.never = c0 + R <= 0.0
        self.always = c0 - R >= 0.0
        self.normal_events = self._normal_events()
        self.samples = samples
        self.stats = {"lcp_solves": 0, "degenerate": 0, "refactorizations": 0,
                      "skipped_depth": 0.0}

    # -- normal events -----------------------------------------------------------------------
    def _normal_events(self):
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
        P = _value(self.Pt, theta)
        return np.where(self.never, False, np.where(self.always, True, P > 0.0))

    # -- the pattern's closed form -----------------------------------------------------------
    def u_at(self, theta):
        """Displacements at theta (stuck nodes hold theirs)."""
        return _value(self.U, theta)

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
                    self._flip(int(j), int(status[j]), theta)
                return
        self._full(status, self.u_at(theta) if u is None else u, theta)

    def _settle(self, rows, theta):
        """Add the dissipation of ``rows`` from their segment starts to theta; restart there."""
        sign = self.sign[rows]
        slip = rows[sign != 0.0]
        if slip.size:
            a = self.a_seg[slip]
            self.W += segment_dissipation(self.bt[slip], self.U[slip], -self.sign[slip], a,
                                          theta)
        self.a_seg[rows] = theta

    def _full(self, status, u, theta):
        import scipy.linalg as sla

        K, n = self.K, self.n
        if self.U is not None:
            self._settle(np.arange(n), theta)
            if self.track:
                for j in (self.B & (status == STICK)).nonzero()[0]:
                    self._tangent_stick(int(j), theta)
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
        Fp = sign[:, None] * self.bt                  # prescribed forces (0 when separated)
        uS = np.where(B, 0.0, u)
        U = np.zeros((n, 3))
        U[:, 0] = uS
        if m:
            KuS = self.Kmul(uS)
            rhs = Fp[Bidx] - self.Qt[Bidx]
            rhs[:, 0] -= KuS[Bidx]
            U[Bidx] = self.G[:m, :m] @ rhs
        F = self.Qt + self.Kmul(U)
        if m:
            res = float(np.max(np.abs(F[Bidx] - Fp[Bidx])) / np.max(self.fscale))
            if res > self.residual:
                raise SolverError(f"exact: equilibrium residual {res:.3g} of the pattern at "
                                  f"θ = {theta:.17g} (is K well conditioned?)", backend="exact",
                                  status="residual")
            F[Bidx] = Fp[Bidx]
        self.status, self.U, self.Ft, self.sign = status.copy(), U, F, sign
        self.B = B
        self.dirty[:] = True
        self.touched[:] = True
        self._any_dirty = True

    # -- the cycle map's Jacobian ------------------------------------------------------------
    def _tangent_stick(self, j, theta):
        """Node j (in B) sticks at theta: its held displacement ``u_j = U_j(θ)`` depends on
        the stuck displacements through ``-(G K_BS)_j``, and on the event angle through its rate
        ``U_j'(θ)``: zero when its slip stops by itself, not when it is stopped by another node
        reaching its limit at theta (then ``self.theta_row``, that angle's own sensitivity)."""
        m, p = self.m, self.pos[j]
        g = self.G[p, :m]
        nz = g.nonzero()[0]
        row = -(g[nz] @ self.K[self.Bidx[nz], :])
        row[self.B] = 0.0
        k = row.nonzero()[0]
        self.Jt[j] = row[k] @ self.Jt[k] if k.size else 0.0
        if self.theta_row is not None:
            rate = float(_value(_rate(self.U[j]), theta))
            self.Jt[j] += rate * self.theta_row

    def _theta_sensitivity(self, j, upper, theta):
        """d(event angle)/d(start state) for stuck node j reaching its upper (or lower) limit:
        ``-(∂g/∂u_S · J_S) / g'`` with g the margin and ``∂F_j/∂u_S = K_jS - K_jB G K_BS``."""
        m = self.m
        Bi = self.Bidx[:m]
        s_row = self.K[j].copy()
        if m:
            kj = self.K[j, Bi]
            nz = kj.nonzero()[0]
            w = kj[nz] @ self.G[nz, :m]
            nw = w.nonzero()[0]
            s_row -= w[nw] @ self.K[Bi[nw], :]
        s_row[self.B] = 0.0
        sigma = 1.0 if upper else -1.0
        dg = float(_value(self.dbt[j], theta)) - sigma * float(_value(_rate(self.Ft[j]), theta))
        if not dg < 0.0:
            return None
        k = s_row.nonzero()[0]
        return sigma * (s_row[k] @ self.Jt[k]) / dg

    def jacobian(self):
        """The cycle map's Jacobian d u(2π) / d u(0) (after a tracked cycle): stuck nodes carry
        their rows; slaved ones (B) follow the stuck ones through ``-G K_BS``."""
        J = self.Jt.copy()
        m = self.m
        if m:
            Bi = self.Bidx[:m]
            S = (~self.B).nonzero()[0]
            J[Bi] = -(self.G[:m, :m] @ self.K[np.ix_(Bi, S)]) @ self.Jt[S]
        return J

    def _flip(self, j, new, theta):
        """Change node j's state by rank-one updates of G = K_BB⁻¹, U and F, on the rows they
        change (all of them for dense K; the slipping cluster around j for a sparse one)."""
        old = int(self.status[j])
        if old == new:
            return
        sgn = -1.0 if new == FORWARD else (1.0 if new == BACKWARD else 0.0)
        if old == STICK:                      # j joins B with a prescribed force
            sup, zs = self._add(j)            # u response (over B) to a unit force at j
            delta = sgn * self.bt[j] - self.Ft[j]
        else:
            p = self.pos[j]
            m = self.m
            col = self.G[:m, p]
            nz = np.nonzero(col)[0]
            sup, zs = self.Bidx[nz], col[nz].copy()
            if new == STICK:                  # j leaves B: u_j keeps its value at theta
                if self.track:
                    self._tangent_stick(j, theta)
                du = -self.U[j].copy()
                du[0] += float(_value(self.U[j], theta))
                delta = du / col[p]
                self._remove(j)
            else:                             # prescribed force changes (slip <-> separation)
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
        self._settle(rows, theta)
        self.U[sup] += np.multiply.outer(zs, delta)
        self.Ft[rows] += np.multiply.outer(Kz[rows], delta)
        self.status[j] = new
        self.flipped[j] = True
        self.sign[j] = sgn
        self.B[j] = new != STICK
        if new == STICK:
            self.U[j] = (float(_value(self.U[j], theta)), 0.0, 0.0)
        # the nodes of B carry their prescribed forces exactly (K z = e_j only to round-off)
        rb = rows[self.B[rows]]
        self.Ft[rb] = self.sign[rb, None] * self.bt[rb]
        self.dirty[rows] = True
        self.touched[rows] = True
        self._any_dirty = True
        self._since += 1

    def _add(self, j):
        """Border G with node j; returns the support (nodes) and values of G's new column."""
        m = self.m
        Bi = self.Bidx[:m]
        kb = self.K[j, Bi]
        nzk = np.nonzero(kb)[0]
        G = self.G
        g = G[:m, nzk] @ kb[nzk] if nzk.size < m else G[:m, :m] @ kb
        s = self.K[j, j] - kb @ g
        if not s > 0:
            raise SolverError(f"exact: K_BB lost positive definiteness adding node {j} "
                              f"(pivot {s:.3g})", backend="exact", status="not_spd")
        sup = g.nonzero()[0]
        if m <= _SMALL or 4 * sup.size > m:
            G[:m, :m] += np.multiply.outer(g, g / s)
        elif sup.size:
            G[np.ix_(sup, sup)] += np.multiply.outer(g[sup], g[sup] / s)
        G[:m, m] = G[m, :m] = -g / s
        G[m, m] = 1.0 / s
        self.Bidx[m] = j
        self.pos[j] = m
        self.m = m + 1
        cols = np.append(sup, m)
        return self.Bidx[cols], G[cols, m].copy()

    def _remove(self, j):
        """Downdate G = K_BB⁻¹ for B without node j (the last node takes its place)."""
        m, p = self.m, self.pos[j]
        G = self.G
        col = G[:m, p].copy()
        sup = col.nonzero()[0]
        if m <= _SMALL or 4 * sup.size > m:
            G[:m, :m] -= np.multiply.outer(col, col / col[p])
        else:
            G[np.ix_(sup, sup)] -= np.multiply.outer(col[sup], col[sup] / col[p])
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

    # -- events ------------------------------------------------------------------------------
    def next_event(self, theta):
        """Entry angles of every constraint of the pattern, shape (2n,): rows 0..n-1 the upper
        margin ``f P - F`` of a stuck node or the slip rate ``±du/dθ`` of a slipping one; rows
        n..2n-1 the lower margin ``f P + F`` of a stuck node (inf elsewhere). Only the rows
        whose functions changed since the last call are recomputed."""
        if not self._any_dirty:
            return self.t_all
        n = self.n
        self._any_dirty = False
        rows = self.dirty.nonzero()[0]
        if rows.size:
            self.dirty[:] = False
            st = self.status[rows]
            stick = (st == STICK)[:, None]
            D = np.where(st == FORWARD, 1.0, np.where(st == BACKWARD, -1.0, 0.0))
            k = rows.size
            T = np.empty((2 * k, 3))
            bt, Ft = self.bt[rows], self.Ft[rows]
            T[:k] = np.where(stick, bt - Ft, D[:, None] * _rate(self.U[rows]))
            T[k:] = np.where(stick, bt + Ft, 0.0)
            ftol = self.rel * self.fscale[rows]
            tol = np.concatenate([np.where(stick[:, 0], ftol, self.rel * self.rscale), ftol])
            t, skipped = next_entry(T, theta, tol, skipped=True)
            if skipped > self.stats["skipped_depth"]:
                self.stats["skipped_depth"] = skipped
            self.t_all[rows] = t[:k]
            self.t_all[rows + n] = t[k:]
        return self.t_all

    # -- deciding the pattern at an event ----------------------------------------------------
    def decide(self, theta, guess, touch_lo, touch_hi, attempt, recontact=None):
        """The pattern valid just after theta.

        First the guess, corrected by principal pivots on the actual pattern (least index: a
        slipping node whose rate is negative sticks, a stuck node driven through its limit
        slips; for a P-matrix this terminates at the LCP's unique solution). After
        ``4 + changes`` pivots, or at a degenerate instant (``attempt`` >= 1), the rate LCP
        decides, with the load rates at theta + η when ``attempt`` >= 2."""
        if attempt == 0:
            pattern = guess.copy()
            for _ in range(4 + int(np.sum(guess != self.status))):
                self.set_pattern(pattern, theta)
                i, new = self._violation(theta)
                if i < 0:
                    return
                if new is None:
                    break
                pattern[i] = new
        eta = 0.0 if attempt <= 1 else _ETAS[min(attempt - 2, len(_ETAS) - 1)]
        if attempt >= 2:
            self.stats["degenerate"] += 1
        self.stats["lcp_solves"] += 1
        u = self.u_at(theta)
        sep = guess == SEPARATION
        F0 = _value(self.Qt, theta) + self.Kmul(u)
        bound = np.where(sep, 0.0, np.maximum(_value(self.bt, theta), 0.0))
        slipping = (guess == FORWARD) | (guess == BACKWARD)
        F0 = np.where(sep, 0.0, np.where(guess == FORWARD, -bound,
                                          np.where(guess == BACKWARD, bound, F0)))
        F0 = np.where(touch_hi, bound, np.where(touch_lo, -bound, F0))
        if recontact is not None and recontact.any():
            # re-entering contact: N = 0 and F = 0 (it was separated), on both limits
            bound, F0 = np.where(recontact, 0.0, bound), np.where(recontact, 0.0, F0)
        tr = theta + eta
        dQ = _value(self.dQt, tr)
        dN = np.where(sep, 0.0, _value(self.dPt, tr))
        _du, new = slip_rates(self.K, self.f, F0, bound, dQ, dN, sep,
                              slipping & (guess == FORWARD), slipping & (guess == BACKWARD),
                              touch_lo, touch_hi)
        self.set_pattern(np.asarray(new, dtype=np.int8), theta, refresh=True, u=u)

    def _violation(self, theta):
        """The least-index node, among those changed since the event began, whose constraint
        is entered now (the event search's own test: a slipping node whose rate turns against
        its direction, a stuck node on a limit whose margin falls), and the state that removes
        it (None: on both limits at N = 0, for the LCP), or (-1, None)."""
        n = self.n
        t = self.next_event(theta)
        rows = self.touched.nonzero()[0]
        horizon = theta + _SAME
        first, second = t[rows] <= horizon, t[rows + n] <= horizon
        bad = first | second
        if not bad.any():
            return -1, None
        k = int(np.argmax(bad))
        i = int(rows[k])
        st = self.status[i]
        if st != STICK:
            return i, STICK
        if first[k] and second[k]:
            return i, None
        return i, (BACKWARD if first[k] else FORWARD)

    # -- one cycle ---------------------------------------------------------------------------
    def cycle(self, u, status, theta_s, track=False):
        """Integrate one cycle from the state (u, status) at θ = 0; returns the end state, W,
        the number of events and the samples. With ``track``, the tangent map is propagated
        too (:meth:`jacobian`)."""
        n = self.n
        self.W = 0.0
        theta = 0.0
        events = 0
        Us = np.empty((theta_s.size, n))
        Fs = np.empty((theta_s.size, n))
        Ss = np.empty((theta_s.size, n), dtype=np.int8)
        k_s = 0
        normal = self.normal_events
        k_n = 0   # normal events at θ = 0 are processed as events at the start
        self.track = False
        self.set_pattern(status, 0.0, refresh=True, u=u)
        self.W = 0.0
        self.track = track
        self.flipped = np.zeros(n, dtype=bool)
        if track:
            self.Jt = np.diag((self.status == STICK).astype(float))
        attempt = 0
        last = -1.0
        while True:
            t_all = self.next_event(theta)
            t_norm = normal[k_n][0] if k_n < len(normal) else np.inf
            t_next = min(float(t_all.min()), t_norm, TWO_PI)
            # samples in [theta, t_next)
            k_end = theta_s.size if t_next >= TWO_PI else int(
                np.searchsorted(theta_s, t_next, side="left"))
            if k_end > k_s:
                th = theta_s[k_s:k_end]
                Us[k_s:k_end] = _value(self.U[None, :, :], th[:, None])
                Fs[k_s:k_end] = _value(self.Ft[None, :, :], th[:, None])
                Ss[k_s:k_end] = self.status
                k_s = k_end
            if t_next >= TWO_PI:
                self._settle(np.arange(n), TWO_PI)
                return self.u_at(TWO_PI), self.status.copy(), self.W, events, (Us, Fs, Ss)
            events += 1
            if events > self.max_events:
                raise SolverError(f"exact: more than {self.max_events} events in one cycle "
                                  f"(θ = {theta:.6g}; {self._describe()})", backend="exact",
                                  status="too_many_events")
            # who acts now
            horizon = t_next + _SAME
            guess = self.status.copy()
            touch_hi = np.zeros(n, dtype=bool)
            touch_lo = np.zeros(n, dtype=bool)
            recontact = np.zeros(n, dtype=bool)
            self.touched[:] = False
            now = np.nonzero(t_all <= horizon)[0]
            if now.size:
                first, second = now[now < n], now[now >= n] - n
                st = self.status
                hi = first[st[first] == STICK]
                guess[first[st[first] != STICK]] = STICK
                touch_hi[hi], touch_lo[second] = True, True
                guess[hi], guess[second] = BACKWARD, FORWARD
                self.touched[first] = True
                self.touched[second] = True
            while k_n < len(normal) and normal[k_n][0] <= horizon:
                _, i, kind = normal[k_n]
                guess[i] = SEPARATION if kind == 0 else STICK
                touch_hi[i] = touch_lo[i] = False
                recontact[i] = kind == 1
                self.touched[i] = True
                k_n += 1
            attempt = attempt + 1 if t_next <= last + _SAME else 0
            if attempt > len(_ETAS) + 2:
                raise SolverError(f"exact: the pattern does not settle at θ = {t_next:.17g} "
                                  f"({self._describe()})", backend="exact",
                                  status="event_loop")
            theta = last = t_next
            self.theta_row = None
            if self.track and now.size:
                hits = (touch_hi | touch_lo).nonzero()[0]
                if hits.size:
                    j = int(hits[0])
                    self.theta_row = self._theta_sensitivity(j, bool(touch_hi[j]), theta)
            self.decide(theta, guess, touch_lo, touch_hi, attempt, recontact)
            self.theta_row = None

    def _describe(self):
        counts = {State(s).label: int(np.sum(self.status == s)) for s in range(4)}
        return ", ".join(f"{v} {k}" for k, v in counts.items() if v)

    def admissible(self, u, guess):
        """The state at θ = 0 from the displacements ``u`` of the nodes stuck in ``guess``: the
        others (slipping, separated) follow from them (their u is not state), and a stuck node
        that ``u`` puts on or beyond a friction limit is decided by the pivots on the pattern or
        the rate LCP, as at an event. Stuck nodes keep their u exactly: correcting all of u
        through K⁻¹ instead would move a stiffly coupled pair along its soft mode by the
        round-off of K u divided by K's smallest eigenvalue, every cycle."""
        contact = self.in_contact(0.0)
        guess = np.where(contact, np.where(guess == SEPARATION, STICK, guess),
                         SEPARATION).astype(np.int8)
        self._full(guess, u, 0.0)
        F = _value(self.Ft, 0.0)
        b0 = np.where(contact, _value(self.bt, 0.0), 0.0)
        stuck = guess == STICK
        self.decide(0.0, guess, stuck & (F <= -b0), stuck & (F >= b0), 0)
        return self.u_at(0.0), self.status.copy()

    def _cho_solve(self, rhs):
        import scipy.linalg as sla

        if not hasattr(self, "_cho"):
            self._cho = sla.cho_factor(self.K)
        return sla.cho_solve(self._cho, rhs)

    def initial_state(self):
        """An admissible state at θ = 0: forces clipped into the cone; the pattern from the
        rate LCP."""
        Q0 = _value(self.Qt, 0.0)
        contact = self.in_contact(0.0)
        # a node whose contact starts exactly at 0 is in contact
        b0 = np.where(contact, _value(self.bt, 0.0), 0.0)
        F0 = np.where(contact, np.clip(Q0, -b0, b0), 0.0)
        u = self._cho_solve(F0 - Q0)
        guess = np.where(contact, STICK, SEPARATION).astype(np.int8)
        touch_hi = contact & (Q0 >= b0)
        touch_lo = contact & (Q0 <= -b0)
        self._full(guess, u, 0.0)
        self.decide(0.0, guess, touch_lo, touch_hi, 1)
        return self.u_at(0.0), self.status.copy()


def _condition(K) -> float:
    """cond(K) = λmax/λmin (symmetric positive definite), from the eigenvalues up to n = 3000;
    beyond, an estimate: the largest absolute row sum over the smallest diagonal entry."""
    n = K.shape[0]
    if n <= 3000:
        ev = np.linalg.eigvalsh(K)
        return float(ev[-1] / ev[0]) if ev[0] > 0 else np.inf
    return float(np.max(np.sum(np.abs(K), axis=1)) / np.min(np.diag(K)))


def _newton_step(J, r, status0, flipped):
    """δ with ``(I - J) δ = r``: the Newton step of the cycle map u -> u(2π) (J its Jacobian,
    r = u(2π) - u). A node stuck at the start that never changed state keeps its displacement
    whatever the others do (J has its unit row, r_i = 0): it is left out, as the steady state
    is not unique in it."""
    n = r.size
    keep = ~((status0 == STICK) & ~flipped)
    delta = np.zeros(n)
    if keep.any():
        A = np.eye(n)[np.ix_(keep, keep)] - J[np.ix_(keep, keep)]
        try:
            delta[keep] = np.linalg.solve(A, r[keep])
        except np.linalg.LinAlgError:
            delta[keep] = np.linalg.lstsq(A, r[keep], rcond=None)[0]
    return delta


def check_system(system):
    """(ω, Q triples, P triples) of a system ``exact`` can solve, or :class:`InputError` naming
    what it cannot and the methods that can."""
    from ..model import ContactSystem
    from ..model.normal import IndependentSprings

    if not isinstance(system, ContactSystem):
        raise InputError("model", f"expected a ContactSystem, got {type(system).__name__}")
    if system.dims != 1:
        raise InputError("method", "'exact' for a ContactSystem handles d = 1; for d = 2 use "
                                   "'clarabel' or 'cvxpy:CLARABEL'")
    if not isinstance(system.normal, IndependentSprings):
        raise InputError("normal", "'exact' needs independent normal springs "
                                   "(IndependentSprings); use 'explicit' or a solver backend")
    omegas = [q.omega for q in (*system.tangential_loads, *system.normal.loads)
              if getattr(q, "amplitudes", ()) and any(q.amplitudes)]
    omega = omegas[0] if omegas else 1.0
    Qt = harmonic_triples(system.tangential_loads, omega, "tangential_loads")
    Pt = harmonic_triples(system.normal.loads, omega, "normal_loads")
    return omega, Qt, Pt


def exact_system_cycle(system, samples: int = 2000, *, tol: float = 1e-12,
                       max_cycles: int = 200, max_events: int | None = None) -> DiscreteCycle:
    """The exact periodic steady state of a :class:`~lcpfric.model.ContactSystem` (d = 1,
    harmonic loads of one frequency, independent normal springs).

    Parameters
    ----------
    system : ContactSystem
    samples : int
        The steady cycle is sampled at ``samples + 1`` equally spaced instants (W does not
        depend on it).
    tol : float
        Periodicity: the start displacements of two successive cycles agree to ``tol`` of the
        largest displacement range over the cycle (at least ``max |Q1| / min K_ii``), or to the
        round-off ``100 eps cond(K) max(|u|, max f N / min K_ii)`` if that is larger.
    max_cycles : int
        Cap on the cycles; reaching it raises :class:`~lcpfric.errors.ConvergenceError`.
    max_events : int, optional
        Cap on the events of one cycle (default 200 n + 1000); reaching it raises
        :class:`~lcpfric.errors.SolverError` naming the state.
    """
    start = time.perf_counter()
    omega, Qt, Pt = check_system(system)
    samples = _checks.positive_int("samples", samples, 4)
    tol = _checks.positive("tol", tol)
    max_cycles = _checks.positive_int("max_cycles", max_cycles)
    f = system.friction
    n = f.size
    from .. import memory

    memory.check(8.0 * (6.0 * n * n + 3.0 * n * (samples + 1)), "model",
                 f"the exact steady state of {n} nodes (dense n x n matrices: K, K_BB⁻¹, the "
                 f"cycle's Jacobian)")
    K = system.dense_stiffness().astype(float)
    # forces of order one: divide by a power of two (exact), W scales by its square
    size = float(max(np.max(np.abs(Qt[:, 0]) + np.hypot(Qt[:, 1], Qt[:, 2])),
                     np.max(f * (np.abs(Pt[:, 0]) + np.hypot(Pt[:, 1], Pt[:, 2])))))
    scale = 2.0 ** round(math.log2(size)) if size > 0 and math.isfinite(size) else 1.0
    kappa = _condition(K)
    # a constant tangential load Q0 only shifts u by -K⁻¹ Q0 (F = Q + K u is unchanged): it is
    # taken out, so that displacements of a small amplitude are not computed on a large offset
    Q0 = Qt[:, 0].copy()
    Qt = Qt.copy()
    Qt[:, 0] = 0.0
    solver = _Solver(K, f, Qt / scale, Pt / scale, samples,
                     max_events or 200 * n + 1000, kappa)
    u_static = -solver._cho_solve(Q0) if np.any(Q0) else np.zeros(n)
    theta_s = np.linspace(0.0, TWO_PI, samples + 1)
    u, status = solver.initial_state()
    floor = tol
    W_cycles, change = [], np.inf
    track, newton = False, 0
    best = None      # (change, start, its status, step) of the best start so far
    lam = 1.0
    for _ in range(max_cycles):
        u_end, status_end, W, events, series = solver.cycle(u, status, theta_s, track)
        W_cycles.append(W * scale * scale)
        r = u_end - u
        # relative to the largest displacement range over the cycle (what the slips are
        # measured against), at least the displacement the tangential amplitudes make;
        # round-off is relative to |u| or the forces' displacement scale, times cond(K)
        ref = max(float(np.max(np.ptp(series[0], axis=0), initial=0.0)), solver.qscale)
        change = float(np.max(np.abs(r), initial=0.0)) / ref
        size = max(float(np.max(np.abs(u_end), initial=0.0)), ref, solver.rscale)
        floor = max(tol, 100.0 * _EPS * kappa * size / ref)
        if change <= floor:
            break
        if best is None or change < 0.9 * best[0]:
            # progress: Newton's step from here (the plain cycle-map step before the Jacobian
            # is tracked)
            step = r
            if track:
                step = _newton_step(solver.jacobian(), r, status, solver.flipped)
                newton += 1
            best, lam = (change, u, status, step, u_end, status_end), 1.0
            u_next, guess = u + step, status_end
        elif lam > 0.125:
            # no progress: back from the best start along a shorter step (damped Newton)
            lam *= 0.5
            u_next, guess = best[1] + lam * best[3], best[5]
        else:
            # Newton's direction does not help here (a kink of the cycle map): one plain step
            # from the best start, whose result is accepted whatever it is
            u_next, guess = best[4], best[5]
            best, lam = None, 1.0
        # the tangent map pays O(n) per event on a chain, O(n²) on dense K: track from the
        # second cycle on unless the first already reached the orbit (a history erased by
        # separation), and then until the end
        track = track or change > 1e3 * tol
        u, status = solver.admissible(u_next, guess)
    else:
        raise ConvergenceError(f"exact: no periodic steady state after {max_cycles} cycles "
                               f"(relative change of the start {change:.3g} > tol {tol:g}); "
                               f"raise max_cycles", None)
    Us, Fs, Ss = series
    N = np.maximum(_value(Pt[None, :, :], theta_s[:, None]), 0.0)
    N = np.where(solver.never, 0.0, N)
    stats = dict(solver.stats, events_per_cycle=events, cycles=len(W_cycles),
                 newton_steps=newton, condition=kappa, periodicity_tol=floor,
                 seconds=time.perf_counter() - start)
    return DiscreteCycle(W=W_cycles[-1], W_cycles=np.asarray(W_cycles), cycles=len(W_cycles),
                         change=change, events=events, omega=omega, theta=theta_s,
                         u=Us * scale + u_static,
                         F=Fs * scale, N=N, state=Ss, stats=stats)
