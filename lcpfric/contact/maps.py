r"""Dissipation maps of the Hertz contact: by MDR (many load cases advanced together) and by
the half-space boundary elements (:func:`halfspace_W_normalized`, point by point, the normal
problem shared by the points of one P̂1).

:func:`mdr_W_normalized` evaluates ``W k_t0 / (μ² P0²)`` of the MDR sphere
(:class:`~lcpfric.contact.mdr.MDRSphere`) at many points ``(P̂1, Q̂1, φ)`` = ``(P1/P0,
Q1/(μ P0), φ)`` at once, for :func:`lcpfric.analysis.sweep.sweep` (local processes or Dask,
resumable). In these units the answer depends on nothing else: with ``P0 = μ = k_t0 = 1`` and
lengths in units of a0 = a(P0), the spring normal forces are ``N_i = (3/2) ∫_cell (a² - x²) dx``
with ``a = P^(1/3)``, the spring stiffnesses ``k_i = Δx`` (so ``Σ k_i = 1`` at a0), and the
support stiffness is given as ``k_support / k_t0``.

Each increment is the MDR increment (:func:`~lcpfric.contact.mdr.bar_increment`, the one the
model uses), here for all points together. The result equals :meth:`MDRSphere.solve` on the same grid to round-off
(``tests/test_contact_maps.py``). Under pure load control (``k_support = 0``) a point whose loads
have ``|Q| > μ P`` at some instant has no equilibrium: its value is NaN.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _checks
from ..errors import InputError
from ..periodic import cycle_change
from .mdr import bar_increment
from .steady import steady_state

__all__ = ["mdr_W_normalized", "halfspace_W_normalized", "gross_sliding_points"]

_SAMPLES = 20001


def gross_sliding_points(P1, Q1, phi, reach: bool = False) -> np.ndarray:
    """Which points have ``|Q̂1 sin(θ + φ)| > 1 + P̂1 sin θ`` at some θ (normalized units);
    with ``reach``, those where it reaches it (to 1e-9: d = 2, where the body then drifts
    across the load, :func:`~lcpfric.contact.steady.gross_sliding`)."""
    theta = np.linspace(0.0, 2 * math.pi, _SAMPLES)
    out = np.zeros(np.shape(P1), dtype=bool)
    for i in range(0, out.size, 256):
        sl = slice(i, min(i + 256, out.size))
        P = 1.0 + P1[sl, None] * np.sin(theta)
        Q = np.abs(Q1[sl, None] * np.sin(theta + phi[sl, None]))
        margin = -1e-9 if reach else 1e-12 * (1.0 + Q)
        out[sl] = np.any(Q > np.maximum(P, 0.0) + margin, axis=1)
    return out


def _points(P1, Q1, phi, steps_per_cycle, k_support, reach=False):
    """The points as flat arrays, the checked steps and support, the output (NaN where pure
    load control has no equilibrium, 0 where Q̂1 = 0) and the points left to compute."""
    P1, Q1, phi = (np.atleast_1d(np.asarray(x, dtype=float)).ravel() for x in (P1, Q1, phi))
    steps = _checks.positive_int("steps_per_cycle", steps_per_cycle, 4)
    ks = _checks.nonnegative("k_support", k_support)
    if not (P1.size == Q1.size == phi.size):
        raise InputError("P1", "P1, Q1 and phi must have one value per point")
    out = np.zeros(P1.size)
    run = Q1 > 0
    if ks == 0.0:
        bad = gross_sliding_points(P1, Q1, phi, reach)
        out[bad] = np.nan
        run &= ~bad
    return P1, Q1, phi, steps, ks, out, run


def mdr_W_normalized(P1, Q1, phi, *, nodes: int = 200, steps_per_cycle: int = 200,
                     k_support: float = 0.0, tol: float = 1e-8, max_cycles: int = 200):
    """``W k_t0 / (μ² P0²)`` of the MDR sphere at the points ``(P1, Q1, phi)`` (flat arrays of
    P̂1, Q̂1 and φ); ``k_support`` in units of k_t0. NaN where pure load control has no
    equilibrium; 0 where Q̂1 = 0."""
    nodes = _checks.positive_int("nodes", nodes)
    tol = _checks.positive("tol", tol)
    max_cycles = _checks.positive_int("max_cycles", max_cycles)
    P1, Q1, phi, steps, ks, out, run = _points(P1, Q1, phi, steps_per_cycle, k_support)
    idx = np.flatnonzero(run)
    if idx.size:
        out[idx] = _batch(P1[idx], Q1[idx], phi[idx], nodes, steps, ks, tol, max_cycles)
    return out


def _batch(P1, Q1, phi, n, steps, ks, tol, max_cycles):
    m = P1.size
    a_max = (1.0 + P1) ** (1.0 / 3.0)                       # (m,)
    dx = a_max / n
    x = (np.arange(n)[None, :] + 0.5) * dx[:, None]         # (m, n)
    k = dx[:, None] * np.ones((1, n))
    theta = np.linspace(0.0, 2 * math.pi, steps + 1)
    P = np.maximum(1.0 + P1[:, None] * np.sin(theta)[None, :], 0.0)    # (m, steps + 1)
    Q = Q1[:, None] * np.sin(theta[None, :] + phi[:, None])
    a = P ** (1.0 / 3.0)
    lo_x, hi_x = x - 0.5 * dx[:, None], x + 0.5 * dx[:, None]
    lo_cube = lo_x * lo_x * lo_x / 3.0

    def limits(j):
        """(3/2) ∫ (a² - x²) dx over each cell's part inside the contact (powers by products:
        ``**`` is several times slower)."""
        aj = a[:, j][:, None]
        hi = np.minimum(hi_x, aj)
        val = aj * aj * (hi - lo_x) - (hi * hi * hi / 3.0 - lo_cube)
        return np.where(hi > lo_x, 1.5 * val, 0.0)

    v = np.zeros((m, n))
    u = np.zeros(m)
    F = np.zeros((m, n))
    prev = None
    W = np.zeros(m)
    active = np.ones(m, dtype=bool)
    result = np.full(m, np.nan)
    scales = (Q1, 1.0 + P1)
    for _ in range(max_cycles):
        v0 = v.copy()
        vmin, vmax = v.copy(), v.copy()
        W = np.zeros(m)
        for j in range(steps):
            b = limits(j + 1)
            u, F1, v1 = bar_increment(v, u, k, b, Q[:, j + 1], ks)
            dv = v1 - v
            share = -0.5 * (F + F1) * dv
            W += np.where(share > 0.0, share, 0.0).sum(axis=1)
            F, v = F1, v1
            np.minimum(vmin, v, out=vmin)
            np.maximum(vmax, v, out=vmax)
        if prev is not None:
            change = cycle_change(np.max(np.abs(v - v0), axis=1), np.max(vmax - vmin, axis=1),
                                  W - prev, W, scales)
            done = active & (change <= tol)
            result[done] = W[done]
            active &= ~done
            if not active.any():
                break
        prev = W
    result[active] = W[active]  # not converged in max_cycles: the last cycle's W
    return result


def halfspace_W_normalized(P1, Q1, phi, *, grid: int = 20, dims: int = 1, nu: float = 0.0,
                           steps_per_cycle: int = 100, k_support: float = 0.0,
                           tol: float = 1e-8, max_cycles: int = 200):
    """``W k_t0 / (μ² P0²)`` of the sphere on the half-space
    (:class:`~lcpfric.contact.halfspace.HalfSpace`) at the points ``(P1, Q1, phi)`` (flat
    arrays of P̂1, Q̂1, φ), ``grid`` elements across the largest contact, ``k_support`` in
    units of k_t0. The points of one P̂1 share one model, so the normal problem of each instant
    is solved once. NaN where pure load control has no equilibrium (with d = 2, also where |Q|
    reaches μP: the body drifts across the load); 0 where Q̂1 = 0."""
    from ..model.loads import Harmonic
    from .halfspace import HalfSpace

    P1, Q1, phi, steps, ks, out, run = _points(P1, Q1, phi, steps_per_cycle, k_support,
                                               reach=dims == 2)
    two_pi = 2.0 * math.pi
    for p1 in np.unique(P1[run]):
        idx = np.flatnonzero(run & (P1 == p1))
        # P0 = μ = 1, R = E = 1: W k_t0 / (μ² P0²) does not depend on them
        model = HalfSpace.sphere(1.0, 1.0, nu, 1.0, Harmonic(1.0, p1, 0.0, two_pi),
                                 Harmonic(0.0, 1.0, 0.0, two_pi), grid=grid, dims=dims)
        model.k_support = ks * model.k_t0
        for i in idx:
            model.Q = Harmonic(0.0, float(Q1[i]), float(phi[i]), two_pi)
            out[i] = steady_state(model, steps, tol=tol, max_cycles=max_cycles,
                                  on_nonconvergence="warn").W_normalized
    return out
