"""Trig triples: every load and every displacement of a fixed stick/slip pattern is
``x(θ) = c0 + cs sin θ + cc cos θ``; its value, its rate, the next angle where it enters a
half-line (an event, in closed form), and the dissipation of a slipping segment in closed form
(:mod:`lcpfric.exact.discrete`)."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = [
    "harmonic_triples",
    "value",
    "rate_of",
    "next_entry",
    "segment_dissipation",
    "multiplier",
    "TWO_PI",
    "REL",
]

TWO_PI = 2.0 * math.pi
REL = 1e-13  # a dip below this fraction of its scale is an event


def harmonic_triples(loads, omega: float, parameter: str) -> np.ndarray:
    """(n, 3) triples ``(c0, cs, cc)`` of harmonic loads at the angular frequency ``omega``.

    ``mean + a sin(ωt + ψ) = mean + a cos ψ sin θ + a sin ψ cos θ``. A load with a harmonic of
    another frequency raises :class:`InputError` naming ``parameter``.
    """
    from ..model.loads import Fourier

    out = np.zeros((len(loads), 3))
    for i, load in enumerate(loads):
        if not isinstance(load, Fourier):
            raise InputError(
                parameter,
                f"'exact' needs harmonic loads (Harmonic or a one-term "
                f"Fourier); load {i} is {type(load).__name__}: use "
                f"'explicit' or a solver backend",
            )
        amps = [a for a in load.amplitudes[1:] if a]
        if amps:
            raise InputError(
                parameter,
                f"'exact' needs harmonic loads of one frequency; load "
                f"{i} has higher harmonics: use 'explicit' or a solver "
                f"backend",
            )
        a = load.amplitudes[0] if load.amplitudes else 0.0
        if a and not math.isclose(load.omega, omega, rel_tol=1e-12):
            raise InputError(
                parameter,
                f"'exact' needs one frequency; load {i} has ω = {load.omega}, others {omega}",
            )
        p = load.phases[0] if load.phases else 0.0
        out[i] = (load.mean, a * math.cos(p), a * math.sin(p)) if a else (load.mean, 0.0, 0.0)
    return out


def value(T, theta):
    """Triples T (..., 3) at the angle(s) theta (broadcast on the leading axis)."""
    s, c = np.sin(theta), np.cos(theta)
    return T[..., 0] + T[..., 1] * s + T[..., 2] * c


def rate_of(T):
    """d/dθ of triples: ``cs cos θ - cc sin θ`` -> (0, -cc, cs)."""
    D = np.empty_like(T)
    D[..., 0] = 0.0
    D[..., 1] = -T[..., 2]
    D[..., 2] = T[..., 1]
    return D


def next_entry(T: np.ndarray, theta: float, tol, skipped: bool = False):
    """Per row of T, the first angle >= ``theta`` where ``g = c0 + cs sin + cc cos`` enters the
    arc where it is below ``-tol`` (inf when it never is).

    ``g = c0 + R sin(x)``, ``x = θ + ψ``, is negative on the arc centred at ``x = 3π/2`` of
    half-width ``h = 2 asin(sqrt(depth / 2R))``, depth = R - c0 (written so that a shallow arc
    keeps its digits). A dip shallower than ``tol`` (a touch) is not an entry. When θ is in the
    first half of the arc (g falling or at its minimum) the entry is ``theta`` itself; in the
    second half g is rising back and, unless it is still below ``-tol``, the next entry is one
    period on; c0 <= -R (negative everywhere) enters at theta. With ``skipped``, also returns
    the deepest dip not treated as an entry, as a fraction of ``tol`` times ``REL`` (the
    scale-relative depth).
    """
    from .kernels import entry  # compiled (numba): the event loop's own closed form

    T = np.asarray(T, dtype=float)
    tols = np.broadcast_to(np.asarray(tol, dtype=float), (T.shape[0],))
    out = np.empty(T.shape[0])
    deepest = 0.0
    for i, (c0, cs, cc) in enumerate(T):
        out[i], ratio = entry(c0, cs, cc, float(theta), float(tols[i]))
        deepest = max(deepest, ratio)
    return (out, deepest * REL) if skipped else out


def segment_dissipation(b: np.ndarray, U: np.ndarray, sign: np.ndarray, a, e: float) -> float:
    """``Σ_i sign_i ∫_{a_i}^e b_i(θ) du_i/dθ dθ`` for triples b (bounds) and U (displacements):
    the dissipation of slipping nodes from their angles ``a`` (scalar or per row) to ``e``, in
    closed form.

    With ``b = b0 + bs S + bc C`` and ``du = us C - uc S``::

        ∫ b du = b0 (us ΔS + uc ΔC) + (bs us - bc uc) Δ(S²)/2 + (bc us - bs uc) Δθ/2
                 + (bc us + bs uc) Δ(sin 2θ)/4

    each difference written with half-angles (``ΔS = 2 cos m sin h``, ...) to keep the digits of
    short segments.
    """
    from .kernels import segment  # compiled (numba): the event loop's own closed form

    a = np.broadcast_to(np.asarray(a, dtype=float), (b.shape[0],))
    return float(sum(s * segment(bi, ui, ai, e) for s, bi, ui, ai in zip(sign, b, U, a)))


def multiplier(K):
    """``x -> K @ x``, through a sparse copy of K when it is mostly zeros (a chain)."""
    n = K.shape[0]
    if n >= 400 and np.count_nonzero(K) <= 0.05 * n * n:
        import scipy.sparse as sp

        Ks = sp.csr_matrix(K)
        return Ks.__matmul__
    return K.__matmul__
