"""The steady cycle of a displacement-driven Jenkins element in two tangential directions (d = 2),
event by event, to integration tolerance (issue 39, item 1).

The element: ``T = kt (X - S)``, X = (x, y) the prescribed motion, S the slider, ``|T| <= F``
with ``F = μ N``, N = max(0, N_raw) the prescribed normal load; the slider moves only where
``|T| = F``, along T (``S' = λ e``, λ >= 0, ``T = F e``, ``e = (cos φ, sin φ)``). Every quantity
is a function of θ = ωt and ' is d/dθ.

* **Stick** (S fixed): ``T = T_s + kt (X(θ) - X(θ_s))``, a trigonometric polynomial; it ends
  where ``g = |T|² - F²`` (a trigonometric polynomial too) rises through zero, found as in d = 1
  (:func:`~lcpfric.exact.trig.sign_changes`: companion-matrix roots refined to the last bit).
* **Slip**: differentiating ``T = F e`` and ``T' = kt (X' - λ e)`` and splitting along e and
  ``e⊥ = (-sin φ, cos φ)``:

      λ = X'·e - F'/kt  (>= 0),        F φ' = kt X'·e⊥ = kt (-sin φ x' + cos φ y').

  φ (with the dissipation ``W = ∫ F λ dθ`` and T's Fourier moments) is integrated by
  :func:`scipy.integrate.solve_ivp` (DOP853); the slip ends (stick) where the normal slip rate
  ``kt λ = kt X'·e - F'`` falls through zero, or at separation.
* **Separation** (N <= 0, between sign changes of N found once): T = 0, S = X. At re-contact the
  element slips along X' if ``kt |X'| > F'`` there, else sticks.

Near a separation (and just after a re-contact into slip) F -> 0 and the direction equation
is stiff: φ relaxes onto the direction of X' at the rate ``kt |X'| / F``. The slip is integrated
until F falls to ``1e-10`` of its largest value, and then joins the separation (the energy left
out is of order ``F²/F'``, below the tolerance).

Cycles are run from the slider's start at t = 0 until the slider at t = 0 repeats to ``tol``
times the slip scale ``μ max N / kt`` (and so does its distance to the fixed point, estimated
from the last two cycles' contraction: slow near the slip limit). Along one axis (y = 0) this
is the d = 1 cycle of :func:`lcpfric.exact.driven.driven_cycle`.
"""

from __future__ import annotations

import math
import time
import numpy as np
from scipy.integrate import solve_ivp

from .. import _checks
from ..errors import ConvergenceError, InputError, SolverError
from ..model.loads import Fourier
from ..results import State
from .driven import fundamental
from .driven2d_result import DrivenCycle2D
from .trig import TWO_PI, TrigPoly, periodic_sign_changes, sign_changes

__all__ = ["DrivenCycle2D", "driven_cycle_2d"]

STICK, SLIP, SEPARATION = int(State.STICK), int(State.FORWARD), int(State.SEPARATION)
#: where a slip heading into separation joins it: F below this fraction of max F
F_FLOOR = 1e-10


def _load(name: str, value) -> Fourier:
    if isinstance(value, Fourier):
        return value
    if isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool):
        return Fourier(_checks.finite(name, value))
    raise InputError(name, f"must be a Fourier load or a number, got {type(value).__name__}")


