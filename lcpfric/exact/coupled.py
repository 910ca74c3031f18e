r"""The exact periodic steady state of a coupled system (d = 1), event by event.

The system is ``F = Q(θ) + K u``, ``N = P(θ) + B u``, ``|F_i| <= f_i N_i``, θ = ωt, every load
harmonic at the one frequency ω, K symmetric positive definite and the coupling block B checked
well posed (:mod:`lcpfric.model.coupling`: every ``K + diag(s f) B`` a P-matrix).

Between events: closed form
---------------------------
Within a fixed pattern (each node stuck, slipping forward with ``F_i = -f_i N_i`` or backward with
``F_i = +f_i N_i``) the stuck nodes R keep their displacements and the slipping nodes S solve,
with ``D_i = +1`` forward and ``-1`` backward,

    (K + diag(D f) B)_SS u_S = -(Q_S + D f P_S) - (K + diag(D f) B)_SR u_R

so every u, F and N is a trig triple ``c0 + cs sin θ + cc cos θ``, and every event is where one
enters a half-line (:func:`~lcpfric.exact.triples.next_entry`, in closed form): a stuck node
reaching a limit (``f N ± F = 0``), a slip rate vanishing (``D du/dθ = 0``), or a normal reaction
reaching zero. The last one is *not* followed: a coupled node that separates would need its normal
stiffness, so it raises :class:`~lcpfric.errors.InputError` naming the node and the instant
(never a clipped reaction). The dissipation ``Σ_S D_i ∫ f_i N_i du_i`` of a segment is
integrated in closed form (:func:`~lcpfric.exact.triples.segment_dissipation`).

At an event: the pattern that holds just after
----------------------------------------------
The nodes on their limits (slipping, or stuck with a zero margin) may each stick or slip towards
their limit's side. A pattern holds just after the event when, for its triples, every stuck node
on a limit has a margin that is not negative just after θ and every slipping node a rate of the
right sign: a sign decided lexicographically on the value and the first two derivatives at θ
(exact for trig triples, so ties of the first-order rate LCP are resolved too). Under Klarbring's
condition exactly one pattern holds (the evolution is unique); it is first guessed (the node that
reached its limit slips, the node whose rate vanished sticks), then searched over the ``2^a``
patterns of the ``a`` nodes on limits (a <= :data:`MAX_ON_LIMIT`), fewest changes first. None
holding raises :class:`~lcpfric.errors.SolverError` naming the instant and the nodes.

Cycles: the physical iteration, not Newton
------------------------------------------
A coupled system's steady state can depend on the start (a node that never slips keeps a
displacement that its transient left and that changes the others' normal reactions): the steady
states form a continuum, and a Newton step on the cycle map would land on *a* steady state, not
the one the start leads to. So the cycles are iterated as they happen, and the approach, often
geometric (ratios 0.25 to 0.6 per cycle), is measured: with ``c_k`` the relative change of the
start over cycle k and ``ρ = c_k / c_(k-1)``, the distance to the limit is at most about
``c_k ρ / (1 - ρ)`` while the ratio holds. The iteration stops when that bound (or ``c_k`` itself,
for a finite approach) is below ``tol``; the bound and the ratio are reported
(``stats['remaining']``, ``stats['ratio']``).
"""

from __future__ import annotations

import itertools
import math
import time

import numpy as np

from ..errors import ConvergenceError, InputError, SolverError
from ..results import State
from .triples import TWO_PI, next_entry, rate_of, segment_dissipation, value

__all__ = ["coupled_system_cycle", "CoupledEvents", "MAX_ON_LIMIT"]

STICK, FORWARD, BACKWARD = int(State.STICK), int(State.FORWARD), int(State.BACKWARD)
#: most nodes on their limits at one event whose patterns are searched (2^a of them)
MAX_ON_LIMIT = 14
_REL = 1e-13  # a dip below this fraction of its scale is an event
_ON = 1e-11  # a stuck node within this fraction of its force scale of a limit is on it
_TIE = 1e-11  # a derivative below this fraction of its scale is zero (lexicographic sign)


