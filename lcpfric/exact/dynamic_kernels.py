r"""Compiled kernels (numba) of the dynamic single node: its closed-form modes, the events of one
period, and the samples of a cycle (issue 40, item 2; the method is :mod:`.dynamic`'s).

Imported when a dynamic node is first solved, never by ``import lcpfric``; compiled on first use
and cached on disk (``cache=True``).

Modes (normalized units, θ = ωt): ``β² u'' + 2ζβ u' + u = g(θ)``, ``g = g0 + gc cos θ + gs sin θ``
(slip s: ``-s n - q``; separation: ``-q``; ``n = 1 + P̂1 sin θ``, ``q = Q̂1 sin(θ + φ)``). A
mode's motion from ``(θa, ua, u'a)`` is the particular ``u_p = g0 + A cos θ + B sin θ``
(``(1-β²) A + 2ζβ B = gc``, ``(1-β²) B - 2ζβ A = gs``) plus ``E(θ - θa) (y_a - y_p(θa))``,
``E(s) = exp(s M)``, ``M = [[0, 1], [-1/β², -2ζ/β]]``, in closed form for every damping: with
``μ = -ζ/β``, ``ν² = (ζ² - 1)/β²`` and ``N = M - μ I``, ``E = e^{μs} (C I + S N)`` where
``(C, S) = (cos ws, sin(ws)/w)`` (``w² = -ν²``), ``(cosh νs, sinh(νs)/ν)`` or ``(1, s)``
(over-damped segments by their two exponentials: no overflow).

``P`` (the parameters, a float array): ``P1, Q1, φ, β, ζ, cell, sep_a, sep_b`` (the scan's cell
and the separation interval in [0, 2π), NaN without separation). A segment is the tuple
``(θa, p0, A, B, h0, h1, g0, gc, gs)`` (``h = y_a - y_p(θa)``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "period_map",
    "sample",
    "linear_response",
    "STICK",
    "SLIP_F",
    "SLIP_B",
    "SEPARATION",
    "MAX_SEGMENTS",
]

STICK, SLIP_F, SLIP_B, SEPARATION = 0, 1, -1, 2
TWO_PI = 2.0 * math.pi
#: segments recorded per period at most
MAX_SEGMENTS = 4096
_EPS = np.finfo(np.float64).eps
_GX, _GW = np.polynomial.legendre.leggauss(8)


@njit(cache=True, nogil=True)
def _prop(P, s):  # pragma: no cover - compiled
    beta, zeta = P[3], P[4]
    b2 = beta * beta
    mu = -zeta / beta
    nu2 = (zeta * zeta - 1.0) / b2
    n00, n10, n11 = -mu, -1.0 / b2, -2.0 * zeta / beta - mu
    if nu2 < 0.0:
        w = math.sqrt(-nu2)
        C, S = math.cos(w * s), math.sin(w * s) / w
    elif nu2 > 0.0:
        nu = math.sqrt(nu2)
        if nu * max(1.0, abs(s)) > 1e-3:
            e1, e2 = math.exp((mu + nu) * s), math.exp((mu - nu) * s)
            p, m = 0.5 * (e1 + e2), 0.5 * (e1 - e2) / nu
            return p + m * n00, m, m * n10, p + m * n11
        C, S = math.cosh(nu * s), math.sinh(nu * s) / nu
    else:
        C, S = 1.0, s
    e = math.exp(mu * s)
    return e * (C + S * n00), e * S, e * S * n10, e * (C + S * n11)


@njit(cache=True, nogil=True)
def _flow(P, s, j00, j01, j10, j11):  # pragma: no cover - compiled
    """``E(s) J``: the period map's Jacobian carried over a mode's flow of length s."""
    e00, e01, e10, e11 = _prop(P, s)
    return (
        e00 * j00 + e01 * j10,
        e00 * j01 + e01 * j11,
        e10 * j00 + e11 * j10,
        e10 * j01 + e11 * j11,
    )


@njit(cache=True, nogil=True)
def _forcing(P, mode):  # pragma: no cover - compiled
    P1, Q1, phi = P[0], P[1], P[2]
    gc, gs = -Q1 * math.sin(phi), -Q1 * math.cos(phi)
    if mode == SEPARATION:
        return 0.0, gc, gs
    return -float(mode), gc, gs - mode * P1


@njit(cache=True, nogil=True)
def _segment(P, mode, th, u, du):  # pragma: no cover - compiled
    beta, zeta = P[3], P[4]
    a, d = 1.0 - beta * beta, 2.0 * zeta * beta
    det = a * a + d * d
    g0, gc, gs = _forcing(P, mode)
    A, B = (a * gc - d * gs) / det, (a * gs + d * gc) / det
    c, s = math.cos(th), math.sin(th)
    return (th, g0, A, B, u - (g0 + A * c + B * s), du - (-A * s + B * c), g0, gc, gs)


@njit(cache=True, nogil=True)
def _state(P, seg, th):  # pragma: no cover - compiled
    th_a, p0, A, B, h0, h1 = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5]
    c, s = math.cos(th), math.sin(th)
    e00, e01, e10, e11 = _prop(P, th - th_a)
    return p0 + A * c + B * s + e00 * h0 + e01 * h1, -A * s + B * c + e10 * h0 + e11 * h1


@njit(cache=True, nogil=True)
def _accel(P, seg, th, u, du):  # pragma: no cover - compiled
    beta, zeta = P[3], P[4]
    g = seg[6] + seg[7] * math.cos(th) + seg[8] * math.sin(th)
    return (g - 2.0 * zeta * beta * du - u) / (beta * beta)


@njit(cache=True, nogil=True)
def _f(P, seg, sign, which, th):  # pragma: no cover - compiled
    """which 0: sign u'; 1: sign u''."""
    u, du = _state(P, seg, th)
    if which == 0:
        return sign * du
    return sign * _accel(P, seg, th, u, du)


