"""The public base of the convex-solver backends: :class:`ConvexStepper`.

A backend solves problem (P) (:mod:`~lcpfric.backends.problem`) at every increment with its
solver; this class does everything else: the scene's plan (the problems of its contact sets,
built on first use and held under the byte budget ``plan_budget``), the independent checks of
every answer (:mod:`~lcpfric.backends.checks`), the active-set refinement
(:mod:`~lcpfric.backends.refine`), the node states and the dissipation. Everything that depends
on a scene lives in the state (:class:`ConvexData`), so one backend instance serves any number
of scenes.

Writing a backend (see also ``docs/architecture.md``): subclass :class:`ConvexStepper`, set
``name``, ``can_soc`` and ``STATUS_MAP`` (its statuses onto :mod:`~lcpfric.backends.status`),
optionally ``settings_key`` (its entry in :data:`~lcpfric.backends.settings.TIGHT_SETTINGS`),
and implement ``build``, ``solve`` and, if its bounds are not a box ``(-b, b)``, ``bounds``;
``handle_bytes`` if the default estimate of its solver object's size does not fit.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace

import numpy as np

from .._checks import boolean, byte_budget, positive
from ..errors import InputError, SolverError
from ..results import CycleResult, State, StepState
from ..steppers.base import Stepper
from ..steppers.dissipation import increment_dissipation
from .checks import worst
from .refine import accept
from ..steppers.rates import first_event, path_is_exact
from .problem import DEFAULT_PLAN_BUDGET, IncrementProblem, ScenePlan
from .settings import CONIC_METHODS, settings_for
from .scalar import ScalarCycle
from .status import UNKNOWN, advice

__all__ = ["ConvexStepper", "ConvexData", "quiet"]


@dataclass(frozen=True)
class ConvexData:
    """What a convex backend carries in ``StepState.data``.

    Attributes
    ----------
    plan : ScenePlan
        The scene's plan: its problems, with their solver objects (``prob.handle``), are built
        on first use and held under the backend's ``plan_budget``.
    bdata : list
        Per grid instant, the bounds in the backend's own form (``bounds(prob, b)``), filled on
        first use (None before).
    stats : dict
        ``solves``, ``refined``, ``unrefined``, ``max_residual`` and ``events`` so far, and the
        plan's ``plans_built``, ``plans_evicted`` and ``plan_peak_bytes`` (bytes) at the time of
        the state (a new dict in every state).
    """

    plan: ScenePlan
    bdata: list
    stats: dict


class ConvexStepper(ScalarCycle, Stepper):
    """A stepper that solves problem (P) with a convex solver at every increment.

    A backend subclass sets ``name`` (registry name), ``can_soc`` (whether it expresses the d = 2
    cone), ``STATUS_MAP`` and, where it differs from the name, ``settings_key`` (its entry in
    :data:`~lcpfric.backends.settings.TIGHT_SETTINGS`), and implements:

    ``build(prob, settings)``
        Build the solver object for an :class:`IncrementProblem` (called when the plan builds
        the problem of a contact set, with the settings for its d) and return it; it is stored
        as ``prob.handle``. A set whose problem was dropped from the plan is built again: the
        object must not rely on an earlier one (it starts cold).
    ``bounds(prob, b)``
        Turn the limits ``b`` (one per node of the set) into whatever the backend's update
        takes (called once per grid instant, and kept: it must not refer to ``prob``).
        Default: the box ``(-b, b)``.
    ``solve(prob, q, bdata) -> (x, status, ok)``
        Update the linear term and the bounds, solve, and return the forces, the backend's own
        status and whether that status means solved.
    ``handle_size`` or ``handle_bytes(prob)`` (optional)
        The estimated bytes of the solver object of ``prob``, counted in the plan's budget
        before it is built: by default ``handle_size = (per entry of the upper triangle of P,
        per object)``, measured for each solver; a backend whose object does not scale so
        overrides ``handle_bytes``.

    Parameters
    ----------
    refine : bool
        Refine the solver's answers on their active set (see :mod:`~lcpfric.backends.refine`).
    check_tol : float
        Largest residual accepted (relative to the problem scale).
    active_tol : float
        δ / s_F of the active-set identification.
    locate_events : bool
        On coupled d = 1 systems, split an increment at the instant where a node starts to
        slip when the single projection cannot be exact there (see :meth:`_increment`): one
        more convex problem per event, and second order instead of first.
    plan_budget : float
        Bytes the scene's plan may hold for its contact sets' problems (``C_AA``, ``C[:, A]``,
        the refinement's operators and :meth:`handle_bytes` of each solver object), at least 1
        (``math.inf``: no bound; default :data:`~lcpfric.backends.problem.DEFAULT_PLAN_BUDGET`,
        256 MiB). The least recently used problems are dropped, and built again when their set
        comes back (the solver starting cold), so a scene whose contact set changes at every
        step runs in bounded memory; the problem in use is always kept. See
        :mod:`~lcpfric.backends.problem`.
    **settings
        Solver settings, overriding lcpfric's tight defaults.
    """

    name = ""
    can_soc = False
    STATUS_MAP: dict[str, str] = {}
    settings_key = ""  # key into TIGHT_SETTINGS (default: the name)
    # the size of a solver object, for the plan's budget: bytes per entry of the upper triangle
    # of P (its copies of P, its KKT system, the factor) and per object
    handle_size: tuple[int, int] = (64, 128 * 1024)
    solver: str | None = None  # the solver of a ':<solver>' backend

    def __init__(self, *, refine: bool = True, check_tol: float = 1e-6,
                 active_tol: float = 1e-6, locate_events: bool = True,
                 plan_budget: float = DEFAULT_PLAN_BUDGET, **settings):
        self.refine = boolean("refine", refine)
        self.locate_events = boolean("locate_events", locate_events)
        self.check_tol = positive("check_tol", check_tol)
        self.active_tol = positive("active_tol", active_tol)
        self.plan_budget = byte_budget("plan_budget", plan_budget)
        self.user_settings = dict(settings)

    @property
    def label(self) -> str:
        return f"{self.name}:{self.solver}" if self.solver else self.name

    def settings_for(self, dims: int) -> dict:
        """The solver settings for problems with d = ``dims``: lcpfric's tight defaults, then
        the user's."""
        return settings_for(self.settings_key or self.name, dims, self.user_settings)

    @property
    def settings(self) -> dict:
        """The settings for d = 1 problems."""
        return self.settings_for(1)

    # -- the backend interface (see the class docstring) ------------------------------------
    def build(self, prob: IncrementProblem, settings: dict):  # pragma: no cover - abstract
        raise NotImplementedError

    def bounds(self, prob: IncrementProblem, b: np.ndarray):
        """The box ``(l, u) = (-b, b)`` of d = 1 (QP backends); conic backends override it."""
        return -b, b.copy()

    def solve(self, prob: IncrementProblem, q: np.ndarray, bdata):  # pragma: no cover
        raise NotImplementedError

    def handle_bytes(self, prob: IncrementProblem) -> int:
        """Estimated bytes of the solver object of ``prob`` (counted in the plan's budget), from
        ``handle_size``: bytes per entry of the upper triangle of P, and per object."""
        per_entry, per_object = self.handle_size
        return per_entry * prob.triu_nnz + per_object

    def status_category(self, status) -> str:
        """lcpfric's status (SOLVED, MAX_ITER, ...) for the backend's own ``status``."""
        return self.STATUS_MAP.get(str(status), UNKNOWN)

    # -- the stepper contract ----------------------------------------------------------------
    def check_system(self, system) -> None:
        if system.dims == 2 and not self.can_soc:
            raise InputError("method", f"{self.label!r} solves QPs only and cannot express the "
                                       f"d = 2 friction cone (a disc per node); use "
                                       f"{CONIC_METHODS}")

    def init(self, scene, u0=None) -> StepState:
        self.check_system(scene.system)
        plan = ScenePlan(scene, self._build, self.handle_bytes, self.plan_budget)
        # the first step's problem now: the backend's settings are checked before any step
        first = np.flatnonzero(plan.contact[1:].any(axis=1))
        if first.size:
            plan.problem(int(first[0]) + 1)
        stats = {"solves": 0, "refined": 0, "unrefined": 0, "max_residual": 0.0, "events": 0,
                 **plan.problems.counts()}
        data = ConvexData(plan, [None] * len(plan.node_bounds), stats)
        return replace(super().init(scene, u0), data=data)

    def _build(self, prob: IncrementProblem):
        """The solver object of a new problem (the plan's ``build``)."""
        return self.guarded(self.build, prob, self.settings_for(prob.dims))

    def bounds_at(self, data: ConvexData, prob: IncrementProblem, j: int):
        """The bounds of grid instant j in the backend's form, made on first use."""
        bdata = data.bdata[j]
        if bdata is None:
            bdata = data.bdata[j] = self.bounds(prob, data.plan.node_bounds[j])
        return bdata

    def guarded(self, fn, *args):
        """Call a backend function, re-raising the backend's own exceptions as SolverError."""
        try:
            return fn(*args)
        except (SolverError, InputError):
            raise
        except Exception as exc:  # the backend's own error types vary
            raise SolverError(f"{self.label}: the solver failed: {type(exc).__name__}: {exc}",
                              backend=self.label, status=type(exc).__name__) from exc

    def step(self, scene, k, state):
        data = state.data
        stats = dict(data.stats)
        u1, F1, extra = self._increment(data, scene, k, state.u, state.F, stats)
        stats.update(data.plan.problems.counts())
        rows = np.array([k + 1])
        self._check_equilibrium(data.plan, scene, rows, u1[None, :], F1[None, :])
        du = u1 - state.u
        s = self._states(data.plan, rows, du[None, :])[0]
        return StepState(u1, F1, s,
                         increment_dissipation(state.F, F1, du, data.plan.dims) + extra,
                         replace(data, stats=stats))

    def cycle(self, scene, state):
        data = state.data
        plan = data.plan
        if plan.m == 1:
            return self.cycle_scalar(scene, state)
        steps = scene.steps
        U = np.empty((steps + 1, plan.m))
        Fs = np.empty_like(U)
        U[0], Fs[0] = state.u, state.F
        u, F = state.u, state.F
        stats = dict(data.stats)
        increment = self._increment
        extra = 0.0  # the sub-increments' dissipation minus the whole increments' trapezoids
        for k in range(steps):
            u, F, dW = increment(data, scene, k, u, F, stats)
            U[k + 1] = u
            Fs[k + 1] = F
            extra += dW
        stats.update(plan.problems.counts())
        # what needs no solver is done for the whole cycle at once: the equilibrium check of
        # every increment, the node states and the dissipation
        rows = np.arange(1, steps + 1)
        self._check_equilibrium(plan, scene, rows, U[1:], Fs[1:])
        dU = np.diff(U, axis=0)
        S = np.empty((steps + 1, plan.n), dtype=np.int8)
        S[0] = state.state
        S[1:] = self._states(plan, rows, dU)
        W = increment_dissipation(Fs[:-1], Fs[1:], dU, plan.dims) + extra
        end = StepState(U[-1].copy(), Fs[-1].copy(), S[-1].copy(), 0.0,
                        replace(data, stats=stats))
        return end, CycleResult(scene.t, U, Fs, S, W, self.stats(end))

    def stats(self, state) -> dict:
        return dict(state.data.stats)

    # -- one increment, any size --------------------------------------------------------------
    def _increment(self, data: ConvexData, scene, k, u, F, stats):
        """Increment k from ``(u, F)`` at t_k: ``(u, F)`` at t_{k+1} and the dissipation to add
        to the increment's trapezoid (nonzero when it was split at events).

        One problem (P) to t_{k+1}; on a coupled d = 1 system whose answer is not the exact
        end state (:func:`~lcpfric.steppers.rates.path_is_exact`: a node slips at the end that
        did not at the start), the increment is split at its events
        (:mod:`~lcpfric.steppers.rates`), one problem (P) per sub-increment."""
        plan = data.plan
        u1, F1, limit = self._project(data, scene, k, u, stats)
        if (not self.locate_events or limit is None or plan.dims != 1 or plan.diagonal
                or path_is_exact(F, plan.bound[k], F1, limit, plan.separating[k + 1],
                                 plan.force_scale)):
            return u1, F1, 0.0
        # split at the events: the first one from the rates at the start, solve to it, and
        # again from there while the rest of the increment is not exact
        f = plan.friction
        Qk, Nk = plan.Q[k], plan.N[k]
        dQ, dN = plan.Q[k + 1] - Qk, plan.N[k + 1] - Nk
        sep = (Nk + plan.N[k + 1]) <= 0.0
        a, ua, Fa = 0.0, u, F
        W = 0.0
        for _ in range(4 * plan.n + 16):
            tau = first_event(plan.K, f, Fa, Qk + a * dQ, Nk + a * dN, dQ, dN, sep, a)
            if tau is None:
                break
            ub, Fb, _ = self._project(data, scene, k, ua, stats, tau)
            stats["events"] += 1
            W += increment_dissipation(Fa, Fb, ub - ua)
            a, ua, Fa = tau, ub, Fb
            u1, F1, limit = self._project(data, scene, k, ua, stats)
            if limit is None or path_is_exact(Fa, f * (Nk + a * dN), F1, limit,
                                              plan.separating[k + 1], plan.force_scale):
                break
        W += increment_dissipation(Fa, F1, u1 - ua)
        return u1, F1, W - increment_dissipation(F, F1, u1 - u)

    def _project(self, data: ConvexData, scene, k, u, stats, frac=None):
        """Solve, refine and check (P) from ``u`` to t_{k+1} (or, with ``frac``, to the instant
        ``t_k + frac (t_{k+1} - t_k)``, loads interpolated); return ``(u, F, limit)`` there,
        ``limit`` marking the nodes on their friction limit (None for an unrefined answer)."""
        plan = data.plan
        j = k + 1
        if frac is None:
            prob = plan.problem(j)
            if prob is None:  # everything separated: F = 0, u = -C Q
                return -plan.CQ[j], np.zeros(plan.m), None
            neg_CQ, b = plan.neg_CQ[j], plan.node_bounds[j]
            bdata = self.bounds_at(data, prob, j)
            CQ = plan.CQ[j]
        else:
            prob = plan.interior_problem(k)
            CQ = plan.CQ[k] + frac * (plan.CQ[j] - plan.CQ[k])
            neg_CQ = -(CQ if prob.full else CQ[prob.dofs])
            b = plan.bound[k, prob.nodes] + frac * (plan.bound[j, prob.nodes]
                                                    - plan.bound[k, prob.nodes])
            bdata = self.bounds(prob, b)
        q = prob.q
        np.subtract(neg_CQ, u if prob.full else u[prob.dofs], out=q)
        x, status, ok = self.guarded(self.solve, prob, q, bdata)
        stats["solves"] += 1
        if not ok:
            self.fail(scene, k, status, None)
        FA, stick, res, kind = accept(prob, np.array(x, dtype=float), q, b,
                                      refine=self.refine, active_tol=self.active_tol,
                                      check_tol=self.check_tol, fscale=plan.force_scale,
                                      cscale=plan.compliance_scale)
        if FA is None:
            self.fail(scene, k, status, res)
        stats[kind] += 1
        stats["max_residual"] = max(stats["max_residual"], worst(res))
        u1 = prob.Cf @ FA
        u1 -= CQ
        limit = None
        if stick is not None:  # a refined stick node keeps its displacement exactly
            st = prob.dofs[stick]
            u1[st] = u[st]
            if prob.dims == 1:
                limit = np.zeros(plan.n, dtype=bool)
                limit[prob.nodes[~stick]] = True
        if prob.full:
            return u1, FA, limit
        F1 = np.zeros(plan.m)
        F1[prob.dofs] = FA
        return u1, F1, limit

    def _check_equilibrium(self, plan, scene, rows, U, Fs):
        """``max |Q + K u - F| / s_F`` of the increments ending at ``rows``; raise on the first
        over ``check_tol``."""
        R = U @ plan.K  # K symmetric
        R += plan.Q[rows]
        R -= Fs
        eq = np.abs(R).max(axis=1) / plan.force_scale
        bad = np.flatnonzero(~(eq <= self.check_tol))
        if bad.size:
            i = bad[0]
            self.fail(scene, int(rows[i]) - 1, "solved", {"equilibrium": float(eq[i])})

    def _states(self, plan, rows, dU):
        """Node states over the increments ending at ``rows``, from their slips ``dU``."""
        eps = self.check_tol * plan.compliance_scale * plan.force_scale
        if plan.dims == 1:
            S = (dU > eps).view(np.int8)  # State.FORWARD is 1
            S[dU < -eps] = State.BACKWARD
        else:
            S = (np.hypot(dU[:, 0::2], dU[:, 1::2]) > eps).view(np.int8)
        S[~plan.contact[rows]] = State.SEPARATION
        return S

    def fail(self, scene, k, status, res):
        """Raise the SolverError of step k (status not solved, or residuals over tolerance)."""
        t0, t1 = scene.t[k], scene.t[k + 1]
        where = f"{self.label}: increment {k} (t = {t0:.6g} -> {t1:.6g})"
        if res is None:
            mapped = self.status_category(status)
            msg = (f"{where} ended with solver status {status!s} ({mapped}): "
                   f"{advice(mapped)}")
        else:
            bad = max(res, key=lambda r: math.inf if res[r] != res[r] else res[r])
            msg = (f"{where}: the solver reported {status!s} but its answer fails lcpfric's "
                   f"residual check ({bad} {res[bad]:.3g} > check_tol {self.check_tol:g}); "
                   f"tighten the solver's tolerances"
                   + ("" if self.refine else " or pass refine=True"))
            if any(v != v for v in res.values()):
                msg += " (the answer contains NaN: check the loads for NaN or inf)"
        raise SolverError(msg, backend=self.label, status=str(status), residuals=res)

    # -- one node, d = 1: the same step in float arithmetic -----------------------------------
def quiet(fn, *args, **kwargs):
    """Call ``fn`` with the backend's warnings silenced (lcpfric raises its own errors)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)
