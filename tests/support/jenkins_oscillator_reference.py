"""A time-domain reference for harmonic balance (tests and benchmarks only): one mass on a spring
k0 and a damper c, with a Jenkins element (stiffness kt in series with a slider of limit μN) to
the ground, forced by ``f cos ωt``:

    m x'' + c x' + k0 x + T = f cos ωt,   T = kt (x - s),   |T| <= μN,

integrated by DOP853 (rtol 1e-12) event by event: in stick the slider s is fixed; it starts to
slip where ``T`` reaches ``±μN`` (then ``T = ±μN``, ``s' = x'``) and sticks again where the mass's
velocity changes sign. Periods are integrated from rest until the state at the period's start
repeats to ``tol``; the steady cycle's first-harmonic coefficients of x (on 4096 samples of the
dense output, by the trapezoidal rule) and its amplitude ``(max x - min x)/2`` are returned.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


def _event(fun, direction):
    fun.terminal = True
    fun.direction = direction
    return fun


def steady_cycle(m, c, k0, kt, slip, f, omega, *, tol=1e-11, max_periods=5000):
    """The steady cycle: ``(a1, b1, amplitude, periods)`` with ``x ≈ a1 cos ωt + b1 sin ωt``."""
    T = 2.0 * math.pi / omega
    x, v, s = 0.0, 0.0, 0.0
    mode = 0  # 0 stick, ±1 slip with T = ±slip

    def period(x, v, s, mode, t0, dense=False):
        t, end = t0, t0 + T
        pieces = []
        for _ in range(10_000):
            if t >= end - 1e-13 * T:
                break
            if mode == 0:

                def rhs(t, y, s=s):
                    return [
                        y[1],
                        (f * math.cos(omega * t) - c * y[1] - k0 * y[0] - kt * (y[0] - s)) / m,
                    ]

                ev = [
                    _event(lambda t, y, s=s: kt * (y[0] - s) - slip, +1),
                    _event(lambda t, y, s=s: kt * (y[0] - s) + slip, -1),
                ]
            else:

                def rhs(t, y, d=mode):
                    return [y[1], (f * math.cos(omega * t) - c * y[1] - k0 * y[0] - d * slip) / m]

                ev = [_event(lambda t, y, d=mode: d * y[1], -1)]
            sol = solve_ivp(rhs, (t, end), [x, v], method="DOP853", rtol=1e-12, atol=1e-15,
                            events=ev, dense_output=dense)  # fmt: skip
            if dense:
                pieces.append(sol)
            t, (x, v) = sol.t[-1], sol.y[:, -1]
            if sol.status == 1:
                if mode == 0:
                    mode = 1 if sol.t_events[0].size else -1
                else:
                    s = x - mode * slip / kt  # sticks with T = mode * slip
                    mode, v = 0, v
        return x, v, s, mode, pieces

    for k in range(max_periods):
        x1, v1, s1, mode1, _ = period(x, v, s, mode, k * T)
        change = max(abs(x1 - x), abs(v1 - v) / omega, abs(s1 - s))
        x, v, s, mode = x1, v1, s1, mode1
        if change <= tol * max(1.0, abs(x)):
            break
    else:
        raise RuntimeError(f"no steady cycle in {max_periods} periods (change {change:.3g})")
    *_, pieces = period(x, v, s, mode, (k + 1) * T, dense=True)
    t0 = (k + 1) * T
    ts = t0 + np.linspace(0.0, T, 4097)
    xs = np.empty(ts.size)
    for sol in pieces:
        on = (ts >= sol.t[0]) & (ts <= sol.t[-1])
        xs[on] = sol.sol(ts[on])[0]
    w = np.full(ts.size, T / 4096)
    w[0] = w[-1] = 0.5 * T / 4096
    a1 = 2.0 / T * np.sum(w * xs * np.cos(omega * ts))
    b1 = 2.0 / T * np.sum(w * xs * np.sin(omega * ts))
    return a1, b1, 0.5 * (xs.max() - xs.min()), k + 2
