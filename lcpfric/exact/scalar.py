"""The cycle of one point in Python floats (about 10 µs), the same events as
:mod:`~lcpfric.exact.vectorized` (tested equal), with the segments kept for time series."""

from __future__ import annotations

import math

from .formulas import (
    AFTER_BACKWARD,
    AFTER_FORWARD,
    BACKWARD,
    crossing,
    delta_series,
    FORWARD,
    HALF_PI,
    MAX_EVENTS,
    RECONTACT,
    S_RANGE,
    SEPARATION,
    sform_W,
    STICK,
    TIE,
    TWO_PI,
)


def _slip_integral_scalar(a, b, P1, Q1, phi, sphi, cphi, L_a, L_b, sign, R, alpha, salpha, calpha):
    """Scalar :func:`slip_integral`, computing only the form it uses."""
    h = 0.5 * (b - a)
    one_m_P1 = 1.0 - P1
    T = abs(one_m_P1) + 4.0 * P1
    direct = (R - Q1) * T * (2.0 * h) < 0.5 * (L_a * L_a + L_b * L_b)
    if direct:
        sphi, cphi = salpha, calpha
    m = 0.5 * (a + b) - 1.5 * math.pi
    sh, sm, cm = math.sin(h), math.sin(m), math.cos(m)
    Vh = 2.0 * math.sin(0.5 * h) ** 2
    vm = 2.0 * math.sin(0.5 * m) ** 2
    h_sin = h * h * h * delta_series(h) if h < 0.5 else h - sh
    I_c = sh * Vh - h_sin + sh * (2.0 * vm * cm - 2.0 * sm * sm * Vh)
    I_s = 2.0 * sm * sh * (vm + cm * Vh)
    K = one_m_P1 * 2.0 * (sm * cphi + cm * sphi) * sh + P1 * (cphi * I_s + sphi * I_c)
    if direct:
        return sign * (R / Q1) * K
    return 0.5 * (L_a - L_b) * ((L_a + L_b) / Q1) + sign * K


