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
5. ``cycle(scene, state)`` (optional): run ``step`` for k = 0..N-1 and collect the cycle. The
   default loops over ``step``; a stepper may override it with a faster loop of the same meaning
   (tested equal to the step-by-step loop).
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

__all__ = ["Stepper", "StepState", "TIME_STEPPER", "check_options"]

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
        F = scene.Q[0] + system.stiffness @ u
        state = np.where(scene.N[0] > 0.0, State.STICK, State.SEPARATION).astype(np.int8)
        return StepState(u=u, F=F, state=state)

    def step(self, scene, k: int, state: StepState) -> StepState:  # pragma: no cover - abstract
        raise NotImplementedError

    def cycle(self, scene, state: StepState) -> tuple[StepState, CycleResult]:
        """Run one cycle from ``state`` at ``scene.t[0]``."""
        steps = scene.steps
        U = np.empty((steps + 1, scene.system.m))
        F = np.empty_like(U)
        S = np.empty((steps + 1, scene.system.n), dtype=np.int8)
        U[0], F[0], S[0] = state.u, state.F, state.state
        W = 0.0
        for k in range(steps):
            state = self.step(scene, k, state)
            U[k + 1], F[k + 1], S[k + 1] = state.u, state.F, state.state
            W += state.dW
        return state, CycleResult(scene.t, U, F, S, W, self.stats(state))

    def stats(self, state: StepState) -> dict:
        """Backend statistics for the result (iterations, refinements, ...)."""
        return {}
