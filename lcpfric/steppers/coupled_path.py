r"""The path of one increment of a coupled system (``N = P(t) + B u``, d = 1), shared by the
steppers that solve whole increments: the convex backends (:mod:`lcpfric.backends.coupled`, a
fixed point of problem (P) on the normal reactions) and ``active-set``
(:mod:`.active_set_coupled`, the coupled pattern iteration). They differ only in how the end
state of a (piece of an) increment is found; the path is this one copy.

With the loads interpolated linearly over an increment and the stick/slip pattern fixed, u, F
and N are linear in time. An end state whose pattern is admissible from the start of the piece
(:func:`~lcpfric.steppers.rates.path_is_exact`, with the limits ``f (P + B u)`` at both ends)
is the exact end state. Otherwise the first event is located from the coupled rate problem at
the start (:func:`coupled_rates`: the rate LCP with ``K + diag(s f) B`` on the rows on a limit,
as the explicit stepper solves it, and the normal reactions' rate ``dP + B du`` in the
margins), the end state is solved to it, and again from there. The dissipation is the sum of
the pieces' trapezoids ``-½ (F_a + F_b)·(u_b - u_a)``, exact on the linear pieces.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .dissipation import increment_dissipation
from .rates import REL, coupled_matrix, first_event, path_is_exact, slip_rates

__all__ = ["coupled_rates", "coupled_path", "pattern_point", "compressed"]


def coupled_rates(K, B, f):
    """The rate problem of a coupled system, for :func:`~lcpfric.steppers.rates.first_event`.

    Parameters
    ----------
    K, B : (n, n) ndarray
        Stiffness and coupling block.
    f : (n,) ndarray
        Friction coefficients.

    Returns
    -------
    callable
        ``rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi) -> (du, states, dF, dN_u)``: the
        slip rates from the rate LCP with the coupled matrix, the node states, the force rates
        ``dQ + K du`` and the normal reactions' rates ``dN + B du``.
    """

    def rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi):
        near = REL * (bound + np.abs(F0)) + 1e-300
        Kr = coupled_matrix(K, B, f, F0, bound, touch_lo, touch_hi)
        du, st = slip_rates(
            Kr, f, F0, bound, dQ, dN, sep, F0 <= -bound + near, F0 >= bound - near,
            touch_lo, touch_hi,
        )  # fmt: skip
        return du, st, dQ + K @ du, dN + B @ du

    return rates


def coupled_path(K, B, f, loads, u, F, end_state, locate: bool, force_scale: float, stats):
    """One increment of a coupled system from ``(u, F)``, split at its events.

    Parameters
    ----------
    K, B : (n, n) ndarray
        Stiffness and coupling block.
    f : (n,) ndarray
        Friction coefficients.
    loads : tuple of (n,) ndarray
        ``(Q_k, P_k, ΔQ, ΔP)``: the loads at the start of the increment and their changes over
        it (P the normal loads, not clipped).
    u, F : (n,) ndarray
        Displacements and forces at the start.
    end_state : callable
        ``end_state(u_a, frac) -> (u, F, limit)``: the end state at the fraction ``frac`` of the
        increment from ``u_a`` (``limit`` the nodes on a friction limit there, or None for an
        answer whose pattern is not known).
    locate : bool
        Split at events (else one end state per increment).
    force_scale : float
        The scale of the forces (the tolerance of "on its limit").
    stats : dict
        Its ``events`` count is raised by the events located.

    Returns
    -------
    tuple
        ``(u, F, W)`` at the end of the increment, W the dissipation of its path.
    """
    Qk, Pk, dQ, dP = loads
    none = np.zeros(f.size, dtype=bool)
    rates = coupled_rates(K, B, f)
    a, ua, Fa = 0.0, u, F
    W = 0.0
    u1, F1, limit = end_state(ua, 1.0)
    for _ in range(4 * f.size + 16):
        Na = Pk + a * dP + B @ ua
        if not locate or limit is None or path_is_exact(Fa, f * Na, F1, limit, None, force_scale):
            break
        tau = first_event(K, f, Fa, Qk + a * dQ, Na, dQ, dP, none, a, rates=rates)
        if tau is None:
            break
        ub, Fb, _ = end_state(ua, tau)
        stats["events"] += 1
        W += increment_dissipation(Fa, Fb, ub - ua)
        a, ua, Fa = tau, ub, Fb
        u1, F1, limit = end_state(ua, 1.0)
    return u1, F1, W + increment_dissipation(Fa, F1, u1 - ua)


def pattern_point(K, B, f, Q, P, ua, sigma, limit):
    """The end state on a stick/slip pattern: the stick nodes at ``ua``, the limit nodes ``i``
    at ``F_i = σ_i f_i (P + B u)_i`` with ``F = Q + K u`` (one linear solve with the rows of
    ``K - diag(σ f) B`` on the limit nodes, a principal submatrix of a P-matrix under
    Klarbring's condition, so nonsingular).

    Parameters
    ----------
    K, B : (n, n) ndarray
        Stiffness and coupling block.
    f : (n,) ndarray
        Friction coefficients.
    Q, P : (n,) ndarray
        The tangential and normal loads at the end.
    ua : (n,) ndarray
        The displacements at the start.
    sigma : (n,) ndarray
        The limit nodes' signs: +1 on the upper limit ``F = +f N`` (backward slip), -1 on the
        lower (forward slip); read only on ``limit``.
    limit : (n,) bool ndarray
        The nodes on a limit.

    Returns
    -------
    (n,) ndarray or None
        The displacements, or None when the solve fails (a singular block).
    """
    L = np.flatnonzero(limit)
    S = np.flatnonzero(~limit)
    u = ua.copy()
    if not L.size:
        return u
    sf = sigma[L] * f[L]
    A = K[np.ix_(L, L)] - sf[:, None] * B[np.ix_(L, L)]
    rhs = sf * (P[L] + B[np.ix_(L, S)] @ ua[S]) - Q[L] - K[np.ix_(L, S)] @ ua[S]
    try:
        u[L] = np.linalg.solve(A, rhs)
    except np.linalg.LinAlgError:
        return None
    return u


def compressed(N, t: float):
    """A coupled system's normal reactions ``N = P + B u`` at the instant t, or
    :class:`~lcpfric.errors.InputError` naming the node whose reaction is not a compression and
    the instant (separation of a coupled node is not modelled: it would need its normal
    stiffness).

    Parameters
    ----------
    N : (n,) ndarray
        The normal reactions.
    t : float
        The instant (for the message).

    Returns
    -------
    (n,) ndarray
        N, when every reaction is positive.
    """
    if np.all(N > 0.0):
        return N
    i = int(np.argmin(N))
    raise InputError(
        "normal_loads",
        f"the normal reaction of node {i} reaches zero at t = {t:.12g}: separation of a node "
        "of a coupled system is not modelled",
    )
