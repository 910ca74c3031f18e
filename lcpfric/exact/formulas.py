"""The closed forms every event of the single node's cycle is computed from (see the package
docstring of :mod:`lcpfric.exact` for the derivation): the moving interval's coefficients, its
extrema, the stick angles, the crossings, the slip integrals (in θ, and in s = θ_s - θ for the
last slip before separation)."""

from __future__ import annotations

import math

import numpy as np
from dataclasses import dataclass

from ..results import State

#: A node's states as plain ints, the values of :class:`lcpfric.results.State`: ``STICK = 0``,
#: ``FORWARD = 1`` (forward slip), ``BACKWARD = 2`` (backward slip), ``SEPARATION = 3``; the
#: states of :class:`~lcpfric.exact.ExactCycle`'s segments (plain ints: the scalar loops compare
#: them millions of times).
STICK, FORWARD, BACKWARD, SEPARATION = (int(s) for s in State)
AFTER_FORWARD, AFTER_BACKWARD, RECONTACT = 0, 1, 2

TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi
MAX_EVENTS = 64  # a harmonic cycle has at most ~10 segments; this only guards against a bug
# event angles are near 10 rad: crossings closer than this to each other are not resolved in θ
TIE = 8 * np.finfo(float).eps * 4 * math.pi
S_RANGE = HALF_PI + 1e-6  # the s-form is used for crossings within π/2 of separation
#: The largest P̂1 and Q̂1 the exact solution accepts, 1e300: above it intermediate products
#: could overflow, so larger amplitudes are refused (:class:`~lcpfric.errors.InputError`).
MAX_AMPLITUDE = 1e300


def mod0(x):
    """x mod 2π in [0, 2π)."""
    return np.mod(x, TWO_PI)


def pmod(x):
    """x mod 2π in (0, 2π]."""
    return TWO_PI - np.mod(-x, TWO_PI)


# -- the last slip before separation, in the angle s = θ_s - θ --------------------------------


def delta_series(y):
    """(y - sin y) / y³ by its Taylor series (y < 0.5: truncation below 1e-16 relative)."""
    y2 = y * y
    return 1.0 / 6 - y2 * (
        1.0 / 120
        - y2 * (1.0 / 5040 - y2 * (1.0 / 362880 - y2 * (1.0 / 39916800 - y2 / 6227020800.0)))
    )


def sform_W(g, a, b, y, xi, c, cq):
    """``(1/Q̂1) ∫_0^y L(s) (a cos s + b sin s) ds`` in the angle s before separation (scalar).

    ``L(s) = g sin s + (1 - cos s)``; ``xi = y / c`` and ``cq = c / Q̂1`` are passed so that an
    angle y below the smallest double (Q̂1 ≪ P̂1) still gives a representable result.
    """
    if y > 0.0:
        sig = math.sin(y) / y
        nu = 2.0 * (math.sin(0.5 * y) / y) ** 2
    else:  # y underflowed (Q̂1/P̂1 < 1e-308): the limits; xi still carries the size
        sig, nu = 1.0, 0.5
    dl = delta_series(y) if y < 0.5 else (y - math.sin(y)) / (y * y * y)
    xa = xi * a
    inner = (
        g * xa * sig * sig
        + y * (xi * g * b * (dl + sig * nu) + xa * (sig * nu - dl))
        + y * y * xi * b * nu * nu
    )
    return 0.5 * (xi * inner) * c * cq


def sform_W_vec(g, a, b, y, xi, c, cq):
    """Vectorized :func:`sform_W`."""
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.maximum(y, 0.0)
        ys = np.where(y > 0.0, y, 1.0)
        sig = np.where(y > 0.0, np.sin(ys) / ys, 1.0)
        nu = np.where(y > 0.0, 2.0 * (np.sin(0.5 * ys) / ys) ** 2, 0.5)
        dl = np.where(y < 0.5, delta_series(y), (ys - np.sin(ys)) / (ys * ys * ys))
        xa = xi * a
        inner = (
            g * xa * sig * sig
            + y * (xi * g * b * (dl + sig * nu) + xa * (sig * nu - dl))
            + y * y * xi * b * nu * nu
        )
        out = 0.5 * (xi * inner) * c * cq
    return np.where(np.isfinite(out), out, 0.0)