def _lexi_sign(T: np.ndarray, theta: float, scale) -> np.ndarray:
    """Sign of the triples T just after θ: of the value, else the first, else the second
    derivative (a trig triple with all three zero at θ is constant: sign 0)."""
    s, c = math.sin(theta), math.cos(theta)
    v = T[:, 0] + T[:, 1] * s + T[:, 2] * c
    d1 = T[:, 1] * c - T[:, 2] * s
    d2 = -(T[:, 1] * s + T[:, 2] * c)
    tol = _TIE * scale
    out = np.where(np.abs(v) > tol, np.sign(v), 0.0)
    out = np.where(out == 0, np.where(np.abs(d1) > tol, np.sign(d1), 0.0), out)
    return np.where(out == 0, np.where(np.abs(d2) > tol, np.sign(d2), 0.0), out)


class CoupledEvents:
    """Patterns, events and cycles of one coupled system (forces in the units given)."""

    def __init__(self, K, B, f, Qt, Pt, max_events):
        self.K, self.B, self.f, self.Qt, self.Pt = K, B, f, Qt, Pt
        self.n = f.size
        self.max_events = max_events
        amp = lambda T: np.abs(T[:, 0]) + np.hypot(T[:, 1], T[:, 2])  # noqa: E731
        self.fscale = float(max(np.max(amp(Qt)), np.max(f * amp(Pt)), 1e-300))
        self.uscale = self.fscale / float(np.min(np.diag(K)))
        self.events = 0

    # -- one pattern -------------------------------------------------------------------------
    def triples(self, status, u):
        """(U, F, N) triples of the pattern ``status`` with the stuck nodes held at ``u``."""
        S = status != STICK
        U = np.zeros((self.n, 3))
        U[:, 0] = np.where(S, 0.0, u)
        if S.any():
            D = np.where(status == FORWARD, 1.0, -1.0)[S]
            Df = D * self.f[S]
            A = self.K[S] + Df[:, None] * self.B[S]
            rhs = -(self.Qt[S] + Df[:, None] * self.Pt[S]) - A[:, ~S] @ U[~S]
            U[S] = np.linalg.solve(A[:, S], rhs)
        return U, self.Qt + self.K @ U, self.Pt + self.B @ U

    def holds(self, status, on_lo, on_hi, theta, trip):
        """Whether the pattern with triples ``trip`` holds just after θ."""
        U, F, N = trip
        fN = self.f[:, None] * N
        stuck = status == STICK
        lo = stuck & on_lo
        hi = stuck & on_hi
        if lo.any() and np.any(_lexi_sign((fN + F)[lo], theta, self.fscale) < 0):
            return False
        if hi.any() and np.any(_lexi_sign((fN - F)[hi], theta, self.fscale) < 0):
            return False
        S = ~stuck
        if S.any():
            D = np.where(status == FORWARD, 1.0, -1.0)[S]
            rate = rate_of(U[S]) * D[:, None]
            if np.any(_lexi_sign(rate, theta, self.uscale) < 0):
                return False
        return True

    def decide(self, status, u, theta, guess):
        """The pattern that holds just after θ from the displacements ``u`` (module docstring)."""
        Uc = np.zeros((self.n, 3))
        Uc[:, 0] = u
        F = value(self.Qt + self.K @ Uc, theta)
        fN = self.f * value(self.Pt + self.B @ Uc, theta)
        tol = _ON * (np.abs(F) + fN + self.fscale * 1e-3)
        on_lo = (fN + F <= tol) | ((status == FORWARD) & (F < 0))
        on_hi = (fN - F <= tol) | ((status == BACKWARD) & (F > 0))
        both = on_lo & on_hi
        if both.any():
            raise InputError(
                "normal_loads",
                f"the normal reaction of node(s) {np.nonzero(both)[0].tolist()} reaches zero "
                f"at θ = {theta:.12g}: separation of a node of a coupled system is not "
                "modelled (its normal stiffness is not part of the system)",
            )
        limit = np.nonzero(on_lo | on_hi)[0]
        candidates = [np.asarray(guess, dtype=np.int8)]
        if limit.size > MAX_ON_LIMIT:
            raise SolverError(
                f"exact (coupled): {limit.size} nodes on their limits at θ = {theta:.12g}, "
                f"more than the {MAX_ON_LIMIT} whose patterns are searched",
                "too_many_on_limit",
            )
        side = np.where(on_lo, FORWARD, BACKWARD).astype(np.int8)
        base = np.where(on_lo | on_hi, STICK, status).astype(np.int8)
        combos = sorted(
            itertools.product((False, True), repeat=limit.size),
            key=lambda c: sum(
                (side[i] if x else STICK) != guess[i] for i, x in zip(limit, c, strict=True)
            ),
        )
        for combo in combos:
            cand = base.copy()
            cand[limit[list(combo)]] = side[limit[list(combo)]]
            candidates.append(cand)
        for cand in candidates:
            # a node may slip only towards the side of the limit it is on
            slip = cand != STICK
            if np.any(slip & ~np.where(cand == FORWARD, on_lo, on_hi)):
                continue
            trip = self.triples(cand, u)
            if self.holds(cand, on_lo, on_hi, theta, trip):
                return cand, trip
        raise SolverError(
            f"exact (coupled): no stick/slip pattern holds just after θ = {theta:.12g} "
            f"(nodes on their limits: {limit.tolist()}, states before: "
            f"{status[limit].tolist()}); is the system well posed?",
            backend="exact",
            status="no_pattern",
        )

    # -- one cycle -----------------------------------------------------------------------------
    @staticmethod
    def _tol(T, theta, scale):
        """Per row, the depth below which a dip is an event: ``1e-13`` of the scale, or twice
        the round-off a row starts with below zero (a pattern decided to hold just after θ,
        whose rows start within the decision's tie tolerance of zero)."""
        return np.maximum(_REL * scale, -2.0 * value(T, theta))

    def cycle(self, u, status, theta_s):
        """One cycle from θ = 0: (u at 2π, status, W, events, (U, F, N, state) at theta_s)."""
        n = self.n
        m = theta_s.size
        Us, Fs, Ns = np.empty((m, n)), np.empty((m, n)), np.empty((m, n))
        Ss = np.empty((m, n), dtype=np.int8)
        theta, W, events, k = 0.0, 0.0, 0, 0
        status, trip = self.decide(status, u, 0.0, status)
        f = self.f[:, None]
        while True:
            U, F, N = trip
            stuck = status == STICK
            D = np.where(status == FORWARD, 1.0, -1.0)
            cand = [np.full(n, np.inf)] * 3
            if stuck.any():
                lo, hi = f * N + F, f * N - F
                cand[0] = np.where(
                    stuck,
                    np.minimum(
                        next_entry(lo, theta, self._tol(lo, theta, self.fscale)),
                        next_entry(hi, theta, self._tol(hi, theta, self.fscale)),
                    ),
                    np.inf,
                )
            if (~stuck).any():
                rate = rate_of(U) * D[:, None]
                cand[1] = np.where(
                    ~stuck, next_entry(rate, theta, self._tol(rate, theta, self.uscale)), np.inf
                )
            tol_f = _REL * self.fscale
            cand[2] = next_entry(N, theta, tol_f)
            ends = np.min(np.vstack(cand), axis=0)
            end = float(min(np.min(ends), TWO_PI))
            # samples in [theta, end)
            j = k
            while j < m and (theta_s[j] < end or (end >= TWO_PI and j == m - 1)):
                j += 1
            if j > k:
                th = theta_s[k:j]
                Us[k:j] = value(U[None], th[:, None])
                Fs[k:j] = value(F[None], th[:, None])
                Ns[k:j] = value(N[None], th[:, None])
                Ss[k:j] = status
                k = j
            if (~stuck).any():
                S = ~stuck
                W += segment_dissipation(f[S] * N[S], U[S], D[S], theta, end)
            u = value(U, end)
            if end >= TWO_PI:
                return u, status, W, events, (Us, Fs, Ns, Ss)
            if cand[2].min() <= end:
                i = int(np.argmin(cand[2]))
                raise InputError(
                    "normal_loads",
                    f"the normal reaction of node {i} reaches zero at θ = {end:.12g} "
                    f"(t = θ/ω): separation of a node of a coupled system is not modelled",
                )
            events += 1
            self.events += 1
            if events > self.max_events:
                raise SolverError(
                    f"exact (coupled): more than {self.max_events} events in one cycle "
                    f"(θ = {end:.12g})",
                    backend="exact",
                    status="too_many_events",
                )
            guess = status.copy()
            hit = ends <= end + 64 * np.finfo(float).eps * TWO_PI
            guess[hit & stuck] = np.where(value(F[hit & stuck], end) < 0, FORWARD, BACKWARD)
            guess[hit & ~stuck] = STICK
            status, trip = self.decide(status, u, end, guess)
            theta = end

    def initial(self, u0):
        """An admissible start at θ = 0: ``u0``, or (None) the default start
        (:func:`lcpfric.model.coupling.static_start`), all nodes stuck there."""
        from ..model.coupling import static_start

        if u0 is None:
            Q, P = value(self.Qt, 0.0), value(self.Pt, 0.0)
            u0 = static_start(self.K, self.B, self.f, Q, P)
        return np.asarray(u0, dtype=float).copy(), np.full(self.n, STICK, dtype=np.int8)


