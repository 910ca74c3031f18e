"""The one cycle loop of many points advanced together: a parameter grid of single nodes
(:mod:`lcpfric.batch`), the MDR sphere's map points (:mod:`lcpfric.analysis.contact_maps`).

A batched stepper holds every point's state as arrays with the points first and advances all
of them one increment at once. It provides

* ``size`` (points) and ``steps`` (increments per cycle, the same for every point);
* ``init()``: the state of every point at the cycle's start;
* ``step(j, state)``: the state after increment j (from instant j to j + 1) and each point's
  dissipation over it (:func:`~lcpfric.steppers.dissipation.node_shares`);
* ``unknowns(state)``: ``(points, k)``, the displacements the cycles compare;
* ``scales()``: the loads' displacement and force scales per point.

:func:`run` runs whole cycles until every point repeats its previous cycle within ``tol``
(the driver's criterion, :func:`~lcpfric.periodic.measure.cycle_change`, per point, in the
form ``"cycles"`` or ``"map"``: :mod:`~lcpfric.periodic.measure`); a point's value is that of
its first converged cycle. A point that does not converge in ``max_cycles`` is NaN in the
result, counted, and reported by ``on_nonconvergence`` (an error by default, or a warning):
never returned as converged.
"""

from __future__ import annotations

import time
import warnings
from typing import Callable

import numpy as np

from ..errors import ConvergenceError, ConvergenceWarning
from ..results import BatchResult
from .measure import MEASURES, cycle_change

__all__ = ["run"]


def run(
    stepper,
    *,
    tol: float,
    max_cycles: int,
    on_nonconvergence: str,
    measure: str,
    quantity: str,
    values: Callable,
    method: str,
    steps_requested: int,
    shape=None,
    start: float | None = None,
) -> BatchResult:
    """Whole cycles of every point of ``stepper`` until each repeats (module docstring).

    Parameters
    ----------
    stepper
        A batched stepper (module docstring).
    tol, max_cycles, on_nonconvergence
        As in :func:`lcpfric.steady_state`, per point.
    measure : {"cycles", "map"}
        The cycles' comparison (:mod:`~lcpfric.periodic.measure`).
    quantity : str
        The result's quantity (``"W_hat"``, ``"W_normalized"``).
    values : callable
        The quantity of every point from its dissipation per cycle (flat arrays).
    method : str
        The method's name, for the result.
    steps_requested : int
    shape : tuple, optional
        The points' shape (the result's arrays take it; ``()``: one point, a float value).
    start : float, optional
        ``time.perf_counter()`` at the call's start (the result's ``seconds``).
    """
    if measure not in MEASURES:
        raise ValueError(f"measure must be one of {MEASURES}")
    start = time.perf_counter() if start is None else start
    npts = stepper.size
    state = stepper.init()
    J = np.full(npts, np.nan)
    cycles = np.full(npts, max_cycles)
    change = np.full(npts, np.inf)
    done = np.zeros(npts, dtype=bool)
    prev_x0 = prev_W = None
    scales = None
    for c in range(max_cycles):
        x0 = stepper.unknowns(state).copy()
        lo, hi = x0.copy(), x0.copy()
        W = np.zeros(npts)
        for j in range(stepper.steps):
            state, dW = stepper.step(j, state)
            W += dW
            x = stepper.unknowns(state)
            np.minimum(lo, x, out=lo)
            np.maximum(hi, x, out=hi)
        if prev_W is not None:
            if scales is None:
                scales = stepper.scales()
            moved = x0 - prev_x0 if measure == "cycles" else x - x0
            ch = cycle_change(
                np.max(np.abs(moved), axis=1), np.max(hi - lo, axis=1), W - prev_W, W, scales
            )
            new = ~done & (ch <= tol)
            J[new] = W[new]
            cycles[new] = c + 1
            change = np.where(done, change, ch)
            done |= new
            if done.all():
                break
        prev_x0, prev_W = x0, W
    left = int(npts - np.count_nonzero(done))
    if left:
        msg = (
            f"{left} of {npts} points reached no periodic steady state in {max_cycles} "
            f"cycles (largest relative change {float(np.max(change[~done])):.3g} > tol "
            f"{tol:g}; their values are NaN); raise max_cycles or loosen tol"
        )
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg)
        if on_nonconvergence == "warn":
            warnings.warn(msg, ConvergenceWarning, stacklevel=3)
    out = values(J)
    shape = (npts,) if shape is None else tuple(shape)
    out = out.reshape(shape)
    return BatchResult(
        values=out if out.ndim else float(out),
        quantity=quantity,
        converged=done.reshape(shape),
        cycles=cycles.reshape(shape),
        change=change.reshape(shape),
        method=method,
        steps_requested=steps_requested,
        steps_used=stepper.steps,
        seconds=time.perf_counter() - start,
    )
