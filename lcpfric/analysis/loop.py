"""The hysteresis loop of a steady state: the friction force against the tangential displacement
over the steady cycle, coloured by stick, slip and separation (``lcpfric loop``).

The loop's enclosed area is the dissipation per cycle, ``W = -∮ F dv`` (Eq. 5). For a steady
state of a time stepper the area of the polygon through the grid points is the trapezoidal sum
of the increments (equal to ``W`` up to the per-node clipping of round-off); for the closed form
it is the trapezoidal integral of the exact cycle sampled at the returned instants (second order
in the sampling).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..results import SteadyState

__all__ = ["HysteresisLoop", "hysteresis_loop", "loop_area"]


@dataclass(frozen=True)
class HysteresisLoop:
    """One node's loop over the steady cycle.

    Attributes
    ----------
    v, F : ndarray
        Tangential displacement and friction force at the cycle's instants (model units).
    state : ndarray of int8
        :class:`~lcpfric.results.State` over the increment ending at each instant.
    area : float
        ``-∮ F dv`` of the polygon (trapezoidal), the node's dissipation per cycle.
    W : float
        The steady state's dissipation per cycle (all nodes), for comparison.
    node : int
        Which node (0 for a single node).
    """

    v: np.ndarray
    F: np.ndarray
    state: np.ndarray
    area: float
    W: float
    node: int = 0


def loop_area(v, F) -> float:
    """``-∮ F dv`` over a closed sampled cycle: ``-Σ ½ (F_k + F_k+1)(v_k+1 - v_k)``."""
    v = np.asarray(v, dtype=float)
    F = np.asarray(F, dtype=float)
    return float(-np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(v)))


def hysteresis_loop(result: SteadyState, node: int = 0) -> HysteresisLoop:
    """The loop (F against v) of ``node`` in a steady state (any method, any system).

    For d = 2 the loop of the node's first tangential direction is returned (its area is then
    that direction's share of the node's dissipation).
    """
    if not isinstance(result, SteadyState):
        raise InputError(
            "result", f"expected a SteadyState (lcpfric.steady_state), got {type(result).__name__}"
        )
    v, F, state = np.asarray(result.v), np.asarray(result.F), np.asarray(result.state)
    if v.ndim == 1:
        if node != 0:
            raise InputError("node", f"a single node has node 0 only, got {node!r}")
        return HysteresisLoop(v, F, state, loop_area(v, F), result.W, 0)
    n = state.shape[1]
    if not isinstance(node, (int, np.integer)) or isinstance(node, bool) or not 0 <= node < n:
        raise InputError("node", f"must be an integer in [0, {n - 1}], got {node!r}")
    d = v.shape[1] // n
    col = node * d
    return HysteresisLoop(
        v[:, col], F[:, col], state[:, node], loop_area(v[:, col], F[:, col]), result.W, int(node)
    )


#: How each state is drawn: (label, colour, line style); greyscale-safe by style.
