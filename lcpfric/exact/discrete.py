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
LCP (the explicit stepper's :meth:`~lcpfric.steppers.explicit.ExplicitStepper._rates`, with the
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
A margin or rate is *meaningfully* negative when its minimum is below ``-1e-11`` of its node's
force (or the system's rate) scale. Shallower dips, a node touching its limit without slipping,
are not events; the deepest one skipped is reported (``skipped_depth``), and the dissipation it
could hide is below that depth times the largest compliance times the largest friction limit.

Cycles
------
The first cycle starts at θ = 0 from an admissible state (forces ``clip(Q(0), -f N, f N)``).
Cycles are repeated until the displacements at the start of the cycle repeat to ``tol`` of their
scale; with uncoupled normal reactions the steady dissipation is unique (Barber, Klarbring and
Ciavarella), so the start does not change it. The number of cycles is reported.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError, SolverError
from ..results import State

__all__ = ["DiscreteCycle", "harmonic_triples", "next_entry", "segment_dissipation",
           "exact_system_cycle"]

STICK, FORWARD, BACKWARD, SEPARATION = (int(State.STICK), int(State.FORWARD),
                                        int(State.BACKWARD), int(State.SEPARATION))
TWO_PI = 2.0 * math.pi
_REL = 1e-11             # a dip below this fraction of its scale is an event
_SAME = 64 * np.finfo(float).eps * TWO_PI   # events closer than this happen together
_ETAS = (1e-9, 1e-7, 1e-5, 1e-3)   # load-rate look-ahead for degenerate instants
_RESIDUAL = 1e-10        # equilibrium residual that triggers a refactorization
_ANDERSON = 6            # cycles remembered by the Anderson acceleration of the cycle map


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
    period on. With ``skipped``, also returns the deepest dip not treated as an entry, as a
    fraction of ``tol`` times 1e-11 (the scale-relative depth).
    """
    c0, cs, cc = T[:, 0], T[:, 1], T[:, 2]
    R = np.hypot(cs, cc)
    depth = R - c0
    out = np.full(c0.shape, np.inf)
    dips = depth > tol
    if skipped:
        shallow = float(np.max(np.where(dips, 0.0, depth / tol), initial=0.0)) * _REL
        if not dips.any():
            return out, shallow
    elif not dips.any():
        return out
    always = dips & (depth >= 2.0 * R)            # c0 <= -R: negative everywhere
    out[always] = theta
    arc = dips & ~always
    if arc.any():
        Ra, da = R[arc], depth[arc]
        h = 2.0 * np.arcsin(np.sqrt(np.minimum(da / (2.0 * Ra), 1.0)))
        psi = np.arctan2(cc[arc], cs[arc])
        d = np.mod(theta + psi - (1.5 * math.pi - h), TWO_PI)   # angle past the entry
        g_now = c0[arc] + Ra * np.sin(theta + psi)
        tol_a = tol[arc] if np.ndim(tol) else tol
        inside = d < 2.0 * h
        now = inside & ((d <= h) | (g_now < -tol_a))
        out[arc] = np.where(now, theta, theta + (TWO_PI - d))
    return (out, shallow) if skipped else out


def segment_dissipation(b: np.ndarray, U: np.ndarray, sign: np.ndarray, a: float,
                        e: float) -> float:
    """``Σ_i sign_i ∫_a^e b_i(θ) du_i/dθ dθ`` for triples b (bounds) and U (displacements):
    the dissipation of the slipping nodes over one segment, in closed form.

    With ``b = b0 + bs S + bc C`` and ``du = us C - uc S``::

        ∫ b du = b0 (us ΔS + uc ΔC) + (bs us - bc uc) Δ(S²)/2 + (bc us - bs uc) Δθ/2
                 + (bc us + bs uc) Δ(sin 2θ)/4

    each difference written with half-angles (``ΔS = 2 cos m sin h``, ...) to keep the digits of
    short segments.
    """
    if b.shape[0] == 0:
        return 0.0
    m, h = 0.5 * (a + e), 0.5 * (e - a)
    sh = math.sin(h)
    dS = 2.0 * math.cos(m) * sh
    dC = -2.0 * math.sin(m) * sh
    dS2 = dS * (math.sin(a) + math.sin(e)) * 0.5
    d2 = 2.0 * math.cos(2.0 * m) * math.sin(2.0 * h)
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

    def __init__(self, K, f, Qt, Pt, samples, max_events):
        self.K = self.Kd = K
        self.n = n = f.size
        self.Kmul = _multiplier(K)
        self.G = np.zeros((n, n))
        self.Bidx = np.zeros(n, dtype=np.intp)
        self.pos = np.full(n, -1, dtype=np.intp)
        self.m = 0
        self._since = 0
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
        self._tol_stick = np.concatenate([_REL * self.fscale, _REL * self.fscale])
        kmin = float(np.min(np.diag(K)))
        self.rscale = max(fmax / kmin, 1e-300)
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
    def set_pattern(self, status, u, theta, refresh=False):
        """Triples of u and F for the pattern ``status`` from the state (u at theta).

        A pattern that differs from the current one in a few nodes is reached by rank-one
        updates (:meth:`_flip`, O(n²) each for dense K); otherwise, or every max(64, |B|)
        updates, it is recomputed from a fresh factorization of K_BB and its equilibrium
        residual checked."""
        old = getattr(self, "status", None)
        if old is not None and not refresh and self._since < max(64, self.m):
            changed = np.nonzero(old != status)[0]
            if changed.size <= 4:
                for j in changed:
                    self._flip(int(j), int(status[j]), theta)
                return
        self._full(status, u, theta)

    def _full(self, status, u, theta):
        import scipy.linalg as sla

        K, n = self.K, self.n
        B = status != STICK
        Bidx = np.nonzero(B)[0]
        m = Bidx.size
        self.m = m
        self.Bidx[:m] = Bidx
        self.pos[:] = -1
        self.pos[Bidx] = np.arange(m)
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
            if res > _RESIDUAL:
                raise SolverError(f"exact: equilibrium residual {res:.3g} of the pattern at "
                                  f"θ = {theta:.17g} (is K well conditioned?)", backend="exact",
                                  status="residual")
            F[Bidx] = Fp[Bidx]
        self.status, self.U, self.Ft, self.sign = status.copy(), U, F, sign
        self.B = B

    def _flip(self, j, new, theta):
        """Change node j's state by rank-one updates of G = K_BB⁻¹, U and F."""
        old = int(self.status[j])
        if old == new:
            return
        sgn = -1.0 if new == FORWARD else (1.0 if new == BACKWARD else 0.0)
        if old == STICK:                      # j joins B with a prescribed force
            z = self._add(j)                  # u response (over B) to a unit force at j
            delta = sgn * self.bt[j] - self.Ft[j]
        elif new == STICK:                    # j leaves B: u_j keeps its value at theta
            p = self.pos[j]
            m = self.m
            z = np.zeros(self.n)
            z[self.Bidx[:m]] = self.G[:m, p]
            du = -self.U[j].copy()
            du[0] += float(_value(self.U[j], theta))
            delta = du / z[j]
            self._remove(j)
        else:                                 # prescribed force changes (slip <-> separation)
            p = self.pos[j]
            m = self.m
            z = np.zeros(self.n)
            z[self.Bidx[:m]] = self.G[:m, p]
            delta = sgn * self.bt[j] - self.Ft[j]
        self.U += np.multiply.outer(z, delta)
        self.Ft += np.multiply.outer(self.Kmul(z), delta)
        self.status[j] = new
        self.sign[j] = sgn
        self.B[j] = new != STICK
        if new == STICK:
            self.U[j] = (float(_value(self.U[j], theta)), 0.0, 0.0)
        # the nodes of B carry their prescribed forces exactly (K z = e_j only to round-off)
        B = self.B
        self.Ft[B] = self.sign[B, None] * self.bt[B]
        self._since += 1

    def _add(self, j):
        """Border G with node j; returns the new column of G scattered over the nodes."""
        m = self.m
        Bi = self.Bidx[:m]
        kb = self.K[j, Bi]
        g = self.G[:m, :m] @ kb
        s = self.K[j, j] - kb @ g
        if not s > 0:
            raise SolverError(f"exact: K_BB lost positive definiteness adding node {j} "
                              f"(pivot {s:.3g})", backend="exact", status="not_spd")
        G = self.G
        G[:m, :m] += np.multiply.outer(g, g / s)
        G[:m, m] = G[m, :m] = -g / s
        G[m, m] = 1.0 / s
        self.Bidx[m] = j
        self.pos[j] = m
        self.m = m + 1
        z = np.zeros(self.n)
        z[self.Bidx[:m + 1]] = G[:m + 1, m]
        return z

    def _remove(self, j):
        """Downdate G = K_BB⁻¹ for B without node j (the last node takes its place)."""
        m, p = self.m, self.pos[j]
        G = self.G
        col = G[:m, p].copy()
        G[:m, :m] -= np.multiply.outer(col, col / col[p])
        last = m - 1
        if p != last:
            G[p, :last] = G[last, :last]
            G[:last, p] = G[:last, last]
            G[p, p] = G[last, last]
            k = self.Bidx[last]
            self.Bidx[p] = k
            self.pos[k] = p
        self.pos[j] = -1
        self.m = last

    # -- events ------------------------------------------------------------------------------
    def next_event(self, theta):
        """Entry angles of every constraint of the pattern, shape (2n,): rows 0..n-1 the upper
        margin ``f P - F`` of a stuck node or the slip rate ``±du/dθ`` of a slipping one; rows
        n..2n-1 the lower margin ``f P + F`` of a stuck node (inf elsewhere)."""
        n = self.n
        st = self.status
        stick = (st == STICK)[:, None]
        D = np.where(st == FORWARD, 1.0, np.where(st == BACKWARD, -1.0, 0.0))
        T = np.empty((2 * n, 3))
        T[:n] = np.where(stick, self.bt - self.Ft, D[:, None] * _rate(self.U))
        T[n:] = np.where(stick, self.bt + self.Ft, 0.0)
        tol = self._tol_stick if not np.any(D) else np.concatenate(
            [np.where(stick[:, 0], _REL * self.fscale, _REL * self.rscale),
             _REL * self.fscale])
        t, skipped = next_entry(T, theta, tol, skipped=True)
        if skipped > self.stats["skipped_depth"]:
            self.stats["skipped_depth"] = skipped
        return t

    # -- deciding the pattern at an event ----------------------------------------------------
    def decide(self, theta, u, guess, touch_lo, touch_hi, attempt, recontact=None):
        """The pattern valid just after theta.

        First the guess, corrected by principal pivots on the actual pattern (least index: a
        slipping node whose rate is negative sticks, a stuck node driven through its limit
        slips; for a P-matrix this terminates at the LCP's unique solution). After
        ``4 + changes`` pivots, or at a degenerate instant (``attempt`` >= 1), the rate LCP
        decides, with the load rates at theta + η when ``attempt`` >= 2."""
        if attempt == 0:
            pattern = guess.copy()
            for _ in range(4 + int(np.sum(guess != self.status))):
                self.set_pattern(pattern, u, theta)
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
        from ..steppers.explicit import ExplicitStepper

        sep = guess == SEPARATION
        F0 = _value(self.Qt, theta) + self._K_u(u)
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
        _du, new = ExplicitStepper._rates(self.Kd, self.f, F0, bound, dQ, dN, sep,
                                          slipping & (guess == FORWARD),
                                          slipping & (guess == BACKWARD), touch_lo, touch_hi)
        self.set_pattern(np.asarray(new, dtype=np.int8), u, theta, refresh=True)

    def _K_u(self, u):
        return self.K @ u

    def _violation(self, theta):
        """The least-index violation of the LCP's conditions at theta for the current pattern
        and the state that removes it, or (-1, None): a slipping node whose rate is against its
        direction sticks; a stuck node on a limit whose margin is falling slips."""
        st = self.status
        sn, cs = math.sin(theta), math.cos(theta)
        U, Ft, bt = self.U, self.Ft, self.bt
        D = np.where(st == FORWARD, 1.0, np.where(st == BACKWARD, -1.0, 0.0))
        stick = st == STICK
        r = D * (U[:, 1] * cs - U[:, 2] * sn)
        F = Ft[:, 0] + Ft[:, 1] * sn + Ft[:, 2] * cs
        b = bt[:, 0] + bt[:, 1] * sn + bt[:, 2] * cs
        dF = Ft[:, 1] * cs - Ft[:, 2] * sn
        db = bt[:, 1] * cs - bt[:, 2] * sn
        tol = _REL * self.fscale
        rtol = tol + _REL * (np.abs(dF) + np.abs(db))
        hi = stick & (F >= b - tol) & (db - dF < -rtol)
        lo = stick & (F <= -b + tol) & (db + dF < -rtol)
        back = r < -_REL * self.rscale
        bad = hi | lo | back
        if not bad.any():
            return -1, None
        i = int(np.argmax(bad))
        if back[i]:
            return i, STICK
        if hi[i] and lo[i]:               # on both limits (N = 0): the LCP decides the sign
            return i, None
        return i, (BACKWARD if hi[i] else FORWARD)

    # -- one cycle ---------------------------------------------------------------------------
    def cycle(self, u, status, theta_s):
        """Integrate one cycle from the state (u, status) at θ = 0; returns the end state, W,
        the number of events and the samples."""
        n = self.n
        W = 0.0
        theta = 0.0
        events = 0
        Us = np.empty((theta_s.size, n))
        Fs = np.empty((theta_s.size, n))
        Ss = np.empty((theta_s.size, n), dtype=np.int8)
        k_s = 0
        normal = self.normal_events
        k_n = 0   # normal events at θ = 0 are processed as events at the start
        self.set_pattern(status, u, 0.0, refresh=True)
        attempt = 0
        last = -1.0
        while True:
            t_all = self.next_event(theta)
            t_norm = normal[k_n][0] if k_n < len(normal) else np.inf
            t_next = min(float(t_all.min()), t_norm, TWO_PI)
            # samples in [theta, t_next)
            k_end = int(np.searchsorted(theta_s, t_next, side="left"))
            if t_next >= TWO_PI:
                k_end = theta_s.size
            if k_end > k_s:
                th = theta_s[k_s:k_end]
                Us[k_s:k_end] = _value(self.U[None, :, :], th[:, None])
                Fs[k_s:k_end] = _value(self.Ft[None, :, :], th[:, None])
                Ss[k_s:k_end] = self.status
                k_s = k_end
            # dissipation of the segment
            slip = np.nonzero(self.sign)[0]
            if slip.size and t_next > theta:
                W += segment_dissipation(self.bt[slip], self.U[slip], self.sign[slip] * -1.0,
                                         theta, t_next)
            u = np.where(self.B, _value(self.U, t_next), u)
            if t_next >= TWO_PI:
                return u, self.status.copy(), W, events, (Us, Fs, Ss)
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
            now = t_all <= horizon
            if now.any():
                st = self.status
                first, second = now[:n], now[n:]
                hi = first & (st == STICK)
                touch_hi[hi], touch_lo[second] = True, True
                guess[first & (st != STICK)] = STICK
                guess[hi], guess[second] = BACKWARD, FORWARD
            while k_n < len(normal) and normal[k_n][0] <= horizon:
                _, i, kind = normal[k_n]
                guess[i] = SEPARATION if kind == 0 else STICK
                touch_hi[i] = touch_lo[i] = False
                recontact[i] = kind == 1
                k_n += 1
            attempt = attempt + 1 if t_next <= last + _SAME else 0
            if attempt > len(_ETAS) + 2:
                raise SolverError(f"exact: the pattern does not settle at θ = {t_next:.17g} "
                                  f"({self._describe()})", backend="exact",
                                  status="event_loop")
            theta = last = t_next
            self.decide(theta, u, guess, touch_lo, touch_hi, attempt, recontact)

    def _describe(self):
        counts = {State(s).label: int(np.sum(self.status == s)) for s in range(4)}
        return ", ".join(f"{v} {k}" for k, v in counts.items() if v)

    def admissible(self, u, guess):
        """The state at θ = 0 nearest ``u`` inside the friction cone (forces clipped, u moved
        accordingly), its pattern from ``guess`` (checked) or the rate LCP."""
        Q0 = _value(self.Qt, 0.0)
        contact = self.in_contact(0.0)
        b0 = np.where(contact, _value(self.bt, 0.0), 0.0)
        F = Q0 + self.K @ u
        Fc = np.where(contact, np.clip(F, -b0, b0), 0.0)
        slip = (guess == FORWARD) | (guess == BACKWARD)
        Fc = np.where(contact & slip, np.where(guess == FORWARD, -b0, b0), Fc)
        if np.any(Fc != F):
            u = u + self._cho_solve(Fc - F)
        guess = np.where(contact, np.where(guess == SEPARATION, STICK, guess),
                         SEPARATION).astype(np.int8)
        touch_hi = contact & (Fc >= b0) & (guess == STICK)
        touch_lo = contact & (Fc <= -b0) & (guess == STICK)
        self._full(guess, u, 0.0)
        self.decide(0.0, u, guess, touch_lo, touch_hi, 0)
        return u, self.status.copy()

    def _cho_solve(self, rhs):
        import scipy.linalg as sla

        if not hasattr(self, "_cho"):
            self._cho = sla.cho_factor(self.Kd)
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
        self.decide(0.0, u, guess, touch_lo, touch_hi, 1)
        return u, self.status.copy()


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
        Periodicity: the start displacements of two successive cycles agree to ``tol`` of their
        scale (the largest |u| and the loads' displacement scale).
    max_cycles : int
        Cap on the cycles; reaching it raises :class:`~lcpfric.errors.ConvergenceError`.
    max_events : int, optional
        Cap on the events of one cycle (default 200 n + 1000); reaching it raises
        :class:`~lcpfric.errors.SolverError` naming the state.
    """
    from ..model.normal import IndependentSprings

    start = time.perf_counter()
    omega, Qt, Pt = check_system(system)
    samples = _checks.positive_int("samples", samples, 4)
    tol = _checks.positive("tol", tol)
    max_cycles = _checks.positive_int("max_cycles", max_cycles)
    f = system.friction
    K = system.dense_stiffness().astype(float)
    n = f.size
    # forces of order one: divide by a power of two (exact), W scales by its square
    size = float(max(np.max(np.abs(Qt[:, 0]) + np.hypot(Qt[:, 1], Qt[:, 2])),
                     np.max(f * (np.abs(Pt[:, 0]) + np.hypot(Pt[:, 1], Pt[:, 2])))))
    scale = 2.0 ** round(math.log2(size)) if size > 0 and math.isfinite(size) else 1.0
    solver = _Solver(K, f, Qt / scale, Pt / scale, samples,
                     max_events or 200 * n + 1000)
    theta_s = np.linspace(0.0, TWO_PI, samples + 1)
    u, status = solver.initial_state()
    u_load = solver.rscale
    W_cycles, change = [], np.inf
    X, R = [], []             # Anderson history: starts and their residuals G(x) - x
    best = np.inf
    for _ in range(max_cycles):
        u_end, status_end, W, events, series = solver.cycle(u, status, theta_s)
        W_cycles.append(W * scale * scale)
        r = u_end - u
        ref = max(float(np.max(np.abs(u_end), initial=0.0)), u_load)
        change = float(np.max(np.abs(r), initial=0.0)) / ref
        if change <= tol:
            break
        if change > best:         # the acceleration made it worse: restart from this cycle
            X, R = [], []
        best = min(best, change)
        X.append(u)
        R.append(r)
        X, R = X[-_ANDERSON - 1:], R[-_ANDERSON - 1:]
        u_next = u_end
        if len(X) >= 2:
            dX = np.diff(np.array(X), axis=0).T
            dR = np.diff(np.array(R), axis=0).T
            gamma = np.linalg.lstsq(dR, r, rcond=None)[0]
            u_next = u + r - (dX + dR) @ gamma
        u, status = solver.admissible(u_next, status_end)
    else:
        raise ConvergenceError(f"exact: no periodic steady state after {max_cycles} cycles "
                               f"(relative change of the start {change:.3g} > tol {tol:g}); "
                               f"raise max_cycles", None)
    Us, Fs, Ss = series
    N = np.maximum(_value(Pt[None, :, :], theta_s[:, None]), 0.0)
    N = np.where(solver.never, 0.0, N)
    stats = dict(solver.stats, events_per_cycle=events, cycles=len(W_cycles),
                 seconds=time.perf_counter() - start)
    return DiscreteCycle(W=W_cycles[-1], W_cycles=np.asarray(W_cycles), cycles=len(W_cycles),
                         change=change, events=events, omega=omega, theta=theta_s, u=Us * scale,
                         F=Fs * scale, N=N, state=Ss, stats=stats)