def coupled_system_cycle(
    system,
    Qt,
    Pt,
    omega,
    samples: int = 2000,
    *,
    tol: float = 1e-12,
    max_cycles: int = 1000,
    u0=None,
    max_events: int | None = None,
):
    """The steady state of a coupled system from a start (the module docstring): the fields
    of a :class:`~lcpfric.exact.discrete.DiscreteCycle`, whose ``stats`` add ``ratio`` (the
    last cycles' contraction) and ``remaining`` (the bound on the distance to the limit of the
    start and of W, relative to the displacement range and to W).

    Called by :func:`lcpfric.exact.discrete.exact_system_cycle` for a system with a coupling
    block (same parameters); ``max_cycles`` (default 1000) bounds a geometric approach:
    reaching it raises :class:`~lcpfric.errors.ConvergenceError` with the change and ratio."""
    start = time.perf_counter()
    f = system.friction
    n = f.size
    K = system.dense_stiffness().astype(float)
    B = np.asarray(system.coupling, dtype=float)
    solver = CoupledEvents(K, B, f, Qt, Pt, max_events or 200 * n + 1000)
    theta_s = np.linspace(0.0, TWO_PI, samples + 1)
    u, status = solver.initial(u0)
    W_cycles, changes, dWs = [], [], []
    remaining, ratio = math.inf, math.nan
    for _ in range(max_cycles):
        u_end, status_end, W, events, series = solver.cycle(u, status, theta_s)
        W_cycles.append(W)
        span = max(float(np.max(np.ptp(series[0], axis=0))), solver.uscale * 1e-6)
        # the start's change relative to the displacement range, and W's relative to the
        # work scale: both must have settled (a slip that shrinks to a touch moves W more
        # than the start)
        change = float(np.max(np.abs(u_end - u))) / span
        wscale = max(abs(W), solver.fscale * solver.uscale * 1e-6)
        dW = abs(W - W_cycles[-2]) / wscale if len(W_cycles) > 1 else math.inf
        changes.append(change)
        dWs.append(dW)
        u, status = u_end, status_end
        if change <= tol and dW <= tol:
            remaining = max(change, dW)
            break
        if len(changes) >= 3 and changes[-2] > 0 and dWs[-2] > 0:
            ratio = max(changes[-1] / changes[-2], changes[-2] / changes[-3], dWs[-1] / dWs[-2])
            if ratio < 0.95:
                remaining = max(change, dW) * ratio / (1.0 - ratio)
                if remaining <= tol:
                    break
    else:
        raise ConvergenceError(
            f"exact (coupled): no periodic steady state after {max_cycles} cycles (relative "
            f"change of the start {changes[-1]:.3g}, last ratio {ratio:.3g}); raise max_cycles",
            None,
        )
    Us, Fs, Ns, Ss = series
    stats = dict(
        events_per_cycle=events,
        cycles=len(W_cycles),
        ratio=ratio,
        remaining=remaining,
        changes=np.asarray(changes),
        coupled=True,
        periodicity_tol=tol,
        seconds=time.perf_counter() - start,
    )
    return dict(
        W=W_cycles[-1],
        W_cycles=np.asarray(W_cycles),
        cycles=len(W_cycles),
        change=changes[-1],
        events=events,
        omega=omega,
        theta=theta_s,
        u=Us,
        F=Fs,
        N=Ns,
        state=Ss,
        stats=stats,
    )
