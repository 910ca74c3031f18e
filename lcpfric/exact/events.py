"""The exact solver's events: the next one of a pattern (where a triple enters a half-line),
the pattern decided at an event (the slip-rate LCP), and one cycle integrated event by event
(:mod:`lcpfric.exact.discrete`, "At an event")."""

from __future__ import annotations

import numpy as np

from ..errors import SolverError
from ..results import State
from ..steppers.rates import slip_rates
from .pattern import Pattern
from .triples import TWO_PI, next_entry, rate_of, value

__all__ = ["EventSolver"]

STICK, FORWARD, BACKWARD, SEPARATION = (
    int(State.STICK),
    int(State.FORWARD),
    int(State.BACKWARD),
    int(State.SEPARATION),
)
_SAME = 64 * np.finfo(float).eps * TWO_PI  # events closer than this happen together
_ETAS = (1e-9, 1e-7, 1e-5, 1e-3)  # load-rate look-ahead for degenerate instants


class EventSolver(Pattern):
    """Event-by-event integration of one system over cycles (:mod:`lcpfric.exact.discrete`)."""

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
            T[:k] = np.where(stick, bt - Ft, D[:, None] * rate_of(self.U[rows]))
            T[k:] = np.where(stick, bt + Ft, 0.0)
            ftol = self.rel * self.fscale[rows]
            tol = np.concatenate(
                [np.where(stick[:, 0], ftol, self.rel * self.rate_scale[rows]), ftol]
            )
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
                i, new = self.violation(theta)
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
        F0 = self.forces_at(theta, u)
        bound = np.where(sep, 0.0, np.maximum(value(self.bt, theta), 0.0))
        slipping = (guess == FORWARD) | (guess == BACKWARD)
        F0 = np.where(
            sep, 0.0, np.where(guess == FORWARD, -bound, np.where(guess == BACKWARD, bound, F0))
        )
        F0 = np.where(touch_hi, bound, np.where(touch_lo, -bound, F0))
        if recontact is not None and recontact.any():
            # re-entering contact: N = 0 and F = 0 (it was separated), on both limits
            bound, F0 = np.where(recontact, 0.0, bound), np.where(recontact, 0.0, F0)
        tr = theta + eta
        dQ = value(self.dQt, tr)
        dN = np.where(sep, 0.0, value(self.dPt, tr))
        _du, new = slip_rates(
            self.K,
            self.f,
            F0,
            bound,
            dQ,
            dN,
            sep,
            slipping & (guess == FORWARD),
            slipping & (guess == BACKWARD),
            touch_lo,
            touch_hi,
        )
        self.set_pattern(np.asarray(new, dtype=np.int8), theta, refresh=True, u=u)

    def violation(self, theta):
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
        k_n = 0  # normal events at θ = 0 are processed as events at the start
        self.track = False
        self.set_pattern(status, 0.0, refresh=True, u=u)
        self.W = 0.0
        self.track = track
        self.flipped = np.zeros(n, dtype=bool)
        self.erased = False
        if track:
            self.Jt = self.start_tangent()
        attempt = 0
        last = -1.0
        while True:
            t_all = self.next_event(theta)
            t_norm = normal[k_n][0] if k_n < len(normal) else np.inf
            t_next = min(float(t_all.min()), t_norm, TWO_PI)
            # samples in [theta, t_next)
            k_end = (
                theta_s.size
                if t_next >= TWO_PI
                else int(np.searchsorted(theta_s, t_next, side="left"))
            )
            if k_end > k_s:
                th = theta_s[k_s:k_end]
                Us[k_s:k_end] = value(self.U[None, :, :], th[:, None])
                Fs[k_s:k_end] = value(self.Ft[None, :, :], th[:, None])
                Ss[k_s:k_end] = self.status
                k_s = k_end
            if t_next >= TWO_PI:
                self.settle(np.arange(n), TWO_PI)
                return self.u_at(TWO_PI), self.status.copy(), self.W, events, (Us, Fs, Ss)
            events += 1
            if events > self.max_events:
                raise SolverError(
                    f"exact: more than {self.max_events} events in one cycle "
                    f"(θ = {theta:.6g}; {self.describe()})",
                    backend="exact",
                    status="too_many_events",
                )
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
                raise SolverError(
                    f"exact: the pattern does not settle at θ = {t_next:.17g} ({self.describe()})",
                    backend="exact",
                    status="event_loop",
                )
            theta = last = t_next
            self.theta_row = None
            if self.track and now.size:
                hits = (touch_hi | touch_lo).nonzero()[0]
                if hits.size:
                    j = int(hits[0])
                    self.theta_row = self.theta_sensitivity(j, bool(touch_hi[j]), theta)
            self.decide(theta, guess, touch_lo, touch_hi, attempt, recontact)
            self.theta_row = None
            # no node stuck: the state is the forces' alone, the start is forgotten (the
            # cycle map is constant from here: its Jacobian is zero)
            self.erased = self.erased or self.m == n

    def describe(self):
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
        guess = np.where(contact, np.where(guess == SEPARATION, STICK, guess), SEPARATION).astype(
            np.int8
        )
        self.full(guess, u, 0.0)
        F = value(self.Ft, 0.0)
        b0 = np.where(contact, value(self.bt, 0.0), 0.0)
        stuck = guess == STICK
        self.decide(0.0, guess, stuck & (F <= -b0), stuck & (F >= b0), 0)
        return self.u_at(0.0), self.status.copy()

    def initial_state(self):
        """An admissible state at θ = 0: forces clipped into the cone; the pattern from the
        rate LCP."""
        Q0 = value(self.Qt, 0.0)
        contact = self.in_contact(0.0)
        # a node whose contact starts exactly at 0 is in contact
        b0 = np.where(contact, value(self.bt, 0.0), 0.0)
        F0 = np.where(contact, np.clip(Q0, -b0, b0), 0.0)
        u = self.state_for_forces(F0 - Q0)
        guess = np.where(contact, STICK, SEPARATION).astype(np.int8)
        touch_hi = contact & (Q0 >= b0)
        touch_lo = contact & (Q0 <= -b0)
        self.full(guess, u, 0.0)
        self.decide(0.0, guess, touch_lo, touch_hi, 1)
        return self.u_at(0.0), self.status.copy()
