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
With a coupling block (``N = P + B v``, :mod:`lcpfric.model.coupling`) the nodes no longer
decouple and the safe state is a linear program over the cycle's instants (HiGHS); it then
means only that *some* start shakes down (the safe state itself): Melan's theorem does not
hold for coupled systems. A node that separates carries no force while separated, so it
sticks at a constant displacement only if its tangential load does not change while it is out
of contact: its band is then empty (a negative margin), as for the single node.

The extrema are taken on ``samples`` instants of the cycle and refined by the parabola through
each extreme sample and its neighbours (an error of the order of ``(2π / samples)⁴`` of the
amplitude for smooth loads: 5e-12 at the default 4096).
"""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["safe_band"]


def _parabola(g: np.ndarray):
    """Per column of periodic samples g (rows): the smallest sample's row, the vertex of the
    parabola through it and its two neighbours as an offset in samples (|offset| <= 1/2), and
    the vertex's value (the sample's where the parabola does not open upwards)."""
    k = np.argmin(g, axis=0)
    cols = np.arange(g.shape[1])
    s = g.shape[0]
    a, b, c = g[(k - 1) % s, cols], g[k, cols], g[(k + 1) % s, cols]
    curv = a - 2.0 * b + c
    up = curv > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        offset = np.where(up, 0.5 * (a - c) / curv, 0.0)
        value = np.where(up, b - (c - a) ** 2 / (8.0 * curv), b)
    return k, offset, value


def _extreme(values: np.ndarray, kind: str) -> np.ndarray:
    """Per column, the minimum (``kind="min"``) or maximum of periodic samples (rows), refined
    by the parabola through the extreme sample and its two neighbours."""
    if kind == "max":
        return -_parabola(-values)[2]
    return _parabola(values)[2]


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
    if system.coupling is not None:
        return _coupled(system, samples)
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


def _vertex_times(g: np.ndarray, t: np.ndarray, dt: float) -> np.ndarray:
    """Per column of periodic samples g (rows at the instants t, spacing dt), the instant of
    the parabola's vertex through the smallest sample and its neighbours."""
    k, offset, _ = _parabola(g)
    return t[k] + offset * dt


def _coupled(system, samples: int):
    """The safe state of a coupled system (``N = P(t) + B v``): the nodes no longer decouple,
    so the largest margin ``α`` with ``|Q_i + y_i| + α S_i <= f_i (P_i + (B K⁻¹ y)_i)`` at every
    instant (``y = K v``, ``S_i = f_i mean P_i``) is a linear program over the cycle's instants
    (scipy's HiGHS), refined by adding each node's most violated instants (of a fine grid, and
    between its points, at the parabola's vertex) until none is violated beyond round-off.
    Returns (safe, margin, v or None, margins): the margins are twice each node's least slack
    over the cycle at the state found, in units of S_i (its band's width for an uncoupled
    node), and the margin is ``2 α``."""
    from scipy.optimize import linprog

    from ..errors import SolverError

    n, K, B, f = system.n, system.dense_stiffness(), system.coupling, system.friction
    M = B @ np.linalg.inv(K)
    period = system.period
    dt = period / samples
    t_fine = np.arange(samples) * dt
    P_fine = system.normal.loads_at(t_fine)
    S = f * np.mean(P_fine, axis=0)
    if np.any(S <= 0):
        raise InputError("normal_loads", "a coupled system's safe state needs mean P_i > 0")
    Q_fine = system.tangential(t_fine)
    scale = float(np.max(np.abs(Q_fine)) + np.max(f * np.abs(P_fine)))
    ts = t_fine[:: max(1, samples // 256)]
    upper = np.hstack([np.eye(n) - f[:, None] * M, S[:, None]])  # Q + y side
    lower = np.hstack([-np.eye(n) - f[:, None] * M, S[:, None]])  # -(Q + y) side
    c = np.zeros(n + 1)
    c[-1] = -1.0

    def slacks(t, y, alpha):
        N = system.normal.loads_at(t) + (M @ y)[None, :]
        F = system.tangential(t) + y[None, :]
        return f * N - F - alpha * S, f * N + F - alpha * S

    for _ in range(60):
        P, Q = system.normal.loads_at(ts), system.tangential(ts)
        A = np.vstack([np.tile(upper, (ts.size, 1)), np.tile(lower, (ts.size, 1))])
        b = np.concatenate([(f * P - Q).ravel(), (f * P + Q).ravel()])
        bounds = [(None, None)] * n + [(None, 10.0)]
        res = linprog(c, A_ub=A, b_ub=b, bounds=bounds, method="highs")
        if res.status != 0:
            raise SolverError(
                f"shakedown: the safe-state linear program failed: {res.message}",
                backend="highs",
                status=str(res.status),
            )
        y, alpha = res.x[:n], float(res.x[n])
        new = []
        for side, g in enumerate(slacks(t_fine, y, alpha)):
            tv = np.mod(_vertex_times(g, t_fine, dt), period)
            gv = np.diagonal(slacks(tv, y, alpha)[side])  # node i at its own vertex tv[i]
            new.append(tv[gv < -1e-13 * scale])
            new.append(t_fine[np.argmin(g, axis=0)][np.min(g, axis=0) < -1e-13 * scale])
        new = np.concatenate(new)
        if new.size == 0:
            break
        ts = np.unique(np.concatenate([ts, new]))
    else:
        raise SolverError(
            f"shakedown: the safe-state linear program still violates its constraints between "
            f"its {ts.size} instants after 60 refinements",
            backend="highs",
            status="not_refined",
        )
    least = []
    for side, g in enumerate(slacks(t_fine, y, 0.0)):
        tv = np.mod(_vertex_times(g, t_fine, dt), period)
        least.append(np.minimum(np.min(g, axis=0), np.diagonal(slacks(tv, y, 0.0)[side])))
    margins = 2.0 * np.minimum(*least) / S
    ok = bool(np.min(margins) >= 0.0)
    return ok, 2.0 * alpha, (np.linalg.solve(K, y) if ok else None), margins
