"""The stepper contract.

Whoever adds a time-stepping method implements a subclass of :class:`Stepper`:

1. ``name``: the registry name users type (``"explicit"``, ``"clarabel"``, ...), and
   ``kind = "time-stepper"``.
2. ``check(system)``: raise :class:`~lcpfric.errors.InputError` when the method cannot treat the
   system (a cone it cannot express, a stiffness it has no closed form for), naming the methods
   that can. Never approximate silently.
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

The periodic driver (:mod:`lcpfric.periodic`) owns the loop over cycles. Options a stepper
accepts are the keyword arguments of its constructor; an unknown one raises
:class:`~lcpfric.errors.InputError` naming the valid ones (:func:`check_options`).
"""

from __future__ import annotations

import inspect

import numpy as np

from ..errors import InputError
from ..results import CycleResult, State, StepState

__all__ = ["Stepper", "StepState", "TIME_STEPPER", "check_options", "Recorder"]

TIME_STEPPER = "time-stepper"


def check_options(cls, options: dict, what: str) -> None:
    """Raise InputError for keyword options that ``cls``'s constructor does not take (unless it
    takes ``**settings``, passed on to a solver that checks them itself)."""
    params = inspect.signature(cls.__init__).parameters
    if any(p.kind is p.VAR_KEYWORD for p in params.values()):
        return
    valid = sorted(n for n, p in params.items()
                   if n != "self" and p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD))
    unknown = sorted(set(options) - set(valid))
    if unknown:
        raise InputError(unknown[0], f"is not an option of {what}; valid options: "
                                     f"{', '.join(valid) if valid else 'none'}")


class Stepper:
    """Base class of time-stepping methods (see the module docstring for the contract)."""

    name: str = ""
    kind: str = TIME_STEPPER

    def __init__(self):
        pass

    @property
    def label(self) -> str:
        """The name to report (``"qpsolvers:proxqp"``, where a solver is chosen)."""
        return self.name

    def check(self, system) -> None:
        """Raise InputError if this stepper cannot treat ``system``."""

    def init(self, scene, u0=None) -> StepState:
        system = scene.system
        u = np.zeros(system.m) if u0 is None else np.array(u0, dtype=float).reshape(system.m)
        F = scene.Q[0] + system.stiffness_times(u)
        state = np.where(scene.N[0] > 0.0, State.STICK, State.SEPARATION).astype(np.int8)
        return StepState(u=u, F=F, state=state)

    def step(self, scene, k: int, state: StepState) -> StepState:  # pragma: no cover - abstract
        raise NotImplementedError

    def cycle(self, scene, state: StepState,
              history: bool = True) -> tuple[StepState, CycleResult]:
        """Run one cycle from ``state`` at ``scene.t[0]`` (``history=False``: keep its ends
        and ranges only)."""
        steps = scene.steps
        record = Recorder(scene, state, history)
        W = 0.0
        for k in range(steps):
            state = self.step(scene, k, state)
            record(k + 1, state.u, state.F, state.state)
            W += state.dW
        return state, record.result(W, self.stats(state))

    def stats(self, state: StepState) -> dict:
        """Backend statistics for the result (iterations, refinements, ...)."""
        return {}


class Recorder:
    """Collects a cycle's series: every instant (``history=True``), or only the first and the
    last with each unknown's running range (``history=False``: O(m) memory, whatever the
    number of steps)."""

    def __init__(self, scene, state: StepState, history: bool = True):
        steps, m, n = scene.steps, scene.system.m, scene.system.n
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
