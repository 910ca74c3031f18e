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

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import boolean, byte_budget, positive, positive_int
from ..errors import InputError
from ..results import CycleResult, StepState
from ..steppers.base import Stepper
from ..steppers.dissipation import increment_dissipation
from .coupled import CoupledIncrements, CoupledPlan
from .plan import ScenePlan
from .problem import DEFAULT_PLAN_BUDGET, IncrementProblem
from .settings import CONIC_METHODS
from .increments import Increments
from .interface import SolverInterface, quiet
from .scalar import ScalarCycle

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..model import ContactSystem
    from ..scene import Scene

__all__ = ["ConvexStepper", "ConvexData", "quiet"]


@dataclass(frozen=True)
class ConvexData:
    """What a convex backend carries in ``StepState.data``.

    Made by :meth:`ConvexStepper.init`; every later state holds the same plan and bounds, and
    its own ``stats``.

    Parameters
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
        the state (a new dict in every state); on a coupled system also
        ``fixed_point_iterations`` and ``fixed_point_max_ratio``
        (:mod:`~lcpfric.backends.coupled`).
    coupled : CoupledPlan or None
        A coupled system's block B, normal loads and contraction bound (None: uncoupled).

    Attributes
    ----------
    plan, bdata, stats, coupled
        The parameters, as given.
    """

    plan: ScenePlan
    bdata: list
    stats: dict
    coupled: CoupledPlan | None = None


