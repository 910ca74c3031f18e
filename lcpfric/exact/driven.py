"""The exact steady cycle of a displacement-driven Jenkins element for any trigonometric motion
x(t) and normal load N(t) (several harmonics; d = 1), event by event (issue 39, item 1).

In contact the slider w is kept in the moving interval ``[lo, hi] = [x - μN/kt, x + μN/kt]``
(``|T| = kt |x - w| <= μN``) and moves only when an end pushes it: a one-dimensional sweeping
process, the same as the single node's (:mod:`lcpfric.exact`), with trigonometric polynomials in
place of sinusoids. Its events are sign changes of trigonometric polynomials
(:func:`~lcpfric.exact.trig.sign_changes`: companion-matrix roots, refined to the last bit in
their bracket), all but one kind found once per element before the cycle:

* stick at w ends where lo rises through w (forward slip, ``T = +μN``) or hi falls through w
  (backward slip, ``T = -μN``): on each monotone piece of lo (hi) the crossing is bracketed;
* forward slip (w = lo) ends at the next maximum of lo, where the slip rate ``x' - μN'/kt``
  changes sign; backward slip (w = hi) at the next minimum of hi;
* separation (``N <= 0``: T = 0, the slider follows x) starts and ends where N changes sign; at
  re-contact the slider slips forward if lo is rising, backward if hi is falling, else sticks.

The cycle is run from the given slider start at t = 0 until the slider's position at t = 0
repeats (to ``tol`` times the slip scale ``μ max N / kt``, above the round-off of x), which
confirms the periodic steady state. Every slip ends at an extremum of lo or hi or at
separation, whatever the start, so a history is forgotten after its first slip: a cycle with
slip repeats after two or three cycles; a shakedown (no slip) repeats at once, wherever the
start left the slider.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError, SolverError
from ..model.jenkins import JenkinsElement
from ..model.loads import Fourier
from .driven_result import (
    BACKWARD,
    FORWARD,
    SEPARATION,
    STICK,
    DrivenCycle,
    Functions,
    assemble,
)
from .trig import TWO_PI, TrigPoly, periodic_sign_changes, solve_bracket

__all__ = ["driven_cycle", "fundamental", "DrivenCycle"]


def fundamental(*loads, names=("motion", "normal")) -> float:
    """The fundamental angular frequency of Fourier loads: the smallest ω of those that vary,
    every other a whole multiple of it (1.0 if none varies).

    Parameters
    ----------
    *loads : Fourier
        The loads.
    names : sequence of str, optional
        Their names, for the error (the parameter named).

    Returns
    -------
    float
        ω.

    Raises
    ------
    InputError
        A load whose ω is not a whole multiple of the fundamental.
    """
    omegas = [ld.omega for ld in loads if any(ld.amplitudes)]
    if not omegas:
        return 1.0
    omega = min(omegas)
    for ld, name in zip(loads, names):
        if any(ld.amplitudes):
            r = ld.omega / omega
            if abs(r - round(r)) > 1e-12 * r:
                raise InputError(
                    name,
                    f"its angular frequency {ld.omega:g} must be a whole multiple of the "
                    f"fundamental {omega:g}",
                )
    return omega


class _Events:
    """The element's events that do not depend on the slider, found once (angles in [0, 2π))."""

    def __init__(self, fns: Functions):
        self.fns = fns
        roots, dirs = periodic_sign_changes(fns.N)
        self.separations, self.recontacts = roots[dirs < 0], roots[dirs > 0]
        self.lo_dlo = (fns.lo, fns.lo.derivative())
        self.hi_dhi = (fns.hi, fns.hi.derivative())
        # extrema: where the derivative falls through 0 (a maximum) or rises (a minimum)
        self.lo_crit, self.lo_kind = periodic_sign_changes(self.lo_dlo[1])
        self.hi_crit, self.hi_kind = periodic_sign_changes(self.hi_dhi[1])
        self.lo_max = self.lo_crit[self.lo_kind < 0]
        self.hi_min = self.hi_crit[self.hi_kind > 0]

    @staticmethod
    def next_at(angles, theta: float) -> float:
        """The first of ``angles`` at or after ``theta`` within the cycle, else 2π."""
        i = np.searchsorted(angles, theta, side="left")
        return float(angles[i]) if i < angles.size else TWO_PI

    def rising_at(self, crit, kind, theta: float) -> int:
        """+1 if the function whose extrema are ``crit`` rises just after ``theta``, -1 if it
        falls, 0 if it is constant: the next extremum is a maximum (kind -1) or a minimum."""
        if crit.size == 0:
            return 0
        i = np.searchsorted(crit, theta, side="right")
        return -int(kind[i % crit.size])

    def crossing(self, bound: str, w: float, start: float, stop: float) -> float:
        """The first instant in [start, stop] where lo rises to w (``bound="lo"``) or hi falls to
        w (``"hi"``); inf if none."""
        f, df = self.lo_dlo if bound == "lo" else self.hi_dhi
        crit, kind = (self.lo_crit, self.lo_kind) if bound == "lo" else (self.hi_crit, self.hi_kind)
        if crit.size == 0:
            return math.inf
        up = bound == "lo"
        inner = crit[(crit > start) & (crit < stop)]
        cuts = np.r_[start, inner, stop]
        vals = f(cuts) - w
        for i in range(cuts.size - 1):
            rising = self.rising_at(crit, kind, cuts[i]) > 0
            if rising != up:
                continue
            vl, vr = (vals[i], vals[i + 1]) if up else (-vals[i], -vals[i + 1])
            if vr <= 0.0:
                continue  # lo stays below w (hi above) on this piece
            if vl >= 0.0:
                return float(cuts[i])  # already there (a touch, or round-off)
            g = f - w
            return solve_bracket(g, df, float(cuts[i]), float(cuts[i + 1]), -1.0 if up else 1.0)
        return math.inf

    def separated_at_start(self) -> bool:
        """Whether θ = 0 is inside a separation (N <= 0 on an interval, not at a touch): the last
        sign change of N at or before θ = 0 (over the period) is a separation."""
        roots = np.r_[self.separations, self.recontacts]
        if roots.size == 0:
            return False  # N > 0 but at isolated touches (its mean is > 0)
        kinds = np.r_[np.ones(self.separations.size), np.zeros(self.recontacts.size)]
        at_zero = roots == 0.0
        last = np.nonzero(at_zero)[0] if at_zero.any() else [int(np.argmax(roots))]
        return bool(kinds[last[0]])

    def recontact_state(self, theta: float) -> int:
        """The state just after re-contact at ``theta`` (the slider at x, lo = hi = x)."""
        if self.rising_at(self.lo_crit, self.lo_kind, theta) > 0:
            return FORWARD
        if self.rising_at(self.hi_crit, self.hi_kind, theta) < 0:
            return BACKWARD
        return STICK

    def run(self, state: int, w: float, max_events: int):
        """One cycle from ``(state, w)`` at θ = 0: its segments and the state at θ = 2π."""
        fns = self.fns
        segs, theta = [], 0.0
        for _ in range(max_events):
            if theta >= TWO_PI:
                return segs, state, w
            if state == SEPARATION:
                end = self.next_at(self.recontacts, theta)
                segs.append((theta, end, SEPARATION, float(fns.x(theta))))
                w = float(fns.x(end))
                if end < TWO_PI:
                    state = self.recontact_state(end)
                theta = end
                continue
            sep = self.next_at(self.separations, theta)
            if state == STICK:
                stop = min(sep, TWO_PI)
                t_lo = self.crossing("lo", w, theta, stop)
                t_hi = self.crossing("hi", w, theta, stop)
                end = min(t_lo, t_hi, stop)
                segs.append((theta, end, STICK, w))
                if end == t_lo:
                    state = FORWARD
                elif end == t_hi:
                    state = BACKWARD
                elif end == sep and sep < TWO_PI:
                    state, w = SEPARATION, float(fns.x(end))
                theta = end
                continue
            fwd = state == FORWARD
            turn = self.next_at(self.lo_max if fwd else self.hi_min, theta)
            end = min(turn, sep, TWO_PI)
            bound = fns.lo if fwd else fns.hi
            segs.append((theta, end, state, float(bound(theta))))
            w = float(bound(end))
            if end == sep and sep < TWO_PI:
                state, w = SEPARATION, float(fns.x(end))
            elif end == turn and turn < TWO_PI:
                state = STICK
            theta = end
        raise SolverError(
            f"driven cycle: more than {max_events} events in one cycle (state {state}, "
            f"θ = {theta:.17g}); please report this case",
            backend="driven",
            status="event_limit",
        )


