"""The periodic steady-state driver: cycles until v(t) repeats.

:func:`steady_state` runs whole cycles of a scene with a stepper until the tangential
displacement over a cycle repeats the previous cycle's within ``tol`` (relative to the cycle's
range of v), or until ``max_cycles``. Non-convergence is reported (``converged=False``, and an
error or a warning by ``on_nonconvergence``), never returned as converged.

For a single node with harmonic loads, ``method="exact"`` returns the closed-form steady state
(:mod:`lcpfric.exact`) with no cycles at all.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import replace

import numpy as np

from . import _checks
from .errors import ConvergenceError, ConvergenceWarning, InputError
from .methods import get_stepper
from .model import ContactSystem, SingleNode
from .results import SteadyState
from .scene import Scene, make_scene

__all__ = ["steady_state"]



def steady_state(model, method: str = "exact", steps_per_cycle: int = 2000, *,
                 tol: float = 1e-10, max_cycles: int = 100, on_nonconvergence: str = "raise",
                 placement: str = "contact", u0=None, **options) -> SteadyState:
    """The periodic steady state and its dissipation per cycle.

    Parameters
    ----------
    model : SingleNode, ContactSystem or Scene
        What to solve. A Scene fixes the grid (then ``steps_per_cycle`` and ``placement`` are
        ignored).
    method : str or Stepper
        ``"exact"``, ``"explicit"``, ``"projection"``, ``"clarabel"``, ``"osqp"``,
        ``"qpsolvers:<solver>"``, ``"cvxpy:<SOLVER>"`` (see :mod:`lcpfric.methods`).
    steps_per_cycle : int
        Increments per cycle (the known separation instants are added). For ``"exact"`` it only
        sets the resolution of the returned time series.
    tol : float
        Convergence test: ``max |v_c - v_{c-1}| <= tol * range(v_c)`` over the grid.
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
        Passed to the stepper (solver tolerances and settings).

    Returns
    -------
    SteadyState
    """
    start = time.perf_counter()
    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles,
                                                                on_nonconvergence)
    if isinstance(method, str) and method.strip().lower() == "exact":
        if options:
            raise InputError("method", f"'exact' takes no solver options, got {sorted(options)}")
        return _exact(model, _checks.positive_int("steps_per_cycle", steps_per_cycle, 4), start)
    if isinstance(model, Scene):
        scene = model
    elif isinstance(model, (SingleNode, ContactSystem)):
        scene = make_scene(model, steps_per_cycle, placement=placement)
    else:
        raise InputError("model", "expected a SingleNode, ContactSystem or Scene, got "
                                  f"{type(model).__name__}")
    stepper = get_stepper(method, **options)
    stepper.check(scene.system)
    work, scale = _unit_scaled(scene)
    state = stepper.init(work, None if u0 is None else np.asarray(u0, dtype=float) / scale)
    W_cycles = []
    prev = None
    change = np.inf
    cyc = None
    for _ in range(max_cycles):
        state, cyc = stepper.cycle(work, state)
        if scale != 1.0:
            cyc.u = cyc.u * scale
            cyc.F = cyc.F * scale
            cyc.W = cyc.W * scale * scale
        W_cycles.append(cyc.W)
        if prev is not None:
            span = float(np.max(np.ptp(cyc.u, axis=0)))
            diff = float(np.max(np.abs(cyc.u - prev)))
            change = diff / span if span > 0 else (0.0 if diff == 0 else np.inf)
            if change <= tol:
                break
        prev = cyc.u
    converged = change <= tol
    result = _assemble(scene, stepper, cyc, np.asarray(W_cycles), converged, change,
                       time.perf_counter() - start)
    if not converged:
        msg = (f"no periodic steady state after {len(W_cycles)} cycles (relative change of v "
               f"{change:.3g} > tol {tol:g}); raise max_cycles or loosen tol")
        result.message = msg
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg, result)
        if on_nonconvergence == "warn":
            warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    return result


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


def _assemble(scene, stepper, cyc, W_cycles, converged, change, seconds) -> SteadyState:
    model = scene.model
    name = stepper.name if not getattr(stepper, "label", None) else stepper.label
    if model is None:
        return SteadyState(W_hat=None, W=float(W_cycles[-1]), W_per_cycle=W_cycles,
                           cycles=len(W_cycles), converged=converged, method=name,
                           steps_per_cycle=scene.steps, t=scene.t, v=cyc.u, F=cyc.F, N=scene.N,
                           state=cyc.state, seconds=seconds, change=change,
                           message="converged" if converged else "",
                           solver_stats=cyc.stats)
    q1 = model.Q1_hat
    W_hat_cycles = W_cycles / q1 if q1 > 0 else np.zeros_like(W_cycles)
    W_hat = float(W_hat_cycles[-1])
    u, F, N = cyc.u[:, 0], cyc.F[:, 0], scene.N[:, 0]
    t, v, F, N = _dimensional(model, scene.t, u, F, N)
    return SteadyState(W_hat=W_hat, W=float(model.W(W_hat)) if model.dimensional else None,
                       W_per_cycle=W_hat_cycles, cycles=len(W_cycles), converged=converged,
                       method=name, steps_per_cycle=scene.steps, t=t, v=v, F=F, N=N,
                       state=cyc.state[:, 0], seconds=seconds, change=change,
                       message="converged" if converged else "", solver_stats=cyc.stats)


def _dimensional(model: SingleNode, t, u, F, N):
    """Map the normalized series (u in f P0/k11, F in f P0, N in P0) to the model's units:
    dimensional (v, F, N) for a dimensional model; (v̂, F̂, N̂) of Eq. (6) for a normalized one."""
    if model.dimensional:
        v = (model.force_unit * u - model.Q0) / model.k11
        return t, v, model.force_unit * F, model.P0 * N
    q1 = model.Q1_hat
    return t, (u / q1 if q1 > 0 else u), F, N


def _exact(model, steps: int, start: float) -> SteadyState:
    from .exact import exact_cycle

    if isinstance(model, Scene):
        model = model.model
    if not isinstance(model, (SingleNode, ContactSystem)):
        raise InputError("model", "expected a SingleNode, ContactSystem or Scene, got "
                                  f"{type(model).__name__}")
    if not isinstance(model, SingleNode):
        raise InputError("method", "'exact' solves the single node (SingleNode); for a general "
                                   "system use 'explicit', 'projection' or a solver backend")
    if not model.is_harmonic:
        raise InputError("method", "'exact' needs harmonic loads P0 + P1 sin(ωt), "
                                   "Q0 + Q1 sin(ωt + φ); for other periodic loads use "
                                   "'explicit' or 'projection'")
    P1, Q1, phi = model.normalized_parameters()
    cyc = exact_cycle(P1, Q1, phi)
    T = model.period
    psi_p = model.normal_load.phase
    t = np.linspace(0.0, T, steps + 1)
    theta = model.omega * t + psi_p
    u = cyc.w(theta)
    Qn = Q1 * np.sin(theta + phi)
    Nn = np.maximum(1.0 + P1 * np.sin(theta), 0.0)
    F = Qn + u
    t, v, F, N = _dimensional(model, t, u, F, Nn)
    W_hat = cyc.W_hat
    return SteadyState(W_hat=W_hat, W=float(model.W(W_hat)) if model.dimensional else None,
                       W_per_cycle=np.array([W_hat]), cycles=1, converged=True, method="exact",
                       steps_per_cycle=steps, t=t, v=v, F=F, N=N, state=cyc.state(theta),
                       seconds=time.perf_counter() - start, change=0.0,
                       message="exact steady state (closed form, no cycles iterated)")
