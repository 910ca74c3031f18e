"""The stepper contract.

Whoever adds a time-stepping method implements a subclass of :class:`Stepper`:

1. ``name``: the registry name users type (``"explicit"``, ``"clarabel"``, ...), and
   ``kind = "time-stepper"``.
2. ``check(scene)``: raise :class:`~lcpfric.errors.InputError` when the method cannot treat the
   scene's model (a cone it cannot express, a stiffness it has no closed form for, a model it
   does not solve), naming the methods that can. Never approximate silently. A stepper of
   discrete systems implements ``check_system(system)``; the base refuses continuum contacts.
3. ``init(scene, u0)``: build everything that depends on the scene (solver problems,
   factorizations) and return the initial :class:`~lcpfric.results.StepState` at
   ``scene.t[0]``, with all of it in ``state.data``. The stepper object itself keeps nothing
   about a scene: one instance serves any number of scenes.
4. ``step(scene, k, state)``: return a new state at ``scene.t[k+1]`` from the state at
   ``scene.t[k]``, without changing the state passed in. ``dW`` is the dissipation
   ``-∫ F · du`` of the increment (:mod:`~lcpfric.steppers.dissipation` for a stepper that
   knows only the increment's ends), and ``F = Q(t_{k+1}) + K u`` must hold.
5. ``cycle(scene, state, history=True)`` (optional): run ``step`` for k = 0..N-1 and collect
   the cycle (with ``history=False`` only its ends and each unknown's range: see
   :class:`~lcpfric.results.CycleResult`). The default loops over ``step``; a stepper may
   override it with a faster loop of the same meaning (tested equal to the step-by-step loop);
   one that cannot run without the history omits the parameter, and the driver says so.
6. ``stats(state)``: the statistics to report (solves, events), from the state.
7. ``restart(scene, state, u)`` (optional): the state at the cycle's start with the
   displacements (slips) u, where the driver's acceleration moves a cycle's start
   (:mod:`lcpfric.periodic.acceleration`). The default puts the forces back inside the friction
   cone (``F = Π(Q + K u)``, ``u = K⁻¹ (F - Q)``).
8. ``cycle_measure``: ``"cycles"`` (the default: a cycle's recorded instants against the
   previous cycle's) or ``"map"`` (the cycle's end against its start, on the scene's ``held``
   unknowns: the continuum contacts, :mod:`.continuum`): how the driver measures a cycle's
   change (:mod:`lcpfric.periodic.measure`).

A stepper's state may hold caches (factorizations, blocks of K) reused from cycle to cycle;
they change the answers by round-off only. The periodic driver (:mod:`lcpfric.periodic`) owns
the loop over cycles. Options a stepper
accepts are the keyword arguments of its constructor; an unknown one raises
:class:`~lcpfric.errors.InputError` naming the valid ones
(:func:`lcpfric.methods.check_options`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..methods import methods_for
from ..results import CycleResult, State, StepState

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..model import ContactSystem
    from ..scene import Scene

__all__ = ["Stepper", "StepState", "TIME_STEPPER", "Recorder", "inside"]

TIME_STEPPER = "time-stepper"


class Stepper:
    """Base class of time-stepping methods (see the module docstring for the contract).

    A subclass sets ``name`` and implements :meth:`step` and, for the scenes it cannot treat,
    :meth:`check_system`; it may override :meth:`init`, :meth:`cycle`, :meth:`restart` and
    :meth:`stats`, and set ``cycle_measure`` and ``can_restart``. Its options are the keyword
    arguments of its constructor (the base takes none).

    Attributes
    ----------
    name : str
        The registry name users type (``"explicit"``, ``"clarabel"``, ...).
    kind : str
        ``"time-stepper"``.
    cycle_measure : str
        ``"cycles"`` (a cycle's recorded instants against the previous cycle's) or ``"map"``
        (the cycle's end against its start, on the scene's ``held`` unknowns): how the driver
        measures a cycle's change (:mod:`lcpfric.periodic.measure`).
    can_restart : bool
        Whether :meth:`restart` can move a cycle's start (the driver then accelerates).
    """

    name: str = ""
    kind: str = TIME_STEPPER
    cycle_measure = "cycles"
    #: whether :meth:`restart` can move a cycle's start (the driver then accelerates)
    can_restart = True

    def __init__(self) -> None:
        pass

    @property
    def label(self) -> str:
        """The name to report (``"qpsolvers:proxqp"``, where a solver is chosen)."""
        return self.name

    def check(self, scene: Scene) -> None:
        """Raise InputError if this stepper cannot treat the scene's model.

        Never approximate silently: a cone the stepper cannot express, a stiffness it has no
        closed form for, a model it does not solve are refused, naming the methods that can.
        The base refuses continuum contacts (a scene without a ``system``) and passes a
        discrete system to :meth:`check_system`.

        Parameters
        ----------
        scene : Scene
            The scene to solve.

        Raises
        ------
        lcpfric.errors.InputError
            ``method``: the stepper cannot treat the scene's model.
        """
        if scene.system is None:
            what = type(scene.model).__name__
            raise InputError(
                "method",
                f"{self.label!r} solves discrete systems (SingleNode, "
                f"ContactSystem), not {what}; methods for {what}: "
                f"{', '.join(methods_for(scene.model))}, or solve its "
                f"ContactSystem, steady_state(model.system(), "
                f"{self.label!r}) (k_support > 0)",
            )
        self.check_system(scene.system)

    def check_system(self, system: ContactSystem) -> None:
        """Raise InputError if this stepper cannot treat ``system``.

        The base accepts every discrete system; a stepper overrides it to refuse what it
        cannot treat.

        Parameters
        ----------
        system : ContactSystem
            The discrete system to solve (a single node's too).

        Raises
        ------
        lcpfric.errors.InputError
            ``method``: the stepper cannot treat the system (never in the base).
        """

    def restart(self, scene: Scene, state: StepState, u: np.ndarray) -> StepState:
        """The state with the displacements u at the cycle's start, its forces in the cone.

        The forces are put back inside the friction cone (:func:`inside`). Called where the driver's
        acceleration moves a cycle's start (:mod:`lcpfric.periodic.acceleration`); a stepper whose
        state holds more than ``u`` and ``F`` overrides it.

        Parameters
        ----------
        scene : Scene
            The scene.
        state : StepState
            The state at the cycle's start (not changed).
        u : (m,) ndarray
            The displacements (slips) to start from.

        Returns
        -------
        StepState
            ``state`` with ``F = Π(Q + K u)`` and ``u = K⁻¹ (F - Q)`` at ``scene.t[0]``.
        """
        from dataclasses import replace

        u, F = inside(u, scene)
        return replace(state, u=u, F=F)

    def init(self, scene: Scene, u0: ArrayLike | None = None) -> StepState:
        """The initial state at ``scene.t[0]``.

        A stepper builds here everything that depends on the scene (solver problems,
        factorizations) and keeps all of it in ``state.data``: the stepper object itself keeps
        nothing about a scene, and one instance serves any number of scenes.

        Parameters
        ----------
        scene : Scene
            A discrete system's scene.
        u0 : (m,) array_like, optional
            The initial tangential displacements (default zero).

        Returns
        -------
        StepState
            ``u = u0``, ``F = Q(t_0) + K u``, each node sticking (N > 0) or separated, no
            ``data`` in the base.
        """
        system = scene.system
        u = np.zeros(system.m) if u0 is None else np.array(u0, dtype=float).reshape(system.m)
        F = scene.Q[0] + system.stiffness_times(u)
        state = np.where(scene.N[0] > 0.0, State.STICK, State.SEPARATION).astype(np.int8)
        return StepState(u=u, F=F, state=state)

    def step(
        self, scene: Scene, k: int, state: StepState
    ) -> StepState:  # pragma: no cover - abstract
        """Increment k: a new state at ``scene.t[k+1]`` from the state at ``scene.t[k]``.

        Each stepper implements it (the base raises :class:`NotImplementedError`), without
        changing the state passed in. ``dW`` of the new state is the dissipation
        ``-∫ F · du`` of the increment (:mod:`~lcpfric.steppers.dissipation` for a stepper
        that knows only the increment's ends), and ``F = Q(t_{k+1}) + K u`` must hold.

        Parameters
        ----------
        scene : Scene
            The scene :meth:`init` was given.
        k : int
            The increment, ``0 <= k < scene.steps``.
        state : StepState
            The state at ``scene.t[k]``.

        Returns
        -------
        StepState
            The state at ``scene.t[k+1]``.

        Raises
        ------
        lcpfric.errors.SolverError
            A stepper whose increment fails (a solver, an event loop that does not settle).
        """
        raise NotImplementedError

    def cycle(
        self, scene: Scene, state: StepState, history: bool = True
    ) -> tuple[StepState, CycleResult]:
        """Run one cycle from ``state`` at ``scene.t[0]``.

        With ``history=False`` only its ends and ranges are kept.

        The default loops over :meth:`step` for k = 0..N-1; a stepper may override it with a
        faster loop of the same meaning (tested equal to the step-by-step loop). One that
        cannot run without the history omits the parameter, and the driver says so.

        Parameters
        ----------
        scene : Scene
            The scene :meth:`init` was given.
        state : StepState
            The state at the cycle's start.
        history : bool
            Keep every instant (default); False keeps the first and last instants and each
            unknown's range (O(m) memory, whatever the number of steps; see
            :class:`~lcpfric.results.CycleResult`).

        Returns
        -------
        end : StepState
            The state at the cycle's end.
        cycle : CycleResult
            The cycle's series, its dissipation ``W`` (the sum of the increments' ``dW``) and
            :meth:`stats` of the end state.

        Raises
        ------
        lcpfric.errors.SolverError
            From :meth:`step`.
        """
        steps = scene.steps
        record = Recorder(scene, state, history)
        W = 0.0
        for k in range(steps):
            state = self.step(scene, k, state)
            record(k + 1, state.u, state.F, state.state)
            W += state.dW
        return state, record.result(W, self.stats(state))

    def stats(self, state: StepState) -> dict[str, Any]:
        """Backend statistics for the result (iterations, refinements, ...).

        Parameters
        ----------
        state : StepState
            A state this stepper made.

        Returns
        -------
        dict
            The statistics to report (solves, events), from the state; empty in the base.
        """
        return {}


class Recorder:
    """Collects a cycle's series: every instant (``history=True``), or only the first and the
    last with each unknown's running range (``history=False``: O(m) memory, whatever the
    number of steps)."""

    def __init__(self, scene, state: StepState, history: bool = True):
        steps, m, n = scene.steps, scene.m, scene.n
        self.history = history
        rows = steps + 1 if history else 2
        self.t = scene.t if history else scene.t[[0, -1]]
        self.U = np.empty((rows, m))
        self.F = np.empty_like(self.U)
        self.S = np.empty((rows, n), dtype=np.int8)
        self.U[0], self.F[0], self.S[0] = state.u, state.F, state.state
        if not history:
            self.lo, self.hi = state.u.copy(), state.u.copy()

    def __call__(self, k: int, u, F, s) -> None:
        if self.history:
            self.U[k], self.F[k], self.S[k] = u, F, s
            return
        self.U[1], self.F[1], self.S[1] = u, F, s
        np.minimum(self.lo, u, out=self.lo)
        np.maximum(self.hi, u, out=self.hi)

    def result(self, W: float, stats: dict) -> CycleResult:
        span = None if self.history else self.hi - self.lo
        return CycleResult(self.t, self.U, self.F, self.S, W, stats, span)


def inside(u, scene):
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