class _Element:
    """The element's functions of θ and its cycle, segment by segment."""

    def __init__(self, kt, mu, x, y, N, harmonics, rtol):
        self.kt, self.mu, self.H, self.rtol = kt, mu, harmonics, rtol
        self.x, self.y, self.N = x, y, N
        self.dx, self.dy, self.dN = x.derivative(), y.derivative(), N.derivative()
        roots, dirs = periodic_sign_changes(N)
        self.separations, self.recontacts = roots[dirs < 0], roots[dirs > 0]
        self.Fmax = mu * (abs(N.cos[0]) + float(np.sum(np.hypot(N.cos[1:], N.sin[1:]))))
        span = abs(x.cos[0]) + abs(y.cos[0])
        for f in (x, y):
            span += float(np.sum(np.hypot(f.cos[1:], f.sin[1:])))
        self.span = span
        self.scale = self.Fmax / kt if self.Fmax > 0 else 1.0

    def X(self, th):
        return np.array([self.x(th), self.y(th)])

    @staticmethod
    def next_at(angles, theta):
        i = np.searchsorted(angles, theta, side="left")
        return float(angles[i]) if i < angles.size else TWO_PI

    def separated_at_start(self) -> bool:
        """θ = 0 inside a separation: the next sign change of N is a re-contact."""
        if self.recontacts.size == 0:
            return False
        return self.next_at(self.recontacts, 0.0) < self.next_at(self.separations, 0.0)

    def stick_force(self, S):
        """T_x, T_y as trigonometric polynomials for the slider fixed at S."""
        return self.kt * (self.x - S[0]), self.kt * (self.y - S[1])

    def stick_end(self, S, a, b):
        """The first instant in (a, b) where ``|T|² - F²`` rises through zero; inf if none."""
        if b <= a:
            return math.inf
        tx, ty = self.stick_force(S)
        g = tx * tx + ty * ty - (self.mu * self.mu) * (self.N * self.N)
        if g.degree == 0:
            return math.inf
        roots, dirs = sign_changes(g, a, b)
        up = roots[dirs > 0]
        return float(up[0]) if up.size else math.inf

    def slip_rate(self, th, phi):
        """``kt λ = kt X'·e - F'`` at θ for the direction φ."""
        return self.kt * (math.cos(phi) * self.dx(th) + math.sin(phi) * self.dy(th)) - (
            self.mu * self.dN(th)
        )

    def slip(self, phi0, a, b):
        """Integrate a slip from θ = a with direction φ0 until it ends or b: (end, reason, sol,
        y_end) with reason "stick", "separation" or "end"."""
        kt, mu, H = self.kt, self.mu, self.H
        k = np.arange(H + 1)
        floor = F_FLOOR * self.Fmax

        def rhs(th, u):
            c, s = math.cos(u[0]), math.sin(u[0])
            dx, dy, F, dF = self.dx(th), self.dy(th), mu * self.N(th), mu * self.dN(th)
            dphi = kt * (-s * dx + c * dy) / max(F, floor)
            dW = F * ((c * dx + s * dy) - dF / kt)
            ck, sk = np.cos(k * th), np.sin(k * th)
            return np.concatenate(([dphi, dW], F * c * ck, F * c * sk, F * s * ck, F * s * sk))

        def stick_event(th, u):
            return self.slip_rate(th, u[0])

        def sep_event(th, u):
            return mu * self.N(th) - floor

        stick_event.terminal, stick_event.direction = True, -1
        sep_event.terminal, sep_event.direction = True, -1
        if mu * self.N(a) < floor:  # a re-contact: start where F has risen to the floor
            roots, dirs = sign_changes(mu * self.N - floor, a, b)
            a = float(roots[dirs > 0][0]) if np.any(dirs > 0) else b
        u0 = np.zeros(2 + 4 * (H + 1))
        u0[0] = phi0
        atol = np.full(u0.size, 1e-14 * max(self.Fmax, 1e-300))
        atol[0] = 1e-14
        atol[1] = 1e-14 * max(self.Fmax * self.span, 1e-300)
        if b <= a:
            return b, "end", None, u0
        events = (stick_event, sep_event)
        opts = dict(method="DOP853", rtol=self.rtol, atol=atol, events=events, dense_output=True)
        sol = solve_ivp(rhs, (a, b), u0, **opts)
        if sol.status < 0:
            raise SolverError(
                f"driven cycle 2d: the slip's integration failed at θ = {sol.t[-1]:.17g}: "
                f"{sol.message}",
                backend="driven2d",
                status="integration",
            )
        if sol.t_events[0].size:
            return float(sol.t_events[0][0]), "stick", sol, sol.y_events[0][0]
        if sol.t_events[1].size:
            return float(sol.t_events[1][0]), "separation", sol, sol.y_events[1][0]
        return b, "end", sol, sol.y[:, -1]

    def recontact(self, theta):
        """The state after re-contact at θ (T = 0): slip along X' (its φ) or stick."""
        d = (self.dx(theta), self.dy(theta))
        if self.kt * math.hypot(d[0], d[1]) > self.mu * self.dN(theta):
            return SLIP, math.atan2(d[1], d[0])
        return STICK, 0.0

    def start_state(self, S):
        """(state, S, φ) at θ = 0 from the slider's start S (pushed into the disk)."""
        if self.separated_at_start():
            return SEPARATION, self.X(0.0), 0.0
        X0, F0 = self.X(0.0), self.mu * max(self.N(0.0), 0.0)
        T = self.kt * (X0 - S)
        mag = math.hypot(T[0], T[1])
        if mag >= F0:
            phi = math.atan2(T[1], T[0]) if mag > 0 else 0.0
            S = X0 - F0 / self.kt * np.array([math.cos(phi), math.sin(phi)])
            if F0 > 0 and self.slip_rate(0.0, phi) > 0:
                return SLIP, S, phi
        return STICK, np.asarray(S, float), 0.0

    def run(self, state, S, phi, max_events):
        """One cycle: segments ``(a, b, state, data)`` and the state at θ = 2π. data is S (stick),
        the solve_ivp solution (slip) or None (separation)."""
        segs, theta = [], 0.0
        for _ in range(max_events):
            if theta >= TWO_PI:
                return segs, state, S, phi
            if state == SEPARATION:
                end = self.next_at(self.recontacts, theta)
                segs.append((theta, end, SEPARATION, None, None))
                S = self.X(end)
                if end < TWO_PI:
                    state, phi = self.recontact(end)
                theta = end
                continue
            sep = self.next_at(self.separations, theta)
            stop = min(sep, TWO_PI)
            if state == STICK:
                t_slip = self.stick_end(S, theta, stop)
                end = min(t_slip, stop)
                segs.append((theta, end, STICK, S.copy(), None))
                if end == t_slip:
                    T = self.kt * (self.X(end) - S)
                    state, phi = SLIP, math.atan2(T[1], T[0])
                elif end == sep and sep < TWO_PI:
                    state, S = SEPARATION, self.X(end)
                theta = end
                continue
            end, reason, sol, u = self.slip(phi, theta, stop)
            if reason == "separation":
                end = sep
            segs.append((theta, end, SLIP, sol, u))
            phi = float(u[0])
            F = self.mu * max(self.N(end), 0.0)
            S = self.X(end) - F / self.kt * np.array([math.cos(phi), math.sin(phi)])
            if reason == "stick":
                state = STICK
            elif end == sep and sep < TWO_PI:
                state, S = SEPARATION, self.X(end)
            theta = end
        raise SolverError(
            f"driven cycle 2d: more than {max_events} events in one cycle (state {state}, "
            f"θ = {theta:.17g}); please report this case",
            backend="driven2d",
            status="event_limit",
        )

    def force_at(self, seg, th):
        """T at the angles ``th`` of a segment, shape (2, len(th))."""
        a, b, st, data, _ = seg
        if st == SEPARATION:
            return np.zeros((2, th.size))
        if st == STICK:
            return self.kt * (np.array([self.x(th), self.y(th)]) - data[:, None])
        phi = (
            data.sol(np.clip(th, data.t[0], data.t[-1]))[0]
            if data is not None
            else np.zeros(th.size)
        )
        F = self.mu * np.maximum(self.N(th), 0.0)
        return F * np.array([np.cos(phi), np.sin(phi)])

    def moments(self, seg):
        """``∫ T_i cos kθ``, ``∫ T_i sin kθ`` over a segment, shape (2, 2, H + 1), and its W."""
        a, b, st, data, u = seg
        H = self.H
        out = np.zeros((2, 2, H + 1))
        if st == SEPARATION or b <= a:
            return out, 0.0
        if st == STICK:
            for i, f in enumerate(self.stick_force(data)):
                m = f.moments(a, b, H)
                out[i, 0], out[i, 1] = m.real, -m.imag
            return out, 0.0
        m = u[2:].reshape(2, 2, H + 1)
        return m, float(u[1])


