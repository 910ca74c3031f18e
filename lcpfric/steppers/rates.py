r"""The rate problem at an instant, the kernel of every stepper that locates events: the slip
rates of the nodes on their friction limits (:func:`slip_rates`), the instants where sticking
nodes reach their limits with those rates held (:func:`limit_crossings`), and, for the steppers
that solve whole increments (the convex backends, ``active-set``), whether an increment's answer
is exact and where its first event lies (:func:`path_is_exact`, :func:`first_event`).

The slip-rate problem
---------------------
For the nodes on the friction limit the slip rates solve a linear complementarity problem
``λ >= 0, Mλ + q >= 0, λ·(Mλ + q) = 0`` with ``M = D S D`` (S the Schur complement of K on the
nodes that are not stuck, D their slip signs). K is positive definite, so M is a P-matrix and
the LCP has exactly one solution (:func:`~lcpfric.steppers.lcp.solve_lcp`, warm-started from
the current slip set). The explicit stepper (:mod:`.explicit`) and the exact event-driven
solver (:mod:`lcpfric.exact.discrete`) decide the states after an event with it.
Events inside an increment: when one projection is exact, and where to split when it is not.

Why one projection per step is first order on coupled systems
-------------------------------------------------------------
For loads interpolated linearly over an increment, the evolution is piecewise linear: with the
slip pattern (which nodes slip, in which direction) fixed, forces, displacements and Coulomb
margins are linear in time, and the pattern changes only at *events*, where a sticking node
reaches its limit. Problem (P) (:mod:`~lcpfric.backends.problem`) returns the state at the end
of the increment that a path with the *end* pattern held throughout would reach. That path is
the exact one (the evolution has one solution) as soon as it is admissible: every node on its
limit at the end (and every node that separates at the end) must already be on that limit at
the start. Otherwise some node reaches its limit inside the increment, at an event, and there

* a node that was slipping may stop (on a coupled system a node starting to slip changes the
  slip rates of the others, possibly to zero): the projection keeps it at its start displacement
  and misses the slip it made before the event, an error O(h) in u on that step, which it keeps
  while it sticks. Measured on a 3-node chain with separation and on a dense 5-node K: one
  step per cycle with a local error of 1e-4 (3e-6 on the dense K) in u that does not shrink
  faster than h, and W converging at first order;
* with no node stopping the end state is exact, but the trapezoid of the dissipation misses the
  kink of the path: an O(h²) error per event, which is second order for the cycle.

On a single node or uncoupled nodes a slipping node stops only where its load rate changes
(on the grid), so one projection per step is exact for the state there.

Events inside an increment: the fix, with one convex problem per sub-increment
--------------------------------------------------
When the end pattern is not admissible from the start (:func:`path_is_exact`), the first event
is located exactly (:func:`first_event`: the slip rates at the start from the rate LCP of the
explicit stepper, the Coulomb margins linear in time until a sticking node reaches its limit),
problem (P) is solved to that instant (loads interpolated) and again from there to the end of
the increment, repeated while the rest is not admissible. The dissipation is the sum of the
sub-increments' trapezoids, exact for the piecewise-linear path. The cost is one solve per
event (a few per cycle), plus a comparison of the start and end patterns on every step.
"""

from __future__ import annotations

import numpy as np

from ..errors import SolverError
from ..results import State
from .lcp import solve_lcp

__all__ = [
    "slip_rates",
    "limit_crossings",
    "path_is_exact",
    "first_event",
    "coupled_matrix",
    "REL",
    "EPS8",
]

STICK, FORWARD, BACKWARD, SEPARATION = (
    State.STICK,
    State.FORWARD,
    State.BACKWARD,
    State.SEPARATION,
)
REL = 1e-12  # relative tolerance for "on the friction limit" and for a margin's rate
EPS8 = 8 * np.finfo(float).eps  # an event closer than this (relative) to τ happens at τ
_ON_LIMIT = 1e-10  # a node within this (relative to the force scale) of its limit is on it


