"""Compiled kernels of the half-space's normal problem (numba): the vector work of one
iteration of Polonsky and Keer's constrained conjugate gradients
(:func:`lcpfric.model.continuum.normal3d.normal_contact`) between its two FFT products.

Imported when a normal problem is first solved, never by ``import lcpfric``; compiled on first
use and cached on disk (``cache=True``). Each kernel does what the numpy expressions it
replaced did, element by element with the same operations; the means, sums and inner products
over the contact are summed in order, where numpy summed pairwise or by BLAS, so they differ
from those in the last bits (``tests/test_halfspace_kernels.py`` checks them against the numpy
expressions). The arrays are ``(N, N)``, of any layout (the products' answers are views).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["gaps", "direction", "update"]


@njit(cache=True, nogil=True)
def gaps(g0, u, p, zz):  # pragma: no cover - compiled
    """The gaps ``g = g0 + u − ḡ`` (ḡ: the mean of ``g0 + u`` over the contact, ``p > 0``), a
    new array, and ``zz`` their copy on the contact, zero elsewhere (in place)."""
    n0, n1 = g0.shape
    g = np.empty((n0, n1))
    s = 0.0
    count = 0
    for i in range(n0):
        for j in range(n1):
            v = g0[i, j] + u[i, j]
            g[i, j] = v
            if p[i, j] > 0.0:
                s += v
                count += 1
    gbar = s / count
    for i in range(n0):
        for j in range(n1):
            g[i, j] -= gbar
            zz[i, j] = g[i, j] if p[i, j] > 0.0 else 0.0
    return g


@njit(cache=True, nogil=True)
def _contact_mean(x, p):  # pragma: no cover - compiled
    """The mean of x over the contact (the elements where p > 0), summed row by row."""
    s = 0.0
    count = 0
    for i in range(p.shape[0]):
        for j in range(p.shape[1]):
            if p[i, j] > 0.0:
                s += x[i, j]
                count += 1
    return s / count


@njit(cache=True, nogil=True)
def direction(g, zz, p, t, G_old, restart, precondition):  # pragma: no cover - compiled
    """The search direction t on the contact (zero elsewhere; in place) from the
    preconditioned gaps z (``zz`` less its mean over the contact; the gaps themselves without
    ``precondition``), conjugate to the last one unless ``restart``: returns ``G = g · z``."""
    n0, n1 = g.shape
    zbar = _contact_mean(zz, p) if precondition else 0.0
    G = 0.0
    for i in range(n0):
        for j in range(n1):
            if p[i, j] > 0.0:
                z = zz[i, j] - zbar if precondition else g[i, j]
                G += g[i, j] * z
    beta = G / G_old
    for i in range(n0):
        for j in range(n1):
            if p[i, j] > 0.0:
                z = zz[i, j] - zbar if precondition else g[i, j]
                t[i, j] = z if restart else z + beta * t[i, j]
            else:
                t[i, j] = 0.0
    return G


@njit(cache=True, nogil=True)
def update(At, g, p, t, u, P, area):  # pragma: no cover - compiled
    """The step along t (``At = A t``): ``(status, change, restart, fresh)``. Status 0: the
    curvature ``(At − its mean on the contact) · t`` is not positive (nothing changed);
    else the pressures p step by ``−τ t`` on the contact, are clipped at zero, the
    penetrating elements enter (``p −= τ g`` where ``p = 0`` and ``g < 0``: ``restart``),
    and are rescaled to the load P, in place; ``change``: ``area Σ|Δp| / P``. ``fresh``:
    whether u must be recomputed (elements left or entered the contact), else u becomes
    ``(u − τ At) × factor`` in place."""
    n0, n1 = p.shape
    mean = _contact_mean(At, p)
    denom = 0.0
    num = 0.0
    for i in range(n0):
        for j in range(n1):
            if p[i, j] > 0.0:
                denom += (At[i, j] - mean) * t[i, j]
                num += g[i, j] * t[i, j]
    if denom <= 0.0:
        return 0, 0.0, True, True
    tau = num / denom
    p_old = p.copy()
    clipped = False
    restart = False
    total = 0.0
    for i in range(n0):
        for j in range(n1):
            v = p[i, j]
            if v > 0.0:
                v -= tau * t[i, j]
            if v < 0.0:
                v = 0.0
                clipped = True
            if v == 0.0 and g[i, j] < 0.0:
                v -= tau * g[i, j]
                restart = True
            p[i, j] = v
            total += v
    factor = P / (area * total)
    change = 0.0
    for i in range(n0):
        for j in range(n1):
            p[i, j] *= factor
            change += abs(p[i, j] - p_old[i, j])
    fresh = restart or clipped
    if not fresh:
        for i in range(n0):
            for j in range(n1):
                u[i, j] = (u[i, j] - tau * At[i, j]) * factor
    return 1, area * change / P, restart, fresh
