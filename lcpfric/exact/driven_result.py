"""The steady cycle of a displacement-driven Jenkins element (:class:`DrivenCycle`) and how it is
assembled from the cycle's segments, whoever found them (the event solver of :mod:`.driven` or
the exact single node, :mod:`.jenkins_node`).

On each segment the force is a trigonometric polynomial in θ = ωt: ``kt (x - w)`` in stick,
``±μ N`` in slip, 0 in separation. So everything is integrated in closed form, segment by segment
(:class:`~lcpfric.exact.trig.TrigPoly`): the Fourier coefficients of T, the dissipation

    forward slip (w = x - μN/kt rising, T = +μN):   ∫ T dw = +μ ∫ N x' dθ - (μ²/2kt) [N²]
    backward slip (w = x + μN/kt falling, T = -μN): ∫ T dw = -μ ∫ N x' dθ - (μ²/2kt) [N²]

and the largest |T| (at the segments' ends and at the extrema of x or N inside them).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..results import State
from .trig import TWO_PI, TrigPoly, periodic_sign_changes

__all__ = ["DrivenCycle", "assemble"]

STICK, FORWARD, BACKWARD, SEPARATION = (int(s) for s in State)


@dataclass(frozen=True)
class DrivenCycle:
    """The steady periodic cycle of a displacement-driven Jenkins element.

    Made by :func:`lcpfric.exact.driven.driven_cycle` (any trigonometric motion and normal
    load) or :func:`lcpfric.exact.jenkins_node.jenkins_cycle` (harmonic ones, through the exact
    single node).

    Parameters
    ----------
    omega, t, x, N, T, w, state, events, segments, W, force_cos, force_sin, force_amplitude
        The cycle (see Attributes).
    cycles, converged, change, method, seconds
        How it was found (see Attributes).

    Attributes
    ----------
    omega : float
        The fundamental angular frequency; the period is 2π/ω.
    t : ndarray
        Instants over one period ``[0, 2π/ω]``: equally spaced samples and every event.
    x, N, T, w : ndarray
        At ``t``: the motion, the normal load ``max(0, N)``, the tangential force
        ``T = kt (x - w)`` and the slider.
    state : ndarray of int8
        At ``t``, the :class:`~lcpfric.results.State` of the segment that starts there (or
        contains it): STICK; FORWARD (the slider moves in +x, ``T = +μN``); BACKWARD (in -x,
        ``T = -μN``); SEPARATION (N = 0, T = 0, the slider follows x).
    events : ndarray
        The instants in (0, 2π/ω) where the state changes.
    segments : tuple
        ``(t_start, t_end, state, w_start)`` of each segment, in order, covering one period.
    W : float
        The dissipation per cycle, ``∮ T dw = ∮ T dx`` (>= 0).
    force_cos, force_sin : ndarray
        Fourier coefficients of T: ``T ≈ force_cos[0] + Σ_k force_cos[k] cos kωt +
        force_sin[k] sin kωt``, k = 1..harmonics (``force_sin[0] = 0``).
    force_amplitude : float
        ``max |T|`` over the cycle.
    cycles : int
        The cycles run from the start until the slider's state at t = 0 repeated.
    converged : bool
        True when it repeated within the tolerance (periodicity confirmed).
    change : float
        The change of the slider over the last cycle, relative to the slip scale μ max N / kt.
    method : str
        ``"driven"`` (event solver) or ``"single-node"`` (the exact single node).
    seconds : float
        Wall time.
    """

    omega: float
    t: np.ndarray
    x: np.ndarray
    N: np.ndarray
    T: np.ndarray
    w: np.ndarray
    state: np.ndarray
    events: np.ndarray
    segments: tuple
    W: float
    force_cos: np.ndarray
    force_sin: np.ndarray
    force_amplitude: float
    cycles: int
    converged: bool
    change: float
    method: str
    seconds: float

    @property
    def period(self) -> float:
        """2π/ω."""
        return TWO_PI / self.omega

    @property
    def first_harmonic(self) -> tuple[float, float]:
        """``(force_cos[1], force_sin[1])``: T's first harmonic ``A cos ωt + B sin ωt``."""
        return float(self.force_cos[1]), float(self.force_sin[1])