def slip_rates(K, f, F0, bound, dQ, dN, sep, was_fwd, was_bwd, touch_lo, touch_hi):
    """Per-node states and displacement rates du (per unit τ) at one instant: the slip-rate
    LCP of the module docstring.

    ``touch_lo``/``touch_hi`` mark nodes whose limit is reached within round-off of this
    instant (treated as on that limit)."""
    n = f.size
    scale = np.abs(F0) + bound
    gtol = REL * scale + 1e-300
    on_lo = ~sep & ((F0 <= -bound + gtol) | touch_lo)
    on_hi = ~sep & ((F0 >= bound - gtol) | touch_hi)
    both = on_lo & on_hi  # at re-contact (N = 0): the sign is decided below
    B = on_lo | on_hi
    s = np.where(on_lo & ~on_hi, 1.0, np.where(on_hi & ~on_lo, -1.0, 0.0))
    Z = sep
    if both.any():
        # sign from the force rate with every limit node stuck
        du0 = np.zeros(n)
        if Z.any():
            du0[Z] = -np.linalg.solve(K[np.ix_(Z, Z)], dQ[Z])
        dF0 = dQ + K @ du0
        s[both] = np.where(dF0[both] < 0.0, 1.0, -1.0)
    du = np.zeros(n)
    state = np.where(sep, SEPARATION, STICK).astype(np.int8)
    for _attempt in range(n + 2):
        if not B.any():
            if Z.any():
                du[Z] = -np.linalg.solve(K[np.ix_(Z, Z)], dQ[Z])
            return du, state
        Bi = np.nonzero(B)[0]
        Zi = np.nonzero(Z)[0]
        KBB = K[np.ix_(Bi, Bi)]
        if Zi.size:
            KZZ = K[np.ix_(Zi, Zi)]
            KZB = K[np.ix_(Zi, Bi)]
            X = np.linalg.solve(KZZ, np.column_stack([KZB, dQ[Zi]]))
            S = KBB - K[np.ix_(Bi, Zi)] @ X[:, :-1]
            qp = dQ[Bi] - K[np.ix_(Bi, Zi)] @ X[:, -1]
        else:
            S, qp = KBB, dQ[Bi]
        D = s[Bi]
        M = D[:, None] * S * D[None, :]
        q = f[Bi] * dN[Bi] + D * qp
        warm = np.where(D > 0, was_fwd[Bi], was_bwd[Bi])
        lam = solve_lcp(M, q, basis=warm)
        du[:] = 0.0
        du[Bi] = D * lam
        if Zi.size:
            du[Zi] = -(X[:, -1] + X[:, :-1] @ du[Bi])
        slip = lam > 0.0
        state[Bi[slip & (D > 0)]] = FORWARD
        state[Bi[slip & (D < 0)]] = BACKWARD
        # a re-contact node that sticks must also respect the limit on its other side
        dF = dQ + K @ du
        flip = both & (state == STICK) & (f * dN - s * dF < -REL * (np.abs(f * dN) + np.abs(dF)))
        if not flip.any():
            return du, state
        s[flip] = -s[flip]
        state[:] = np.where(sep, SEPARATION, STICK)
    raise SolverError(
        "explicit stepper: could not decide the slip directions at re-contact",
        backend="explicit",
        status="recontact_sign",
    )


def limit_crossings(K, f, F0, bound, dQ, dN, du, node_state, tau, dF=None):
    """Per node, the instant (fraction of the increment, 2 for never) where a sticking node
    reaches its upper and its lower friction limit, the rates ``du`` held from ``tau``: the
    margins ``f N ∓ F`` are linear in time, so the instants are exact. Returns (upper, lower).
    ``dF``, the force rates ``dQ + K du``, when the caller has them.
    """
    if dF is None:
        dF = dQ + K @ du
    stick = node_state == STICK
    rtol = REL * (np.abs(f * dN) + np.abs(dF)) + 1e-300
    gtol = REL * (bound + np.abs(F0))
    events = []
    with np.errstate(divide="ignore", invalid="ignore"):
        for g, r in ((bound - F0, f * dN - dF), (bound + F0, f * dN + dF)):
            hit = stick & (r < -rtol) & (g > gtol)
            events.append(np.where(hit, tau + g / -r, 2.0))
    return events


