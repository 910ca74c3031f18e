"""Result types, one per level: a cycle (:class:`CycleResult`) and a steady state
(:class:`SteadyState`). Sweeps return an ``xarray.Dataset`` (see :mod:`lcpfric.sweep`)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

__all__ = ["CycleResult", "SteadyState", "State"]


class State:
    """Codes of the states of Eq. (3) in the ``state`` time series."""

    STICK = 0
    FORWARD = 1   # forward slip, dv/dt > 0, F = -f N
    BACKWARD = 2  # backward slip, dv/dt < 0, F = +f N
    SEPARATION = 3

    names = ("stick", "forward slip", "backward slip", "separation")


@dataclass
class CycleResult:
    """One cycle on the scene's grid, in the units the stepper works in.

    ``u`` and ``F`` have shape (N+1, m); ``state`` (N+1, n). ``W`` is ``-∮ F · du`` (trapezoidal
    in F over each increment, which is exact for the piecewise-linear histories the steppers
    produce between events).
    """

    t: np.ndarray
    u: np.ndarray
    F: np.ndarray
    state: np.ndarray
    W: float
    stats: dict = field(default_factory=dict)


@dataclass
class SteadyState:
    """The periodic steady state found by :func:`lcpfric.steady_state`.

    Attributes
    ----------
    W_hat : float or None
        Dimensionless dissipation per cycle Ŵ (Eq. 7) of a single node; None for a general system.
    W : float or None
        Dimensional dissipation per cycle (Eq. 5) where the scene is dimensional, else None.
    W_per_cycle : ndarray
        The dissipation of every cycle run (Ŵ for a single node, else W), in order.
    cycles : int
        Cycles run.
    converged : bool
        Whether v(t) over the last cycle repeated the previous cycle's within ``tol``.
    method : str
        Registry name of the method.
    steps_per_cycle : int
        Increments per cycle actually used (including inserted transition instants).
    t, v, F, N, state : ndarray
        The last cycle's time series (dimensional where the scene is; for a single node v, F, N
        are 1-D; for a general system v and F are (steps+1, m), N and state (steps+1, n)).
    seconds : float
        Wall time of the computation.
    change : float
        The last cycle-to-cycle change of v relative to its range (what ``tol`` is compared to).
    message : str
        What happened, in words.
    solver_stats : dict
        Backend statistics (iterations, refinements, statuses seen), where there are any.
    """

    W_hat: float | None
    W: float | None
    W_per_cycle: np.ndarray
    cycles: int
    converged: bool
    method: str
    steps_per_cycle: int
    t: np.ndarray
    v: np.ndarray
    F: np.ndarray
    N: np.ndarray
    state: np.ndarray
    seconds: float
    change: float = 0.0
    message: str = ""
    solver_stats: dict = field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.converged

    def summary(self) -> dict:
        """The scalar results as a JSON-serializable dict."""
        return {
            "W_hat": self.W_hat,
            "W": self.W,
            "method": self.method,
            "steps_per_cycle": self.steps_per_cycle,
            "cycles": self.cycles,
            "converged": self.converged,
            "change": self.change,
            "seconds": self.seconds,
            "message": self.message,
        }

    def to_json(self) -> str:
        return json.dumps(self.summary())

    def __repr__(self) -> str:
        head = f"W_hat={self.W_hat!r}" if self.W_hat is not None else f"W={self.W!r}"
        return (f"SteadyState({head}, method={self.method!r}, steps_per_cycle="
                f"{self.steps_per_cycle}, cycles={self.cycles}, converged={self.converged})")
