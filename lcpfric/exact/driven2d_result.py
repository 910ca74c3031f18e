"""The result of :func:`lcpfric.exact.driven2d.driven_cycle_2d`: the steady cycle of a
displacement-driven Jenkins element in two tangential directions (:class:`DrivenCycle2D`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["DrivenCycle2D"]


@dataclass(frozen=True)
class DrivenCycle2D:
    """The steady periodic cycle of a displacement-driven Jenkins element in d = 2.

    Made by :func:`lcpfric.exact.driven2d.driven_cycle_2d`.

    Parameters
    ----------
    omega, t, x, N, T, slider, state, events, W, force_cos, force_sin, force_amplitude
        The cycle (see Attributes).
    cycles, converged, change, seconds
        How it was found (see Attributes).

    Attributes
    ----------
    omega : float
        The fundamental angular frequency; the period is 2π/ω.
    t : ndarray
        Instants over one period ``[0, 2π/ω]``: equally spaced samples and every event.
    x, T, slider : ndarray
        At ``t``, shape (2, len(t)): the motion X, the force ``T = kt (X - S)``, the slider S.
    N : ndarray
        The normal load ``max(0, N)`` at ``t``.
    state : ndarray of int8
        :class:`~lcpfric.results.State` at ``t``: STICK, FORWARD (slip, in any direction; as
        :func:`lcpfric.harmonic.jenkins_march` in d = 2) or SEPARATION.
    events : ndarray
        The instants in (0, 2π/ω) where the state changes.
    W : float
        The dissipation per cycle ``∮ μN |dS|``.
    force_cos, force_sin : ndarray
        Shape (2, harmonics + 1): ``T_i ≈ force_cos[i, 0] + Σ_k force_cos[i, k] cos kωt +
        force_sin[i, k] sin kωt`` (``force_sin[:, 0] = 0``); i = 0 for T_x, 1 for T_y.
    force_amplitude : float
        ``max |T|`` over the samples and events.
    cycles : int
        The cycles run from the start until the slider at t = 0 repeated.
    converged : bool
        True when it repeated within the tolerance.
    change : float
        The slider's change over the last cycle, relative to the slip scale μ max N / kt.
    seconds : float
        Wall time.
    """

    omega: float
    t: np.ndarray
    x: np.ndarray
    N: np.ndarray
    T: np.ndarray
    slider: np.ndarray
    state: np.ndarray
    events: np.ndarray
    W: float
    force_cos: np.ndarray
    force_sin: np.ndarray
    force_amplitude: float
    cycles: int
    converged: bool
    change: float
    seconds: float

    @property
    def first_harmonic(self) -> np.ndarray:
        """``[[A_x, B_x], [A_y, B_y]]``: ``T_i ≈ A_i cos ωt + B_i sin ωt`` (first harmonic)."""
        return np.stack((self.force_cos[:, 1], self.force_sin[:, 1]), axis=1)