def path_is_exact(F_start, b_start, F_end, limit, separating, fscale: float) -> bool:
    """Whether the projection's answer over a (sub-)increment is the exact end state: every
    node on its limit at the end (``limit``, with the sign of ``F_end``) is on that limit at
    the start, and so is every node that separates at the end (either limit)."""
    tol = _ON_LIMIT * fscale
    if limit.any():
        side = np.sign(F_end[limit])
        if not np.all(side * F_start[limit] >= b_start[limit] - tol):
            return False
    if separating is not None and separating.any():
        if not np.all(np.abs(F_start[separating]) >= b_start[separating] - tol):
            return False
    return True


def first_event(K, f, F0, Q0, N0, dQ, dN, sep, tau: float, rates=None):
    """The first instant in ``(tau, 1)`` (fraction of the increment) where a sticking node
    reaches its friction limit, starting at ``tau`` from the forces ``F0`` (loads
    ``Q0 = Q(tau)``, ``N0 = N(tau)``; rates ``dQ``, ``dN`` per unit fraction), or None.

    The slip rates at ``tau`` solve the rate problem: by default the slip-rate LCP
    (:func:`slip_rates`, one copy); ``rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi) -> (du,
    node states, force rates dQ + K du)`` replaces it (the active-set backend solves it with its
    own iteration; K is then not used, and may be None for a matrix-free system). A fourth
    item, when ``rates`` returns one, is the normal reactions' rate with the slips (a coupled
    system, ``dN + B du``: the convex backends' coupled increments). With the rates fixed every
    Coulomb margin is linear, so the instant is exact."""
    n = f.size
    bound = f * N0
    near = REL * (bound + np.abs(F0)) + 1e-300
    was_fwd = ~sep & (F0 <= -bound + near)
    was_bwd = ~sep & (F0 >= bound - near)
    touch_lo = touch_hi = np.zeros(n, dtype=bool)
    for _ in range(n + 2):
        if rates is None:
            du, state = slip_rates(
                K, f, F0, bound, dQ, dN, sep, was_fwd, was_bwd, touch_lo, touch_hi
            )
            dF, dNu = None, dN
        else:
            du, state, dF, *rest = rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi)
            dNu = rest[0] if rest else dN  # a coupled system's N moves with the slips
        events = limit_crossings(K, f, F0, bound, dQ, dNu, du, state, tau, dF)
        t_end = min(float(np.min(events[0])), float(np.min(events[1])))
        now = tau + EPS8 * max(1.0, tau)
        if t_end <= now:  # limits reached within round-off of tau: decide those nodes at tau
            touch_hi, touch_lo = events[0] <= now, events[1] <= now
            continue
        return t_end if t_end < 1.0 else None
    return None


def coupled_matrix(K, B, f, F0, bound, touch_lo, touch_hi):
    """``K + diag(s f) B`` with s = +1 on the nodes on their lower limit (forward slip,
    ``F = -f N``), -1 on the upper, 0 elsewhere: the rate problem's matrix of a coupled system
    on the rows on a limit (the other rows are not used).

    Parameters
    ----------
    K, B : (n, n) ndarray
        Stiffness and coupling block.
    f, F0, bound : (n,) ndarray
        Friction coefficients, forces and limits ``f N`` at the instant.
    touch_lo, touch_hi : (n,) bool ndarray
        Nodes reaching their lower / upper limit within round-off of the instant.

    Returns
    -------
    (n, n) ndarray
        The matrix.
    """
    gtol = REL * (np.abs(F0) + bound) + 1e-300
    s = np.where((F0 <= -bound + gtol) | touch_lo, 1.0, 0.0)
    s = np.where((F0 >= bound - gtol) | touch_hi, -1.0, s)
    return K + (s * f)[:, None] * B
