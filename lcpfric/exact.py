"""The exact periodic steady state of the single node (``method="exact"``).

Why it is exact
---------------
Write ``w = F̂ - Q̂ = Q̂1 v̂`` (the tangential displacement in units of f P0 / k11) and
``L(θ) = max(P̂(θ), 0)`` with ``θ = ωt``. Coulomb's law (Eq. 8) keeps w inside the moving interval
``[lo(θ), hi(θ)] = [-L - Q̂, L - Q̂]`` and w moves only when an end of the interval pushes it: a
one-dimensional sweeping process (NOTES.md). The dissipation is ``Ŵ = ∮ L |dv̂| = (1/Q̂1) ∮ L |dw|``.

While in contact both ends are pure sinusoids (Eqs. 9-10 with Q0 = 0)::

    lo(θ) = -(1 + R_lo sin(θ + α_lo)),   R_lo e^{iα_lo} = (P̂1 + Q̂1 cos φ) + i Q̂1 sin φ
    hi(θ) =   1 - R_hi sin(θ + α_hi),    R_hi e^{iα_hi} = (Q̂1 cos φ - P̂1) + i Q̂1 sin φ

so every event has a closed form: forward slip (w = lo) ends at the maximum of lo,
``θ + α_lo = 3π/2``, with ``w = R_lo - 1``; backward slip (w = hi) ends at the minimum of hi,
``θ + α_hi = π/2``, with ``w = 1 - R_hi``; the stick that follows ends where the other bound
reaches w; separation starts and ends where ``P̂ = 0``, at ``θ_s = 3π/2 - β`` and
``θ_c = 3π/2 + β``, ``β = atan(g)``, ``g = sqrt(P̂1² - 1)``. A slip segment dissipates
``∫ L |dw| = ½ (L_a² - L_b²) ± Q̂1 ∫ L cos(θ + φ) dθ`` (on a slip segment w = ∓L - Q̂).

Entering the periodic orbit in one step
---------------------------------------
The sweeping process is a contraction, and its steady state is reached exactly:

* with separation (P̂1 >= 1) the interval shrinks to the point ``w = -Q̂`` at re-contact, so
  every history passes through ``(θ_c, -Q̂(θ_c))``: start there;
* without separation, forward slip on the periodic orbit (if there is any slip) ends at the
  maximum of lo, so the orbit passes through ``(3π/2 - α_lo, R_lo - 1)``: start there. If the
  orbit does not slip (shakedown, R_lo + R_hi <= 2) that start sticks for the whole cycle.

One cycle from that start is the steady state; no cycles are iterated. All points of a grid are
advanced together, one event per numpy pass, so a whole map costs a few array operations.

Keeping the digits of short segments
------------------------------------
Event angles are near 10 rad, so an angle computed as a difference of absolute angles carries
an error of ~1e-15 rad. Segments far shorter than 1 rad decide Ŵ in three places, and each is
written in a variable measured from where it happens:

1. *The last slip before separation* (Q̂1 ≪ P̂1, or φ near 0 or π). Stuck since re-contact,
   w sits ``e = w + Q̂(θ_s) = -2 Q̂1 sin φ sin β`` from the point the interval closes on
   (``Q̂(θ_s) - Q̂(θ_c)`` in closed form), and the bound on the side of e reaches it a short angle
   s before θ_s. In ``s = θ_s - θ``::

       L(s) = g sin s + (1 - cos s),     Q̂(s) = q cos s - q' sin s   (q, q': Q̂, dQ̂/dθ at θ_s)
       lo(s) - w = -e - a sin s - b (1 - cos s),   a = g - q',  b = 1 - q   (forward, e < 0)
       hi(s) - w = -e + a sin s + b (1 - cos s),   a = g + q',  b = 1 + q   (backward, e > 0)

   so the slip starts at the smallest root of ``a sin s + b (1 - cos s) = c = |e|``; with
   t = tan(s/2) that is ``(2b - c) t² + 2a t - c = 0``, whose root
   ``t = c / (a + sqrt(a² + (2b - c) c))`` has no cancellation however small c (:func:`_crossing`).
   Its dissipation is ``∫_0^x L(s) (a cos s + b sin s) ds``, in closed form::

       2 J = g a S² + g b (D + S V) + a (S V - D) + b V²,
       S = sin x, V = 1 - cos x = 2 sin²(x/2), D = x - sin x (Taylor series below 0.5)

   every term positive and of the size of the result (:func:`_sform_W`, written with x/c and
   c/Q̂1 so that x below the smallest double still gives Ŵ). With x ≈ c/a, J ≈ g c²/(2a), hence
   for Q̂1 ≪ g the asymptote ``Ŵ ≈ 2 Q̂1 sin²φ (1 - 1/P̂1²)`` (checked in the tests). The
   earlier θ-form lost this segment entirely below Q̂1/P̂1 ≈ 1e-15 (``exact_W_hat(2, 1e-15, 1)``
   returned 0 for 1.06e-15) and lost digits as eps/x above. If the bound turns before θ_s
   (a < 0) the slip ends at its extremum ``s_m = atan2(-a, b)``, also in s.
2. *The stick at an extremum when Q̂1 ≫ 1*: after forward slip, hi falls to ``w = R_lo - 1`` at
   the angle ``τ`` after the maximum with ``τ + Δ = 2 asin(sqrt((2 - (R_lo - R_hi)) / (2 R_hi)))``,
   ``R_lo - R_hi = 4 P̂1 Q̂1 cos φ / (R_lo + R_hi)``, ``Δ = α_hi - α_lo
   = atan2(2 P̂1 Q̂1 sin φ, Q̂1² - P̂1²)`` (and symmetrically after backward slip;
   :func:`_stick_angles`). The arcsine of ``(1 - w)/R_hi`` next to -1 used before lost half the
   digits of τ ~ Q̂1^(-1/2): at Q̂1 = 1e17 Ŵ came out 2 instead of 4.
3. *Slips next to the minimum of P̂ when P̂1 is close to 1* (L ~ Q̂1²): L and ``∫ L cos(θ + φ)``
   are written in ``u = θ - 3π/2`` with half-angle products (:func:`_slip_integral`), and
   ``R_lo - 1 = (R_lo² - 1)/(R_lo + 1)`` with ``R_lo² - 1 = (P̂1 - 1)(P̂1 + 1) + Q̂1 (2 P̂1 cos φ
   + Q̂1)`` (:func:`_extrema`).

φ enters through sin φ and cos φ of the caller's value (exact to round-off for any φ); angles use
φ reduced through them. Dissipation is accumulated as Ŵ, slip by slip, so no product of two
amplitudes is formed: P̂1, Q̂1 up to :data:`MAX_AMPLITUDE` = 1e300 are accepted.

Accuracy
--------
Checked against an independent mpmath solution (``benchmarks/exact_reference.py``: 60 to 140
digits, started from w = 0 and run to the periodic cycle, slip integrals from a different
antiderivative; itself checked against Eqs. (11)/(12), the energy identity ∮ L|dw| = ∮ w dQ̂,
a fine-grid simulation and the asymptote above) by ``benchmarks/exact_audit.py``. The result is
within 1e-9 relative of the exact Ŵ wherever Ŵ is well-conditioned. Where it is not — next to
the border of a zero régime (shakedown, or Q̂1 = P̂1 at φ = 0 or π), and next to P̂1 = 1 with
Q̂1 ≲ 1e-4 where the minimum of L is below the round-off of P̂ — the error is within the change of
the exact Ŵ when the inputs move by 16 units of round-off (relative for P̂1 and Q̂1, absolute
16 eps max(1, |φ|) for φ): the answer is exact for inputs indistinguishable from the given ones.
Results in the subnormal range (below 2.2e-308) carry the absolute error of that range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _checks
from .errors import InputError

__all__ = ["exact_W_hat", "ExactCycle", "exact_cycle", "STICK", "FORWARD", "BACKWARD",
           "SEPARATION", "MAX_AMPLITUDE"]

STICK, FORWARD, BACKWARD, SEPARATION = 0, 1, 2, 3
_AFTER_FORWARD, _AFTER_BACKWARD, _RECONTACT = 0, 1, 2

TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi
_MAX_EVENTS = 64  # a harmonic cycle has at most ~10 segments; this only guards against a bug
# event angles are near 10 rad: crossings closer than this to each other are not resolved in θ
_TIE = 8 * np.finfo(float).eps * 4 * math.pi
_S_RANGE = HALF_PI + 1e-6  # the s-form is used for crossings within π/2 of separation
MAX_AMPLITUDE = 1e300  # P̂1, Q̂1 above this could overflow intermediate products: refused


def _mod0(x):
    """x mod 2π in [0, 2π)."""
    return np.mod(x, TWO_PI)


def _pmod(x):
    """x mod 2π in (0, 2π]."""
    return TWO_PI - np.mod(-x, TWO_PI)


# -- the last slip before separation, in the angle s = θ_s - θ --------------------------------

def _delta_series(y):
    """(y - sin y) / y³ by its Taylor series (y < 0.5: truncation below 1e-16 relative)."""
    y2 = y * y
    return (1.0 / 6 - y2 * (1.0 / 120 - y2 * (1.0 / 5040 - y2 * (
        1.0 / 362880 - y2 * (1.0 / 39916800 - y2 / 6227020800.0)))))


def _sform_W(g, a, b, y, xi, c, cq):
    """``(1/Q̂1) ∫_0^y L(s) (a cos s + b sin s) ds`` in the angle s before separation (scalar).

    ``L(s) = g sin s + (1 - cos s)``; ``xi = y / c`` and ``cq = c / Q̂1`` are passed so that an
    angle y below the smallest double (Q̂1 ≪ P̂1) still gives a representable result.
    """
    if y > 0.0:
        sig = math.sin(y) / y
        nu = 2.0 * (math.sin(0.5 * y) / y) ** 2
    else:  # y underflowed (Q̂1/P̂1 < 1e-308): the limits; xi still carries the size
        sig, nu = 1.0, 0.5
    dl = _delta_series(y) if y < 0.5 else (y - math.sin(y)) / (y * y * y)
    xa = xi * a
    inner = (g * xa * sig * sig + y * (xi * g * b * (dl + sig * nu) + xa * (sig * nu - dl))
             + y * y * xi * b * nu * nu)
    return 0.5 * (xi * inner) * c * cq


def _sform_W_vec(g, a, b, y, xi, c, cq):
    """Vectorized :func:`_sform_W`."""
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.maximum(y, 0.0)
        ys = np.where(y > 0.0, y, 1.0)
        sig = np.where(y > 0.0, np.sin(ys) / ys, 1.0)
        nu = np.where(y > 0.0, 2.0 * (np.sin(0.5 * ys) / ys) ** 2, 0.5)
        dl = np.where(y < 0.5, _delta_series(y), (ys - np.sin(ys)) / (ys * ys * ys))
        xa = xi * a
        inner = (g * xa * sig * sig + y * (xi * g * b * (dl + sig * nu) + xa * (sig * nu - dl))
                 + y * y * xi * b * nu * nu)
        out = 0.5 * (xi * inner) * c * cq
    return np.where(np.isfinite(out), out, 0.0)


def _crossing(a, b, c):
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
        tau = 1.0 / (a + r)           # t / c
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


def _crossing_vec(a, b, c):
    """Vectorized :func:`_crossing`: (x, x / c) with x = -1 where there is no such root."""
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

def _slip_integral(a, b, P1, Q1, phi, sphi, cphi, L_a, L_b, sign, R, alpha, salpha, calpha):
    """``(1/Q̂1) ∫_a^b L |dw|`` over a slip segment in θ, in the better conditioned of two forms.

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
    lib = math if isinstance(a, float) else np
    m = 0.5 * (a + b) - 1.5 * math.pi
    h = 0.5 * (b - a)
    sh, sm, cm = lib.sin(h), lib.sin(m), lib.cos(m)
    Vh = 2.0 * lib.sin(0.5 * h) ** 2
    vm = 2.0 * lib.sin(0.5 * m) ** 2
    if lib is math:
        h_sin = h * h * h * _delta_series(h) if h < 0.5 else h - sh
    else:
        h_sin = np.where(h < 0.5, h * h * h * _delta_series(h), h - sh)
    I_c = sh * Vh - h_sin + sh * (2.0 * vm * cm - 2.0 * sm * sm * Vh)
    I_s = 2.0 * sm * sh * (vm + cm * Vh)  # V_a + V_b = 2 (1 - cos m cos h)
    one_m_P1 = 1.0 - P1
    K_phi = one_m_P1 * 2.0 * (sm * cphi + cm * sphi) * sh + P1 * (cphi * I_s + sphi * I_c)
    K_alpha = one_m_P1 * 2.0 * (sm * calpha + cm * salpha) * sh + P1 * (calpha * I_s
                                                                         + salpha * I_c)
    split = 0.5 * (L_a - L_b) * ((L_a + L_b) / Q1) + sign * K_phi
    direct = sign * (R / Q1) * K_alpha
    # sizes of the terms each form sums (its round-off is eps times that), over Q̂1
    T = (abs(one_m_P1) if lib is math else np.abs(one_m_P1)) + 4.0 * P1
    use_direct = (R - Q1) * T * (2.0 * h) < 0.5 * (L_a * L_a + L_b * L_b)
    if lib is math:
        return direct if use_direct else split
    return np.where(use_direct, direct, split)


