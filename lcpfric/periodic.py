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
import inspect
import time
import warnings
from dataclasses import replace

import numpy as np

from . import _checks, memory
from .cycle_memory import SlipMemory
from .errors import ConvergenceError, ConvergenceWarning, InputError
from .methods import CLOSED_FORM, get_stepper
from .model import ContactSystem, SingleNode
from .model.system import COMPLIANCE_DENSE
from .results import CycleResult, State, SteadyState
from .scene import Scene, column_reduce, make_scene

__all__ = ["steady_state", "cycle_change", "load_scales", "DRIVER_OPTIONS"]

#: The driver's own keyword options (everything else goes to the method).
DRIVER_OPTIONS = ("steps_per_cycle", "tol", "max_cycles", "on_nonconvergence", "placement", "u0",
                  "history")


def cycle_change(du, v_span, dW, W, load_span):
    """The convergence measure of a cycle (the one criterion, shared with :mod:`lcpfric.batch`).

    ``max(du / s_v, |dW| / s_W)`` with the scales

    * ``s_v = max(v_span, load_span)``: the cycle's range of the displacements, or the loads'
      displacement scale (the range of the tangential loads times the compliance), whichever is
      larger. It does not vanish when the system shakes down or slips very little, so such a
      steady state is confirmed like any other;
    * ``s_W = max(|W|, s_u · s_F)``, the same for the dissipation, with ``s_u`` the loads'
      displacement scale and ``s_F`` the largest friction limit f N: the dissipating forces
      never exceed it (the tangential load itself may be far larger).

    Parameters
    ----------
    du : float or ndarray
        ``max |v_c - v_{c-1}|`` over the grid (per point of a batch).
    v_span : float or ndarray
        The cycle's range of v.
    dW, W : float or ndarray
        ``W_c - W_{c-1}`` and ``W_c``.
    load_span : tuple (displacement, force) of floats or ndarrays
        The loads' scales: the range of Q times the compliance, and the largest friction
        limit f N.
    """
    u_scale, f_scale = (np.asarray(x, dtype=float) for x in load_span)
    s_v = np.maximum(np.asarray(v_span, dtype=float), u_scale)
    s_W = np.maximum(np.abs(np.asarray(W, dtype=float)), u_scale * f_scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(s_v > 0, np.abs(du) / np.where(s_v > 0, s_v, 1.0),
                     np.where(np.asarray(du) == 0, 0.0, np.inf))
        b = np.where(s_W > 0, np.abs(dW) / np.where(s_W > 0, s_W, 1.0),
                     np.where(np.asarray(dW) == 0, 0.0, np.inf))
    out = np.maximum(a, b)
    return out if out.ndim else float(out)


def load_scales(scene, compliance) -> tuple[float, float]:
    """The loads' displacement and force scales of a scene: ``(c r, b)`` with r the largest
    range of a tangential load over the cycle, c the largest diagonal compliance and b the
    largest friction limit f N."""
    parts = column_reduce(scene.Q, lambda x: (np.min(x, axis=0), np.max(x, axis=0)))
    lo = np.min([p[0] for p in parts], axis=0)
    hi = np.max([p[1] for p in parts], axis=0)
    r = float(np.max(hi - lo, initial=0.0))
    return compliance * r, _largest_limit(scene)


def _largest_limit(scene) -> float:
    """The largest friction limit f N over the scene (chunk by chunk: Q and N may be
    :class:`~lcpfric.scene.Rows`)."""
    f = scene.system.friction
    return float(max(column_reduce(scene.N, lambda x: float(np.max(x * f, initial=0.0)))))


def steady_state(model, method: str = "exact", steps_per_cycle: int = 2000, *,
                 tol: float = 1e-10, max_cycles: int = 100, on_nonconvergence: str = "raise",
                 placement: str = "contact", u0=None, history: bool = True,
                 **options) -> SteadyState:
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
        Convergence test: the change of v over the cycle, relative to the larger of its range
        and the loads' displacement scale, and the change of W relative to the larger of W and
        the loads' energy scale, both at most ``tol`` (:func:`cycle_change`). A shakedown (no
        node slips over the steady cycle, W = 0) is confirmed like any other steady state, and
        the message says so.
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
    history : bool
        Keep every instant of the last cycle in the result (default). ``False`` keeps its
        first and last instants only (``t``, ``v``, ``F``, ``N``, ``state`` then have two rows),
        so that memory does not grow with steps x unknowns (1e5 nodes at 2000 steps would be
        1.6 GB per series); convergence is then judged on the state at the cycle's start,
        which determines the whole cycle, and on each unknown's range over the cycle. Time
        steppers whose ``cycle`` takes ``history`` support it (``active-set``, ``explicit``,
        ``projection``); the others raise InputError.
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
    history = _checks.boolean("history", history)
    if not history and (solver.kind == CLOSED_FORM
                        or "history" not in inspect.signature(solver.cycle).parameters):
        raise InputError("history", f"history=False is not supported by {solver.label!r} (it "
                                    f"keeps the whole cycle); use 'active-set', 'explicit' or "
                                    f"'projection', or history=True")
    if not isinstance(model, Scene):
        steps = _checks.positive_int("steps_per_cycle", steps_per_cycle, 4)
        size = model.m if isinstance(model, ContactSystem) else 1
        memory.check(memory.steady_state_bytes(steps if history else 1,
                                               getattr(solver, "label", ""), size),
                     "steps_per_cycle", f"a steady state with {steps} steps per cycle")
    if solver.kind == CLOSED_FORM:
        return solver.steady_state(model, steps_per_cycle, max_cycles=max_cycles)
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
    loads = load_scales(work, _compliance_scale(scene.system))
    W_cycles = []
    prev, prev_W = None, 0.0
    change = np.inf
    starts = [state.u]
    extrapolations = 0
    # d = 2 with the cycle kept: each cycle's change scaled node by node by what the cycle
    # remembers of its start (lcpfric.cycle_memory; exact for uncoupled nodes), then, for
    # coupled ones, Anderson's acceleration; else Aitken's jumps where one slow mode shows
    slip_memory = (SlipMemory(_node_compliance(scene.system), scene.system.n)
                   if history and scene.system.dims == 2 else None)
    accelerate = (Anderson() if slip_memory is not None and not scene.system.is_diagonal()
                  else None)
    for _ in range(max_cycles):
        state, cyc = (solver.cycle(work, state) if history
                      else solver.cycle(work, state, history=False))
        W_cycles.append(cyc.W * scale * scale)
        if prev is not None:
            change = cycle_change(np.max(np.abs(cyc.u - prev)), np.max(cyc.u_span),
                                  (cyc.W - prev_W), cyc.W, loads)
            if change <= tol:
                break
        prev, prev_W = cyc.u, cyc.W
        starts.append(state.u)
        if slip_memory is not None:
            x0 = cyc.u[0]
            R = slip_memory.of_cycle(cyc.u, _Limits(work))
            end = x0 + slip_memory.step(R, cyc.u[-1] - x0)
            nxt = accelerate(x0, end) if accelerate is not None else None
            jump = _inside(end if nxt is None else nxt, work)
        else:
            jump = _extrapolate(starts, work)
        if jump is not None:
            state = replace(state, u=jump[0], F=jump[1])
            starts = [jump[0]]
            extrapolations += 1
    shakedown = _shakedown(cyc)
    if scale != 1.0:
        cyc = CycleResult(cyc.t, cyc.u * scale, cyc.F * scale, cyc.state, cyc.W * scale * scale,
                          cyc.stats, None if cyc.span is None else cyc.span * scale)
    converged = bool(change <= tol)
    result = _assemble(scene, solver, cyc, np.asarray(W_cycles), converged, change,
                       _requested(model, steps_per_cycle), time.perf_counter() - start)
    if extrapolations:
        result = replace(result, solver_stats={**result.solver_stats,
                                               "extrapolations": extrapolations})
    if converged and shakedown:
        result = replace(result, message="converged: shakedown (no node slips over the steady "
                                         "cycle)")
    if not converged:
        msg = (f"no periodic steady state after {len(W_cycles)} cycles (relative change of the "
               f"cycle {change:.3g} > tol {tol:g}); raise max_cycles or loosen tol")
        result = replace(result, message=msg)
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg, result)
        if on_nonconvergence == "warn":
            warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    return result


