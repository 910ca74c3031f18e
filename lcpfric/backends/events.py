r"""Events inside an increment: when one projection is exact, and where to split when it is not.

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

The fix, with one convex problem per sub-increment
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

from ..steppers.explicit import ExplicitStepper, limit_crossings

__all__ = ["path_is_exact", "first_event"]

_REL = 1e-12  # as in the explicit stepper: "on the limit" and "a margin's rate", relative
_EPS8 = 8 * np.finfo(float).eps
_ON_LIMIT = 1e-10  # a node within this (relative to the force scale) of its limit is on it


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

    The slip rates at ``tau`` solve the rate problem: by default the explicit stepper's rate LCP
    (its ``_rates``, one copy); ``rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi) -> (du,
    node states, force rates dQ + K du)`` replaces it (the active-set backend solves it with its
    own iteration; K is then not used, and may be None for a matrix-free system). With
    the rates fixed every Coulomb margin is linear, so the instant is exact."""
    n = f.size
    bound = f * N0
    near = _REL * (bound + np.abs(F0)) + 1e-300
    was_fwd = ~sep & (F0 <= -bound + near)
    was_bwd = ~sep & (F0 >= bound - near)
    touch_lo = touch_hi = np.zeros(n, dtype=bool)
    for _ in range(n + 2):
        if rates is None:
            du, state = ExplicitStepper._rates(K, f, F0, bound, dQ, dN, sep, was_fwd, was_bwd,
                                               touch_lo, touch_hi)
            dF = None
        else:
            du, state, dF = rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi)
        events = limit_crossings(K, f, F0, bound, dQ, dN, du, state, tau, dF)
        t_end = min(float(np.min(events[0])), float(np.min(events[1])))
        now = tau + _EPS8 * max(1.0, tau)
        if t_end <= now:  # limits reached within round-off of tau: decide those nodes at tau
            touch_hi, touch_lo = events[0] <= now, events[1] <= now
            continue
        return t_end if t_end < 1.0 else None
    return None
