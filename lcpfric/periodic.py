"""The periodic steady-state driver: cycles until the cycle repeats.

:func:`steady_state` asks the registry (:mod:`lcpfric.methods`) for the method. A closed-form
method returns the steady state directly. A time stepper is run whole cycles at a time on a
scene (:mod:`lcpfric.scene`) until the tangential displacement over a cycle repeats the previous
cycle's (:func:`cycle_change`, the one convergence criterion, shared with :mod:`lcpfric.batch`),
or until ``max_cycles``. Non-convergence is reported (``converged=False``, and an error or a
warning by ``on_nonconvergence``), never returned as converged.
"""

from __future__ import annotations

import difflib
import time
import warnings
from dataclasses import replace

import numpy as np

from . import _checks
from .errors import ConvergenceError, ConvergenceWarning, InputError
from .methods import CLOSED_FORM, get_stepper
from .model import ContactSystem, SingleNode
from .results import CycleResult, SteadyState
from .scene import Scene, make_scene

__all__ = ["steady_state", "cycle_change", "DRIVER_OPTIONS"]

#: The driver's own keyword options (everything else goes to the method).
DRIVER_OPTIONS = ("steps_per_cycle", "tol", "max_cycles", "on_nonconvergence", "placement", "u0")


def cycle_change(diff, span):
    """The convergence measure of a cycle: the change ``diff`` of the displacements from the
    previous cycle, relative to ``span`` (0 where both vanish, inf where only the span does).
    Works on scalars and on arrays (one entry per point of a batch)."""
    diff = np.asarray(diff, dtype=float)
    span = np.asarray(span, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(span > 0, diff / np.where(span > 0, span, 1.0),
                       np.where(diff == 0, 0.0, np.inf))
    return out if out.ndim else float(out)


def steady_state(model, method: str = "exact", steps_per_cycle: int = 2000, *,
                 tol: float = 1e-10, max_cycles: int = 100, on_nonconvergence: str = "raise",
                 placement: str = "contact", u0=None, **options) -> SteadyState:
    """The periodic steady state and its dissipation per cycle.

    Parameters
    ----------
    model : SingleNode, ContactSystem or Scene
        What to solve. A Scene fixes the grid (then ``steps_per_cycle`` and ``placement`` are
        ignored).
    method : str or method instance
        A registry name (:func:`lcpfric.available_methods`): ``"exact"``, ``"explicit"``,
        ``"projection"``, ``"clarabel"``, ``"osqp"``, ``"qpsolvers:<solver>"``,
        ``"cvxpy:<SOLVER>"``.
    steps_per_cycle : int
        Increments per cycle requested (the known separation instants are added: see
        ``steps_used`` of the result). For a closed-form method it only sets the number of
        samples of the returned time series.
    tol : float
        Convergence test: ``max |v_c - v_{c-1}| <= tol * range(v_c)`` over the grid
        (:func:`cycle_change`).
    max_cycles : int
        Cap on the cycles run.
    on_nonconvergence : {"raise", "warn", "ignore"}
        What to do when ``max_cycles`` is reached first: raise :class:`ConvergenceError`, warn
        with :class:`ConvergenceWarning`, or only set ``converged=False``.
    placement : {"contact", "uniform"}
        Step placement (see :mod:`lcpfric.scene`); "contact" spends no steps where every node is
        separated.
    u0 : array_like, optional
        Initial tangential displacement (default zero).
    **options
        The method's own options (solver tolerances and settings). An option that neither the
        driver nor the method takes raises :class:`InputError` naming the valid ones.

    Returns
    -------
    SteadyState
    """
    start = time.perf_counter()
    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles,
                                                                on_nonconvergence)
    solver = _method(method, options)
    if solver.kind == CLOSED_FORM:
        return solver.steady_state(model, steps_per_cycle)
    if isinstance(model, Scene):
        scene = model
    elif isinstance(model, (SingleNode, ContactSystem)):
        scene = make_scene(model, steps_per_cycle, placement=placement)
    else:
        raise InputError("model", "expected a SingleNode, ContactSystem or Scene, got "
                                  f"{type(model).__name__}")
    solver.check(scene.system)
    if u0 is not None:
        u0 = _checks.finite_array("u0", u0)
        if u0.size != scene.system.m:
            raise InputError("u0", f"needs {scene.system.m} displacements (n·d), got {u0.size}")
    work, scale = _unit_scaled(scene)
    state = solver.init(work, None if u0 is None else u0 / scale)
    W_cycles = []
    prev = None
    change = np.inf
    for _ in range(max_cycles):
        state, cyc = solver.cycle(work, state)
        W_cycles.append(cyc.W * scale * scale)
        if prev is not None:
            change = cycle_change(np.max(np.abs(cyc.u - prev)), np.max(np.ptp(cyc.u, axis=0)))
            if change <= tol:
                break
        prev = cyc.u
    if scale != 1.0:
        cyc = CycleResult(cyc.t, cyc.u * scale, cyc.F * scale, cyc.state, cyc.W * scale * scale,
                          cyc.stats)
    converged = bool(change <= tol)
    result = _assemble(scene, solver, cyc, np.asarray(W_cycles), converged, change,
                       _requested(model, steps_per_cycle), time.perf_counter() - start)
    if not converged:
        msg = (f"no periodic steady state after {len(W_cycles)} cycles (relative change of v "
               f"{change:.3g} > tol {tol:g}); raise max_cycles or loosen tol")
        result = replace(result, message=msg)
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg, result)
        if on_nonconvergence == "warn":
            warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    return result