def _extrapolate(starts: list, scene: Scene):
    """Jump to the fixed point of a slowly contracting cycle map, or None.

    The cycle maps the state at the cycle's start to the next cycle's start; near the steady
    state, with the stick/slip pattern settled, it is affine, and a slow approach (a weakly
    grounded system drifting back, ratio ρ close to 1 per cycle) is dominated by one mode. When
    the last three differences ``d`` shrink at one steady ratio ρ in [0.3, 0.999], the start is
    moved to ``s + ρ/(1 - ρ) d`` (Aitken's extrapolation), its force put back inside the friction
    cone (``F = Π(Q + K u)``, ``u = K⁻¹ (F - Q)``). Nothing is taken from it but a starting
    point: convergence is still confirmed by two whole cycles that repeat.
    """
    u = aitken(starts)
    if u is None:
        return None
    return _inside(u, scene)


def _inside(u, scene):
    """``(u, F)`` at the cycle's start with the force put back inside the friction cone
    (``F = Π(Q + K u)``, ``u = K⁻¹ (F - Q)``)."""
    system = scene.system
    Q0, bound = scene.Q[0], scene.N[0] * system.friction
    F = Q0 + system.stiffness_times(u)
    if system.dims == 1:
        Fp = np.clip(F, -bound, bound)
    else:
        F2 = F.reshape(-1, 2)
        norm = np.hypot(F2[:, 0], F2[:, 1])
        shrink = np.where(norm > bound, bound / np.where(norm > 0, norm, 1.0), 1.0)
        Fp = (F2 * shrink[:, None]).ravel()
    if np.any(Fp != F):
        u = u + system.solve(Fp - F)
    return u, Fp


