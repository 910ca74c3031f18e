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

so every event has a closed form: stick ends where ``lo(θ) = w`` on a rising flank or
``hi(θ) = w`` on a falling flank (an arcsine); forward slip (w = lo) ends at the maximum of lo,
``θ + α_lo = 3π/2``, with ``w = R_lo - 1``; backward slip (w = hi) ends at the minimum of hi,
``θ + α_hi = π/2``, with ``w = 1 - R_hi``; separation starts and ends where ``P̂ = 0``, at
``θ_s = π + asin(1/P̂1)`` and ``θ_c = 2π - asin(1/P̂1)``. The dissipation of a slip segment,
``∫ L(θ) |dw/dθ| dθ``, is integrated in closed form as ``½ (L_a² - L_b²) ± Q̂1 ∫ L cos(θ+φ) dθ``
(on a slip segment w = ∓L - Q̂), with the endpoint values of L taken from w: written so, a slip
of 1e-12 rad just before separation at P̂1 = 1e6 keeps its digits, where the direct form
``∫ L (X cos θ + Y sin θ)`` sums O(1) terms to 1e-12.

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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["exact_W_hat", "ExactCycle", "exact_cycle", "STICK", "FORWARD", "BACKWARD",
           "SEPARATION"]

STICK, FORWARD, BACKWARD, SEPARATION = 0, 1, 2, 3
_AFTER_FORWARD, _AFTER_BACKWARD, _RECONTACT = 0, 1, 2

TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi
_MAX_EVENTS = 64  # a harmonic cycle has at most ~10 segments; this only guards against a bug


def _mod0(x):
    """x mod 2π in [0, 2π)."""
    return np.mod(x, TWO_PI)


def _pmod(x):
    """x mod 2π in (0, 2π]."""
    return TWO_PI - np.mod(-x, TWO_PI)


def _slip_integral(a, b, P1, Q1, phi, L_a, L_b, sign):
    """∫_a^b L |dw| over a slip segment, well-conditioned for any P̂1, Q̂1.

    On a slip segment w = ∓L - Q̂ (lower bound: forward slip, sign = -1; upper bound: backward
    slip, sign = +1), so ``L |dw| = -L dL ∓ ... `` integrates to
    ``½ (L_a² - L_b²) + sign · Q̂1 ∫_a^b L cos(θ + φ) dθ``. The endpoint values of L come from
    quantities of the size of w (see the callers), so no product of P̂1 with R is formed; the
    remaining integral is written with half-angle products so that short segments lose no digits.
    """
    lib = math if isinstance(a, float) else np
    m = 0.5 * (a + b)
    h = 0.5 * (b - a)
    s2h = lib.sin(2.0 * h)
    # ∫ (1 + P̂1 sin θ) cos(θ + φ) dθ
    K = (2.0 * lib.cos(m + phi) * lib.sin(h)
         + P1 * (0.5 * lib.sin(2.0 * m + phi) * s2h - h * lib.sin(phi)))
    return 0.5 * (L_a - L_b) * (L_a + L_b) + sign * Q1 * K


@dataclass
class _Coefficients:
    P1: np.ndarray
    Q1: np.ndarray
    phi: np.ndarray
    R_lo: np.ndarray
    a_lo: np.ndarray
    R_hi: np.ndarray
    a_hi: np.ndarray

    @classmethod
    def of(cls, P1, Q1, phi):
        A = P1 + Q1 * np.cos(phi)
        B = Q1 * np.sin(phi)
        C = Q1 * np.cos(phi) - P1
        D = B
        return cls(P1, Q1, phi, np.hypot(A, B), np.arctan2(B, A), np.hypot(C, D),
                   np.arctan2(D, C))