def run_scalar(
    P1: float,
    Q1: float,
    phi: float,
    sphi: float | None = None,
    cphi: float | None = None,
    record: bool = True,
):
    """The same event loop as :func:`run_vectorized` for one point, in scalar arithmetic (about 10x
    faster than numpy on one-element arrays). Needs Q̂1 > 0. Returns (Ŵ, segments); segments are
    collected only if ``record``."""
    if sphi is None:
        sphi, cphi = math.sin(phi), math.cos(phi)
    A, B = P1 + Q1 * cphi, Q1 * sphi
    C = Q1 * cphi - P1
    R_lo, a_lo = math.hypot(A, B), math.atan2(B, A)
    R_hi, a_hi = math.hypot(C, B), math.atan2(B, C)
    sep = P1 >= 1.0
    # max lo = R_lo - 1 and min hi = 1 - R_hi (see _extrema)
    if P1 < 4.0 and Q1 < 4.0 and abs((P1 - 1.0) * (P1 + 1.0)) + Q1 * (2.0 * P1 + Q1) <= 1.0:
        g2 = (P1 - 1.0) * (P1 + 1.0)
        lo_max = (g2 + Q1 * (2.0 * P1 * cphi + Q1)) / (R_lo + 1.0)
        hi_min = (Q1 * (2.0 * P1 * cphi - Q1) - g2) / (1.0 + R_hi)
    else:
        lo_max, hi_min = R_lo - 1.0, 1.0 - R_hi
    if not sep and R_lo + R_hi <= 2.0:  # shakedown: the orbit sticks at the start
        th = 1.5 * math.pi - a_lo
        return 0.0, ([(th, th + TWO_PI, STICK, lo_max)] if record else None)
    # the sticks after a slip (see _stick_angles)
    s = R_lo + R_hi
    dR = 4.0 * cphi * P1 * (Q1 / s)
    delta = math.atan2(2.0 * P1 * sphi * (Q1 / (Q1 + P1)), Q1 - P1)
    y_f = (2.0 - dR) / (2.0 * R_hi) if R_hi > 0.0 else math.inf
    y_b = (2.0 + dR) / (2.0 * R_lo)
    X_f = 2.0 * math.asin(math.sqrt(y_f)) if 0.0 <= y_f <= 1.0 else math.nan
    X_b = 2.0 * math.asin(math.sqrt(y_b)) if 0.0 <= y_b <= 1.0 else math.nan
    segments = [] if record else None
    L_from_w = Q1 <= P1
    if sep:
        g = math.sqrt(P1 - 1.0) * math.sqrt(P1 + 1.0)
        asin_inv = math.atan2(1.0, g)
        theta_c = TWO_PI - asin_inv
        th, stop = theta_c, math.pi + asin_inv + TWO_PI
        q_s = -Q1 * math.sin(asin_inv + phi)
        dq_s = -Q1 * math.cos(asin_inv + phi)
        eq_c = -2.0 * sphi * (g / math.hypot(1.0, g))
        w = -Q1 * math.sin(theta_c + phi)
        pl, ph = (theta_c + a_lo) % TWO_PI, (theta_c + a_hi) % TWO_PI
        kind = RECONTACT
        if HALF_PI <= pl < 1.5 * math.pi:
            state, psi = FORWARD, pl
        elif ph >= 1.5 * math.pi or ph < HALF_PI:
            state, psi = BACKWARD, (ph - TWO_PI if ph >= 1.5 * math.pi else ph)
        else:
            state, psi = STICK, 0.0
    else:
        th = 1.5 * math.pi - a_lo
        stop = th + TWO_PI
        w, state, kind, psi = lo_max, STICK, AFTER_FORWARD, 0.0
    W = 0.0
    x_f = -1.0  # s = θ_s - θ at the start of a slip found in s (else -1)
    for _ in range(MAX_EVENTS):
        if state == STICK:
            d_lo = d_hi = math.inf
            if kind == RECONTACT:
                d_lo, up_lo = TWO_PI - (-(math.pi - 2.0 * pl)) % TWO_PI, (math.pi - pl) % TWO_PI
                d_hi, dn_hi = TWO_PI - (-(math.pi - 2.0 * ph)) % TWO_PI, math.pi - ph
            elif kind == AFTER_FORWARD:
                if X_f == X_f:  # not NaN
                    d_hi, dn_hi = TWO_PI - (delta - X_f) % TWO_PI, X_f - HALF_PI
            elif X_b == X_b:
                d_lo, up_lo = TWO_PI - (-(X_b + delta)) % TWO_PI, X_b + HALF_PI
            t_lo, t_hi = th + d_lo, th + d_hi
            fin = 0
            # the last crossing before separation, found in s = θ_s - θ (used only within π/2
            # of separation: an earlier event needs no s)
            if sep and (t_lo if t_lo < t_hi else t_hi) > stop - S_RANGE:
                eq = eq_c if kind == RECONTACT else (w + q_s) / Q1
                e = eq * Q1
                if e == 0.0 and kind == RECONTACT and g > 0.0:
                    # θ_c and θ_s are both roots of lo = w and of hi = w (a bound crosses a
                    # level twice a period): w sticks to separation
                    t_lo = t_hi = math.inf
                elif e < 0.0 and kind != AFTER_FORWARD:
                    x, xi = crossing(g - dq_s, 1.0 - q_s, -e)
                    if 0.0 <= x <= stop - th:
                        t_lo, fin = stop - x, FORWARD
                        if t_hi > t_lo - TIE:  # not resolved before it: w is above hi's path
                            t_hi = math.inf
                elif e > 0.0 and kind != AFTER_BACKWARD:
                    x, xi = crossing(g + dq_s, 1.0 + q_s, e)
                    if 0.0 <= x <= stop - th:
                        t_hi, fin = stop - x, BACKWARD
                        if t_lo > t_hi - TIE:
                            t_lo = math.inf
            if t_lo <= t_hi and (t_lo < stop or fin == FORWARD):
                state, psi, t_end = FORWARD, up_lo, t_lo
            elif t_hi < t_lo and (t_hi < stop or fin == BACKWARD):
                state, psi, t_end = BACKWARD, dn_hi, t_hi
            else:
                record and segments.append((th, stop, STICK, w))
                break
            record and segments.append((th, t_end, STICK, w))
            th = t_end
            if fin == state:
                x_f, c_f, cq_f = x, abs(e), abs(eq)
        else:
            fwd = state == FORWARD
            w_end = lo_max if fwd else hi_min
            if x_f >= 0.0:  # found in s: reaches separation unless its bound turns first
                a_s, b_s = (g - dq_s, 1.0 - q_s) if fwd else (g + dq_s, 1.0 + q_s)
                W += sform_W(g, a_s, b_s, x_f, xi, c_f, cq_f)
                if a_s >= 0.0:
                    record and segments.append((th, stop, state, w))
                    break
                s_m = min(math.atan2(-a_s, b_s), x_f)  # the bound's extremum
                W -= sform_W(g, a_s, b_s, s_m, s_m / c_f, c_f, cq_f)
                record and segments.append((th, stop - s_m, state, w))
                th, w, x_f = stop - s_m, w_end, -1.0
                kind = AFTER_FORWARD if fwd else AFTER_BACKWARD
                state = STICK
                continue
            end_phase = 1.5 * math.pi if fwd else HALF_PI
            b = th + max(end_phase - psi, 0.0)
            done = b >= stop
            b = min(b, stop)
            if L_from_w:
                L_a = abs(w + Q1 * math.sin(th + phi))
            else:
                L_a = max(0.0, (1.0 - P1) + 2.0 * P1 * math.sin(0.5 * (th - 1.5 * math.pi)) ** 2)
            L_b = (
                0.0
                if done and sep
                else max(0.0, (1.0 - P1) + 2.0 * P1 * math.sin(0.5 * (b - 1.5 * math.pi)) ** 2)
            )
            if fwd:
                W += _slip_integral_scalar(
                    th, b, P1, Q1, phi, sphi, cphi, L_a, L_b, -1.0, R_lo, a_lo, B / R_lo, A / R_lo
                )
            else:
                W += _slip_integral_scalar(
                    th,
                    b,
                    P1,
                    Q1,
                    phi,
                    sphi,
                    cphi,
                    L_a,
                    L_b,
                    1.0,
                    R_hi,
                    a_hi,
                    B / R_hi if R_hi > 0 else 0.0,
                    C / R_hi if R_hi > 0 else 1.0,
                )
            record and segments.append((th, b, state, w))
            th = b
            w = w_end
            if done:
                break
            kind = AFTER_FORWARD if fwd else AFTER_BACKWARD
            state = STICK
    else:  # pragma: no cover - would be a bug in the event logic
        raise RuntimeError("exact solver: event loop did not terminate; please report this case")
    if sep and record:
        segments.append((stop, theta_c + TWO_PI, SEPARATION, float("nan")))
    return W, segments
