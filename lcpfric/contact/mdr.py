r"""The Hertz contact (sphere) by the method of dimensionality reduction (Popov and Heß), d = 1.

Two identical elastic spheres (effective radius R, each of modulus E and ratio ν; composite
moduli E*, G* of :func:`~lcpfric.contact.closed_forms.moduli`) under a normal load P(t) and a
tangential load Q(t) along one direction. The method of dimensionality reduction maps the 3-D
contact onto a row of independent springs on a rigid bar, the 1-D profile ``g(x) = x²/R``:

* **normal** (known before any tangential computation: the problems are uncoupled): at each
  instant the approach ``d = a²/R`` with the Hertz radius ``a = (3PR/(4E*))^(1/3)``; spring i
  on the cell ``[x_i - Δx/2, x_i + Δx/2]`` of ``[0, a_max]`` carries the normal force
  ``N_i = 2 E* ∫_cell max(0, d - x²/R) dx`` (the cell's exact share: ``Σ N_i = P`` exactly;
  the factor 2 counts the springs at ``±x``, which behave alike). ``P <= 0`` is complete
  separation;
* **tangential**: spring stiffness ``k_i = 2 G* Δx`` (so ``Σ k_i = 2 a G* = k_t0`` in full
  stick), spring force ``k_i (u - v_i)`` with ``v_i`` the slip of spring i and ``u`` the bar's
  displacement, ``|k_i (u - v_i)| <= μ N_i``; the bar is held by Q(t) and, in parallel with the
  contact, by a support of stiffness ``k_support`` (the structure that holds the body; 0 is
  pure load control): ``Σ_i k_i (u - v_i) + k_support u = Q``.

Within Mindlin's approximation this reproduces the 3-D contact (exactly when ν = 0): the 1-D
stick zone ``|x| < c`` is the 3-D stick radius, and the dissipation is the 3-D one.

The increment (no solver: a closed form serves)
-----------------------------------------------
The increment to ``t_{j+1}`` is problem (P) of the other backends, the maximum-dissipation
projection of the trial state, for this system: given the bar's displacement u the springs are
independent, and each one's answer is its return mapping ``F_i(u) = clip(k_i (v_i - u), -b_i,
b_i)``, ``b_i = μ N_i(t_{j+1})`` (lcpfric's sign: ``F_i = k_i (v_i - u)`` is the friction
force, and the slip opposes it). The bar's equilibrium ``h(u) = Σ F_i(u) - k_support u + Q = 0``
is one monotone piecewise-linear equation in u, solved exactly: its 2n breakpoints ``v_i ∓
b_i/k_i`` are sorted, the segment holding the root is found by bisection on them, and the root
by linear interpolation. O(n log n) per increment; the rank-one coupling of the springs through
the bar is never formed as a matrix. With ``k_support = 0`` the equation has a root only when
``|Q| <= μ P`` (else the whole contact slides): such loads are refused before any work, naming
the instants and the fix (a support stiffness).

The dissipation of an increment is lcpfric's (:func:`~lcpfric.steppers.dissipation.
increment_dissipation`), cycles are repeated until the slips repeat
(:func:`~lcpfric.periodic.cycle_change`, the driver's criterion).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError
from ..model.loads import Harmonic, Load
from ..periodic import cycle_change
from ..results import State
from ..steppers.dissipation import increment_dissipation
from .closed_forms import hertz_contact, moduli

__all__ = ["MDRSphere", "MDRResult", "MAX_NODES"]

#: largest number of springs (the arrays are nodes x steps)
MAX_NODES = 200_000
STICK, FORWARD, BACKWARD, SEPARATION = (int(State.STICK), int(State.FORWARD),
                                        int(State.BACKWARD), int(State.SEPARATION))


@dataclass(frozen=True)
class MDRResult:
    """The periodic steady state of an MDR contact.

    Attributes
    ----------
    W : float
        Dissipation per cycle (last cycle): force x length, in the units of P and R.
    W_normalized : float
        ``W k_t0 / (μ² P0²)`` with ``k_t0 = 2 a0 G*`` at the mean load P0.
    W_cycles : ndarray
        W of every cycle run.
    k_t0, a_max : float
        Initial tangential stiffness at P0; the largest contact radius over the cycle.
    nodes, nodes_in_contact_max : int
        Springs on ``[0, a_max]``; the most in contact at one instant.
    steps_per_cycle, cycles : int
    converged : bool
    change : float
        The last cycle's relative change (:func:`~lcpfric.periodic.cycle_change`).
    seconds : float
    t, x : ndarray
        Instants of the last cycle (``steps + 1``, fractions of the period times the period) and
        the spring positions (cell centres).
    a : ndarray
        Contact radius at each instant.
    state, F : ndarray or None
        ``(steps + 1, nodes)`` spring states (:class:`~lcpfric.results.State`) and friction
        forces of the last cycle, when ``record=True``.
    """

    W: float
    W_normalized: float
    W_cycles: np.ndarray
    k_t0: float
    a_max: float
    nodes: int
    nodes_in_contact_max: int
    steps_per_cycle: int
    cycles: int
    converged: bool
    change: float
    seconds: float
    t: np.ndarray
    x: np.ndarray
    a: np.ndarray
    state: np.ndarray | None = None
    F: np.ndarray | None = None

    def stick_radius(self) -> np.ndarray:
        """At each instant of the last cycle, the outer edge of the sticking springs around the
        centre (0 when none sticks; needs ``record=True``)."""
        if self.state is None:
            raise InputError("record", "the stick radius needs solve(..., record=True)")
        dx = self.x[1] - self.x[0] if self.x.size > 1 else 2 * self.x[0]
        out = np.zeros(self.state.shape[0])
        for j, s in enumerate(self.state):
            slipping = np.flatnonzero(s != STICK)
            first = slipping[0] if slipping.size else s.size
            out[j] = first * dx
        return out


class MDRSphere:
    """The Hertz contact of two identical spheres, by dimensionality reduction (see the module
    docstring).

    Parameters
    ----------
    R, E, nu, mu : float
        Effective radius, each body's Young's modulus and Poisson's ratio (``0 <= ν < 0.5``),
        friction coefficient.
    P, Q : Load or float
        Normal and tangential loads (total forces); floats are constant loads. P(t) <= 0 is
        complete separation.
    k_support : float
        Tangential stiffness of the support in parallel with the contact (0: pure load
        control, where ``|Q| > μP`` at any instant is refused).
    nodes : int
        Springs on ``[0, a_max]``, a_max the largest contact radius over the cycle.
    """

    def __init__(self, R, E, nu, mu, P, Q, *, k_support: float = 0.0, nodes: int = 2000):
        self.R = _checks.positive("R", R)
        self.E = _checks.positive("E", E)
        self.mu = _checks.positive("mu", mu)
        self.moduli = moduli(self.E, nu)
        self.nu = float(nu)
        self.P = _load("P", P)
        self.Q = _load("Q", Q)
        periods = [ld.period for ld in (self.P, self.Q) if not ld.is_constant]
        if len(periods) == 2 and not math.isclose(periods[0], periods[1], rel_tol=1e-12):
            raise InputError("Q", f"P and Q must share one period; got {periods}")
        self.period = periods[0] if periods else 1.0
        self.k_support = _checks.nonnegative("k_support", k_support)
        self.nodes = _checks.positive_int("nodes", nodes)
        if self.nodes > MAX_NODES:
            raise InputError("nodes", f"must be at most {MAX_NODES}, got {self.nodes}")
        P0 = self.P.mean
        if not P0 > 0:
            raise InputError("P", f"the mean normal load P0 must be > 0, got {P0!r}")
        self.P0 = float(P0)
        ts = np.linspace(0.0, self.period, 4097)
        self.P_max = float(max(np.max(self.P(ts)), P0))
        self.a_max = hertz_contact(self.P_max, self.R, self.E, self.nu)["a"]
        self.k_t0 = hertz_contact(self.P0, self.R, self.E, self.nu)["k_t0"]
        self.dx = self.a_max / self.nodes
        self.x = (np.arange(self.nodes) + 0.5) * self.dx
        self.k = np.full(self.nodes, 2.0 * self.moduli["G*"] * self.dx)

    # -- the normal problem ---------------------------------------------------------------------
    def radius(self, t) -> np.ndarray:
        """Hertz contact radius a(t) (0 in separation)."""
        P = np.maximum(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float), 0.0)
        return (3.0 * P * self.R / (4.0 * self.moduli["E*"])) ** (1.0 / 3.0)

    def normal_forces(self, t) -> np.ndarray:
        """``(len(t), nodes)`` spring normal forces: each cell's exact share of the pressure of
        the 1-D profile (their sum is P(t))."""
        a = self.radius(np.atleast_1d(t))[:, None]
        lo = self.x[None, :] - 0.5 * self.dx
        hi = np.minimum(self.x[None, :] + 0.5 * self.dx, a)
        R = self.R

        def prim(x):  # ∫ (a²/R - x²/R) dx
            return (a * a * x - x ** 3 / 3.0) / R

        return np.where(hi > lo, 2.0 * self.moduli["E*"] * (prim(hi) - prim(lo)), 0.0)

    def gross_sliding(self, t) -> np.ndarray:
        """The instants of ``t`` where ``|Q| > μ max(P, 0)``: no equilibrium under pure load
        control."""
        t = np.asarray(t, dtype=float)
        P, Q = self.P(t), self.Q(t)
        margin = 1e-12 * (abs(self.mu * self.P0) + np.abs(Q))
        return t[np.abs(Q) > self.mu * np.maximum(P, 0.0) + margin]

    # -- the steady state -----------------------------------------------------------------------
    def solve(self, steps: int = 400, *, tol: float = 1e-10, max_cycles: int = 200,
              on_nonconvergence: str = "raise", record: bool = False) -> MDRResult:
        """The periodic steady state on ``steps`` uniform increments per cycle, from the virgin
        state (no slip, u = 0)."""
        start = time.perf_counter()
        steps = _checks.positive_int("steps", steps, 4)
        tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles,
                                                                    on_nonconvergence)
        if self.nodes * (steps + 1) * 8 * (4 if record else 2) > 4 << 30:
            raise InputError("steps", f"{steps} steps x {self.nodes} springs would take more "
                                      f"than 4 GiB; fewer steps or nodes")
        t = np.linspace(0.0, self.period, steps + 1)
        if self.k_support == 0.0:
            fine = np.union1d(t, np.linspace(0.0, self.period, 20001))
            bad = self.gross_sliding(fine)
            if bad.size:
                show = ", ".join(f"{x / self.period:.4g}" for x in bad[:: max(1, bad.size // 4)][:4])
                raise InputError("k_support", f"is 0 (pure load control) but |Q(t)| > μ P(t) at "
                                              f"{bad.size} of {fine.size} sampled instants "
                                              f"(fractions of the period: {show}, ...): the "
                                              f"whole contact slides and has no equilibrium; "
                                              f"give the structure that holds the body, "
                                              f"k_support > 0, or loads with |Q| <= μ P")
        b = self.mu * self.normal_forces(t)                  # (steps + 1, nodes)
        Q = np.asarray(self.Q(t), dtype=float)
        v = np.zeros(self.nodes)
        F = np.zeros(self.nodes)
        u = 0.0
        W_cycles, change = [], math.inf
        du_scale = abs(self.Q.amplitude if not self.Q.is_constant else self.Q.mean) / self.k_t0
        scales = (du_scale, self.mu * self.P_max)
        prev = None
        for _ in range(max_cycles):
            v0 = v.copy()
            keep = record
            Fs = np.empty((steps + 1, self.nodes)) if keep else None
            Ss = np.empty((steps + 1, self.nodes), dtype=np.int8) if keep else None
            if keep:
                Fs[0], Ss[0] = F, _states(F, b[0], None, self.dx)
            W = 0.0
            vmin, vmax = v.copy(), v.copy()
            for j in range(steps):
                u, F1, v1 = self._increment(v, u, b[j + 1], Q[j + 1])
                W += increment_dissipation(F, F1, v1 - v)
                if keep:
                    Fs[j + 1], Ss[j + 1] = F1, _states(F1, b[j + 1], v1 - v, self.dx)
                F, v = F1, v1
                np.minimum(vmin, v, out=vmin)
                np.maximum(vmax, v, out=vmax)
            W_cycles.append(W)
            if prev is not None:
                change = float(cycle_change(np.max(np.abs(v - v0)), np.max(vmax - vmin),
                                            W - prev, W, scales))
                if change <= tol:
                    break
            prev = W
        converged = bool(change <= tol)
        if not converged and on_nonconvergence != "ignore":
            msg = (f"MDR: no periodic steady state after {len(W_cycles)} cycles (relative "
                   f"change {change:.3g} > tol {tol:g}); raise max_cycles or loosen tol")
            if on_nonconvergence == "raise":
                raise ConvergenceError(msg, None)
            import warnings

            from ..errors import ConvergenceWarning

            warnings.warn(msg, ConvergenceWarning, stacklevel=2)
        W = W_cycles[-1]
        return MDRResult(W=W, W_normalized=W * self.k_t0 / (self.mu * self.P0) ** 2,
                         W_cycles=np.asarray(W_cycles), k_t0=self.k_t0, a_max=self.a_max,
                         nodes=self.nodes,
                         nodes_in_contact_max=int(np.max(np.count_nonzero(b > 0, axis=1))),
                         steps_per_cycle=steps, cycles=len(W_cycles), converged=converged,
                         change=change, seconds=time.perf_counter() - start, t=t, x=self.x,
                         a=self.radius(t), state=Ss, F=Fs)

    def _increment(self, v, u, b, Q):
        """The exact increment (module docstring): ``(u, F, v)`` at the next instant."""
        k, ks = self.k, self.k_support
        lo_bp, hi_bp = v - b / k, v + b / k  # below lo: F = +b; above hi: F = -b

        def h(x):
            return float(np.sum(np.clip(k * (v - x), -b, b))) - ks * x + Q

        pts = np.sort(np.concatenate([lo_bp, hi_bp]))
        h_lo, h_hi = h(pts[0]), h(pts[-1])
        if h_lo <= 0.0:  # the root is below every breakpoint: every spring at +b
            if ks == 0.0:
                u1 = pts[0] if h_lo == 0.0 else _no_root(Q, b)
            else:
                u1 = pts[0] + h_lo / ks
        elif h_hi >= 0.0:  # above every breakpoint: every spring at -b
            if ks == 0.0:
                u1 = pts[-1] if h_hi == 0.0 else _no_root(Q, b)
            else:
                u1 = pts[-1] + h_hi / ks
        else:
            i, j = 0, pts.size - 1  # h(pts[i]) > 0 > h(pts[j])
            while j - i > 1:
                mid = (i + j) // 2
                if h(pts[mid]) > 0.0:
                    i = mid
                else:
                    j = mid
            x0, x1 = pts[i], pts[j]
            h0, h1 = h(x0), h(x1)
            u1 = x0 + (x1 - x0) * h0 / (h0 - h1) if h0 != h1 else x0
        F = np.clip(k * (v - u1), -b, b)
        stick = np.abs(k * (v - u1)) <= b
        v1 = np.where(stick, v, u1 + F / k)
        return u1, F, v1


def _states(F, b, dv, dx) -> np.ndarray:
    """Spring states: separated (b = 0), slipping (moved this increment), or sticking."""
    s = np.full(F.shape, STICK, dtype=np.int8)
    if dv is not None:
        s[dv > 0.0] = FORWARD
        s[dv < 0.0] = BACKWARD
    s[b <= 0.0] = SEPARATION
    return s


def _no_root(Q, b):
    raise InputError("k_support", f"is 0 and |Q| = {abs(Q):.6g} exceeds the friction limit "
                                  f"μP = {float(np.sum(b)):.6g} of the whole contact at an "
                                  f"increment: gross sliding has no equilibrium under pure load "
                                  f"control; give k_support > 0")


def _load(name: str, x) -> Load:
    if isinstance(x, Load):
        return x
    try:
        value = float(x)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a Load (lcpfric.model.loads) or a number, got "
                               f"{type(x).__name__}") from None
    return Harmonic(_checks.finite(name, value), 0.0)