def _run(P1, Q1, phi):
    """Advance every point one event at a time over the steady cycle; return J = ∮ L |dw|.

    Vectorized twin of :func:`_run_scalar` (the tests check the two agree point by point)."""
    c = _Coefficients.of(P1, Q1, phi)
    n = P1.size
    sep = P1 >= 1.0
    asin_inv = np.arcsin(np.minimum(1.0, 1.0 / np.where(sep, P1, 1.0)))
    theta_c = TWO_PI - asin_inv           # re-contact
    theta_s = math.pi + asin_inv + TWO_PI  # the separation that ends the steady cycle

    th = np.where(sep, theta_c, 1.5 * math.pi - c.a_lo)
    stop = np.where(sep, theta_s, th + TWO_PI)
    w = np.where(sep, -Q1 * np.sin(theta_c + phi), c.R_lo - 1.0)
    state = np.full(n, STICK, dtype=np.int8)
    kind = np.full(n, _AFTER_FORWARD, dtype=np.int8)
    psi = np.zeros(n)  # phase of the pushing boundary at the start of a slip segment
    J = np.zeros(n)

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
            with np.errstate(divide="ignore", invalid="ignore"):
                c_lo = (-1.0 - wi) / c.R_lo[i]
                c_hi = (1.0 - wi) / c.R_hi[i]
            ok_lo = np.abs(c_lo) <= 1.0
            ok_hi = np.abs(c_hi) <= 1.0
            up_lo = np.where(ok_lo, math.pi - np.arcsin(np.clip(c_lo, -1, 1)), 0.0)
            dn_hi = np.where(ok_hi, np.arcsin(np.clip(c_hi, -1, 1)), 0.0)
            d_lo = np.where(ok_lo, _mod0(up_lo - (thi + c.a_lo[i])), np.inf)
            d_hi = np.where(ok_hi, _mod0(dn_hi - (thi + c.a_hi[i])), np.inf)
            # After forward slip w sits at the maximum of lo: lo next reaches w one period later.
            after_f = k == _AFTER_FORWARD
            d_lo[after_f] = TWO_PI
            up_lo[after_f] = 1.5 * math.pi
            after_b = k == _AFTER_BACKWARD
            d_hi[after_b] = TWO_PI
            dn_hi[after_b] = HALF_PI
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
            t_end = np.minimum(np.minimum(t_lo, t_hi), stop[i])
            done = t_end >= stop[i]
            to_f = ~done & (t_lo <= t_hi)
            to_b = ~done & ~to_f
            active[i[done]] = False
            th[i] = t_end
            state[i[to_f]] = FORWARD
            psi[i[to_f]] = up_lo[to_f]
            state[i[to_b]] = BACKWARD
            psi[i[to_b]] = dn_hi[to_b]
        # -- forward slip on lo, until its maximum (θ + α_lo = 3π/2) or separation --------------
        for slip, end_phase, sign, w_end, next_kind in (
                (FORWARD, 1.5 * math.pi, -1.0, c.R_lo - 1.0, _AFTER_FORWARD),
                (BACKWARD, HALF_PI, 1.0, 1.0 - c.R_hi, _AFTER_BACKWARD)):
            i = np.nonzero(active & (state == slip))[0]
            if not i.size:
                continue
            a = th[i]
            b = a + np.maximum(end_phase - psi[i], 0.0)
            done = b >= stop[i]
            b = np.minimum(b, stop[i])
            L_a = np.abs(w[i] + Q1[i] * np.sin(a + phi[i]))  # w = ∓L - Q̂ on the bound
            L_b = np.where(done & sep[i], 0.0, np.maximum(1.0 + P1[i] * np.sin(b), 0.0))
            J[i] += _slip_integral(a, b, P1[i], Q1[i], phi[i], L_a, L_b, sign)
            th[i] = b
            w[i] = w_end[i]
            active[i[done]] = False
            cont = i[~done]
            state[cont] = STICK
            kind[cont] = next_kind
    else:  # pragma: no cover - would be a bug in the event logic
        raise RuntimeError("exact solver: event loop did not terminate; please report this case")
    return J