def driven_cycle(
    element: JenkinsElement,
    motion: Fourier,
    *,
    normal: Fourier | None = None,
    start: float | None = None,
    harmonics: int = 1,
    samples: int = 256,
    tol: float = 1e-12,
    max_cycles: int = 100,
) -> DrivenCycle:
    """The exact steady cycle of a Jenkins element driven by a trigonometric motion, event by
    event (see the module docstring).

    Parameters
    ----------
    element : JenkinsElement
        The element: kt, μ and its normal side.
    motion : Fourier
        x(t), a :class:`~lcpfric.model.Fourier` (or :class:`~lcpfric.model.Harmonic`) load:
        any number of harmonics.
    normal : Fourier, optional
        The normal side in place of the element's harmonic one: the normal load (clipped at
        zero), or with the element's ``kn`` the normal displacement u_n (N = max(0, N0 + kn
        u_n)); see :meth:`~lcpfric.model.jenkins.JenkinsElement.normal_load`.
    start : float, optional
        The slider's position at t = 0 (default: the motion's mean). A start outside the
        interval the friction law allows at t = 0 is first pushed to its nearer end (where a
        slow ramp of x to x(0) at N(0) would leave it); in separation at t = 0 it is x(0).
    harmonics : int, optional
        The highest harmonic of T computed, >= 1.
    samples : int, optional
        Equally spaced samples of the series over the period (the events are added), >= 4.
    tol : float, optional
        Periodicity: the slider at t = 0 repeats within ``tol`` times the slip scale
        ``μ max N / kt`` (plus 16 units of round-off of ``max |x|``).
    max_cycles : int, optional
        Cap on the cycles, >= 1.

    Returns
    -------
    DrivenCycle
        The steady cycle (``method="driven"``).

    Raises
    ------
    InputError
        A parameter out of range or of the wrong type, loads whose frequencies are not whole
        multiples of one fundamental.
    lcpfric.errors.ConvergenceError
        The slider's start did not repeat within ``max_cycles`` cycles.
    lcpfric.errors.SolverError
        An event limit was reached (a bug: please report).

    Examples
    --------
    >>> from lcpfric.model import Fourier
    >>> from lcpfric.model.jenkins import JenkinsElement
    >>> el = JenkinsElement(kt=1.0, mu=1.0, N0=1.0)
    >>> cyc = driven_cycle(el, el.motion(3.0))
    >>> round(cyc.W, 12)  # 4 Fs (a - Fs/kt)
    8.0
    """
    started = time.perf_counter()
    if not isinstance(element, JenkinsElement):
        raise InputError("element", f"must be a JenkinsElement, got {type(element).__name__}")
    if not isinstance(motion, Fourier):
        raise InputError("motion", "must be a Fourier load (Harmonic or Fourier)")
    harmonics = _checks.positive_int("harmonics", harmonics)
    samples = _checks.positive_int("samples", samples, 4)
    tol = _checks.positive("tol", tol)
    max_cycles = _checks.positive_int("max_cycles", max_cycles)
    load = element.normal_load(motion.omega, normal)
    omega = fundamental(motion, load)
    x, N = TrigPoly.from_load(motion, omega), TrigPoly.from_load(load, omega)
    fns = Functions(element.kt, element.mu, x, N)
    ev = _Events(fns)
    max_events = 50 + 4 * (ev.lo_crit.size + ev.hi_crit.size + ev.separations.size)
    # the slider matters through T = kt (x - w): its periodicity is judged on the force's scale
    # μ max N / kt, above the round-off of x (|x| may be far larger than the slips)
    bound = abs(N.cos[0]) + float(np.sum(np.hypot(N.cos[1:], N.sin[1:])))
    scale = element.mu / element.kt * bound
    floor = 16.0 * np.finfo(float).eps * (abs(x.cos[0]) + float(np.sum(np.hypot(x.cos, x.sin))))
    scale = scale if scale > 0.0 else 1.0
    w = x.cos[0] if start is None else _checks.finite("start", start)
    if ev.separated_at_start():
        state, w = SEPARATION, float(x(0.0))
    else:  # in contact (N(0) may be 0 at a touch: then lo = hi = x there)
        lo0, hi0 = fns.lo(0.0), fns.hi(0.0)
        state, w = STICK, float(min(max(w, min(lo0, hi0)), max(lo0, hi0)))
    change, converged = math.inf, False
    for cycles in range(1, max_cycles + 1):
        segs, state_end, w_end = ev.run(state, w, max_events)
        change = abs(w_end - w) / scale
        if abs(w_end - w) <= tol * scale + floor:
            converged = True
            break
        state, w = state_end, w_end
    if not converged:
        raise ConvergenceError(
            f"driven cycle: the slider's start did not repeat within {max_cycles} cycles "
            f"(relative change {change:.3g} > tol {tol:g}); raise max_cycles",
            None,
        )
    return assemble(
        fns,
        omega,
        segs,
        harmonics=harmonics,
        samples=samples,
        cycles=cycles,
        converged=converged,
        change=change,
        method="driven",
        started=started,
    )
