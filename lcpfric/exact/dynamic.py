r"""The exact periodic steady state of the dynamic single node (issue 40, item 2): event by event
with closed-form segments (:mod:`.dynamic_modes`), the periodic orbit by Newton's method on the
period map with its exact Jacobian, verified, its Floquet multipliers reported.

Events (normalized units of :mod:`.dynamic_modes`, θ = ωt):

* **slip** (direction s): stops where ``u' = 0``; then stick if ``|u + q| <= n`` there, else a
  reversal. No closed form: ``s u'`` is scanned on a grid finer than both the forcing's and the
  oscillator's periods, sign changes are refined by Brent's method, and a local minimum of
  ``s u'`` between samples (a root pair hiding between two positive samples) is found as a root
  of ``u''`` and tested. After a release from stick ``u'`` grows like ``τ²`` (the acceleration
  vanishes there too), so the first cell after a release is searched on a geometric sub-grid.
* **stick**: ends where ``u + q = ±n``: ``a cos θ + b sin θ = c``, closed form (downward
  crossings of the slack ``n - |u + q|`` only); the slip that follows has ``s = -sign(u + q)``.
* **separation** (``n = 1 + P̂1 sin θ <= 0``, P̂1 > 1): closed-form start and end; in between the
  free motion, whose turning points are found like the stops (they bound the amplitude).

The period map ``Φ: (u, u') at θ = 0 -> (u, u') at θ = 2π`` (θ = 0 is always in contact:
``n(0) = 1``) is differentiated exactly: each mode's flow contributes its propagator ``E``, a
stick ``[[1, 0], [0, 0]]``, and the events their saltation matrices (a stop into stick
``[[1, 0], [0, 0]]``, a reversal ``[[1, 0], [0, a⁺/a⁻]]`` with the accelerations on both sides;
release, separation and contact are continuous in the vector field: identity). Newton's method
on ``Φ(z) = z`` from a few periods of the motion (from each start) converges in a handful of
iterations; the orbit's monodromy matrix is ``∂Φ/∂z`` at the fixed point, its eigenvalues the
Floquet multipliers (stable when both are inside the unit circle; a stick phase makes one of
them 0). W per cycle: ``∫ n |u'| dθ`` over the slips, by Gauss-Legendre quadrature on the scan's
cells (the integrand is analytic on each).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..errors import SolverError
from .dynamic_modes import Oscillator, Segment, free_forcing, slip_forcing

__all__ = ["DynamicNode", "DynamicOrbit", "period_map", "periodic_orbit"]

TWO_PI = 2.0 * math.pi
#: cells per the shorter of the forcing's and the oscillator's periods
_CELLS = 24
_GAUSS = np.polynomial.legendre.leggauss(8)
STICK, SLIP_F, SLIP_B, SEPARATION = 0, 1, -1, 2


@dataclass
class PeriodRun:
    """One period of motion from a state: the end state, the Jacobian, W, the segments."""

    z: np.ndarray
    jacobian: np.ndarray
    J: float
    segments: list = field(default_factory=list)  # (θa, θb, mode, Segment or u_stick)
    u_min: float = math.inf
    u_max: float = -math.inf
    events: int = 0


class DynamicNode:
    """The normalized node's data and its closed-form pieces."""

    def __init__(self, P1, Q1, phi, beta, zeta):
        self.P1, self.Q1, self.phi = float(P1), float(Q1), float(phi)
        self.osc = Oscillator(beta, zeta)
        self.cell = min(TWO_PI, self.osc.natural) / _CELLS
        self.sep = None
        if self.P1 > 1.0:  # n <= 0 on [π + asin(1/P̂1), 2π - asin(1/P̂1)]
            g = math.asin(1.0 / self.P1)
            self.sep = (math.pi + g, TWO_PI - g)

    def q(self, th):
        return self.Q1 * np.sin(th + self.phi)

    def n(self, th):
        return 1.0 + self.P1 * np.sin(th)

    def release(self, u, th0, th1):
        """The first θ in (th0, th1] where stick at u ends (slack n - |u + q| reaches 0 going
        down), and the slip direction; None if it holds."""
        best = None
        sp, cp = math.sin(self.phi), math.cos(self.phi)
        for sign in (1.0, -1.0):  # u + q = sign n:  Q1 sin φ cos θ + (Q1 cos φ - sign P1) sin θ
            a, b, c = self.Q1 * sp, self.Q1 * cp - sign * self.P1, sign - u
            R = math.hypot(a, b)
            if R == 0.0 or abs(c) > R:
                continue
            base, half = math.atan2(b, a), math.acos(max(-1.0, min(1.0, c / R)))
            for root in (base + half, base - half):
                k = math.ceil((th0 - root) / TWO_PI)
                t = root + k * TWO_PI
                while t <= th0 + 1e-13 * max(1.0, abs(th0)):
                    t += TWO_PI
                if t > th1:
                    continue
                # the slack sign n - sign (u + q) decreases through 0: d/dθ(u + q) sign > n'
                rate = sign * self.Q1 * math.cos(t + self.phi) - self.P1 * math.cos(t)
                if rate > 0.0 and (best is None or t < best[0]):
                    best = (t, -int(sign))
        return best

    def separation_within(self, th0, th1):
        """``(start, end)`` of the first separation interval meeting [th0, th1), or None."""
        if self.sep is None:
            return None
        k = math.floor(th0 / TWO_PI)
        for j in (k - 1, k, k + 1):
            a, b = self.sep[0] + j * TWO_PI, self.sep[1] + j * TWO_PI
            if b > th0 and a < th1:
                return a, b
        return None


