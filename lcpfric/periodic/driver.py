"""The periodic steady-state driver: cycles until the cycle repeats, for every model and method.

:func:`steady_state` asks the registry (:mod:`lcpfric.methods`) for the method. A closed-form
method returns the steady state directly. A time stepper is run whole cycles at a time on the
model's scene (:mod:`lcpfric.scene`) until a cycle repeats the previous one within ``tol``
(:mod:`.measure`: the one convergence measure), or until ``max_cycles``; between cycles the
start may be moved towards the fixed point of the cycle map (:mod:`.acceleration`). A stepper
that settles over many cycles (the half-space with d = 2) has its early cycles' increments
solved loosely (:func:`loose_tolerance`). The last cycle becomes the result in the model's
units (:mod:`.assemble`). Non-convergence is reported (``converged=False``, and an error or a
warning by ``on_nonconvergence``), never returned as converged. ``progress`` watches each cycle.
"""

from __future__ import annotations

import difflib
import inspect
import math
import time
import warnings
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Callable, NamedTuple

import numpy as np

from .. import _checks, memory
from ..errors import ConvergenceError, ConvergenceWarning, InputError
from ..methods import CLOSED_FORM, get_stepper
from ..model import ContactSystem, SingleNode
from ..model.inertia import dynamic_method
from .newmark_steady import system_steady_state
from ..model.coupling import coupled_start
from ..model.system_checks import admissible_start
from ..results import SteadyState
from ..scene import Scene, make_scene
from .acceleration import FrictionLimits, choose
from .assemble import assemble, is_shakedown, warn_unresolved
from .measure import cycle_change, displacement_change, load_scales, unit_scaled

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..exact.solver import ExactSolver
    from ..model.continuum import HalfPlaneCylinder, HalfSpace, MDRSphere
    from ..steppers.base import Stepper

__all__ = ["steady_state", "loose_tolerance", "CycleProgress", "DRIVER_OPTIONS"]

#: The driver's own keyword options: the names of :func:`steady_state`'s keyword arguments that
#: the driver takes itself (everything else goes to the method).
DRIVER_OPTIONS = (
    "steps_per_cycle",
    "tol",
    "max_cycles",
    "on_nonconvergence",
    "placement",
    "u0",
    "history",
    "progress",
)
#: steppers with loose early cycles: the increments' tolerance, this times the last cycle's
#: change, at most ``_LOOSE_MAX`` (and at least the final one)
_LOOSE, _LOOSE_MAX = 1e-2, 1e-6
#: their last cycles' increments, this times the cycle tolerance (at most the stepper's own
#: ``increment_tol``, at least ``_LOOSE`` times the cycle tolerance)
_FINAL = 0.1
#: their smallest cycle tolerance (its increments, a tenth of it, near the 1e-13 that they
#: hold at best)
_TOL_MIN = 1e-12


class CycleProgress(NamedTuple):
    """What :func:`steady_state` passes to its ``progress`` callable after each cycle.

    Parameters
    ----------
    cycle : int
        The cycle just run, from 1.
    change : float
        Its convergence measure, the change from the cycle before (:mod:`.measure`; ``inf`` first).
    tol : float
        The run stops once ``change <= tol`` (at full accuracy, for loose early cycles) ...
    max_cycles : int
        ... or after this many cycles.
    W : float
        The cycle's dissipation, in the model's units.
    """

    cycle: int
    change: float
    tol: float
    max_cycles: int
    W: float