def driven_cycle_2d(
    x,
    y,
    normal,
    kt: float,
    mu: float,
    *,
    start=None,
    harmonics: int = 1,
    samples: int = 256,
    rtol: float = 1e-12,
    tol: float = 1e-10,
    max_cycles: int = 200,
) -> DrivenCycle2D:
    """The steady cycle of a Jenkins element driven by a 2-D trigonometric motion, event by
    event (see the module docstring).

    Parameters
    ----------
    x, y : Fourier or float
        The motion's components x(t), y(t): :class:`~lcpfric.model.Fourier` loads (any number
        of harmonics) or constants.
    normal : Fourier or float
        The normal load N(t), clipped at zero (separation: T = 0, the slider follows).
    kt : float
        Tangential stiffness, > 0.
    mu : float
        Friction coefficient, > 0.
    start : array_like of 2 floats, optional
        The slider at t = 0 (default: the motion's mean); outside the disk ``|T| <= μN(0)`` it
        is first projected onto it.
    harmonics : int, optional
        The highest harmonic of T computed, >= 1.
    samples : int, optional
        Equally spaced samples over the period (the events are added), >= 4.
    rtol : float, optional
        The relative tolerance of the slip's integration (DOP853).
    tol : float, optional
        Periodicity: the slider at t = 0 repeats within ``tol`` times ``μ max N / kt``, and so
        does its distance to the fixed point estimated from the contraction over the last two
        cycles (a slow contraction, near the slip limit, runs further).
    max_cycles : int, optional
        Cap on the cycles, >= 1.

    Returns
    -------
    DrivenCycle2D
        The steady cycle.

    Raises
    ------
    InputError
        A parameter out of range or of the wrong type (named), loads whose frequencies are not
        whole multiples of one fundamental.
    lcpfric.errors.ConvergenceError
        The slider's start did not repeat within ``max_cycles`` cycles.
    lcpfric.errors.SolverError
        The integration failed or an event limit was reached.

    Examples
    --------
    >>> import math
    >>> from lcpfric.model import Harmonic
    >>> cyc = driven_cycle_2d(Harmonic(0, 2, math.pi / 2), Harmonic(0, 2, 0), 1.0, 1.0, 1.0)
    >>> round(cyc.W / (2 * math.pi * math.sqrt(3)), 9)  # 2π μN sqrt(a² - (μN/kt)²)
    1.0
    """
    started = time.perf_counter()
    loads = {"x": _load("x", x), "y": _load("y", y), "normal": _load("normal", normal)}
    kt = _checks.positive("kt", kt)
    mu = _checks.positive("mu", mu)
    harmonics = _checks.positive_int("harmonics", harmonics)
    samples = _checks.positive_int("samples", samples, 4)
    rtol = _checks.positive("rtol", rtol)
    tol = _checks.positive("tol", tol)
    max_cycles = _checks.positive_int("max_cycles", max_cycles)
    if loads["normal"].mean <= 0:
        raise InputError("normal", f"the mean normal load must be > 0, got {loads['normal'].mean}")
    omega = fundamental(*loads.values(), names=tuple(loads))
    xp, yp, Np = (TrigPoly.from_load(ld, omega) for ld in loads.values())
    el = _Element(kt, mu, xp, yp, Np, harmonics, rtol)
    if start is None:
        S = np.array([xp.cos[0], yp.cos[0]])
    else:
        S = _checks.finite_array("start", start)
        if S.shape != (2,):
            raise InputError("start", f"must be 2 numbers (the slider's x, y), got {S.shape}")
    state, S, phi = el.start_state(np.array(S, dtype=float))
    max_events = 100 + 8 * (xp.degree + yp.degree + Np.degree + 2)
    floor = 16.0 * np.finfo(float).eps * el.span
    change, converged, last = math.inf, False, math.inf
    for cycles in range(1, max_cycles + 1):
        segs, state_end, S_end, phi_end = el.run(state, S, phi, max_events)
        diff = float(np.hypot(*(S_end - S)))
        change = diff / el.scale
        # the distance left to the fixed point, for a contraction by q per cycle: diff q/(1-q)
        q = min(diff / last, 0.99) if last > floor else 0.0
        if diff <= tol * el.scale + floor and diff * q / (1.0 - q) <= tol * el.scale + floor:
            converged = True
            break
        last = diff
        state, S, phi = state_end, S_end, phi_end
    if not converged:
        raise ConvergenceError(
            f"driven cycle 2d: the slider's start did not repeat within {max_cycles} cycles "
            f"(relative change {change:.3g} > tol {tol:g}); raise max_cycles",
            None,
        )
    return _assemble(el, omega, segs, samples, cycles, change, started)