@njit(cache=True, nogil=True)
def _brent(P, seg, sign, which, a, b, fa, fb):  # pragma: no cover - compiled
    """Brent's method for the root of ``_f`` in [a, b] (fa, fb of opposite signs or 0)."""
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    c, fc = a, fa
    d = e = b - a
    for _ in range(200):
        if (fb > 0.0) == (fc > 0.0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 2.0 * _EPS * abs(b) + 0.5e-15
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p, q = 2.0 * m * s, 1.0 - s
            else:
                q, r = fa / fc, fb / fc
                p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0 else -tol)
        fb = _f(P, seg, sign, which, b)
    return b


@njit(cache=True, nogil=True)
def _first_stop(P, seg, sign, th0, th1, after_rest, noise):  # pragma: no cover - compiled
    """The first θ in (th0, th1] where ``sign u'`` reaches 0, or -1 (:mod:`.dynamic`)."""
    cell = P[5]
    n = max(2, int(math.ceil((th1 - th0) / cell)))
    h = (th1 - th0) / n
    a = th0
    fa = _f(P, seg, sign, 0, a)
    da = _f(P, seg, sign, 1, a)
    moving = not after_rest
    # the samples: after a release (u' ~ τ²) a geometric sub-grid of the first cell, then the
    # cells; otherwise the cells
    sub = 31 if after_rest else 0
    skip = 1 if after_rest else 0
    for k in range(sub + n - skip):
        if k < sub:
            b = th0 + h * 2.0 ** (k - 30)
        else:
            i = k - sub + skip
            b = th1 if i == n - 1 else th0 + (i + 1) * h
        fb = _f(P, seg, sign, 0, b)
        db = _f(P, seg, sign, 1, b)
        if moving:
            if fb <= 0.0:
                return _brent(P, seg, sign, 0, a, b, fa, fb)
            if da < 0.0 < db:  # a minimum between two positive samples
                m = _brent(P, seg, sign, 1, a, b, da, db)
                fm = _f(P, seg, sign, 0, m)
                if fm <= 0.0:
                    return _brent(P, seg, sign, 0, a, m, fa, fm)
        elif fb > noise:
            moving = True
        a, fa, da = b, fb, db
    if not moving:
        return th0
    return -1.0


@njit(cache=True, nogil=True)
def _quad(P, seg, sign, th0, th1):  # pragma: no cover - compiled
    """∫ n sign u' dθ over [th0, th1], 8-point Gauss-Legendre on the scan's cells."""
    if th1 <= th0:
        return 0.0
    n = max(1, int(math.ceil((th1 - th0) / P[5])))
    h = (th1 - th0) / n
    out = 0.0
    for i in range(n):
        mid = th0 + (i + 0.5) * h
        for k in range(8):
            t = mid + 0.5 * h * _GX[k]
            out += _GW[k] * 0.5 * h * (1.0 + P[0] * math.sin(t)) * sign * _state(P, seg, t)[1]
    return out