class Functions:
    """The trigonometric polynomials of one element and motion, in θ = ωt (built once)."""

    def __init__(self, kt: float, mu: float, x: TrigPoly, N: TrigPoly, extrema=None):
        self.kt, self.mu, self.x, self.N = kt, mu, x, N
        r = mu / kt
        self.lo, self.hi = x - r * N, x + r * N  # the slider's bounds in contact
        self.dx, self.dN = x.derivative(), N.derivative()
        self.Ndx = N * self.dx
        # where x and N have their extrema (the same for every amplitude of one motion's shape)
        self.x_extrema, self.N_extrema = extrema or (
            periodic_sign_changes(self.dx)[0],
            periodic_sign_changes(self.dN)[0],
        )

    def force(self, state: int, w: float) -> TrigPoly:
        """T on a segment of ``state`` (with the slider at ``w`` for a stick)."""
        if state == STICK:
            return self.kt * (self.x - w)
        if state == SEPARATION or self.mu == 0.0:
            return TrigPoly([0.0])
        return (self.mu if state == FORWARD else -self.mu) * self.N

    def dissipation(self, state: int, a: float, b: float) -> float:
        """``∫ T dw`` over a slip segment (0 otherwise)."""
        if state not in (FORWARD, BACKWARD) or self.mu == 0.0:
            return 0.0
        sign = 1.0 if state == FORWARD else -1.0
        Na, Nb = self.N(a), self.N(b)
        return sign * self.mu * self.Ndx.integral(a, b) - 0.5 * self.mu * self.mu / self.kt * (
            (Nb - Na) * (Nb + Na)
        )

    def slider(self, state: int, w: float, theta):
        """w at the angles ``theta`` of a segment."""
        if state == STICK:
            return np.full(np.shape(theta), w)
        if state == FORWARD:
            return self.lo(theta)
        if state == BACKWARD:
            return self.hi(theta)
        return self.x(theta)

    def largest_force(self, state: int, w: float, a: float, b: float) -> float:
        """max |T| over a segment: at its ends and the extrema of x (stick) or N (slip)."""
        if state == SEPARATION or b < a:
            return 0.0
        inner = self.x_extrema if state == STICK else self.N_extrema
        inner = np.concatenate((inner - TWO_PI, inner, inner + TWO_PI))
        pts = np.concatenate(([a, b], inner[(inner > a) & (inner < b)]))
        # |T| <= μN holds exactly: round-off of kt (x - w) at a stick's ends is cut there
        bound = self.mu * np.maximum(self.N(pts), 0.0)
        return float(np.max(np.minimum(np.abs(self.force(state, w)(pts)), bound)))


def assemble(
    fns: Functions,
    omega: float,
    segments,
    *,
    harmonics: int,
    samples: int,
    cycles: int,
    converged: bool,
    change: float,
    method: str,
    started: float,
    W: float | None = None,
) -> DrivenCycle:
    """The :class:`DrivenCycle` of ``segments`` ``(θ_start, θ_end, state, w_start)`` covering
    ``[0, 2π]`` in order.

    Parameters
    ----------
    fns : Functions
        The element's functions of θ.
    omega : float
        ω (t = θ/ω).
    segments : sequence of tuple
        The cycle's segments in θ.
    harmonics : int
        The highest harmonic of T to compute.
    samples : int
        Equally spaced samples of the series (the events are added).
    cycles, converged, change, method : int, bool, float, str
        As :class:`DrivenCycle` keeps them.
    started : float
        ``time.perf_counter()`` when the solve began.
    W : float, optional
        The dissipation when the solver already has it (the exact single node's); default:
        integrated over the slip segments here.

    Returns
    -------
    DrivenCycle
        The cycle.
    """
    segs = [s for s in segments if s[1] > s[0]] or [segments[0]]
    moments = np.zeros(harmonics + 1, dtype=complex)
    dissipated, largest = 0.0, 0.0
    for a, b, st, w in segs:
        moments += fns.force(st, w).moments(a, b, harmonics)
        dissipated += fns.dissipation(st, a, b)
        largest = max(largest, fns.largest_force(st, w, a, b))
    force_cos = np.r_[moments[0].real / TWO_PI, moments[1:].real / math.pi]
    force_sin = np.r_[0.0, -moments[1:].imag / math.pi]
    starts = np.array([s[0] for s in segs])
    states = np.array([s[2] for s in segs], dtype=np.int8)
    events = starts[1:][states[1:] != states[:-1]]
    theta = np.unique(np.r_[np.linspace(0.0, TWO_PI, samples + 1), starts])
    idx = np.clip(np.searchsorted(starts, theta, side="right") - 1, 0, len(segs) - 1)
    x = fns.x(theta)
    w = np.empty_like(theta)
    T = np.empty_like(theta)
    for i, (a, b, st, w0) in enumerate(segs):
        at = idx == i
        if at.any():
            w[at] = fns.slider(st, w0, theta[at])
            T[at] = fns.force(st, w0)(theta[at])
    state = states[idx]
    N = np.where(state == SEPARATION, 0.0, np.maximum(fns.N(theta), 0.0))  # round-off at its ends
    return DrivenCycle(
        omega=omega,
        t=theta / omega,
        x=x,
        N=N,
        T=T,
        w=w,
        state=state,
        events=events / omega,
        segments=tuple((a / omega, b / omega, int(st), float(w0)) for a, b, st, w0 in segs),
        W=max(dissipated if W is None else W, 0.0),
        force_cos=force_cos,
        force_sin=force_sin,
        force_amplitude=largest,
        cycles=cycles,
        converged=converged,
        change=change,
        method=method,
        seconds=time.perf_counter() - started,
    )