def steady_state(
    model: SingleNode | ContactSystem | MDRSphere | HalfPlaneCylinder | HalfSpace | Scene,
    method: str | Stepper | ExactSolver | None = None,
    steps_per_cycle: int | None = None,
    *,
    tol: float = 1e-10,
    max_cycles: int | None = None,
    on_nonconvergence: str = "raise",
    placement: str | None = None,
    u0: ArrayLike | None = None,
    history: bool = True,
    progress: Callable[[CycleProgress], Any] | None = None,
    **options: Any,
) -> SteadyState:
    """The periodic steady state and its dissipation per cycle.

    A closed-form method (``"exact"``) returns the steady state directly. A time stepper is
    run whole cycles at a time on the model's scene until a cycle repeats the previous one
    within ``tol``, or until ``max_cycles``; between cycles the start may be moved towards the
    fixed point of the cycle map. Non-convergence is reported (``converged=False``, and an
    error or a warning by ``on_nonconvergence``), never returned as converged.

    Parameters
    ----------
    model : SingleNode, ContactSystem, MDRSphere, HalfPlaneCylinder, HalfSpace or Scene
        What to solve. A Scene fixes the grid (then ``steps_per_cycle`` and ``placement`` are
        ignored).
    method : str or method instance, optional
        A registry name (:func:`lcpfric.methods.methods_for` lists a model's): ``"exact"``,
        ``"explicit"``, ``"projection"``, ``"clarabel"``, ``"osqp"``, ``"active-set"``,
        ``"qpsolvers:<solver>"``, ``"cvxpy:<SOLVER>"`` for discrete systems; ``"mdr-bar"``,
        ``"halfplane-pdas"``, ``"newton-cg"`` for the continuum contacts. Default: the
        model's (``exact`` for a discrete system, the contact's own stepper).
    steps_per_cycle : int, optional
        Increments per cycle requested (the known separation instants are added: see
        ``steps_used`` of the result); for a closed-form method the number of samples of the
        returned time series. Default: 2000 for a discrete system, 400 for a contact; at
        least 4.
    tol : float
        Convergence test, > 0 (:mod:`lcpfric.periodic.measure`): the change of the displacements
        over the cycle, relative to the larger of their range and the loads' displacement
        scale, and the change of W relative to the larger of W and the loads' energy scale,
        both at most ``tol``. A shakedown (nothing slips over the steady cycle, W = 0) is
        confirmed like any other steady state, and the message says so. A stepper whose
        early cycles are solved loosely (the half-space with d = 2) needs ``tol >= 1e-12``.
    max_cycles : int, optional
        Cap on the cycles run, at least 1 (default: 100 for a discrete system, 200 for a
        contact).
    on_nonconvergence : {"raise", "warn", "ignore"}
        What to do when ``max_cycles`` is reached first: raise
        :class:`~lcpfric.errors.ConvergenceError`, warn with
        :class:`~lcpfric.errors.ConvergenceWarning`, or only set ``converged=False``.
    placement : {"contact", "uniform"}, optional
        Step placement (see :mod:`lcpfric.scene`); "contact" (a discrete system's default)
        spends no steps where every node is separated; a contact's steps are uniform.
    u0 : array_like, optional
        A discrete system's (or the single node's) initial tangential displacement, m = n·d
        finite values, admissible at t = 0 (``||Q_i(0) + (K u0)_i|| <= f_i N_i(0)`` at every
        node in contact; checked); default: the loads' own start (zero displacement for the
        time steppers, the forces clipped into the cone for ``exact``). Ignored for a
        continuum contact. ``exact`` follows it event by event; where the steady state does
        not depend on the start (no shakedown, or uncoupled systems' W) the result is the
        same.
    history : bool
        Keep every instant of the last cycle in the result (default). ``False`` keeps its
        first and last instants only (``t``, ``v``, ``F``, ``N``, ``state`` then have two rows),
        so that memory does not grow with steps x unknowns; convergence is then judged on the
        state at the cycle's start, which determines the whole cycle, and on each unknown's
        range over the cycle. Time steppers whose ``cycle`` takes ``history`` support it; the
        others raise InputError.
    progress : callable, optional
        Called after each cycle with a :class:`CycleProgress`; it changes no bit of the result,
        an exception raised in it stops the run, and a closed-form method never calls it.
    **options
        The method's own options (solver tolerances and settings). An option that neither the
        driver nor the method takes raises :class:`~lcpfric.errors.InputError` naming the
        valid ones.

    Returns
    -------
    SteadyState
        The steady state: ``W``, the dissipation per cycle of the last cycle (and ``W_hat``
        for a single node), the last cycle's time series, ``converged``, ``cycles``,
        ``change``, ``message`` and the method's ``solver_stats``
        (:class:`~lcpfric.results.SteadyState`). With ``on_nonconvergence="warn"`` or
        ``"ignore"`` an unconverged result is returned with ``converged=False``.

    Raises
    ------
    lcpfric.errors.InputError
        Bad options (``tol``, ``max_cycles``, ``steps_per_cycle``, ``on_nonconvergence``,
        ``history``, ``u0`` out of range or of the wrong size, ``progress`` not callable), an
        unknown method name or option (naming the valid ones), a model that is none of the
        above, a model the method cannot treat (naming the methods that can), ``history=False``
        with a method that keeps the whole cycle, or a computation over the memory limit
        (:mod:`lcpfric.memory`).
    lcpfric.errors.SolverNotFound
        The method needs an optional package that is not installed (a
        :class:`~lcpfric.errors.MissingDependency`, so an ImportError; the message names what
        to install).
    lcpfric.errors.ConvergenceError
        ``max_cycles`` was reached before the cycle repeated and ``on_nonconvergence`` is
        ``"raise"``; its ``result`` is the unconverged SteadyState. The exact solution of a
        ContactSystem raises it when its own cycles do not settle, whatever
        ``on_nonconvergence``.
    lcpfric.errors.SolverError
        A step failed: a solver's status was not solved or its answer failed lcpfric's
        residual checks, or an event loop did not settle (the message names the increment).

    Warns
    -----
    lcpfric.errors.ConvergenceWarning
        ``max_cycles`` was reached and ``on_nonconvergence="warn"``.
    lcpfric.errors.ResolutionWarning
        A continuum contact's steady cycle in which no element slips while the loads change:
        a slip zone thinner than an element is not resolved.

    See Also
    --------
    lcpfric.methods.methods_for : The methods for a model.
    lcpfric.exact.exact_W_hat : The single node's Ŵ on parameter grids, in closed form.

    Examples
    --------
    The paper's single node in normalized units, by the closed form:

    >>> import lcpfric
    >>> node = lcpfric.SingleNode.normalized(P1=0.5, Q1=2.0, phi=0.0)
    >>> result = lcpfric.steady_state(node, method="exact", steps_per_cycle=100)
    >>> round(result.W_hat, 12)
    1.866666666667
    >>> result.converged, result.cycles, result.t.shape
    (True, 1, (101,))

    Bad input raises :class:`~lcpfric.errors.InputError` naming the parameter:

    >>> lcpfric.steady_state(node, method="exact", tol=0.0)
    Traceback (most recent call last):
        ...
    lcpfric.errors.InputError: tol: must be > 0 (allowed range (0, inf)), got 0.0
    """
    start = time.perf_counter()
    base = _base(model)
    method = base.default_method if method is None else method
    coupled = isinstance(model, (ContactSystem, SingleNode)) and model.coupling is not None
    if max_cycles is None:  # a coupled system's cycles run as they happen: more of them
        max_cycles = 1000 if coupled else base.default_max_cycles
    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles, on_nonconvergence)
    solver = _method(method, options)
    history = _checks.boolean("history", history)
    if progress is not None and not callable(progress):
        raise InputError("progress", f"must be a callable or None, got {type(progress).__name__}")
    if not history and (
        solver.kind == CLOSED_FORM or "history" not in inspect.signature(solver.cycle).parameters
    ):
        raise InputError(
            "history",
            f"history=False is not supported by {solver.label!r} (it "
            f"keeps the whole cycle); use 'active-set', 'explicit' or "
            f"'projection', or history=True",
        )
    steps = _requested(model, steps_per_cycle, base)
    if isinstance(model, (SingleNode, ContactSystem)):
        memory.check(
            memory.steady_state_bytes(
                steps if history else 1,
                getattr(solver, "label", ""),
                model.m if isinstance(model, ContactSystem) else 1,
            ),
            "steps_per_cycle",
            f"a steady state with {steps} steps per cycle",
        )
    if coupled:  # the methods that solve it, and one default start for all of them
        u0 = coupled_start(model, solver.name, u0)
    dynamic = dynamic_method(model, solver.name)
    checked = u0 is not None and isinstance(model, (SingleNode, ContactSystem)) and not dynamic
    if checked:
        u0 = admissible_start(model if isinstance(model, ContactSystem) else model.system(), u0)
    if dynamic and hasattr(model, "dynamic_methods"):  # a DynamicSystem: shooting
        return system_steady_state(model, steps, max_cycles, u0, solver.backend, solver.options)
    if solver.kind == CLOSED_FORM or dynamic:  # a dynamic node: the method's own orbit
        return solver.steady_state(model, steps, max_cycles=max_cycles, u0=u0)
    scene = (
        model
        if isinstance(model, Scene)
        else make_scene(model, steps, placement=placement, history=history)
    )
    solver.check(scene)
    loose = scene.system is None and solver.loose(scene)
    if loose and tol < _TOL_MIN:
        raise InputError(
            "tol",
            f"= {tol:g} is below what the increments can hold: the last "
            f"cycles' increments are solved to a tenth of it, and they hold "
            f"about 1e-13 at best; give tol >= {_TOL_MIN:g}",
        )
    if u0 is not None and scene.system is not None and not checked:
        u0 = admissible_start(scene.system, u0)
    work, scale = unit_scaled(scene)
    state = solver.init(work, None if u0 is None else u0 / scale)
    scales = work.scales if work.system is None else load_scales(work, _compliance_scale(work))
    accelerate = choose(work, solver, history, state.u)
    held = work.held if solver.cycle_measure == "map" else None
    W_cycles, changes = [], []
    prev, change, smallest = None, math.inf, math.inf
    extrapolations = 0
    accurate = True
    for _ in range(max_cycles):
        options = {}
        if loose:
            # a slowly settling stepper solves its early cycles' increments loosely, each to a
            # hundredth of the last cycle's change (at most 1e-6), and to a tenth of the cycle
            # tolerance (or its own, if tighter) once the cycles nearly repeat; only a cycle at
            # that accuracy can end the iteration
            final = max(_LOOSE * tol, min(solver.increment_tol, _FINAL * tol))
            options["tol"] = max(final, loose_tolerance(change))
            accurate = options["tol"] == final
        state, cyc = (
            solver.cycle(work, state, **options)
            if history
            else solver.cycle(work, state, history=False, **options)
        )
        W_cycles.append(cyc.W * scale * scale)
        if prev is not None:
            change = cycle_change(
                displacement_change(solver.cycle_measure, cyc, prev, held),
                np.max(cyc.u_span),
                cyc.W - prev.W,
                cyc.W,
                scales,
            )
            changes.append(change)
            if accurate:
                smallest = min(smallest, change)
        if progress is not None:
            progress(
                CycleProgress(len(W_cycles), float(change), tol, max_cycles, float(W_cycles[-1]))
            )
        if change <= tol and accurate:
            break
        prev = cyc
        jump = (
            accelerate(cyc, FrictionLimits(work) if work.system is not None else None)
            if accelerate is not None
            else None
        )
        if jump is not None:
            state = solver.restart(work, state, jump)
            accelerate.restarted(state.u)
            extrapolations += 1
    if scale != 1.0:
        cyc = replace(
            cyc,
            u=cyc.u * scale,
            F=cyc.F * scale,
            W=cyc.W * scale * scale,
            span=None if cyc.span is None else cyc.span * scale,
        )
    converged = bool(change <= tol and accurate)
    result = assemble(
        scene,
        solver,
        cyc,
        np.asarray(W_cycles),
        converged,
        change,
        steps,
        time.perf_counter() - start,
        np.asarray(changes),
        extrapolations,
    )
    if converged and is_shakedown(cyc):
        result = replace(
            result, message="converged: shakedown (no node slips over the steady cycle)"
        )
    if not converged:
        at = (
            f"; the smallest at full accuracy {smallest:.3g}"
            if loose and smallest < math.inf
            else ""
        )

        msg = (
            f"{type(scene.system if scene.model is None else scene.model).__name__}: no "
            f"periodic steady state after {len(W_cycles)} cycles "
            f"(relative change of the cycle {change:.3g} > tol {tol:g}{at}); raise "
            f"max_cycles or loosen tol"
        )
        msg += _stiff_hint(scene)
        result = replace(result, message=msg)
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg, result)
        if on_nonconvergence == "warn":
            warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    if scene.system is None:
        warn_unresolved(scene, result.W)
    return result


