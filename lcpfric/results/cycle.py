"""What a stepper gives: the states of a node (:class:`State`), the state at one instant of the
grid (:class:`StepState`, passed into and returned by ``Stepper.step``) and one cycle on the
scene's grid (:class:`CycleResult`). Re-exported by :mod:`lcpfric.results`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

import numpy as np

__all__ = ["State", "StepState", "CycleResult"]


class State(IntEnum):  # the Enum API's arguments are not documented: numpydoc ignore=PR01
    """The states of a node (paper, Eq. 3), as stored in every ``state`` time series (int8).

    Parameters
    ----------
    value : int
        The code: ``State(1)`` is ``State.FORWARD``.

    Attributes
    ----------
    STICK, FORWARD, BACKWARD, SEPARATION : State
        0 stick; 1 forward slip (du/dt > 0, F = -f N); 2 backward slip (du/dt < 0, F = +f N);
        3 separation (N = 0, F = 0).
    """

    STICK = 0
    FORWARD = 1  # forward slip, du/dt > 0, F = -f N
    BACKWARD = 2  # backward slip, du/dt < 0, F = +f N
    SEPARATION = 3  # N = 0, F = 0

    @property
    def label(self) -> str:
        """The state in words (``"forward slip"``)."""
        return _LABELS[self]


_LABELS = {
    State.STICK: "stick",
    State.FORWARD: "forward slip",
    State.BACKWARD: "backward slip",
    State.SEPARATION: "separation",
}


@dataclass(frozen=True)
class StepState:
    """The state at one grid instant, passed into and returned by ``Stepper.step``.

    Parameters
    ----------
    u, F, state, dW, data
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    u : (m,) ndarray
        Tangential displacements.
    F : (m,) ndarray
        Friction forces, ``Q + K u``.
    state : (n,) ndarray of int8
        Per node, a :class:`State` code (over the increment that ended here).
    dW : float
        Dissipation of the increment that ended here.
    data : Any
        What the stepper carries from ``init`` (its matrices, solver objects, the scene's plan)
        and its statistics. Never shared between two states that a stepper may change.
    """

    u: np.ndarray
    F: np.ndarray
    state: np.ndarray
    dW: float = 0.0
    data: Any = field(default=None)


@dataclass(frozen=True)
class CycleResult:
    """One cycle on the scene's grid, in the units the stepper works in.

    ``u`` and ``F`` have shape (N+1, m); ``state`` (N+1, n). ``W`` is ``-∮ F · du``
    (:func:`lcpfric.steppers.dissipation.increment_dissipation` summed over the increments, or
    the exact integral between a stepper's events).

    A cycle run without its history (``history=False``, for systems too large to keep every
    instant) holds only the first and last instants in ``t``, ``u``, ``F`` and ``state``, and
    in ``span`` each unknown's range (max - min) over the whole cycle; with the history
    ``span`` is None (it is ``np.ptp(u, axis=0)``).

    ``memory`` is what the cycle remembers of its start, node by node (``(n, 2, 2)``, d = 2:
    :class:`lcpfric.steppers.slip_memory.SlipMemory`), for a stepper that tracks it during the
    cycle; None otherwise (the driver then takes it from the recorded cycle where it needs it).

    Parameters
    ----------
    t, u, F, state : ndarray
        The grid's instants and, at each, the displacements, forces and node states (above).
    W : float
        Dissipation of the cycle.
    stats : dict, optional
        The stepper's statistics over the cycle.
    span, memory : ndarray or None, optional
        As above. All are kept as the attributes of the same names.
    """

    t: np.ndarray
    u: np.ndarray
    F: np.ndarray
    state: np.ndarray
    W: float
    stats: dict = field(default_factory=dict)
    span: np.ndarray | None = None
    memory: np.ndarray | None = None

    @property
    def u_span(self) -> np.ndarray:
        """Each unknown's range over the cycle."""
        return np.ptp(self.u, axis=0) if self.span is None else self.span