@njit(cache=True, nogil=True)
def _release(P, u, th0, th1):  # pragma: no cover - compiled
    """The first θ in (th0, th1] where stick at u ends, and the slip direction (θ < 0: none)."""
    P1, Q1, phi = P[0], P[1], P[2]
    best, direction = -1.0, 0
    for isg in range(2):  # u + q = sgn n:  a cos θ + b sin θ = c
        sgn = 1.0 - 2.0 * isg
        a, b, c = Q1 * math.sin(phi), Q1 * math.cos(phi) - sgn * P1, sgn - u
        R = math.hypot(a, b)
        if R == 0.0 or abs(c) > R:
            continue
        base, half = math.atan2(b, a), math.acos(max(-1.0, min(1.0, c / R)))
        for ir in range(2):
            root = base + half if ir == 0 else base - half
            t = root + math.ceil((th0 - root) / TWO_PI) * TWO_PI
            while t <= th0 + 1e-13 * max(1.0, abs(th0)):
                t += TWO_PI
            if t > th1:
                continue
            rate = sgn * Q1 * math.cos(t + phi) - P1 * math.cos(t)  # the slack falls
            if rate > 0.0 and (best < 0.0 or t < best):
                best, direction = t, -int(sgn)
    return best, direction


@njit(cache=True, nogil=True)
def _mode_at(P, th, u, du, contact):  # pragma: no cover - compiled
    n = 1.0 + P[0] * math.sin(th)
    if not contact and n <= 0.0:
        return SEPARATION
    if du > 0.0:
        return SLIP_F
    if du < 0.0:
        return SLIP_B
    F = u + P[1] * math.sin(th + P[2])
    if abs(F) <= n:
        return STICK
    return SLIP_B if F > n else SLIP_F


@njit(cache=True, nogil=True)
def _turning(P, seg, th0, th1, lohi):  # pragma: no cover - compiled
    """The free motion's extremes of u over [th0, th1] (its turning points) into ``lohi``."""
    n = max(2, int(math.ceil((th1 - th0) / P[5])))
    h = (th1 - th0) / n
    a = th0
    ua, fa = _state(P, seg, a)
    for i in range(n):
        b = th1 if i == n - 1 else th0 + (i + 1) * h
        ub, fb = _state(P, seg, b)
        lohi[0], lohi[1] = min(lohi[0], ub), max(lohi[1], ub)
        if (fa > 0.0 and fb < 0.0) or (fa < 0.0 and fb > 0.0):
            sgn = 1.0 if fa > 0.0 else -1.0
            m = _brent(P, seg, sgn, 0, a, b, sgn * fa, sgn * fb)
            um = _state(P, seg, m)[0]
            lohi[0], lohi[1] = min(lohi[0], um), max(lohi[1], um)
        a, fa = b, fb


@njit(cache=True, nogil=True)
def _separation(P, th0, th1):  # pragma: no cover - compiled
    """The first separation interval meeting [th0, th1): (a, b), or (-1, -1)."""
    if math.isnan(P[6]):
        return -1.0, -1.0
    k = float(math.floor(th0 / TWO_PI))
    for i in range(3):
        j = k - 1.0 + i
        a, b = P[6] + j * TWO_PI, P[7] + j * TWO_PI
        if b > th0 and a < th1:
            return a, b
    return -1.0, -1.0


