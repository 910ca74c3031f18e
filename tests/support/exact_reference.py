"""An independent high-precision reference for the single node's Ŵ (needs mpmath).

    python tests/support/exact_reference.py P1 Q1 phi      # prints the reference Ŵ

Written separately from :mod:`lcpfric.exact` and differently from it, so that the two are not
"the same approximation twice":

* arithmetic: mpmath at ``dps`` decimal digits (default: 60 plus twice the decimal exponent
  spread of the inputs), so an angle step of 1e-40 rad is still resolved to 20 digits;
* start: not the periodic orbit's known point, but ``w = 0`` (projected into the interval) at
  θ = 0, run for whole cycles until two successive cycles agree (with separation the second
  cycle is already periodic; without it the run goes on until the cycle's dissipation and end
  state repeat to ``10^(-dps/2)``);
* dissipation: each slip segment's ``∫ L |dw|`` from its antiderivative in θ
  (``∫ (1 + P̂1 sin θ) R cos(θ + a) dθ``), not from the library's ``½ΔL² ± Q̂1∫L cos`` form;
  the energy identity ``∮ L|dw| = ∮ w dQ̂`` is evaluated along the same path as a second,
  independent sum (:func:`reference_cycle` returns both).

Bounds are written as ``lo = -1 - R_l sin(θ + a_l)`` with ``R_l e^{i a_l} = P̂1 + Q̂1 e^{iφ}``
and ``hi = 1 + R_h sin(θ + a_h)`` with ``R_h e^{i a_h} = P̂1 - Q̂1 e^{iφ}``.
"""

from __future__ import annotations

import math
import sys

import mpmath as mp
import numpy as np

__all__ = [
    "reference_W_hat",
    "reference_cycle",
    "default_dps",
    "input_spread",
    "grid_W_hat",
    "jang_barber_mp",
]


def default_dps(P1: float, Q1: float) -> int:
    spread = 0.0
    for x in (P1, Q1):
        if x > 0:
            spread += abs(math.log10(x))
    if P1 > 0 and abs(P1 - 1.0) > 0:
        spread += max(0.0, -math.log10(abs(P1 - 1.0)))
    return int(60 + 2 * math.ceil(spread))


class _Node:
    def __init__(self, P1, Q1, phi):
        self.P1, self.Q1, self.phi = P1, Q1, phi
        zl = P1 + Q1 * mp.expj(phi)
        zh = P1 - Q1 * mp.expj(phi)
        self.Rl, self.al = abs(zl), mp.arg(zl)
        self.Rh, self.ah = abs(zh), mp.arg(zh)
        self.sep = P1 >= 1
        if self.sep:
            a = mp.asin(1 / P1)
            self.th_s, self.th_c = mp.pi + a, 2 * mp.pi - a  # separated on (th_s, th_c)

    def L(self, th):
        return max(1 + self.P1 * mp.sin(th), mp.mpf(0))

    def Q(self, th):
        return self.Q1 * mp.sin(th + self.phi)

    def lo(self, th):
        return -1 - self.Rl * mp.sin(th + self.al)

    def hi(self, th):
        return 1 + self.Rh * mp.sin(th + self.ah)

    def G(self, th, R, a):
        """Antiderivative of (1 + P1 sin θ)(-R cos(θ + a)) in θ."""
        return -R * (mp.sin(th + a) + self.P1 * (-mp.cos(2 * th + a) / 4 - th * mp.sin(a) / 2))

    def H(self, th, sign, R, a):
        """Antiderivative of (sign (1 + R sin(θ + a))) Q1 cos(θ + φ): ∫ bound dQ̂ in θ."""
        return (
            sign
            * self.Q1
            * (
                mp.sin(th + self.phi)
                + R * (-mp.cos(2 * th + a + self.phi) / 2 + th * mp.sin(a - self.phi)) / 2
            )
        )


def _next_at(psi, a, th0, strict, eps):
    """Smallest θ with θ + a ≡ psi (mod 2π) and θ > th0 + eps (strict) or θ > th0 - eps."""
    two_pi = 2 * mp.pi
    th = psi - a
    lim = th0 + eps if strict else th0 - eps
    k = mp.floor((lim - th) / two_pi) + 1
    return th + two_pi * k


