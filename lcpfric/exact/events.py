"""The exact solver's events: the next one of a pattern (where a triple enters a half-line),
the pattern decided at an event (the slip-rate LCP), and one cycle integrated event by event
(:mod:`lcpfric.exact.discrete`, "At an event")."""

from __future__ import annotations

import numpy as np

from ..errors import SolverError
from ..results import State
from ..steppers.rates import slip_rates
from .pattern import Pattern
from .triples import TWO_PI, value

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

    # -- deciding the pattern at an event ----------------------------------------------------
    def pivots(self, pattern, k, budget, skip_set, theta):
        """:func:`lcpfric.exact.loop.pivots` on this solver's state: (code, k)."""
        lin, tri, flg, tan, wk = self.bundles()
        code, k = self.loop.pivots(
            pattern, k, budget, skip_set, theta, lin, tri, flg, tan, wk,
            (self.fscale, self.rate_scale), self.t_all, self.ints, self.fl,
        )  # fmt: skip
        self.raise_code(code)
        return code, k

    def decide(self, theta, guess, touch_lo, touch_hi, attempt, recontact=None, resume=None):
        """The pattern valid just after theta.

        First the guess, corrected by principal pivots on the actual pattern (least index: a
        slipping node whose rate is negative sticks, a stuck node driven through its limit
        slips; for a P-matrix this terminates at the LCP's unique solution;
        :func:`lcpfric.exact.loop.pivots`, resumed from ``resume = (pattern, k, budget, code)``
        where the compiled loop stopped). After ``4 + changes`` pivots, or at a degenerate
        instant (``attempt`` >= 1), the rate LCP decides, with the load rates at theta + η when
        ``attempt`` >= 2."""
        loop = self.loop
        if attempt == 0:
            if resume is None:
                pattern = np.array(guess, dtype=np.int8)
                budget = 4 + int(np.sum(guess != self.status))
                code, k = self.pivots(pattern, 0, budget, False, theta)
            else:
                pattern, k, budget, code = resume
            while code == loop.FULL:
                self.full(pattern, self.u_at(theta), theta)
                code, k = self.pivots(pattern, k, budget, True, theta)
            if code == loop.DONE:
                return
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

    # -- one cycle ---------------------------------------------------------------------------
    def cycle(self, u, status, theta_s, track=False):
        """Integrate one cycle from the state (u, status) at θ = 0 (:func:`lcpfric.exact.loop.
        run`, with :meth:`decide` finishing the events it returns); returns the end state, W,
        the number of events and the samples. With ``track``, the tangent map is propagated
        too (:meth:`jacobian`)."""
        k, loop, n = self.kernels, self.loop, self.n
        samples = (
            np.empty((theta_s.size, n)),
            np.empty((theta_s.size, n)),
            np.empty((theta_s.size, n), dtype=np.int8),
        )
        self.track = False
        self.set_pattern(status, 0.0, refresh=True, u=u)
        self.W = 0.0
        self.track = track
        self.flipped[:] = False
        self.erased = False
        if track:
            self.Jt = self.start_tangent()
        ints, fl = self.ints, self.fl
        ints[[k.EVENTS, k.KS, k.KN, k.ATTEMPT, k.HAS_TROW]] = 0
        fl[k.THETA], fl[k.LAST] = 0.0, -1.0
        # normal events at θ = 0 are processed as events at the start
        ev = tuple(np.zeros(n, dtype=dt) for dt in (np.int8, bool, bool, bool, np.int8))
        while True:
            code = loop.run(
                theta_s, samples, self.normal, ev, *self.bundles(),
                (self.fscale, self.rate_scale), self.t_all, ints, fl,
            )  # fmt: skip
            self.raise_code(code)
            theta = float(fl[k.THETA])
            if code == loop.END:
                events = int(ints[k.EVENTS])
                return self.u_at(TWO_PI), self.status.copy(), self.W, events, samples
            if code == loop.TOO_MANY:
                raise SolverError(
                    f"exact: more than {self.max_events} events in one cycle "
                    f"(θ = {theta:.6g}; {self.describe()})",
                    backend="exact",
                    status="too_many_events",
                )
            if code == loop.UNSETTLED:
                raise SolverError(
                    f"exact: the pattern does not settle at θ = {theta:.17g} ({self.describe()})",
                    backend="exact",
                    status="event_loop",
                )
            guess, touch_lo, touch_hi, recontact, pattern = ev
            attempt = int(ints[k.ATTEMPT])
            resume = None
            if attempt == 0:
                resume = (pattern, int(ints[k.PIVOT_K]), int(ints[k.BUDGET]))
                resume += (int(ints[k.PIVOT_CODE]),)
            self.decide(
                theta, guess.copy(), touch_lo.copy(), touch_hi.copy(), attempt,
                recontact.copy(), resume,
            )  # fmt: skip
            ints[k.HAS_TROW] = 0
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
