"""An independent event-driven integration of the dynamic single node (tests only): the equation
of motion integrated by DOP853 (rtol 1e-12) with the stops and separation as its events, and a
stick's end found on a fine sample grid refined by Brent's method. It shares nothing with
lcpfric.exact.dynamic but the equations (normalized units, θ = ωt):

    β² u'' + 2ζβ u' + u = F - Q̂1 sin(θ + φ),   n = 1 + P̂1 sin θ,
    slip s = sign u': F = -s n;  stick (u' = 0): F = u + q, |F| <= n;  separation (n <= 0): F = 0.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def one_period(P1, Q1, phi, beta, zeta, z, theta0=0.0):
    """Integrate one period from ``z = (u, u')`` at ``theta0``: ``(z_end, J, u_min, u_max)``
    with ``J = ∫ n |u'| dθ`` over the slips."""
    b2, c = beta * beta, 2.0 * zeta * beta

    def q(t):
        return Q1 * math.sin(t + phi)

    def n(t):
        return 1.0 + P1 * math.sin(t)

    def rhs(F, s=0.0):
        # J' = s n u' (not n |u'|: smooth through the stop, where the integrator's last step
        # reaches past the event and is cut back by its dense output)
        def f(t, y):
            return [y[1], (F(t) - q(t) - c * y[1] - y[0]) / b2, s * n(t) * y[1]]

        return f

    th, end = theta0, theta0 + 2 * math.pi
    u, du = float(z[0]), float(z[1])
    J, lo, hi = 0.0, u, u
    for _ in range(10_000):
        if th >= end - 1e-13:
            break
        if n(th) <= 1e-14 and P1 > 1.0:  # separated (re-contact: n back above 0)
            ev = _event(lambda t, y: n(t), +1)
            sol = solve_ivp(
                rhs(lambda t: 0.0),
                (th, end),
                [u, du, 0.0],
                method="DOP853",
                rtol=1e-12,
                atol=1e-14,
                events=ev,
                dense_output=True,
            )
            lo, hi = _extremes(sol, lo, hi)
            th, (u, du) = sol.t[-1], sol.y[:2, -1]
            if sol.status == 1:
                th += 1e-12  # just past re-contact
            continue
        F0 = u + q(th)
        if du == 0.0 and abs(F0) <= n(th):  # stick: until |u + q| = n
            slack = lambda t: n(t) - abs(u + q(t))  # noqa: E731
            grid = np.linspace(th, end, max(2, int(20000 * (end - th) / (2 * math.pi))))
            vals = np.array([slack(t) for t in grid])
            bad = np.flatnonzero(vals[1:] < 0.0)
            if bad.size == 0:
                th = end
                continue
            i = bad[0]
            th = brentq(slack, grid[i], grid[i + 1], xtol=1e-15)
            s = -1.0 if u + q(th) > 0 else 1.0
        else:
            s = math.copysign(1.0, du) if du != 0.0 else (-1.0 if F0 > n(th) else 1.0)
        F = lambda t, s=s: -s * n(t)  # noqa: E731
        events = [_event(lambda t, y, s=s: s * y[1], -1)]
        if P1 > 1.0:
            events.append(_event(lambda t, y: n(t), -1))
        sol = solve_ivp(
            rhs(F, s),
            (th, end),
            [u, du, 0.0],
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            events=events,
            dense_output=True,
        )
        J += sol.y[2, -1]
        th, (u, du) = sol.t[-1], sol.y[:2, -1]
        lo, hi = _extremes(sol, lo, hi)
        if sol.status == 1:
            if sol.t_events[0].size:  # a stop
                du = 0.0
                if abs(u + q(th)) > n(th):  # a reversal: start just after, from rest
                    pass
            else:  # separation
                th += 1e-12
    return np.array([u, du]), J, lo, hi


def _extremes(sol, lo, hi):
    """The running min and max of u, with the dense output's turning points."""
    t = np.linspace(sol.t[0], sol.t[-1], 4001)
    y = sol.sol(t)
    lo, hi = min(lo, y[0].min()), max(hi, y[0].max())
    for i in np.flatnonzero(np.sign(y[1, :-1]) * np.sign(y[1, 1:]) < 0):
        m = brentq(lambda s: sol.sol(s)[1], t[i], t[i + 1], xtol=1e-15)
        lo, hi = min(lo, sol.sol(m)[0]), max(hi, sol.sol(m)[0])
    return lo, hi


def _event(fun, direction):
    fun.terminal = True
    fun.direction = direction
    return fun