class _Limits:
    """The friction limits ``f N`` at each instant of a scene, row by row."""

    def __init__(self, scene):
        self.N, self.f = scene.N, scene.system.friction

    def __getitem__(self, k):
        return np.asarray(self.N[k], dtype=float) * self.f


def _node_compliance(system) -> np.ndarray:
    """Each node's self-compliance (d = 2: the mean of its two diagonal entries of C)."""
    c = np.asarray(system.compliance_diagonal(), dtype=float).reshape(system.n, -1)
    return c.mean(axis=1)


def aitken(starts: list):
    """Aitken's jump ``s + ρ/(1 - ρ) d`` from the last of the cycles' starting states, when the
    last three differences d shrink at one steady ratio ρ in [0.3, 0.999]; else None (see
    :func:`_extrapolate`)."""
    if len(starts) < 4:
        return None
    d = [np.linalg.norm(starts[i + 1] - starts[i]) for i in range(len(starts) - 4, len(starts) - 1)]
    if d[0] == 0 or d[1] == 0:
        return None
    r1, r2 = d[1] / d[0], d[2] / d[1]
    if not (0.3 <= r2 <= 0.999 and abs(r2 - r1) <= 0.05 * r2):
        return None
    return starts[-1] + r2 / (1.0 - r2) * (starts[-1] - starts[-2])


