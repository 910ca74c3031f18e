"""The cycle of many points at once: one event per numpy pass over all points."""

from __future__ import annotations

import math

import numpy as np

from .formulas import (
    AFTER_BACKWARD,
    AFTER_FORWARD,
    BACKWARD,
    Coefficients,
    crossing_vec,
    FORWARD,
    HALF_PI,
    L_of,
    MAX_EVENTS,
    mod0,
    pmod,
    RECONTACT,
    S_RANGE,
    sform_W_vec,
    slip_integral,
    STICK,
    TIE,
    TWO_PI,
)


def run_vectorized(P1, Q1, phi, sphi=None, cphi=None):
    """Advance every point one event at a time over the steady cycle; return Ŵ = ∮ L |dw| / Q̂1.

    Needs Q̂1 > 0. ``sphi``, ``cphi``: sin φ and cos φ of the caller's unreduced φ (default: of
    ``phi``). Vectorized twin of :func:`run_scalar` (the tests check they agree point by point).
    """
    if sphi is None:
        sphi, cphi = np.sin(phi), np.cos(phi)
    c = Coefficients.of(P1, Q1, phi, sphi, cphi)
    n = P1.size
    sep = P1 >= 1.0
    g = np.sqrt(np.where(sep, P1 - 1.0, 0.0)) * np.sqrt(P1 + 1.0)
    asin_inv = np.arctan2(1.0, g)  # asin(1/P̂1), accurate next to P̂1 = 1
    theta_c = TWO_PI - asin_inv  # re-contact
    theta_s = math.pi + asin_inv + TWO_PI  # the separation that ends the steady cycle
    q_s = -Q1 * np.sin(asin_inv + phi)  # Q̂ and dQ̂/dθ at separation
    dq_s = -Q1 * np.cos(asin_inv + phi)
    eq_c = -2.0 * sphi * (g / np.hypot(1.0, g))  # (w + Q̂(θ_s)) / Q̂1 when stuck since re-contact

    th = np.where(sep, theta_c, 1.5 * math.pi - c.a_lo)
    stop = np.where(sep, theta_s, th + TWO_PI)
    w = np.where(sep, -Q1 * np.sin(theta_c + phi), c.lo_max)
    state = np.full(n, STICK, dtype=np.int8)
    kind = np.full(n, AFTER_FORWARD, dtype=np.int8)
    psi = np.zeros(n)  # phase of the pushing boundary at the start of a slip segment
    xs = np.full(n, -1.0)  # s = θ_s - θ at the start of a slip found in s (else -1)
    xis = np.zeros(n)  # that s / c
    cs = np.zeros(n)  # c = |w + Q̂(θ_s)| of that slip
    cqs = np.zeros(n)  # c / Q̂1
    W = np.zeros(n)
    L_from_w = Q1 <= P1  # L at a slip's start from w (exact 0 at re-contact) or from θ

    # At re-contact w = lo = hi; classify by the phase of each boundary (half-open intervals, so
    # that a boundary at its extremum is assigned exactly one state).
    psi_lo_c = mod0(theta_c + c.a_lo)
    psi_hi_c = mod0(theta_c + c.a_hi)
    fwd0 = sep & (psi_lo_c >= HALF_PI) & (psi_lo_c < 1.5 * math.pi)
    bwd0 = sep & ~fwd0 & ((psi_hi_c >= 1.5 * math.pi) | (psi_hi_c < HALF_PI))
    state[fwd0] = FORWARD
    psi[fwd0] = psi_lo_c[fwd0]
    state[bwd0] = BACKWARD
    psi[bwd0] = np.where(psi_hi_c >= 1.5 * math.pi, psi_hi_c - TWO_PI, psi_hi_c)[bwd0]
    kind[sep & ~fwd0 & ~bwd0] = RECONTACT

    # shakedown (no separation, R_lo + R_hi <= 2): the orbit sticks at its start, Ŵ = 0
    active = sep | (c.R_lo + c.R_hi > 2.0)
    for _ in range(MAX_EVENTS):
        if not active.any():
            break
        # -- stick: the next time lo rises through w or hi falls through w, or separation -------
        i = np.nonzero(active & (state == STICK))[0]
        if i.size:
            k = kind[i]
            wi, thi = w[i], th[i]
            d_lo = np.full(i.size, np.inf)
            d_hi = np.full(i.size, np.inf)
            up_lo = np.zeros(i.size)
            dn_hi = np.zeros(i.size)
            # After forward slip w sits at the maximum of lo (lo does not rise through it); hi
            # falls to it after the angle X_f - Δ (see _stick_angles). Symmetrically after
            # backward slip.
            after_f = k == AFTER_FORWARD
            X = c.X_f[i]
            ok = after_f & ~np.isnan(X)
            d_hi[ok] = pmod(X[ok] - c.delta[i[ok]])
            dn_hi[ok] = X[ok] - HALF_PI
            after_b = k == AFTER_BACKWARD
            X = c.X_b[i]
            ok = after_b & ~np.isnan(X)
            d_lo[ok] = pmod(X[ok] + c.delta[i[ok]])
            up_lo[ok] = X[ok] + HALF_PI
            # At re-contact w is on both ends; each crossing is the other root of a known one.
            rc = k == RECONTACT
            if rc.any():
                pl = psi_lo_c[i[rc]]
                ph = psi_hi_c[i[rc]]
                d_lo[rc] = pmod(math.pi - 2.0 * pl)
                up_lo[rc] = mod0(math.pi - pl)  # in [π/2, 3π/2]: pl may be >= 3π/2
                d_hi[rc] = pmod(math.pi - 2.0 * ph)
                dn_hi[rc] = math.pi - ph
            t_lo = thi + d_lo
            t_hi = thi + d_hi
            # With separation ahead, the last crossing before it is found in s = θ_s - θ, where
            # a crossing 1e-300 rad before separation is still resolved (see crossing).
            fin_lo = np.zeros(i.size, dtype=bool)
            fin_hi = np.zeros(i.size, dtype=bool)
            # (only within π/2 of separation: an earlier event needs no s)
            sp = sep[i] & (np.minimum(t_lo, t_hi) > stop[i] - S_RANGE)
            if sp.any():
                r = np.nonzero(sp)[0]
                ir = i[r]
                Qi = Q1[ir]
                eq = np.where(rc[r], eq_c[ir], (wi[r] + q_s[ir]) / Qi)  # e/Q̂1, e = w + Q̂(θ_s)
                e = eq * Qi
                fwd = e < 0.0
                gi = g[ir]
                a_s = np.where(fwd, gi - dq_s[ir], gi + dq_s[ir])
                b_s = np.where(fwd, 1.0 - q_s[ir], 1.0 + q_s[ir])
                x, xi = crossing_vec(a_s, b_s, np.abs(e))
                valid = (x >= 0.0) & (x <= stop[ir] - thi[r])
                fin_lo[r] = fwd & ~after_f[r] & valid
                fin_hi[r] = (e > 0.0) & ~after_b[r] & valid
                t_end = stop[ir] - x
                tl, th_ = t_lo[r], t_hi[r]
                tl = np.where(fin_lo[r], t_end, tl)
                th_ = np.where(fin_hi[r], t_end, th_)
                # the other bound's crossing counts only if resolved before the last one
                th_ = np.where(fin_lo[r] & (th_ > tl - TIE), np.inf, th_)
                tl = np.where(fin_hi[r] & (tl > th_ - TIE), np.inf, tl)
                # e = 0 at re-contact: θ_c and θ_s are both roots of lo = w and of hi = w, so w
                # sticks to separation
                closed = rc[r] & (e == 0.0) & (gi > 0.0)
                t_lo[r] = np.where(closed, np.inf, tl)
                t_hi[r] = np.where(closed, np.inf, th_)
                xs[ir] = np.where(fin_lo[r] | fin_hi[r], x, -1.0)
                xis[ir] = xi
                cs[ir] = np.abs(e)
                cqs[ir] = np.abs(eq)
            lo_first = t_lo <= t_hi
            to_f = lo_first & ((t_lo < stop[i]) | fin_lo)
            to_b = ~lo_first & ((t_hi < stop[i]) | fin_hi)
            done = ~to_f & ~to_b
            xs[i[~((to_f & fin_lo) | (to_b & fin_hi))]] = -1.0
            active[i[done]] = False
            th[i] = np.where(to_f, t_lo, np.where(to_b, t_hi, stop[i]))
            state[i[to_f]] = FORWARD
            psi[i[to_f]] = up_lo[to_f]
            state[i[to_b]] = BACKWARD
            psi[i[to_b]] = dn_hi[to_b]
        # -- slip on a bound, until its extremum or separation -----------------------------------
        for slip, end_phase, sign, w_end, next_kind in (
            (FORWARD, 1.5 * math.pi, -1.0, c.lo_max, AFTER_FORWARD),
            (BACKWARD, HALF_PI, 1.0, c.hi_min, AFTER_BACKWARD),
        ):
            i = np.nonzero(active & (state == slip))[0]
            if not i.size:
                continue
            # (a) a slip found in s: it reaches separation unless its bound turns first (a < 0)
            fs = xs[i] >= 0.0
            if fs.any():
                j = i[fs]
                if slip == FORWARD:
                    a_s, b_s = g[j] - dq_s[j], 1.0 - q_s[j]
                else:
                    a_s, b_s = g[j] + dq_s[j], 1.0 + q_s[j]
                x = xs[j]
                W[j] += sform_W_vec(g[j], a_s, b_s, x, xis[j], cs[j], cqs[j])
                turn = a_s < 0.0
                # the bound's extremum at s_m (a cos s + b sin s = 0): stick there after it
                s_m = np.where(turn, np.arctan2(-a_s, b_s), 0.0)
                s_m = np.minimum(s_m, x)
                with np.errstate(divide="ignore", invalid="ignore"):
                    xi_m = np.where(turn, s_m / cs[j], 0.0)
                W[j] -= np.where(turn, sform_W_vec(g[j], a_s, b_s, s_m, xi_m, cs[j], cqs[j]), 0.0)
                th[j] = stop[j] - s_m
                w[j] = w_end[j]
                active[j[~turn]] = False
                state[j[turn]] = STICK
                kind[j[turn]] = next_kind
                xs[j] = -1.0
                i = i[~fs]
                if not i.size:
                    continue
            # (b) a slip in θ
            a = th[i]
            b = a + np.maximum(end_phase - psi[i], 0.0)
            done = b >= stop[i]
            b = np.minimum(b, stop[i])
            L_a = np.where(L_from_w[i], np.abs(w[i] + Q1[i] * np.sin(a + phi[i])), L_of(P1[i], a))
            L_b = np.where(done & sep[i], 0.0, L_of(P1[i], b))
            if slip == FORWARD:
                R, al, sa, ca = c.R_lo[i], c.a_lo[i], c.s_lo[i], c.c_lo[i]
            else:
                R, al, sa, ca = c.R_hi[i], c.a_hi[i], c.s_hi[i], c.c_hi[i]
            W[i] += slip_integral(
                a, b, P1[i], Q1[i], phi[i], sphi[i], cphi[i], L_a, L_b, sign, R, al, sa, ca
            )
            th[i] = b
            w[i] = w_end[i]
            active[i[done]] = False
            cont = i[~done]
            state[cont] = STICK
            kind[cont] = next_kind
    else:  # pragma: no cover - would be a bug in the event logic
        raise RuntimeError("exact solver: event loop did not terminate; please report this case")
    return W
