"""The stepper contract.

Whoever adds a method implements a subclass of :class:`Stepper`:

1. ``name``: the registry name users type (``"explicit"``, ``"clarabel"``, ...).
2. ``check(system)``: raise :class:`~lcpfric.errors.InputError` when the method cannot treat the
   system (a cone it cannot express, a stiffness it has no closed form for), naming the methods
   that can. Never approximate silently.
3. ``init(scene, u0)``: build everything that depends only on the scene (solver problems,
   factorizations) and return the initial :class:`StepState` at ``scene.t[0]``.
4. ``step(scene, k, state)``: return the state at ``scene.t[k+1]`` from the state at
   ``scene.t[k]``. The state is passed in and out explicitly; a stepper keeps no hidden state
   between calls other than what ``init`` built. ``dW`` is the dissipation ``-∫ F · du`` of the
   increment (:func:`slip_dissipation` for a stepper that knows only the increment's ends), and
   ``F = Q(t_{k+1}) + K u`` must hold.
5. ``cycle(scene, state)`` (optional): run ``step`` for k = 0..N-1 and collect the cycle. The
   default loops over ``step``; a stepper may override it with a faster loop of the same meaning.

The periodic driver (:mod:`lcpfric.periodic`) owns the loop over cycles.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..results import CycleResult

__all__ = ["Stepper", "StepState"]


@dataclass
class StepState:
    """The state at one grid instant.

    Attributes
    ----------
    u : (m,) ndarray
        Tangential displacements.
    F : (m,) ndarray
        Friction forces, ``Q + K u``.
    state : (n,) ndarray of int8
        Per node: 0 stick, 1 forward slip, 2 backward slip, 3 separation (over the increment
        that ended here).
    dW : float
        Dissipation of the increment that ended here.
    data : Any
        Stepper-specific data carried between steps (warm starts, statistics).
    """

    u: np.ndarray
    F: np.ndarray
    state: np.ndarray
    dW: float = 0.0
    data: Any = field(default=None)


class Stepper:
    """Base class of time-stepping methods (see the module docstring for the contract)."""

    name: str = ""

    def check(self, system) -> None:
        """Raise InputError if this stepper cannot treat ``system``."""

    def init(self, scene, u0=None) -> StepState:
        system = scene.system
        u = np.zeros(system.m) if u0 is None else np.array(u0, dtype=float).reshape(system.m)
        F = scene.Q[0] + _matvec(system.stiffness, u)
        return StepState(u=u, F=F, state=np.zeros(system.n, dtype=np.int8))

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


def _matvec(K, u):
    return K @ u


def slip_dissipation(F0, F1, du, dims: int = 1) -> float:
    """Dissipation of an increment known by its ends: ``Σ_i max(0, -½(F_i,k + F_i,k+1)·Δu_i)``.

    The trapezoidal rule for ``-∫ F · du`` (second order; it weighs a slip that ends an increment
    at separation by the small stick force it started from, which a rule in ``f N |Δu|`` would
    not), with each node's share clipped at zero: a node's dissipation is never negative, and
    only at a slip reversal inside an increment can the trapezoid dip below zero, by its own
    discretization error.
    """
    share = -0.5 * (F0 + F1) * du
    if dims != 1:
        share = np.reshape(share, (-1, dims)).sum(axis=1)
    return float(np.sum(np.maximum(share, 0.0)))