class Anderson:
    """Anderson's acceleration (type II, depth m, 10 by default) of a cycle map ``x -> G(x)``:
    from the last ``m + 1`` pairs ``(x_k, G(x_k))``, the next start is ``G(x_k) - ΔG γ`` with
    γ the least-squares coefficients of the residuals' differences ``ΔF`` that best cancel
    ``f_k = G(x_k) - x_k``. Near the steady state the map is affine with a few slow modes (the
    stick/slip pattern has settled), which this removes in about as many cycles as there are
    modes, where the plain iteration contracts only by the slowest mode's ratio per cycle. A
    history whose residuals grow is dropped (the map is not in its affine regime yet). Where
    it stalls (the residual shrinks by less than a tenth per cycle, three cycles running: the
    map is not affine at that scale), the plain iteration goes on, with Aitken's jumps
    (:func:`aitken`) when one slow mode shows. Nothing is taken from the extrapolation but a
    starting point: convergence is still a whole cycle that repeats."""

    def __init__(self, depth: int = 10):
        self.depth = depth
        self.x: list = []
        self.g: list = []
        self.norms: list = []
        self.starts: list | None = None       # the plain iteration's starts, once stalled

    def __call__(self, x: np.ndarray, g: np.ndarray):
        """The next start after the cycle from ``x`` that ended at ``g``, or None (go on
        from g)."""
        f = g - x
        self.norms.append(float(np.linalg.norm(f)))
        if self.starts is None and len(self.norms) >= 4 and all(
                b > 0.9 * a for a, b in zip(self.norms[-4:-1], self.norms[-3:])):
            self.starts = [x]
        if self.starts is not None:
            self.starts.append(g)
            jump = aitken(self.starts)
            if jump is not None:
                self.starts = [jump]
            return jump
        if self.x and self.norms[-1] > self.norms[-2]:
            self.x, self.g = [], []
        self.x = (self.x + [x])[-(self.depth + 1):]
        self.g = (self.g + [g])[-(self.depth + 1):]
        if len(self.x) < 2:
            return None
        G = np.array(self.g).T
        R = G - np.array(self.x).T
        gamma = np.linalg.lstsq(np.diff(R, axis=1), f, rcond=1e-12)[0]
        return g - np.diff(G, axis=1) @ gamma


#: beyond this many unknowns the compliance scale is estimated (C is not formed)
_COMPLIANCE_DENSE = COMPLIANCE_DENSE


def _compliance_scale(system) -> float:
    """The largest diagonal compliance, max C_ii (C = K⁻¹; 1/k for a diagonal K). Beyond
    :data:`_COMPLIANCE_DENSE` unknowns C is not formed and the estimate from below 1/min K_ii is
    used (a scale for the convergence test only; see
    :meth:`~lcpfric.model.ContactSystem.compliance_diagonal`)."""
    return float(np.max(system.compliance_diagonal()))


def _shakedown(cyc: CycleResult) -> bool:
    """A shakedown: no node recorded slipping over the cycle and no dissipation at all."""
    return cyc.W == 0.0 and not np.any((cyc.state == State.FORWARD)
                                       | (cyc.state == State.BACKWARD))


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
    size = _largest_limit(scene)
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
                  steps_requested=requested, steps_used=scene.steps, t=cyc.t,
                  state=cyc.state if model is None else cyc.state[:, 0], seconds=seconds,
                  change=change, message="converged" if converged else "",
                  solver_stats=cyc.stats)
    if model is None:
        N = scene.N if cyc.t.size == scene.t.size else scene.N[[0, -1]]
        return SteadyState(W=float(W_cycles[-1]), W_cycles=W_cycles, v=cyc.u, F=cyc.F,
                           N=np.asarray(N), **common)
    # a single node is advanced in the units f P0 (force), f P0/k11 (displacement): J = Q̂1 Ŵ
    q1 = model.Q1_hat
    W_hat_cycles = W_cycles / q1 if q1 > 0 else np.zeros_like(W_cycles)
    v, F, N = model.series(cyc.u[:, 0], cyc.F[:, 0], scene.N[:, 0])
    return SteadyState(W=float(model.W(W_hat_cycles[-1])),
                       W_cycles=np.atleast_1d(model.W(W_hat_cycles)), v=v, F=F, N=N,
                       normalization=model.normalization(), W_hat_cycles=W_hat_cycles, **common)