class ConvexStepper(SolverInterface, Increments, CoupledIncrements, ScalarCycle, Stepper):
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
        Largest residual accepted (relative to the problem scale), > 0.
    active_tol : float
        δ / s_F of the active-set identification, > 0.
    locate_events : bool
        On coupled d = 1 systems, split an increment at the instant where a node starts to
        slip when the single projection cannot be exact there (see ``_increment`` in the
        source): one more convex problem per event, and second order instead of first.
    plan_budget : float
        Bytes the scene's plan may hold for its contact sets' problems (``C_AA``, ``C[:, A]``,
        the refinement's operators and :meth:`handle_bytes` of each solver object), at least 1
        (``math.inf``: no bound; default :data:`~lcpfric.backends.problem.DEFAULT_PLAN_BUDGET`,
        256 MiB). The least recently used problems are dropped, and built again when their set
        comes back (the solver starting cold), so a scene whose contact set changes at every
        step runs in bounded memory; the problem in use is always kept. See
        :mod:`~lcpfric.backends.problem`.
    fixed_point_tol : float
        A coupled system (``N = P + B u``): the fixed point on the normal reactions stops when
        an iteration changes u by at most this times ``c · s_F``, > 0 (default 1e-13; see
        :mod:`~lcpfric.backends.coupled`).
    fixed_point_max : int
        A coupled system: convex solves allowed per fixed point (default 100); beyond, a
        :class:`~lcpfric.errors.SolverError` with status ``"coupled_fixed_point"``.
    pattern_steps : bool
        A coupled system: take the fixed point on each answer's stick/slip pattern as the next
        iterate (default True; two solves per piece when the pattern is right), falling back
        to plain fixed-point steps when they do not pay.
    **settings
        Solver settings, overriding lcpfric's tight defaults
        (:data:`~lcpfric.backends.settings.TIGHT_SETTINGS`). They are checked by the solver
        when the first problem is built (:meth:`init`).

    Attributes
    ----------
    name : str
        Registry name (class attribute).
    can_soc : bool
        Whether the backend expresses the d = 2 cone (class attribute).
    STATUS_MAP : dict
        The solver's own statuses -> lcpfric's (:mod:`~lcpfric.backends.status`); an unknown
        status is :data:`~lcpfric.backends.status.UNKNOWN` (class attribute).
    settings_key : str
        The backend's entry in :data:`~lcpfric.backends.settings.TIGHT_SETTINGS` ("": the
        name).
    handle_size : tuple of int
        Bytes of a solver object per entry of the upper triangle of P, and per object (for
        :meth:`handle_bytes`).
    solver : str or None
        The solver of a ``:<solver>`` backend (``"proxqp"`` of ``"qpsolvers:proxqp"``).
    refine, check_tol, active_tol, locate_events, plan_budget, fixed_point_tol, fixed_point_max,
    pattern_steps
        The options, as checked.
    user_settings : dict
        The user's solver settings (``**settings``).

    Raises
    ------
    lcpfric.errors.InputError
        ``refine``, ``locate_events`` or ``pattern_steps`` not a bool, ``check_tol``,
        ``active_tol`` or ``fixed_point_tol`` not a finite number > 0, ``fixed_point_max`` not
        an integer >= 1, ``plan_budget`` not a number >= 1 (or ``math.inf``).
    """

    def __init__(
        self,
        *,
        refine: bool = True,
        check_tol: float = 1e-6,
        active_tol: float = 1e-6,
        locate_events: bool = True,
        plan_budget: float = DEFAULT_PLAN_BUDGET,
        fixed_point_tol: float = 1e-13,
        fixed_point_max: int = 100,
        pattern_steps: bool = True,
        **settings: Any,
    ) -> None:
        self.refine = boolean("refine", refine)
        self.locate_events = boolean("locate_events", locate_events)
        self.check_tol = positive("check_tol", check_tol)
        self.active_tol = positive("active_tol", active_tol)
        self.plan_budget = byte_budget("plan_budget", plan_budget)
        self.fixed_point_tol = positive("fixed_point_tol", fixed_point_tol)
        self.fixed_point_max = positive_int("fixed_point_max", fixed_point_max)
        self.pattern_steps = boolean("pattern_steps", pattern_steps)
        self.user_settings = dict(settings)

    # -- the stepper contract ----------------------------------------------------------------
    def check_system(self, system: ContactSystem) -> None:
        """Refuse a system whose cone the backend cannot express.

        Parameters
        ----------
        system : ContactSystem
            The discrete system to solve.

        Raises
        ------
        lcpfric.errors.InputError
            ``method``: d = 2 and the backend solves QPs only (``can_soc`` false); the
            message names the methods that can (:data:`~lcpfric.backends.CONIC_METHODS`).
        """
        if system.dims == 2 and not self.can_soc:
            raise InputError(
                "method",
                f"{self.label!r} solves QPs only and cannot express the "
                f"d = 2 friction cone (a disc per node); use "
                f"{CONIC_METHODS}",
            )

    def init(self, scene: Scene, u0: ArrayLike | None = None) -> StepState:
        """The initial state at ``scene.t[0]``, with the scene's plan.

        Builds the :class:`~lcpfric.backends.problem.ScenePlan` and the first step's problem
        now, so that the backend's settings are checked before any step.

        Parameters
        ----------
        scene : Scene
            A discrete system's scene.
        u0 : (m,) array_like, optional
            The initial tangential displacements (default zero).

        Returns
        -------
        StepState
            ``u = u0``, ``F = Q(t_0) + K u``, the nodes sticking or separated, and
            :class:`ConvexData` in ``data``.

        Raises
        ------
        lcpfric.errors.InputError
            The backend cannot express the system's cone (:meth:`check_system`), the loads on
            the grid are not finite, or the solver does not take a setting.
        lcpfric.errors.SolverError
            The solver failed to build the first problem.
        """
        self.check_system(scene.system)
        plan = ScenePlan(scene, self._build, self.handle_bytes, self.plan_budget)
        # the first step's problem now: the backend's settings are checked before any step
        first = np.flatnonzero(plan.contact[1:].any(axis=1))
        if first.size:
            plan.problem(int(first[0]) + 1)
        stats = {
            "solves": 0,
            "refined": 0,
            "unrefined": 0,
            "max_residual": 0.0,
            "events": 0,
            **plan.problems.counts(),
        }
        coupled = CoupledPlan.of(scene)
        if coupled is not None:
            stats.update(fixed_point_iterations=0, fixed_point_max_ratio=0.0)
        data = ConvexData(plan, [None] * len(plan.node_bounds), stats, coupled)
        return replace(super().init(scene, u0), data=data)

    def _build(self, prob: IncrementProblem):
        """The solver object of a new problem (the plan's ``build``)."""
        return self.guarded(self.build, prob, self.settings_for(prob.dims))

    def bounds_at(self, data: ConvexData, prob: IncrementProblem, j: int) -> Any:
        """The bounds of a grid instant in the backend's form, made on first use.

        Parameters
        ----------
        data : ConvexData
            The state's data (its ``bdata`` is filled in place).
        prob : IncrementProblem
            The problem of the instant's contact set.
        j : int
            The grid instant.

        Returns
        -------
        Any
            :meth:`bounds` of the instant's limits, kept in ``data.bdata[j]``.
        """
        bdata = data.bdata[j]
        if bdata is None:
            bdata = data.bdata[j] = self.bounds(prob, data.plan.node_bounds[j])
        return bdata

    def step(self, scene: Scene, k: int, state: StepState) -> StepState:
        """Increment k: the state at ``scene.t[k+1]`` from the state at ``scene.t[k]``.

        Problem (P) to t_{k+1}, refined and checked; on a coupled d = 1 system whose answer
        cannot be the exact end state, split at its events (``locate_events``).

        Parameters
        ----------
        scene : Scene
            The scene :meth:`init` was given.
        k : int
            The increment, ``0 <= k < scene.steps``.
        state : StepState
            The state at ``scene.t[k]`` (not changed).

        Returns
        -------
        StepState
            The new state, its ``dW`` the increment's dissipation and its ``data`` the same
            plan with updated stats.

        Raises
        ------
        lcpfric.errors.SolverError
            The solver failed, its status is not solved, or the answer fails the residual
            checks (``check_tol``), equilibrium included.
        """
        data = state.data
        stats = dict(data.stats)
        u1, F1, extra = self._increment(data, scene, k, state.u, state.F, stats)
        stats.update(data.plan.problems.counts())
        rows = np.array([k + 1])
        self._check_equilibrium(data.plan, scene, rows, u1[None, :], F1[None, :])
        du = u1 - state.u
        s = self._states(data.plan, rows, du[None, :])[0]
        return StepState(
            u1,
            F1,
            s,
            increment_dissipation(state.F, F1, du, data.plan.dims) + extra,
            replace(data, stats=stats),
        )

    def cycle(self, scene: Scene, state: StepState) -> tuple[StepState, CycleResult]:
        """One cycle from ``state`` at ``scene.t[0]``: :meth:`step` for every increment.

        The same answers as the step-by-step loop; the equilibrium checks, node states and
        dissipation are computed for the whole cycle at once, and a one-unknown scene runs in
        Python floats (:class:`~lcpfric.backends.scalar.ScalarCycle`). The whole history is
        kept (no ``history`` parameter: the driver refuses ``history=False``).

        Parameters
        ----------
        scene : Scene
            The scene :meth:`init` was given.
        state : StepState
            The state at the cycle's start.

        Returns
        -------
        end : StepState
            The state at the cycle's end (``dW = 0``).
        cycle : CycleResult
            Every instant of the cycle, its dissipation and :meth:`stats`.

        Raises
        ------
        lcpfric.errors.SolverError
            As :meth:`step`, at the first increment that fails.
        """
        data = state.data
        plan = data.plan
        if plan.m == 1 and data.coupled is None:
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
        end = StepState(U[-1].copy(), Fs[-1].copy(), S[-1].copy(), 0.0, replace(data, stats=stats))
        return end, CycleResult(scene.t, U, Fs, S, W, self.stats(end))

    def stats(self, state: StepState) -> dict[str, Any]:
        """The backend's statistics, from a state.

        Parameters
        ----------
        state : StepState
            A state this backend made.

        Returns
        -------
        dict
            A copy of :attr:`ConvexData.stats`: ``solves``, ``refined``, ``unrefined``,
            ``max_residual``, ``events``, ``plans_built``, ``plans_evicted``,
            ``plan_peak_bytes``.
        """
        return dict(state.data.stats)