def reference_cycle(
    P1: float, Q1: float, phi: float, dps: int | None = None, max_cycles: int = 12
) -> dict:
    """Ŵ and diagnostics of the steady cycle by a high-precision event-by-event simulation.

    Returns a dict with ``W_hat`` (mpf), ``J`` = ∮ L|dw|, ``J_energy`` = ∮ w dQ̂ over the same
    cycle (equal to J on a periodic Coulomb path), ``cycles`` run and ``dps``.
    """
    dps = default_dps(P1, Q1) if dps is None else dps
    with mp.workdps(dps):
        P1m, Q1m = mp.mpf(P1), mp.mpf(Q1)
        # φ reduced mod 2π with enough digits for its exponent (sin(θ + φ) with φ = 1e300 would
        # otherwise lose θ)
        with mp.workdps(dps + 20 + max(0, int(math.log10(abs(phi) + 1)))):
            phim = mp.mpf(phi) % (2 * mp.pi)
        phim = +phim
        if Q1m == 0:
            return dict(W_hat=mp.mpf(0), J=mp.mpf(0), J_energy=mp.mpf(0), cycles=0, dps=dps)
        n = _Node(P1m, Q1m, phim)
        eps = mp.mpf(10) ** (-(dps - 15))
        two_pi = 2 * mp.pi
        th = mp.mpf(0)  # θ = 0 is in contact (L = 1)
        w = min(max(mp.mpf(0), n.lo(th)), n.hi(th))
        mode = "stick"
        arc_end = _next_at(n.th_s, 0, th, False, eps) if n.sep else mp.inf
        cycle_end = two_pi
        J = Jq = mp.mpf(0)
        history = []
        for _ in range(400 * max_cycles):
            if mode == "sep":  # w = -Q̂ until re-contact, then classify by the bounds' slopes
                th_c = _next_at(n.th_c, 0, th, False, eps)
                nxt = min(th_c, cycle_end)
                Jq -= (n.Q(nxt) ** 2 - n.Q(th) ** 2) / 2
                th, w = nxt, -n.Q(nxt)
                if th == th_c:
                    arc_end = _next_at(n.th_s, 0, th, True, eps)
                    # which bound, if any, pushes w just after re-contact (compared a short
                    # step later, so that zero slopes at P̂1 = 1 are classified too)
                    dlo, dhi = -n.Rl * mp.cos(th + n.al), n.Rh * mp.cos(th + n.ah)
                    tiny = mp.mpf(10) ** (-(dps // 3))
                    if abs(dlo) <= tiny * n.Rl or abs(dhi) <= tiny * (1 + n.Rh):
                        h = mp.mpf(10) ** (-(dps // 4))
                        dlo, dhi = n.lo(th + h) - w, n.hi(th + h) - w
                    mode = "fwd" if dlo > 0 else ("bwd" if dhi < 0 else "stick")
            elif mode == "stick":
                end = min(arc_end, cycle_end)
                t_lo = t_hi = mp.inf
                # a crossing at θ itself counts (a stick split at a cycle's end) unless it is
                # a tangential touch (w at the bound's extremum, after a slip)
                touch = 1 - mp.mpf(10) ** (-(dps // 2))
                cl = (-1 - w) / n.Rl
                if abs(cl) <= 1:  # lo rises through w where cos(θ + a_l) < 0
                    t_lo = _next_at(mp.pi - mp.asin(cl), n.al, th, abs(cl) > touch, eps)
                if n.Rh > 0:
                    ch = (w - 1) / n.Rh
                    if abs(ch) <= 1:  # hi falls through w where cos(θ + a_h) < 0
                        t_hi = _next_at(mp.pi - mp.asin(ch), n.ah, th, abs(ch) > touch, eps)
                nxt = min(t_lo, t_hi, end)
                Jq += w * (n.Q(nxt) - n.Q(th))
                th = nxt
                if nxt < end:
                    mode = "fwd" if t_lo <= t_hi else "bwd"
            else:
                end = min(arc_end, cycle_end)
                R, a, sign, bound = (
                    (n.Rl, n.al, -1, n.lo) if mode == "fwd" else (n.Rh, n.ah, 1, n.hi)
                )
                ext = _next_at(3 * mp.pi / 2, a, th, False, eps)  # end of the bound's motion
                nxt = min(ext, end)
                J += n.G(nxt, R, a) - n.G(th, R, a)
                Jq += n.H(nxt, sign, R, a) - n.H(th, sign, R, a)
                th, w = nxt, bound(nxt)
                if ext < end:
                    mode = "stick"
            if mode != "sep" and n.sep and th == arc_end:
                mode, w = "sep", -n.Q(th)
            if th == cycle_end:
                history.append((J, Jq, w))
                J = Jq = mp.mpf(0)
                cycle_end += two_pi
                if _settled(history, dps, n.sep):
                    break
                if len(history) >= max_cycles:
                    raise RuntimeError("reference: no periodic cycle within max_cycles")
        else:
            raise RuntimeError("reference: too many events")
        J, Jq, _ = history[-1]
        return dict(W_hat=J / Q1m, J=J, J_energy=Jq, cycles=len(history), dps=dps)


def _settled(history, dps, sep):
    if len(history) < 2:
        return False
    if sep:
        return True  # one separation fixes the state: the second cycle is periodic
    (J1, _, w1), (J2, _, w2) = history[-2], history[-1]
    tol = mp.mpf(10) ** (-(dps // 2))
    return abs(J1 - J2) <= tol * (abs(J2) + tol) and abs(w1 - w2) <= tol * (1 + abs(w2))


def grid_W_hat(P1, Q1, phi, steps: int = 200_000, cycles: int = 4):
    """A third, plain reference: the sweeping process on a fine uniform grid in double precision
    (catch-up: w_{n+1} = clip(w_n, lo_{n+1}, hi_{n+1}), J += L_mid |Δw|), for arrays of points.

    Its error is O(1/steps^2) (slip ends between grid points) and its round-off ~1e-13 per
    cycle: a check of the event logic of :func:`reference_cycle` at moderate inputs only.
    """
    import numpy as np

    P1, Q1, phi = (np.asarray(x, dtype=float).ravel() for x in np.broadcast_arrays(P1, Q1, phi))
    h = 2 * math.pi / steps
    sep = P1 >= 1.0
    a = np.arcsin(np.minimum(1.0, 1.0 / np.where(sep, P1, 1.0)))
    w_c = -Q1 * np.sin(2 * math.pi - a + phi)  # w at re-contact and at separation: -Q̂ there
    w_s = -Q1 * np.sin(math.pi + a + phi)
    w = np.zeros(P1.size)
    J = np.zeros(P1.size)
    L_prev = np.ones(P1.size)
    for k in range(cycles * steps + 1):
        th = k * h
        L = np.maximum(1.0 + P1 * math.sin(th), 0.0)
        Qh = Q1 * np.sin(th + phi)
        # the separation instants are known: a step across one is split there
        recontact = sep & (L_prev == 0) & (L > 0)
        w = np.where(recontact, w_c, w)
        w_new = np.clip(w, -L - Qh, L - Qh)
        separating = sep & (L_prev > 0) & (L == 0)
        if k > (cycles - 1) * steps:
            J += np.where(
                separating, 0.5 * L_prev * np.abs(w_s - w), 0.5 * (L + L_prev) * np.abs(w_new - w)
            )
        w, L_prev = w_new, L
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(Q1 > 0, J / np.where(Q1 > 0, Q1, 1.0), 0.0)


def jang_barber_mp(P1, Q1):
    """Eqs. (11)/(12) (φ = 0, corrected) in mpmath, for checking :func:`reference_cycle`."""
    P1, Q1 = mp.mpf(P1), mp.mpf(Q1)
    if P1 < 1:
        return 4 * (Q1 - 1) * (Q1 - P1**2) / (Q1**2 - P1**2) if Q1 > 1 else mp.mpf(0)
    return (Q1 - P1) * (1 + P1) ** 2 / (P1 * (Q1 + P1)) if Q1 > P1 else mp.mpf(0)


def input_spread(P1: float, Q1: float, phi: float, ulps: int = 16) -> float:
    """The largest change of the exact Ŵ when one input moves by ``ulps`` units of round-off:
    P̂1 and Q̂1 by the relative ``ulps eps``, φ by the absolute ``ulps eps max(1, |φ|)``.

    A measure of the conditioning: an answer within it is exact for inputs indistinguishable
    from the given ones.
    """
    eps = 2.0**-52
    ref = reference_cycle(P1, Q1, phi)["W_hat"]
    d = ulps * eps
    out = mp.mpf(0)
    for p, q, f in (
        (P1 * (1 + d), Q1, phi),
        (P1 * (1 - d), Q1, phi),
        (P1, Q1 * (1 + d), phi),
        (P1, Q1 * (1 - d), phi),
        (P1, Q1, phi + d * max(1.0, abs(phi))),
        (P1, Q1, phi - d * max(1.0, abs(phi))),
    ):
        out = max(out, abs(reference_cycle(p, q, f)["W_hat"] - ref))
    return float(out)


def reference_W_hat(P1: float, Q1: float, phi: float, dps: int | None = None) -> float:
    """The reference Ŵ rounded to a float (Ŵ >= 0: a round-off of -1e-68 at a zero is 0)."""
    return max(float(reference_cycle(P1, Q1, phi, dps)["W_hat"]), 0.0)


if __name__ == "__main__":
    p, q, f = (float(x) for x in sys.argv[1:4])
    r = reference_cycle(p, q, f)
    print(
        f"W_hat = {mp.nstr(r['W_hat'], 25)}  (energy identity: "
        f"{mp.nstr(r['J_energy'] / mp.mpf(q) if q else 0, 25)}; cycles {r['cycles']}, "
        f"dps {r['dps']})"
    )


def draw(n: int, seed: int) -> np.ndarray:
    """(n, 3) array of (P̂1, Q̂1, φ) from the mixture in the module docstring."""
    rng = np.random.default_rng(seed)
    m = max(1, n // 9)
    lu = lambda lo, hi, k: 10.0 ** rng.uniform(lo, hi, k)  # noqa: E731
    phi = lambda k: rng.uniform(0, 2 * math.pi, k)  # noqa: E731
    fam = []
    fam.append(np.c_[lu(-20, 20, m), lu(-20, 20, m), phi(m)])
    P = lu(-20, 20, m)
    fam.append(np.c_[P, P * lu(-20, 20, m), phi(m)])
    P = 1.0 + lu(-16, 2, m)
    fam.append(np.c_[P, P * lu(-20, -3, m), phi(m)])
    P = 1.0 + rng.choice([-1, 1], m) * lu(-16, 0, m)
    fam.append(np.c_[P, lu(-8, 8, m), phi(m)])
    fam.append(
        np.c_[
            lu(-3, 8, m),
            lu(-8, 8, m),
            rng.choice([0.0, math.pi, 2 * math.pi], m) + rng.choice([-1, 1], m) * lu(-12, 0, m),
        ]
    )
    P = lu(-2, 8, m)
    near0 = rng.choice([0.0, math.pi], m) + rng.choice([-1, 1], m) * lu(-12, -1, m)
    fam.append(
        np.c_[
            P,
            P * (1 + np.where(rng.random(m) < 0.2, 0.0, rng.choice([-1, 1], m) * lu(-16, 0, m))),
            np.where(rng.random(m) < 0.5, phi(m), near0),
        ]
    )
    fam.append(np.c_[rng.uniform(0, 4, m), rng.uniform(0, 4, m), phi(m)])
    P = rng.uniform(0, 50, m)
    off = np.where(rng.random(m) < 0.5, 0.0, rng.choice([-1, 1], m) * lu(-8, 0, m))
    fam.append(
        np.c_[P, np.maximum(P + rng.uniform(-3, 3, m), 0.0), rng.choice([0.0, math.pi], m) + off]
    )
    k = n - 8 * m
    base = np.array(
        [[p, q] for p in (0.0, 0.5, 1.0, 2.0, 1e10) for q in (0.0, 0.5, 1.0, 2.0, 1e10)]
        + [[x, x] for x in (0.5, 1.0, 2.0, 1e10)]
    )
    idx = rng.integers(0, len(base), k)
    fam.append(
        np.c_[base[idx], np.r_[rng.choice([0.0, math.pi / 2, math.pi], k // 2), phi(k - k // 2)]]
    )
    return np.concatenate(fam)