def _L(lib, P1, theta):
    """L = max(P̂, 0) at θ, as ``(1 - P̂1) + 2 P̂1 sin²((θ - 3π/2)/2)`` (exact next to the minimum
    of P̂ when P̂1 is close to 1)."""
    return lib.maximum(0.0, (1.0 - P1) + 2.0 * P1 * lib.sin(0.5 * (theta - 1.5 * math.pi)) ** 2) \
        if lib is np else max(0.0, (1.0 - P1) + 2.0 * P1 * math.sin(0.5 * (theta - 1.5 * math.pi)) ** 2)


@dataclass
class _Coefficients:
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
        delta, X_f, X_b = _stick_angles(np, P1, Q1, sphi, cphi, R_lo, R_hi)
        lo_max, hi_min = _extrema(np, P1, Q1, cphi, R_lo, R_hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            s_lo, c_lo = np.where(R_lo > 0, B / R_lo, 0.0), np.where(R_lo > 0, A / R_lo, 1.0)
            s_hi, c_hi = np.where(R_hi > 0, B / R_hi, 0.0), np.where(R_hi > 0, C / R_hi, 1.0)
        return cls(P1, Q1, phi, R_lo, np.arctan2(B, A), R_hi, np.arctan2(B, C), lo_max, hi_min,
                   X_f, X_b, delta, s_lo, c_lo, s_hi, c_hi)


def _extrema(lib, P1, Q1, cphi, R_lo, R_hi):
    """max lo = R_lo - 1 and min hi = 1 - R_hi, without the cancellation of R - 1 when R is
    close to 1 (P̂1 close to 1 and Q̂1 small, where w sits within Q̂1² of L = 0): written
    ``(R² - 1) / (R + 1)`` with ``R_lo² - 1 = (P̂1 - 1)(P̂1 + 1) + Q̂1 (2 P̂1 cos φ + Q̂1)``."""
    # The form is used where its terms are small (P̂1 near 1, Q̂1 small), so that it is not
    # itself a cancellation; the clip only keeps large amplitudes from overflowing.
    P1c = min(P1, 4.0) if lib is math else np.minimum(P1, 4.0)
    Q1c = min(Q1, 4.0) if lib is math else np.minimum(Q1, 4.0)
    g2 = (P1c - 1.0) * (P1c + 1.0)
    size = abs(g2) + Q1c * (2.0 * P1c + Q1c)
    num_lo = g2 + Q1c * (2.0 * P1c * cphi + Q1c)
    num_hi = Q1c * (2.0 * P1c * cphi - Q1c) - g2
    if lib is math:
        small = size <= 1.0
        lo_max = num_lo / (R_lo + 1.0) if small else R_lo - 1.0
        hi_min = num_hi / (1.0 + R_hi) if small else 1.0 - R_hi
        return lo_max, hi_min
    small = size <= 1.0
    lo_max = np.where(small, num_lo / (R_lo + 1.0), R_lo - 1.0)
    hi_min = np.where(small, num_hi / (1.0 + R_hi), 1.0 - R_hi)
    return lo_max, hi_min
    ok = (P1 < 1e100) & (Q1 < 1e100)
    lo_max = np.where((R_lo < 2.0) & ok, num_lo / (R_lo + 1.0), R_lo - 1.0)
    hi_min = np.where((R_hi < 2.0) & ok, num_hi / (1.0 + R_hi), 1.0 - R_hi)
    return lo_max, hi_min
    small_lo, small_hi = R_lo < 2.0, R_hi < 2.0
    with np.errstate(over="ignore", invalid="ignore"):
        lo_max = np.where(small_lo, (g2 + Q1 * (2.0 * P1 * cphi + Q1)) / (R_lo + 1.0), R_lo - 1.0)
        hi_min = np.where(small_hi, (Q1 * (2.0 * P1 * cphi - Q1) - g2) / (1.0 + R_hi), 1.0 - R_hi)
    return lo_max, hi_min


def _stick_angles(lib, P1, Q1, sphi, cphi, R_lo, R_hi):
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
        s = R_lo + R_hi
        dR = 4.0 * cphi * P1 * (Q1 / s) if lib is np else (
            4.0 * cphi * P1 * (Q1 / s) if s > 0.0 else 0.0)
        delta = lib.atan2(2.0 * P1 * sphi * (Q1 / (Q1 + P1)), Q1 - P1) if lib is math else \
            np.arctan2(2.0 * P1 * sphi * (Q1 / (Q1 + P1)), Q1 - P1)
        if lib is math:
            y_f = (2.0 - dR) / (2.0 * R_hi) if R_hi > 0.0 else math.inf
            y_b = (2.0 + dR) / (2.0 * R_lo) if R_lo > 0.0 else math.inf
            X_f = 2.0 * math.asin(math.sqrt(y_f)) if 0.0 <= y_f <= 1.0 else math.nan
            X_b = 2.0 * math.asin(math.sqrt(y_b)) if 0.0 <= y_b <= 1.0 else math.nan
        else:
            y_f = (2.0 - dR) / (2.0 * R_hi)
            y_b = (2.0 + dR) / (2.0 * R_lo)
            X_f = np.where((y_f >= 0.0) & (y_f <= 1.0),
                           2.0 * np.arcsin(np.sqrt(np.clip(y_f, 0.0, 1.0))), np.nan)
            X_b = np.where((y_b >= 0.0) & (y_b <= 1.0),
                           2.0 * np.arcsin(np.sqrt(np.clip(y_b, 0.0, 1.0))), np.nan)
    return delta, X_f, X_b


def _run(P1, Q1, phi, sphi=None, cphi=None):
    """Advance every point one event at a time over the steady cycle; return Ŵ = ∮ L |dw| / Q̂1.

    Needs Q̂1 > 0. ``sphi``, ``cphi``: sin φ and cos φ of the caller's unreduced φ (default: of
    ``phi``). Vectorized twin of :func:`_run_scalar` (the tests check they agree point by point).
    """
    if sphi is None:
        sphi, cphi = np.sin(phi), np.cos(phi)
    c = _Coefficients.of(P1, Q1, phi, sphi, cphi)
    n = P1.size
    sep = P1 >= 1.0
    g = np.sqrt(np.where(sep, P1 - 1.0, 0.0)) * np.sqrt(P1 + 1.0)
    asin_inv = np.arctan2(1.0, g)         # asin(1/P̂1), accurate next to P̂1 = 1
    theta_c = TWO_PI - asin_inv           # re-contact
    theta_s = math.pi + asin_inv + TWO_PI  # the separation that ends the steady cycle
    q_s = -Q1 * np.sin(asin_inv + phi)     # Q̂ and dQ̂/dθ at separation
    dq_s = -Q1 * np.cos(asin_inv + phi)
    eq_c = -2.0 * sphi * (g / np.hypot(1.0, g))  # (w + Q̂(θ_s)) / Q̂1 when stuck since re-contact

    th = np.where(sep, theta_c, 1.5 * math.pi - c.a_lo)
    stop = np.where(sep, theta_s, th + TWO_PI)
    w = np.where(sep, -Q1 * np.sin(theta_c + phi), c.lo_max)
    state = np.full(n, STICK, dtype=np.int8)
    kind = np.full(n, _AFTER_FORWARD, dtype=np.int8)
    psi = np.zeros(n)  # phase of the pushing boundary at the start of a slip segment
    xs = np.full(n, -1.0)  # s = θ_s - θ at the start of a slip found in s (else -1)
    xis = np.zeros(n)      # that s / c
    cs = np.zeros(n)       # c = |w + Q̂(θ_s)| of that slip
    cqs = np.zeros(n)      # c / Q̂1
    W = np.zeros(n)
    L_from_w = Q1 <= P1    # L at a slip's start from w (exact 0 at re-contact) or from θ

    # At re-contact w = lo = hi; classify by the phase of each boundary (half-open intervals, so
    # that a boundary at its extremum is assigned exactly one state).
    psi_lo_c = _mod0(theta_c + c.a_lo)
    psi_hi_c = _mod0(theta_c + c.a_hi)
    fwd0 = sep & (psi_lo_c >= HALF_PI) & (psi_lo_c < 1.5 * math.pi)
    bwd0 = sep & ~fwd0 & ((psi_hi_c >= 1.5 * math.pi) | (psi_hi_c < HALF_PI))
    state[fwd0] = FORWARD
    psi[fwd0] = psi_lo_c[fwd0]
    state[bwd0] = BACKWARD
    psi[bwd0] = np.where(psi_hi_c >= 1.5 * math.pi, psi_hi_c - TWO_PI, psi_hi_c)[bwd0]
    kind[sep & ~fwd0 & ~bwd0] = _RECONTACT

    active = np.ones(n, dtype=bool)
    for _ in range(_MAX_EVENTS):
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
            after_f = k == _AFTER_FORWARD
            X = c.X_f[i]
            ok = after_f & ~np.isnan(X)
            d_hi[ok] = _pmod(X[ok] - c.delta[i[ok]])
            dn_hi[ok] = X[ok] - HALF_PI
            after_b = k == _AFTER_BACKWARD
            X = c.X_b[i]
            ok = after_b & ~np.isnan(X)
            d_lo[ok] = _pmod(X[ok] + c.delta[i[ok]])
            up_lo[ok] = X[ok] + HALF_PI
            # At re-contact w is on both ends; each crossing is the other root of a known one.
            rc = k == _RECONTACT
            if rc.any():
                pl = psi_lo_c[i[rc]]
                ph = psi_hi_c[i[rc]]
                d_lo[rc] = _pmod(math.pi - 2.0 * pl)
                up_lo[rc] = _mod0(math.pi - pl)  # in [π/2, 3π/2]: pl may be >= 3π/2
                d_hi[rc] = _pmod(math.pi - 2.0 * ph)
                dn_hi[rc] = math.pi - ph
            t_lo = thi + d_lo
            t_hi = thi + d_hi
            # With separation ahead, the last crossing before it is found in s = θ_s - θ, where
            # a crossing 1e-300 rad before separation is still resolved (see _crossing).
            fin_lo = np.zeros(i.size, dtype=bool)
            fin_hi = np.zeros(i.size, dtype=bool)
            sp = sep[i]
            if sp.any():
                Qi = Q1[i]
                eq = np.where(rc, eq_c[i], (wi + q_s[i]) / Qi)   # e / Q̂1, e = w + Q̂(θ_s)
                e = eq * Qi
                lo_fin = sp & (e < 0.0) & ~after_f
                hi_fin = sp & (e > 0.0) & ~after_b
                fwd = e < 0.0
                gi = g[i]
                a_s = np.where(fwd, gi - dq_s[i], gi + dq_s[i])
                b_s = np.where(fwd, 1.0 - q_s[i], 1.0 + q_s[i])
                x, xi = _crossing_vec(a_s, b_s, np.abs(e))
                valid = (x >= 0.0) & (x <= stop[i] - thi)
                fin_lo = lo_fin & valid
                fin_hi = hi_fin & valid
                t_lo = np.where(fin_lo, stop[i] - x, t_lo)
                t_hi = np.where(fin_hi, stop[i] - x, t_hi)
                # the other bound's crossing counts only if resolved before the last one
                t_hi = np.where(fin_lo & (t_hi > t_lo - _TIE), np.inf, t_hi)
                t_lo = np.where(fin_hi & (t_lo > t_hi - _TIE), np.inf, t_lo)
                fin = fin_lo | fin_hi
                # e = 0 at re-contact: θ_c and θ_s are both roots of lo = w and of hi = w, so w
                # sticks to separation
                closed = sp & rc & (e == 0.0) & (gi > 0.0)
                t_lo = np.where(closed, np.inf, t_lo)
                t_hi = np.where(closed, np.inf, t_hi)
                xs[i] = np.where(fin, x, -1.0)
                xis[i] = xi
                cs[i] = np.abs(e)
                cqs[i] = np.abs(eq)
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
                (FORWARD, 1.5 * math.pi, -1.0, c.lo_max, _AFTER_FORWARD),
                (BACKWARD, HALF_PI, 1.0, c.hi_min, _AFTER_BACKWARD)):
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
                W[j] += _sform_W_vec(g[j], a_s, b_s, x, xis[j], cs[j], cqs[j])
                turn = a_s < 0.0
                # the bound's extremum at s_m (a cos s + b sin s = 0): stick there after it
                s_m = np.where(turn, np.arctan2(-a_s, b_s), 0.0)
                s_m = np.minimum(s_m, x)
                with np.errstate(divide="ignore", invalid="ignore"):
                    xi_m = np.where(turn, s_m / cs[j], 0.0)
                W[j] -= np.where(turn, _sform_W_vec(g[j], a_s, b_s, s_m, xi_m, cs[j], cqs[j]),
                                 0.0)
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
            L_a = np.where(L_from_w[i], np.abs(w[i] + Q1[i] * np.sin(a + phi[i])),
                           _L(np, P1[i], a))
            L_b = np.where(done & sep[i], 0.0, _L(np, P1[i], b))
            if slip == FORWARD:
                R, al, sa, ca = c.R_lo[i], c.a_lo[i], c.s_lo[i], c.c_lo[i]
            else:
                R, al, sa, ca = c.R_hi[i], c.a_hi[i], c.s_hi[i], c.c_hi[i]
            W[i] += _slip_integral(a, b, P1[i], Q1[i], phi[i], sphi[i], cphi[i], L_a, L_b, sign,
                                   R, al, sa, ca)
            th[i] = b
            w[i] = w_end[i]
            active[i[done]] = False
            cont = i[~done]
            state[cont] = STICK
            kind[cont] = next_kind
    else:  # pragma: no cover - would be a bug in the event logic
        raise RuntimeError("exact solver: event loop did not terminate; please report this case")
    return W