@njit(cache=True, nogil=True)
def period_map(P, u, du, th0, jac, segs, lohi):  # pragma: no cover - compiled
    """One period from ``(u, u')`` at ``th0``: returns ``(u, u', J, segments, status)``; the
    Jacobian ``∂(u, u')_end/∂(u, u')_0`` into ``jac`` (2, 2), the segments ``(θa, θb, mode, ua,
    u'a)`` into ``segs`` (status 1: more than ``MAX_SEGMENTS``), the extremes of u into
    ``lohi`` (module docstring; :mod:`.dynamic` for the method)."""
    th, th_end = th0, th0 + TWO_PI
    j00, j01, j10, j11 = 1.0, 0.0, 0.0, 1.0
    J = 0.0
    mode = _mode_at(P, th, u, du, False)
    if mode == STICK:
        du, j10, j11 = 0.0, 0.0, 0.0
    after_rest = mode != STICK and mode != SEPARATION and du == 0.0
    lohi[0], lohi[1] = u, u
    nseg = 0
    while th < th_end:
        if nseg >= segs.shape[0]:
            jac[0, 0], jac[0, 1], jac[1, 0], jac[1, 1] = j00, j01, j10, j11
            return u, du, J, nseg, 1
        segs[nseg, 0], segs[nseg, 2], segs[nseg, 3], segs[nseg, 4] = th, mode, u, du
        if mode == STICK:
            t_rel, direction = _release(P, u, th, th_end)
            stop = th_end if t_rel < 0.0 else t_rel
            segs[nseg, 1] = stop
            nseg += 1
            th = stop
            if t_rel >= 0.0:
                mode, after_rest = direction, True
            continue
        if mode == SEPARATION:
            a, b = _separation(P, th, th_end)
            stop = th_end if a < 0.0 else min(th_end, b)
            seg = _segment(P, SEPARATION, th, u, du)
            _turning(P, seg, th, stop, lohi)
            u, du = _state(P, seg, stop)
            j00, j01, j10, j11 = _flow(P, stop - th, j00, j01, j10, j11)
            segs[nseg, 1] = stop
            nseg += 1
            th = stop
            if th < th_end:
                mode = _mode_at(P, th, u, du, True)
                after_rest = du == 0.0
            continue
        s = mode
        seg = _segment(P, s, th, u, du)
        a, b = _separation(P, th, th_end)
        limit = a if (a > th and a < th_end) else th_end
        noise = 64.0 * _EPS * (abs(seg[2]) + abs(seg[3]) + abs(seg[5]) + abs(seg[4]) / P[3])
        stop = _first_stop(P, seg, float(s), th, limit, after_rest, noise)
        end = limit if stop < 0.0 else stop
        J += _quad(P, seg, float(s), th, end)
        j00, j01, j10, j11 = _flow(P, end - th, j00, j01, j10, j11)
        u, du = _state(P, seg, end)
        segs[nseg, 1] = end
        nseg += 1
        lohi[0], lohi[1] = min(lohi[0], u), max(lohi[1], u)
        th = end
        if stop < 0.0:  # the period's end, or separation
            if th < th_end:
                mode, after_rest = SEPARATION, False
            continue
        du = 0.0
        F = u + P[1] * math.sin(th + P[2])
        n = 1.0 + P[0] * math.sin(th)
        a_old = _accel(P, seg, th, u, 0.0)
        if abs(F) <= n:  # stick: the velocity's sensitivity projected out
            mode, j10, j11 = STICK, 0.0, 0.0
        else:  # reversal: the saltation a+/a- on the velocity
            mode = -s
            a_new = _accel(P, _segment(P, mode, th, u, 0.0), th, u, 0.0)
            ratio = a_new / a_old if a_old != 0.0 else 1.0
            j10, j11 = ratio * j10, ratio * j11
            after_rest = True
    jac[0, 0], jac[0, 1], jac[1, 0], jac[1, 1] = j00, j01, j10, j11
    return u, du, J, nseg, 0


@njit(cache=True, nogil=True)
def sample(P, segs, nseg, theta, out):  # pragma: no cover - compiled
    """``(u, u', F, state)`` at the angles θ (in the period of ``segs``) into ``out`` (4, m);
    state codes of :class:`~lcpfric.results.State` (stick 0, forward 1, backward 2,
    separation 3)."""
    for k in range(theta.size):
        t = theta[k]
        i = 0
        while i < nseg - 1 and segs[i + 1, 0] <= t:
            i += 1
        mode = int(segs[i, 2])
        q = P[1] * math.sin(t + P[2])
        if mode == STICK:
            u = segs[i, 3]
            out[0, k], out[1, k], out[2, k], out[3, k] = u, 0.0, u + q, 0.0
            continue
        seg = _segment(P, mode, segs[i, 0], segs[i, 3], segs[i, 4])
        u, du = _state(P, seg, t)
        out[0, k], out[1, k] = u, du
        if mode == SEPARATION:
            out[2, k], out[3, k] = 0.0, 3.0
        else:
            out[2, k] = -mode * (1.0 + P[0] * math.sin(t))
            out[3, k] = 1.0 if mode == SLIP_F else 2.0


@njit(cache=True, nogil=True)
def linear_response(P):  # pragma: no cover - compiled
    """``(u, u')`` at θ = 0 of the frictionless forced response (the separated mode's
    particular solution): a start."""
    seg = _segment(P, SEPARATION, 0.0, 0.0, 0.0)
    return seg[1] + seg[2], seg[3]