def loose_tolerance(change: float) -> float:
    """Steppers with loose early cycles: the increments' tolerance after a cycle whose change
    was ``change`` (a hundredth of it, at most ``_LOOSE_MAX``; the final tolerance is the
    floor). ``benchmarks/studies/late_cycles.py`` measures other schedules against it."""
    return min(_LOOSE_MAX, _LOOSE * change)


def _base(model):
    """The model whose defaults apply (a scene's model, or its system)."""
    if isinstance(model, Scene):
        return model.model if model.model is not None else model.system
    if not hasattr(type(model), "default_method"):
        raise InputError(
            "model",
            "expected a SingleNode, ContactSystem, continuum contact "
            f"(MDRSphere, HalfPlaneCylinder, HalfSpace) or Scene, got "
            f"{type(model).__name__}",
        )
    return model


def _compliance_scale(scene) -> float:
    """The largest diagonal compliance, max C_ii (C = K⁻¹; 1/k for a diagonal K). Beyond
    :data:`~lcpfric.model.system.COMPLIANCE_DENSE` unknowns C is not formed and the estimate
    from below 1/min K_ii is used (a scale for the convergence test only; see
    :meth:`~lcpfric.model.ContactSystem.compliance_diagonal`)."""
    return float(np.max(scene.system.compliance_diagonal()))


def _stiff_hint(scene) -> str:
    """What answers a system of nearly rigid clusters, for the message of a failure."""
    from ..exact.clusters import stiff_hint

    return stiff_hint(scene.system)


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
        raise InputError(
            exc.parameter, f"{exc.detail}{hint}; the driver's options: {', '.join(DRIVER_OPTIONS)}"
        ) from None


def _requested(model, steps_per_cycle, base) -> int:
    if isinstance(model, Scene):
        return model.steps_requested
    steps = base.default_steps if steps_per_cycle is None else steps_per_cycle
    return _checks.positive_int("steps_per_cycle", steps, 4)