def _slip_integral_scalar(a, b, P1, Q1, phi, sphi, cphi, L_a, L_b, sign, R, alpha, salpha,
                          calpha):
    """Scalar :func:`_slip_integral`, computing only the form it uses."""
    h = 0.5 * (b - a)
    one_m_P1 = 1.0 - P1
    T = abs(one_m_P1) + 4.0 * P1
    direct = (R - Q1) * T * (2.0 * h) < 0.5 * (L_a * L_a + L_b * L_b)
    if direct:
        phi, sphi, cphi = alpha, salpha, calpha
    m = 0.5 * (a + b) - 1.5 * math.pi
    sh, sm, cm = math.sin(h), math.sin(m), math.cos(m)
    Vh = 2.0 * math.sin(0.5 * h) ** 2
    vm = 2.0 * math.sin(0.5 * m) ** 2
    h_sin = h * h * h * _delta_series(h) if h < 0.5 else h - sh
    I_c = sh * Vh - h_sin + sh * (2.0 * vm * cm - 2.0 * sm * sm * Vh)
    I_s = 2.0 * sm * sh * (vm + cm * Vh)
    K = one_m_P1 * 2.0 * (sm * cphi + cm * sphi) * sh + P1 * (cphi * I_s + sphi * I_c)
    if direct:
        return sign * (R / Q1) * K
    return 0.5 * (L_a - L_b) * ((L_a + L_b) / Q1) + sign * K


