"""The hysteresis loop of a steady state: the friction force against the tangential displacement
over the steady cycle, coloured by stick, slip and separation (``lcpfric loop``).

The loop's enclosed area is the dissipation per cycle, ``W = -∮ F dv`` (Eq. 5). For a steady
state of a time stepper the area of the polygon through the grid points is the trapezoidal sum
of the increments (equal to ``W`` up to the per-node clipping of round-off); for the closed form
it is the trapezoidal integral of the exact cycle sampled at the returned instants (second order
in the sampling).

:func:`state_shares` gives the share of the cycle's *time* each node spends in each state: every
increment's duration counts for the state it ends in (a state series holds the state over the
increment ending at each instant), so a non-uniform grid (the default event-adapted placement,
which may cross a whole separation in one step) weighs its steps by their length; the closed form
of the single node gives the shares exactly, from the instants of its events.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..results import State, SteadyState

__all__ = ["HysteresisLoop", "hysteresis_loop", "loop_area", "state_shares", "time_shares"]


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


def time_shares(t, state) -> dict[State, float]:
    """The share of the time from ``t[0]`` to ``t[-1]`` spent in each state.

    Each increment ``[t[k-1], t[k]]`` counts for ``state[k]``, the state over the increment
    ending at ``t[k]`` (as in every state series of the steppers), so the shares are time shares
    on any grid, uniform or not.

    Parameters
    ----------
    t : array_like
        Increasing instants, at least two.
    state : array_like of int
        The :class:`~lcpfric.results.State` codes at the instants (same length as ``t``).

    Returns
    -------
    dict
        ``{State: share}`` for every state, in the order of :class:`~lcpfric.results.State`; the
        shares add up to 1.

    Raises
    ------
    InputError
        ``t`` not increasing, with fewer than two instants, or not the length of ``state``.

    Examples
    --------
    >>> shares = time_shares([0.0, 1.0, 4.0], [0, 0, 3])
    >>> {s.label: x for s, x in shares.items()}
    {'stick': 0.25, 'forward slip': 0.0, 'backward slip': 0.0, 'separation': 0.75}
    """
    t = np.asarray(t, dtype=float)
    state = np.asarray(state)
    if t.ndim != 1 or t.size < 2 or state.shape != t.shape:
        raise InputError(
            "t",
            f"needs at least two instants and one state at each; got {t.shape} instants and "
            f"{state.shape} states",
        )
    dt = np.diff(t)
    if not np.all(np.isfinite(dt)) or np.any(dt < 0) or t[-1] <= t[0]:
        raise InputError("t", "the instants must be finite and increasing")
    total = float(t[-1] - t[0])
    ends = state[1:]
    return {code: float(dt[ends == code].sum()) / total for code in State}


def state_shares(result: SteadyState, node: int = 0, model=None) -> dict[State, float]:
    """The share of the steady cycle's time that ``node`` spends in each state.

    Time shares (:func:`time_shares`) of the last cycle's series, whatever the method and the
    placement of the steps; for the closed form of the single node (``method="exact"``, with
    ``model`` given) exact, from the instants of its events.

    Parameters
    ----------
    result : SteadyState
        A steady state of any method (:func:`lcpfric.steady_state`), with the whole cycle's
        series.
    node : int, optional
        Which node of a system (0 for a single node).
    model : SingleNode, optional
        The single node ``result`` was computed for: with ``method="exact"`` the shares then
        come from its closed-form cycle (:func:`lcpfric.exact.exact_cycle`) instead of the
        sampled series.

    Returns
    -------
    dict
        ``{State: share}`` for every state, in the order of :class:`~lcpfric.results.State`; the
        shares add up to 1.

    Raises
    ------
    InputError
        ``result`` is not a SteadyState, or ``node`` is not one of its nodes.
    """
    loop = hysteresis_loop(result, node)  # checks result and node
    from ..model import SingleNode

    if result.method == "exact" and isinstance(model, SingleNode) and model.is_harmonic:
        from ..exact import exact_cycle

        out = dict.fromkeys(State, 0.0)
        for start, end, code, _ in exact_cycle(*model.normalized_parameters()).segments:
            out[State(code)] += (end - start) / (2.0 * np.pi)
        return out
    return time_shares(result.t, loop.state)