def _first_root(seg, sign, th0, th1, cell, after_rest, noise=0.0):
    """The first θ in (th0, th1] where ``fun = sign u'`` of the segment (> 0 just after th0)
    reaches 0, or None: sign changes on a grid refined by Brent's method, local minima between
    samples tested. ``after_rest``: fun starts from 0 (at rest); the samples until it exceeds
    ``noise`` (its round-off: u' is a difference of terms of its own scale) are the rest."""

    def fun(t):
        return sign * seg.state1(t)[1]

    def dfun(t):
        u, du = seg.state1(t)
        return sign * seg.acceleration1(t, u, du)

    n = max(2, math.ceil((th1 - th0) / cell))
    grid = np.linspace(th0, th1, n + 1)
    if after_rest:  # fun ~ τ² (release) or ~ τ (reversal): a geometric sub-grid in cell 1
        sub = th0 + (grid[1] - th0) * np.geomspace(2.0**-30, 1.0, 31)
        grid = np.concatenate([[th0], sub, grid[2:]])
    y = seg.state(grid)
    f = sign * y[1]
    d = sign * seg.acceleration(grid, y)
    start = 0
    if after_rest:
        pos = np.flatnonzero(f[1:] > noise)
        if pos.size == 0:
            return th0
        # the samples before the first positive one are at rest within round-off (u' ~ τ²)
        start = int(pos[0]) + 1
    for i in range(start, grid.size - 1):
        a, b = grid[i], grid[i + 1]
        if f[i + 1] <= 0.0:
            return brentq(fun, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        if d[i] < 0.0 < d[i + 1]:  # a minimum between two positive samples
            m = brentq(dfun, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps)
            if fun(m) <= 0.0:
                return brentq(fun, a, m, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return None


def _quadrature(fun, th0, th1, cell):
    """∫ fun over [th0, th1] by 8-point Gauss-Legendre on cells no longer than ``cell``."""
    if th1 <= th0:
        return 0.0
    n = max(1, math.ceil((th1 - th0) / cell))
    edges = np.linspace(th0, th1, n + 1)
    x, w = _GAUSS
    mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
    pts = (mid[:, None] + half[:, None] * x[None, :]).ravel()
    return float(np.sum(fun(pts).reshape(n, -1) * w[None, :] * half[:, None]))


def _mode_at(node, th, y, contact=False):
    """The mode starting at θ in state y (``contact``: at re-contact, n = 0 to round-off)."""
    if not contact and node.n(th) <= 0.0:
        return SEPARATION
    if y[1] > 0.0:
        return SLIP_F
    if y[1] < 0.0:
        return SLIP_B
    F = y[0] + node.q(th)
    n = node.n(th)
    if abs(F) <= n:
        return STICK
    return SLIP_B if F > n else SLIP_F


def period_map(node: DynamicNode, z, theta0: float = 0.0, record: bool = False) -> PeriodRun:
    """One period from ``z = (u, u')`` at ``theta0``: the end state, ``∂z_end/∂z``, W·Q̂1."""
    th, th_end = float(theta0), float(theta0) + TWO_PI
    y = np.array(z, dtype=float)
    Jac = np.eye(2)
    J = 0.0
    run = PeriodRun(z=y, jacobian=Jac, J=0.0)
    mode = _mode_at(node, th, y)
    if mode == STICK:
        y[1] = 0.0
        Jac = np.array([[1.0, 0.0], [0.0, 0.0]]) @ Jac
    after_rest = mode in (SLIP_F, SLIP_B) and y[1] == 0.0
    run.u_min = run.u_max = y[0]
    for _ in range(10_000):
        if th >= th_end:
            break
        run.events += 1
        if mode == STICK:
            rel = node.release(y[0], th, th_end)
            stop = th_end if rel is None else rel[0]
            if record:
                run.segments.append((th, stop, STICK, float(y[0])))
            th = stop
            if rel is not None:
                mode, after_rest = rel[1], True
            continue
        if mode == SEPARATION:
            sep = node.separation_within(th, th_end)
            stop = min(th_end, sep[1]) if sep else th_end
            seg = Segment(node.osc, free_forcing(node.Q1, node.phi), th, y)
            _extrema(node, seg, th, stop, run)
            y = np.array(seg.state1(stop))
            Jac = np.reshape(node.osc.propagator1(stop - th), (2, 2)) @ Jac
            if record:
                run.segments.append((th, stop, SEPARATION, seg))
            th = stop
            if th < th_end:
                mode = _mode_at(node, th, y, contact=True)
                after_rest = y[1] == 0.0
            continue
        s = mode
        seg = Segment(node.osc, slip_forcing(s, node.P1, node.Q1, node.phi), th, y)
        sep = node.separation_within(th, th_end)
        limit = min(th_end, sep[0]) if sep and sep[0] > th else th_end
        stop = _first_root(
            seg,
            s,
            th,
            limit,
            node.cell,
            after_rest,
            noise=64 * np.finfo(float).eps * seg.velocity_scale(),
        )
        end = limit if stop is None else stop
        J += _quadrature(lambda t: node.n(t) * s * seg.state(t)[1], th, end, node.cell)
        Jac = np.reshape(node.osc.propagator1(end - th), (2, 2)) @ Jac
        y = np.array(seg.state1(end))
        if record:
            run.segments.append((th, end, mode, seg))
        run.u_min, run.u_max = min(run.u_min, y[0]), max(run.u_max, y[0])
        th = end
        if stop is None:  # the period's end or separation
            if th < th_end:
                mode, after_rest = SEPARATION, False
            continue
        y[1] = 0.0
        F = y[0] + node.q(th)
        n = node.n(th)
        a_old = seg.acceleration1(th, y[0], 0.0)
        if abs(F) <= n:  # stick
            mode = STICK
            Jac = np.array([[1.0, 0.0], [0.0, 0.0]]) @ Jac
        else:  # reversal
            mode = -s
            new = Segment(node.osc, slip_forcing(-s, node.P1, node.Q1, node.phi), th, y)
            a_new = new.acceleration1(th, y[0], 0.0)
            ratio = a_new / a_old if a_old != 0.0 else 1.0
            Jac = np.array([[1.0, 0.0], [0.0, ratio]]) @ Jac
            after_rest = True
    else:  # pragma: no cover - a bound on chattering
        raise SolverError(
            "dynamic single node: more than 10000 events in one period",
            backend="exact",
            status="events",
        )
    run.z, run.jacobian, run.J = y, Jac, J
    return run


def _extrema(node, seg, th0, th1, run):
    """Turning points of the free motion (separation) for the amplitude."""
    if th1 <= th0:
        return
    n = max(2, math.ceil((th1 - th0) / node.cell))
    grid = np.linspace(th0, th1, n + 1)
    y = seg.state(grid)
    run.u_min, run.u_max = min(run.u_min, float(y[0].min())), max(run.u_max, float(y[0].max()))
    v = y[1]
    for i in np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0):
        t = brentq(lambda s: seg.state1(s)[1], grid[i], grid[i + 1], xtol=1e-15)
        u = seg.state1(t)[0]
        run.u_min, run.u_max = min(run.u_min, u), max(run.u_max, u)


@dataclass(frozen=True)
class DynamicOrbit:
    """A periodic orbit of the normalized dynamic node.

    Attributes
    ----------
    z : ndarray
        ``(u, u')`` at θ = 0 on the orbit.
    J : float
        ``∫ n |u'| dθ`` per cycle (``Ŵ = J / Q̂1``).
    amplitude : float
        ``(max u - min u) / 2`` over the cycle.
    floquet : ndarray
        The Floquet multipliers (the monodromy matrix's eigenvalues, complex).
    stable : bool
        Both multipliers inside the unit circle (to 1e-9), or stuck throughout (a neutral family
        of rest states).
    iterations : int
        Newton's iterations.
    periods : int
        Periods of motion computed in all.
    residual : float
        ``|Φ(z) - z|`` at the end.
    """

    z: np.ndarray
    J: float
    amplitude: float
    floquet: np.ndarray
    stable: bool
    iterations: int
    periods: int
    residual: float


def periodic_orbit(
    node: DynamicNode, start, *, warmup: int = 1, max_iter: int = 40, tol: float = 1e-12
) -> DynamicOrbit:
    """Newton's method on the period map from ``start`` (after ``warmup`` periods of motion).

    Raises
    ------
    SolverError
        Newton's method did not reach ``tol`` (status ``"newton"``).
    """
    z = np.array(start, dtype=float)
    run = period_map(node, z)
    periods = 1
    for _ in range(warmup):
        z = run.z
        run = period_map(node, z)
        periods += 1
    scale = max(1.0, node.Q1, abs(z[0]), abs(z[1]) * node.osc.beta)
    res = math.inf
    for it in range(1, max_iter + 1):  # run: the period from z
        r = run.z - z
        res = float(np.max(np.abs(r)))
        if res <= tol * scale:
            break
        A = run.jacobian - np.eye(2)
        try:
            step = -np.linalg.solve(A, r)
        except np.linalg.LinAlgError:
            step = -np.linalg.lstsq(A, r, rcond=None)[0]
        # backtracking on the residual (the map is piecewise smooth); the accepted trial's
        # period is the next iteration's
        lam, best = 1.0, None
        for _ in range(30):
            trial = z + lam * step
            tr = period_map(node, trial)
            periods += 1
            if float(np.max(np.abs(tr.z - trial))) < res:
                best = (trial, tr)
                break
            lam *= 0.5
        if best is None:  # no decrease along Newton's direction: a period of motion instead
            z = run.z
            run = period_map(node, z)
            periods += 1
        else:
            z, run = best
    else:
        raise SolverError(
            f"dynamic single node: the periodic orbit not found (|Φ(z) - z| = {res:.3g} after "
            f"{max_iter} Newton iterations)",
            backend="exact",
            status="newton",
        )
    final = run
    mult = np.linalg.eigvals(final.jacobian)
    amp = 0.5 * (final.u_max - final.u_min)
    return DynamicOrbit(
        z=z,
        J=final.J,
        amplitude=amp,
        floquet=mult,
        # a cycle stuck throughout: a neutral family of rest states (multiplier 1), each stable
        stable=bool(np.all(np.abs(mult) < 1.0 - 1e-9)) or (final.J == 0.0 and final.z[1] == 0.0),
        iterations=it,
        periods=periods,
        residual=res,
    )