def _assemble(el, omega, segs, samples, cycles, change, started) -> DrivenCycle2D:
    segs = [s for s in segs if s[1] > s[0]] or segs[:1]
    mom, W = np.zeros((2, 2, el.H + 1)), 0.0
    for seg in segs:
        m, w = el.moments(seg)
        mom += m
        W += w
    scale = np.r_[1.0 / TWO_PI, np.full(el.H, 1.0 / math.pi)]
    force_cos, force_sin = mom[:, 0] * scale, mom[:, 1] * scale
    force_sin[:, 0] = 0.0
    starts = np.array([s[0] for s in segs])
    states = np.array([s[2] for s in segs], dtype=np.int8)
    events = starts[1:][states[1:] != states[:-1]]
    theta = np.unique(np.r_[np.linspace(0.0, TWO_PI, samples + 1), starts])
    idx = np.clip(np.searchsorted(starts, theta, side="right") - 1, 0, len(segs) - 1)
    T = np.empty((2, theta.size))
    for i, seg in enumerate(segs):
        at = idx == i
        if at.any():
            T[:, at] = el.force_at(seg, theta[at])
    X = el.X(theta)
    state = states[idx]
    N = np.where(state == SEPARATION, 0.0, np.maximum(el.N(theta), 0.0))
    return DrivenCycle2D(
        omega=omega,
        t=theta / omega,
        x=X,
        N=N,
        T=T,
        slider=X - T / el.kt,
        state=state,
        events=events / omega,
        W=max(W, 0.0),
        force_cos=force_cos,
        force_sin=force_sin,
        force_amplitude=float(np.max(np.hypot(T[0], T[1]))),
        cycles=cycles,
        converged=True,
        change=change,
        seconds=time.perf_counter() - started,
    )