def crossing(a, b, c):
    """The smallest s > 0 with ``a sin s + b (1 - cos s) = c`` (c > 0), and s / c; or (-1, 0)
    when that s is not in (0, π/2] (then the arcsine in θ is as accurate).

    With t = tan(s/2) the equation is ``(2b - c) t² + 2a t - c = 0``, whose small root
    ``t = c / (a + sqrt(a² + (2b - c) c))`` keeps every digit however small c is.
    """
    A = 2.0 * b - c
    sc = math.sqrt(c)
    if a > 0.0:
        if A >= 0.0:
            r = math.hypot(a, math.sqrt(A) * sc)
        else:
            k = math.sqrt(-A) * sc
            if k > a:
                return -1.0, 0.0
            r = math.sqrt((a - k) * (a + k))
        tau = 1.0 / (a + r)  # t / c
        t = c * tau
    elif A > 0.0:
        t = (math.hypot(a, math.sqrt(A) * sc) - a) / A
        tau = t / c
    else:
        return -1.0, 0.0
    if not t <= 1.0:
        return -1.0, 0.0
    x = 2.0 * math.atan(t)
    return x, (2.0 * math.atan(t) / t if t > 0.0 else 2.0) * tau


def crossing_vec(a, b, c):
    """Vectorized :func:`crossing`: (x, x / c) with x = -1 where there is no such root."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        A = 2.0 * b - c
        sc = np.sqrt(c)
        sA = np.sqrt(np.abs(A)) * sc
        r_pos = np.hypot(a, sA)
        r_neg = np.sqrt(np.maximum((a - sA) * (a + sA), 0.0))
        pos = a > 0.0
        ok = np.where(pos, (A >= 0.0) | (sA <= a), A > 0.0)
        tau = np.where(pos, 1.0 / (a + np.where(A >= 0.0, r_pos, r_neg)), 0.0)
        t = np.where(pos, c * tau, (r_pos - a) / np.where(A > 0.0, A, 1.0))
        tau = np.where(pos, tau, t / c)
        ok &= t <= 1.0
        x = 2.0 * np.arctan(t)
        xi = np.where(t > 0.0, x / np.where(t > 0.0, t, 1.0), 2.0) * tau
    return np.where(ok, x, -1.0), np.where(ok, xi, 0.0)


# -- the other slip segments, in θ --------------------------------------------------------------


def slip_integral(a, b, P1, Q1, phi, sphi, cphi, L_a, L_b, sign, R, alpha, salpha, calpha):
    """``(1/Q̂1) ∫_a^b L |dw|`` over slip segments in θ (arrays), in the better conditioned of
    two forms (:func:`_slip_integral_scalar` is the scalar twin).

    On a slip segment w is on a bound, ``w = ∓L - Q̂`` (lower bound: forward slip, sign = -1;
    upper bound: backward slip, sign = +1), whose motion is ``dw/dθ = sign R cos(θ + α)``
    ((R, α) = (R_lo, α_lo) or (R_hi, α_hi)). Hence two exact forms::

        split:   ∫ L |dw| = ½ (L_a² - L_b²) + sign · Q̂1 K(φ)
        direct:  ∫ L |dw| = sign · R K(α),         K(ψ) = ∫_a^b L cos(θ + ψ) dθ

    The split form keeps the digits of a slip that ends where L vanishes (P̂1 ≫ Q̂1 next to
    separation); the direct form those of a bound that barely moves while L and Q̂ change a lot
    (R ≪ P̂1, e.g. Q̂1 = P̂1 and φ small, where the split form is the difference of two terms a
    million times larger). Each form's round-off is bounded by the size of its terms and the
    smaller is used.

    K(ψ) is written in ``u = θ - 3π/2`` (the minimum of P̂), where
    ``L = (1 - P̂1) + P̂1 (1 - cos u)``::

        K(ψ) = (1 - P̂1) ∫ sin(u + ψ) du + P̂1 [cos ψ ∫ (1 - cos u) sin u du
                                               + sin ψ ∫ (1 - cos u) cos u du]

    and each integral is expanded in half-angle products of the segment's middle m and half
    length h (``∫(1 - cos u) cos u = sin h (1 - cos h) - (h - sin h) + sin h (2 v cos m -
    2 sin²m (1 - cos h))``, v = 1 - cos m, and so on), whose terms are all of the size of the
    result: short segments, and segments next to the minimum of P̂ where L is small (P̂1 close
    to 1), keep their digits. Everything is divided by Q̂1 term by term (no product of two large
    amplitudes).
    """
    m = 0.5 * (a + b) - 1.5 * math.pi
    h = 0.5 * (b - a)
    sh, sm, cm = np.sin(h), np.sin(m), np.cos(m)
    Vh = 2.0 * np.sin(0.5 * h) ** 2
    vm = 2.0 * np.sin(0.5 * m) ** 2
    h_sin = np.where(h < 0.5, h * h * h * delta_series(h), h - sh)
    I_c = sh * Vh - h_sin + sh * (2.0 * vm * cm - 2.0 * sm * sm * Vh)
    I_s = 2.0 * sm * sh * (vm + cm * Vh)  # V_a + V_b = 2 (1 - cos m cos h)
    one_m_P1 = 1.0 - P1
    K_phi = one_m_P1 * 2.0 * (sm * cphi + cm * sphi) * sh + P1 * (cphi * I_s + sphi * I_c)
    K_alpha = one_m_P1 * 2.0 * (sm * calpha + cm * salpha) * sh + P1 * (calpha * I_s + salpha * I_c)
    split = 0.5 * (L_a - L_b) * ((L_a + L_b) / Q1) + sign * K_phi
    direct = sign * (R / Q1) * K_alpha
    # sizes of the terms each form sums (its round-off is eps times that), times Q̂1
    T = np.abs(one_m_P1) + 4.0 * P1
    use_direct = (R - Q1) * T * (2.0 * h) < 0.5 * (L_a * L_a + L_b * L_b)
    return np.where(use_direct, direct, split)


def L_of(P1, theta):
    """L = max(P̂, 0) at θ, as ``(1 - P̂1) + 2 P̂1 sin²((θ - 3π/2)/2)`` (exact next to the minimum
    of P̂ when P̂1 is close to 1)."""
    return np.maximum(0.0, (1.0 - P1) + 2.0 * P1 * np.sin(0.5 * (theta - 1.5 * math.pi)) ** 2)


@dataclass
class Coefficients:
    P1: np.ndarray
    Q1: np.ndarray
    phi: np.ndarray
    R_lo: np.ndarray
    a_lo: np.ndarray
    R_hi: np.ndarray
    a_hi: np.ndarray

    lo_max: np.ndarray  # R_lo - 1
    hi_min: np.ndarray  # 1 - R_hi
    X_f: np.ndarray  # stick after forward slip: hi falls to w at θ_max + X_f - (α_hi - α_lo)
    X_b: np.ndarray  # stick after backward slip: lo rises to w at θ_min + X_b + (α_hi - α_lo)
    delta: np.ndarray  # α_hi - α_lo
    s_lo: np.ndarray  # sin α_lo, cos α_lo, sin α_hi, cos α_hi
    c_lo: np.ndarray
    s_hi: np.ndarray
    c_hi: np.ndarray

    @classmethod
    def of(cls, P1, Q1, phi, sphi, cphi):
        A = P1 + Q1 * cphi
        B = Q1 * sphi
        C = Q1 * cphi - P1
        R_lo, R_hi = np.hypot(A, B), np.hypot(C, B)
        delta, X_f, X_b = _stick_angles(P1, Q1, sphi, cphi, R_lo, R_hi)
        lo_max, hi_min = _extrema(P1, Q1, cphi, R_lo, R_hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            s_lo, c_lo = np.where(R_lo > 0, B / R_lo, 0.0), np.where(R_lo > 0, A / R_lo, 1.0)
            s_hi, c_hi = np.where(R_hi > 0, B / R_hi, 0.0), np.where(R_hi > 0, C / R_hi, 1.0)
        return cls(
            P1,
            Q1,
            phi,
            R_lo,
            np.arctan2(B, A),
            R_hi,
            np.arctan2(B, C),
            lo_max,
            hi_min,
            X_f,
            X_b,
            delta,
            s_lo,
            c_lo,
            s_hi,
            c_hi,
        )


def _extrema(P1, Q1, cphi, R_lo, R_hi):
    """max lo = R_lo - 1 and min hi = 1 - R_hi, without the cancellation of R - 1 when R is
    close to 1 (P̂1 close to 1 and Q̂1 small, where w sits within Q̂1² of L = 0): written
    ``(R² - 1) / (R + 1)`` with ``R_lo² - 1 = (P̂1 - 1)(P̂1 + 1) + Q̂1 (2 P̂1 cos φ + Q̂1)``.

    The form is used where its terms are small (P̂1 near 1, Q̂1 small), so that it is not itself
    a cancellation; the clip only keeps large amplitudes from overflowing.
    """
    P1c, Q1c = np.minimum(P1, 4.0), np.minimum(Q1, 4.0)
    g2 = (P1c - 1.0) * (P1c + 1.0)
    small = np.abs(g2) + Q1c * (2.0 * P1c + Q1c) <= 1.0
    lo_max = np.where(small, (g2 + Q1c * (2.0 * P1c * cphi + Q1c)) / (R_lo + 1.0), R_lo - 1.0)
    hi_min = np.where(small, (Q1c * (2.0 * P1c * cphi - Q1c) - g2) / (1.0 + R_hi), 1.0 - R_hi)
    return lo_max, hi_min


def _stick_angles(P1, Q1, sphi, cphi, R_lo, R_hi):
    """The stick after a slip, as an angle from the extremum where the slip ended.

    After forward slip w = max lo = R_lo - 1 (at θ + α_lo = 3π/2); hi = 1 - R_hi sin(θ + α_hi)
    falls to w where ``cos(τ + Δ) = (R_lo - 2) / R_hi`` (τ: angle since the maximum,
    Δ = α_hi - α_lo), i.e. ``τ + Δ = X_f = 2 asin(sqrt((2 - (R_lo - R_hi)) / (2 R_hi)))``; after
    backward slip, symmetrically, ``τ - Δ = X_b = 2 asin(sqrt((2 + (R_lo - R_hi)) / (2 R_lo)))``.
    Written with ``R_lo - R_hi = 4 P̂1 Q̂1 cos φ / (R_lo + R_hi)`` and
    ``Δ = atan2(2 P̂1 Q̂1 sin φ, Q̂1² - P̂1²)``, a stick of 1e-10 rad at Q̂1 = 1e20 keeps its digits
    (an arcsine of ``(±1 - w) / R`` next to ±1 loses half of them). X = NaN: no crossing.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        dR = 4.0 * cphi * P1 * (Q1 / (R_lo + R_hi))
        delta = np.arctan2(2.0 * P1 * sphi * (Q1 / (Q1 + P1)), Q1 - P1)
        y_f = (2.0 - dR) / (2.0 * R_hi)
        y_b = (2.0 + dR) / (2.0 * R_lo)
        X_f = np.where(
            (y_f >= 0.0) & (y_f <= 1.0), 2.0 * np.arcsin(np.sqrt(np.clip(y_f, 0.0, 1.0))), np.nan
        )
        X_b = np.where(
            (y_b >= 0.0) & (y_b <= 1.0), 2.0 * np.arcsin(np.sqrt(np.clip(y_b, 0.0, 1.0))), np.nan
        )
    return delta, X_f, X_b