def _run_scalar(P1: float, Q1: float, phi: float, sphi: float | None = None,
                cphi: float | None = None, record: bool = True):
    """The same event loop as :func:`_run` for one point, in scalar arithmetic (about 10x faster
    than numpy on one-element arrays). Needs Q̂1 > 0. Returns (Ŵ, segments); segments are
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
        kind = _RECONTACT
        if HALF_PI <= pl < 1.5 * math.pi:
            state, psi = FORWARD, pl
        elif ph >= 1.5 * math.pi or ph < HALF_PI:
            state, psi = BACKWARD, (ph - TWO_PI if ph >= 1.5 * math.pi else ph)
        else:
            state, psi = STICK, 0.0
    else:
        th = 1.5 * math.pi - a_lo
        stop = th + TWO_PI
        w, state, kind, psi = lo_max, STICK, _AFTER_FORWARD, 0.0
    W = 0.0
    x_f = -1.0  # s = θ_s - θ at the start of a slip found in s (else -1)
    for _ in range(_MAX_EVENTS):
        if state == STICK:
            d_lo = d_hi = math.inf
            if kind == _RECONTACT:
                d_lo, up_lo = TWO_PI - (-(math.pi - 2.0 * pl)) % TWO_PI, (math.pi - pl) % TWO_PI
                d_hi, dn_hi = TWO_PI - (-(math.pi - 2.0 * ph)) % TWO_PI, math.pi - ph
            elif kind == _AFTER_FORWARD:
                if X_f == X_f:  # not NaN
                    d_hi, dn_hi = TWO_PI - (delta - X_f) % TWO_PI, X_f - HALF_PI
            elif X_b == X_b:
                d_lo, up_lo = TWO_PI - (-(X_b + delta)) % TWO_PI, X_b + HALF_PI
            t_lo, t_hi = th + d_lo, th + d_hi
            fin = 0
            # the last crossing before separation, found in s = θ_s - θ (used only within π/2
            # of separation: an earlier event needs no s)
            if sep and (t_lo if t_lo < t_hi else t_hi) > stop - _S_RANGE:
                eq = eq_c if kind == _RECONTACT else (w + q_s) / Q1
                e = eq * Q1
                if e == 0.0 and kind == _RECONTACT and g > 0.0:
                    # θ_c and θ_s are both roots of lo = w and of hi = w (a bound crosses a
                    # level twice a period): w sticks to separation
                    t_lo = t_hi = math.inf
                elif e < 0.0 and kind != _AFTER_FORWARD:
                    x, xi = _crossing(g - dq_s, 1.0 - q_s, -e)
                    if 0.0 <= x <= stop - th:
                        t_lo, fin = stop - x, FORWARD
                        if t_hi > t_lo - _TIE:  # not resolved before it: w is above hi's path
                            t_hi = math.inf
                elif e > 0.0 and kind != _AFTER_BACKWARD:
                    x, xi = _crossing(g + dq_s, 1.0 + q_s, e)
                    if 0.0 <= x <= stop - th:
                        t_hi, fin = stop - x, BACKWARD
                        if t_lo > t_hi - _TIE:
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
                W += _sform_W(g, a_s, b_s, x_f, xi, c_f, cq_f)
                if a_s >= 0.0:
                    record and segments.append((th, stop, state, w))
                    break
                s_m = min(math.atan2(-a_s, b_s), x_f)  # the bound's extremum
                W -= _sform_W(g, a_s, b_s, s_m, s_m / c_f, c_f, cq_f)
                record and segments.append((th, stop - s_m, state, w))
                th, w, x_f = stop - s_m, w_end, -1.0
                kind = _AFTER_FORWARD if fwd else _AFTER_BACKWARD
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
            L_b = 0.0 if done and sep else max(
                0.0, (1.0 - P1) + 2.0 * P1 * math.sin(0.5 * (b - 1.5 * math.pi)) ** 2)
            if fwd:
                W += _slip_integral_scalar(th, b, P1, Q1, phi, sphi, cphi, L_a, L_b, -1.0, R_lo,
                                           a_lo, B / R_lo, A / R_lo)
            else:
                W += _slip_integral_scalar(th, b, P1, Q1, phi, sphi, cphi, L_a, L_b, 1.0, R_hi,
                                           a_hi, B / R_hi if R_hi > 0 else 0.0,
                                           C / R_hi if R_hi > 0 else 1.0)
            record and segments.append((th, b, state, w))
            th = b
            w = w_end
            if done:
                break
            kind = _AFTER_FORWARD if fwd else _AFTER_BACKWARD
            state = STICK
    else:  # pragma: no cover - would be a bug in the event logic
        raise RuntimeError("exact solver: event loop did not terminate; please report this case")
    if sep and record:
        segments.append((stop, theta_c + TWO_PI, SEPARATION, float("nan")))
    return W, segments


# -- public entry points ------------------------------------------------------------------------

_FAST_TYPES = frozenset((float, int, np.float64, np.int64))  # not bool (a subclass of int)


def _validated(P1, Q1, phi):
    """The checked, flattened inputs: (P̂1, Q̂1, φ reduced to [0, 2π), sin φ, cos φ, shape)."""
    P1 = _checks.finite_array("P1", P1, nonneg=True, upper=MAX_AMPLITUDE)
    Q1 = _checks.finite_array("Q1", Q1, nonneg=True, upper=MAX_AMPLITUDE)
    phi = _checks.finite_array("phi", phi)
    try:
        P1, Q1, phi = np.broadcast_arrays(P1, Q1, phi)
    except ValueError:
        raise InputError("P1, Q1, phi", f"shapes {P1.shape}, {Q1.shape} and {phi.shape} do not "
                                        "broadcast together") from None
    shape = P1.shape
    phi = phi.ravel()
    # sin and cos of the caller's φ are exact to round-off for any φ; φ reduced through them
    # stays consistent with them (φ mod the double 2π would drift by 2.4e-16 per turn)
    sphi, cphi = np.sin(phi), np.cos(phi)
    return (P1.ravel().astype(float), Q1.ravel().astype(float),
            np.mod(np.arctan2(sphi, cphi), TWO_PI), sphi, cphi, shape)


def _scalar_error(P1, Q1, phi):
    """Raise the InputError, naming the parameter, for scalars the fast path refused."""
    _checks.amplitude("P1", P1, MAX_AMPLITUDE)
    _checks.amplitude("Q1", Q1, MAX_AMPLITUDE)
    _checks.finite("phi", phi)
    raise AssertionError("unreachable: the fast path refused valid input")  # pragma: no cover


def exact_W_hat(P1, Q1, phi):
    """Exact steady-state Ŵ for arrays of (P̂1, Q̂1, φ), broadcast together.

    Parameters
    ----------
    P1, Q1 : float or array_like
        P̂1 and Q̂1, in ``[0, MAX_AMPLITUDE]`` (1e300). Q̂1 = 0 gives the limit Ŵ = 0.
    phi : float or array_like
        φ in radians, any finite value.

    Raises :class:`~lcpfric.errors.InputError` (naming the parameter) for anything else: NaN,
    inf, negative amplitudes, strings, booleans.

    Accuracy: 1e-9 relative (measured worst over a log-uniform audit from 1e-20 to 1e20:
    see the module docstring), except where Ŵ itself is ill-conditioned, next to the border of
    a zero régime (shakedown, or Q̂1 <= P̂1 at φ = 0 with separation); there the result is the
    exact Ŵ of inputs within a few units of round-off of the given ones.

    Returns
    -------
    ndarray (or float for scalar input)
    """
    if type(P1) in _FAST_TYPES and type(Q1) in _FAST_TYPES and type(phi) in _FAST_TYPES:
        try:
            p, q, f = float(P1), float(Q1), float(phi)
        except OverflowError:  # an int beyond the double range
            _scalar_error(P1, Q1, phi)
        # one comparison chain rejects NaN, inf, negatives and the too large
        if not (0.0 <= p <= MAX_AMPLITUDE and 0.0 <= q <= MAX_AMPLITUDE and -_INF < f < _INF):
            _scalar_error(P1, Q1, phi)
        if q == 0.0:
            return 0.0
        sf, cf = math.sin(f), math.cos(f)
        W = _run_scalar(p, q, math.atan2(sf, cf) % TWO_PI, sf, cf, False)[0]
        return W if W > 0.0 else 0.0
    p, q, f, sf, cf, shape = _validated(P1, Q1, phi)
    W = np.zeros(p.shape)
    pos = q > 0.0
    if pos.all():
        W = _run(p, q, f, sf, cf)
    elif pos.any():
        W[pos] = _run(p[pos], q[pos], f[pos], sf[pos], cf[pos])
    W = np.maximum(W, 0.0)  # Ŵ >= 0 analytically; clip round-off of exact-zero cycles
    W = W.reshape(shape)
    return W if W.ndim else float(W)


_INF = math.inf


@dataclass(frozen=True)
class ExactCycle:
    """The exact steady cycle of one point, as segments in θ = ωt.

    ``segments`` is a tuple of ``(theta_start, theta_end, state, w_start)``; ``W_hat`` the
    dissipation per cycle.
    """

    P1: float
    Q1: float
    phi: float
    W_hat: float
    segments: tuple

    def __post_init__(self):
        arr = np.array([s[:3] for s in self.segments], dtype=float)
        object.__setattr__(self, "_starts", arr[:, 0])
        object.__setattr__(self, "_states", arr[:, 2].astype(np.int8))
        object.__setattr__(self, "_w0", np.array([s[3] for s in self.segments]))

    def _locate(self, theta):
        x = self._starts[0] + np.mod(np.asarray(theta, dtype=float) - self._starts[0], TWO_PI)
        idx = np.clip(np.searchsorted(self._starts, x, side="right") - 1, 0,
                      self._starts.size - 1)
        return x, idx

    def state(self, theta):
        """The state (STICK, FORWARD, BACKWARD, SEPARATION) at the angles ``theta``."""
        return self._states[self._locate(theta)[1]]

    def w(self, theta):
        """w = F̂ - Q̂ = Q̂1 v̂ at the angles ``theta`` (any real values)."""
        x, idx = self._locate(theta)
        st = self._states[idx]
        L = np.maximum(1.0 + self.P1 * np.sin(x), 0.0)
        Qh = self.Q1 * np.sin(x + self.phi)
        out = self._w0[idx].copy()
        out = np.where(st == FORWARD, -L - Qh, out)
        out = np.where(st == BACKWARD, L - Qh, out)
        return np.where(st == SEPARATION, -Qh, out)


def exact_cycle(P1: float, Q1: float, phi: float) -> ExactCycle:
    """The exact steady cycle of one point, with its segments (for time series and plots).

    Inputs are checked as in :func:`exact_W_hat`; one point only.
    """
    p, q, f, sf, cf, _ = _validated(P1, Q1, phi)
    if p.size != 1:
        raise InputError("P1", "exact_cycle takes one point (scalars); use exact_W_hat for "
                               "arrays")
    p, q, f, sf, cf = float(p[0]), float(q[0]), float(f[0]), float(sf[0]), float(cf[0])
    if q > 0.0:
        W, segments = _run_scalar(p, q, f, sf, cf)
    else:  # Q̂1 = 0: w stays where it is (any constant; 0 here) and nothing slips
        W, segments = 0.0, _zero_load_segments(p)
    segs = tuple((float(a), float(b), int(s), float(w0)) for a, b, s, w0 in segments
                 if b > a or s == STICK)
    return ExactCycle(p, q, f, max(W, 0.0), segs)


def _zero_load_segments(P1):
    if P1 >= 1.0:
        a = math.asin(1.0 / P1)
        return [(TWO_PI - a, 3 * math.pi + a, STICK, 0.0),
                (3 * math.pi + a, 4 * math.pi - a, SEPARATION, float("nan"))]
    return [(0.0, TWO_PI, STICK, 0.0)]
