"""Shakedown of a discrete system: does a constant displacement exist under which every node
sticks over the whole cycle (a safe state), and by what margin?

With the normal reactions prescribed (an uncoupled system, paper Eq. 2) the forces of a constant
displacement v are ``F(t) = Q(t) + y`` with ``y = K v``, and K is invertible, so every y is
reachable: the nodes decouple. Node i has a safe y_i exactly when its load band fits::

    lo_i = max_t (-f_i N_i(t) - Q_i(t))  <=  hi_i = min_t (f_i N_i(t) - Q_i(t))

(the single node's test, :func:`lcpfric.analysis.shakedown.shakedown`, node by node), and the
system has a safe state when every node has one; ``v = K⁻¹ y`` with each y_i in the middle of
its range. By Melan's theorem for frictional systems with uncoupled normal reactions (Klarbring,
Barber, Spagnoli and Ciavarella), a safe state with a positive margin means shakedown from every
start: the steady dissipation is then zero whatever the initial state (tested against ``exact``).
A node that separates carries no force while separated, so it sticks at a constant displacement
only if its tangential load does not change while it is out of contact: its band is then empty
(a negative margin), as for the single node.

The extrema are taken on ``samples`` instants of the cycle and refined by the parabola through
each extreme sample and its neighbours (an error of the order of ``(2π / samples)⁴`` of the
amplitude for smooth loads: 5e-12 at the default 4096).
"""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["safe_band"]


def _extreme(values: np.ndarray, kind: str) -> np.ndarray:
    """Per column, the minimum (``kind="min"``) or maximum of periodic samples (rows), refined
    by the parabola through the extreme sample and its two neighbours (kept only where it lies
    beyond the sample, between them)."""
    g = -values if kind == "max" else values
    k = np.argmin(g, axis=0)
    cols = np.arange(g.shape[1])
    s = g.shape[0]
    a, b, c = g[(k - 1) % s, cols], g[k, cols], g[(k + 1) % s, cols]
    curv = a - 2.0 * b + c
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = b - (c - a) ** 2 / (8.0 * curv)
    best = np.where((curv > 0) & (vertex <= b) & (vertex >= b - np.abs(c - a)), vertex, b)
    return -best if kind == "max" else best


def safe_band(system, samples: int = 4096):
    """The safe state of a :class:`~lcpfric.model.ContactSystem` (module docstring), as
    :func:`lcpfric.shakedown` reports it.

    Parameters
    ----------
    system : ContactSystem
        d = 1, any normal model whose reactions do not depend on the displacements, any
        periodic loads.
    samples : int
        Instants of the cycle on which the extrema are taken (then refined), >= 64.

    Returns
    -------
    shakedown : bool
        Whether a safe state exists.
    margin : float
        The narrowest node's band ``hi_i - lo_i`` in units of its mean friction limit
        ``f_i mean(N_i)`` (< 0: none).
    state : ndarray or None
        A safe displacement v (each node's force in the middle of its band), or None.
    margins : ndarray
        Every node's margin.

    Raises
    ------
    InputError
        Not a ContactSystem, d = 2, or ``samples`` out of range.
    """
    from ..model import ContactSystem

    if not isinstance(system, ContactSystem):
        raise InputError("model", f"expected a ContactSystem, got {type(system).__name__}")
    if system.dims != 1:
        raise InputError(
            "dims",
            "the safe state of a system is decided for d = 1 (one tangential direction); "
            "for d = 2 run the steady state (its W is 0 when it shakes down)",
        )
    samples = _checks.positive_int("samples", samples, 64)
    t = np.arange(samples) * (system.period / samples)
    fN = system.friction * system.normal.reactions(t)  # (samples, n)
    Q = system.tangential(t)
    hi = _extreme(fN - Q, "min")
    lo = _extreme(-fN - Q, "max")
    limit = np.mean(fN, axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        margins = np.where(limit > 0, (hi - lo) / limit, -np.inf)
    ok = bool(np.all(margins >= 0.0))
    state = system.solve(0.5 * (lo + hi)) if ok else None
    return ok, float(np.min(margins)), state, margins