def _method(method, options: dict):
    """The registry's instance for ``method``; an unknown option names the driver's and the
    method's valid ones."""
    try:
        return get_stepper(method, **options)
    except InputError as exc:
        if exc.parameter not in options:
            raise
        close = difflib.get_close_matches(exc.parameter, DRIVER_OPTIONS, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise InputError(exc.parameter, f"{exc.detail}{hint}; the driver's options: "
                                        f"{', '.join(DRIVER_OPTIONS)}") from None


def _requested(model, steps_per_cycle) -> int:
    if isinstance(model, Scene):
        return model.steps_requested
    return _checks.positive_int("steps_per_cycle", steps_per_cycle, 4)


def _unit_scaled(scene: Scene) -> tuple[Scene, float]:
    """The scene with forces divided by s, a power of two near the largest friction limit.

    Steppers then see forces of order one whatever the units (loads of 1e6, or 1e-6): the
    convex solvers' tolerances are absolute, and at P̂1 = Q̂1 = 1e6 Clarabel otherwise stops
    "DualInfeasible". Q, f N and so u and F scale by 1/s and W by 1/s². Dividing by a power of
    two is exact in floating point, so the closed-form steppers give the same bits either way.
    """
    # the answer F lies within ±f N: its size is the largest friction limit
    size = float(np.max(scene.N * scene.system.friction, initial=0.0))
    if not np.isfinite(size) or size == 0.0:
        return scene, 1.0
    scale = float(2.0 ** np.round(np.log2(size)))
    if scale == 1.0:
        return scene, 1.0
    return replace(scene, Q=scene.Q / scale, N=scene.N / scale,
                   _cache={"contact": scene.contact}), scale  # contact is scale-free


def _assemble(scene, solver, cyc, W_cycles, converged, change, requested,
              seconds) -> SteadyState:
    model = scene.model
    common = dict(cycles=len(W_cycles), converged=converged, method=solver.label,
                  steps_requested=requested, steps_used=scene.steps, t=scene.t,
                  state=cyc.state if model is None else cyc.state[:, 0], seconds=seconds,
                  change=change, message="converged" if converged else "",
                  solver_stats=cyc.stats)
    if model is None:
        return SteadyState(W=float(W_cycles[-1]), W_cycles=W_cycles, v=cyc.u, F=cyc.F,
                           N=scene.N, **common)
    # a single node is advanced in the units f P0 (force), f P0/k11 (displacement): J = Q̂1 Ŵ
    q1 = model.Q1_hat
    W_hat_cycles = W_cycles / q1 if q1 > 0 else np.zeros_like(W_cycles)
    v, F, N = model.series(cyc.u[:, 0], cyc.F[:, 0], scene.N[:, 0])
    return SteadyState(W=float(model.W(W_hat_cycles[-1])),
                       W_cycles=np.atleast_1d(model.W(W_hat_cycles)), v=v, F=F, N=N,
                       normalization=model.normalization(), W_hat_cycles=W_hat_cycles, **common)
