"""The dissipation of an increment known by its ends: the one formula every stepper uses.

Over an increment from (u_a, F_a) to (u_b, F_b) the dissipation ``-∫ F · du`` (Eq. 5) is taken
by the trapezoidal rule, ``-½ (F_a + F_b) · (u_b - u_a)``, node by node, with each node's share
clipped at zero:

* it is exact for the piecewise-linear histories the explicit stepper produces between its
  events, and second order for the projection steppers;
* it weighs a slip that ends an increment at separation by the small stick force it started
  from, which a rule in ``f N |Δu|`` would not;
* a node's dissipation is never negative: only at a slip reversal inside an increment can the
  trapezoid dip below zero, by its own discretization error.

:func:`node_shares` is the array form (any leading shape, e.g. all increments of a cycle, or all
points of a batch); :func:`scalar_share` is its twin for one unknown in Python floats, for the
scalar fast paths of the single node (tested equal to the array form).
"""

from __future__ import annotations

import numpy as np

__all__ = ["node_shares", "increment_dissipation", "scalar_share"]


def node_shares(F0, F1, du, dims: int = 1) -> np.ndarray:
    """Each node's clipped trapezoid share ``max(0, -½ (F0 + F1)·du)``.

    ``F0``, ``F1`` and ``du`` have shape ``(..., m)`` with m = n·d; the result ``(..., n)``.
    """
    share = -0.5 * (F0 + F1) * du
    if dims != 1:
        share = share[..., 0::2] + share[..., 1::2]
    return np.maximum(share, 0.0)


def increment_dissipation(F0, F1, du, dims: int = 1) -> float:
    """The dissipation of one increment, or of several (summed): ``Σ node_shares``."""
    return float(node_shares(F0, F1, du, dims).sum())


def scalar_share(F0: float, F1: float, du: float) -> float:
    """:func:`node_shares` of one unknown, in Python floats."""
    share = -0.5 * (F0 + F1) * du
    return share if share > 0.0 else 0.0