def _run_scalar(P1: float, Q1: float, phi: float):
    """The same event loop as :func:`_run` for one point, in scalar arithmetic (about 10x faster
    than numpy on one-element arrays). Returns (J, segments)."""
    A, B = P1 + Q1 * math.cos(phi), Q1 * math.sin(phi)
    C = Q1 * math.cos(phi) - P1
    R_lo, a_lo = math.hypot(A, B), math.atan2(B, A)
    R_hi, a_hi = math.hypot(C, B), math.atan2(B, C)
    segments = []
    if P1 >= 1.0:
        asin_inv = math.asin(min(1.0, 1.0 / P1))
        theta_c = TWO_PI - asin_inv
        th, stop = theta_c, math.pi + asin_inv + TWO_PI
        w = -Q1 * math.sin(theta_c + phi)
        pl, ph = (theta_c + a_lo) % TWO_PI, (theta_c + a_hi) % TWO_PI
        if HALF_PI <= pl < 1.5 * math.pi:
            state, psi = FORWARD, pl
        elif ph >= 1.5 * math.pi or ph < HALF_PI:
            state, psi = BACKWARD, (ph - TWO_PI if ph >= 1.5 * math.pi else ph)
        else:
            state, kind, psi = STICK, _RECONTACT, 0.0
    else:
        th = 1.5 * math.pi - a_lo
        stop = th + TWO_PI
        w, state, kind, psi = R_lo - 1.0, STICK, _AFTER_FORWARD, 0.0
    J = 0.0
    for _ in range(_MAX_EVENTS):
        if state == STICK:
            if kind == _RECONTACT:
                d_lo, up_lo = TWO_PI - (-(math.pi - 2.0 * pl)) % TWO_PI, (math.pi - pl) % TWO_PI
                d_hi, dn_hi = TWO_PI - (-(math.pi - 2.0 * ph)) % TWO_PI, math.pi - ph
            else:
                d_lo = d_hi = math.inf
                c_lo = (-1.0 - w) / R_lo if R_lo > 0 else math.inf
                c_hi = (1.0 - w) / R_hi if R_hi > 0 else math.inf
                if abs(c_lo) <= 1.0:
                    up_lo = math.pi - math.asin(c_lo)
                    d_lo = (up_lo - (th + a_lo)) % TWO_PI
                if abs(c_hi) <= 1.0:
                    dn_hi = math.asin(c_hi)
                    d_hi = (dn_hi - (th + a_hi)) % TWO_PI
                if kind == _AFTER_FORWARD:
                    d_lo, up_lo = TWO_PI, 1.5 * math.pi
                else:
                    d_hi, dn_hi = TWO_PI, HALF_PI
            t_lo, t_hi = th + d_lo, th + d_hi
            t_end = min(t_lo, t_hi, stop)
            segments.append((th, t_end, STICK, w))
            if t_end >= stop:
                break
            th = t_end
            state, psi = (FORWARD, up_lo) if t_lo <= t_hi else (BACKWARD, dn_hi)
        else:
            end_phase = 1.5 * math.pi if state == FORWARD else HALF_PI
            b = th + max(end_phase - psi, 0.0)
            done = b >= stop
            b = min(b, stop)
            L_a = abs(w + Q1 * math.sin(th + phi))  # w = ∓L - Q̂ on the bound
            L_b = 0.0 if done and P1 >= 1.0 else max(1.0 + P1 * math.sin(b), 0.0)
            J += _slip_integral(th, b, P1, Q1, phi, L_a, L_b,
                                -1.0 if state == FORWARD else 1.0)
            segments.append((th, b, state, w))
            th = b
            w = R_lo - 1.0 if state == FORWARD else 1.0 - R_hi
            if done:
                break
            kind = _AFTER_FORWARD if state == FORWARD else _AFTER_BACKWARD
            state = STICK
    else:  # pragma: no cover - would be a bug in the event logic
        raise RuntimeError("exact solver: event loop did not terminate; please report this case")
    if P1 >= 1.0:
        segments.append((stop, theta_c + TWO_PI, SEPARATION, float("nan")))
    return J, segments


def _prepare(P1, Q1, phi):
    P1, Q1, phi = np.broadcast_arrays(np.asarray(P1, dtype=float), np.asarray(Q1, dtype=float),
                                      np.asarray(phi, dtype=float))
    shape = P1.shape
    return P1.ravel(), Q1.ravel(), np.mod(phi.ravel(), TWO_PI), shape


_SCALARS = (float, int, np.floating, np.integer)


def exact_W_hat(P1, Q1, phi):
    """Exact steady-state Ŵ for arrays of (P̂1, Q̂1, φ), broadcast together.

    Parameters are assumed validated (finite, P̂1 >= 0, Q̂1 >= 0); see :func:`lcpfric.steady_state`
    for the checked entry point. Q̂1 = 0 gives the limit Ŵ = 0.

    Returns
    -------
    ndarray (or float for scalar input)
    """
    if isinstance(P1, _SCALARS) and isinstance(Q1, _SCALARS) and isinstance(phi, _SCALARS):
        q = float(Q1)
        if q <= 0.0:
            return 0.0
        J = _run_scalar(float(P1), q, float(phi) % TWO_PI)[0]
        return max(J / q, 0.0)
    p, q, f, shape = _prepare(P1, Q1, phi)
    J = _run(p, q, f)
    with np.errstate(divide="ignore", invalid="ignore"):
        W = np.where(q > 0, J / np.where(q > 0, q, 1.0), 0.0)
    W = np.maximum(W, 0.0)  # J >= 0 analytically; clip round-off of exact-zero cycles
    W = W.reshape(shape)
    return W if W.ndim else float(W)


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
    """The exact steady cycle of one point, with its segments (for time series and plots)."""
    p, q, f, _ = _prepare(P1, Q1, phi)
    if p.size != 1:
        raise ValueError("exact_cycle takes one point; use exact_W_hat for arrays")
    J, segments = _run_scalar(float(p[0]), float(q[0]), float(f[0]))
    W = J / float(q[0]) if q[0] > 0 else 0.0
    segs = tuple((float(a), float(b), int(s), float(w0)) for a, b, s, w0 in segments
                 if b > a or s == STICK)
    return ExactCycle(float(p[0]), float(q[0]), float(f[0]), max(W, 0.0), segs)
