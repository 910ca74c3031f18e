r"""The exact periodic steady state of the dynamic single node (issue 40, item 2): event by event
with closed-form segments (compiled: :mod:`.dynamic_kernels`), the periodic orbit by Newton's
method on the period map with its exact Jacobian, verified, its Floquet multipliers reported.

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
from dataclasses import dataclass

import numpy as np

from ..errors import SolverError

__all__ = ["DynamicNode", "DynamicOrbit", "PeriodRun", "period_map", "periodic_orbit"]

TWO_PI = 2.0 * math.pi
#: cells per the shorter of the forcing's and the oscillator's periods
CELLS = 24


class DynamicNode:
    """The normalized dynamic node: ``P̂1, Q̂1, φ, β, ζ`` and its kernels' parameter array.

    Parameters
    ----------
    P1, Q1, phi, beta, zeta : float
        As for :func:`~lcpfric.exact.dynamic_api.dynamic_cycle` (checked there).
    """

    def __init__(self, P1, Q1, phi, beta, zeta):
        self.P1, self.Q1, self.phi = float(P1), float(Q1), float(phi)
        self.beta, self.zeta = float(beta), float(zeta)
        sep = (math.nan, math.nan)
        if self.P1 > 1.0:  # n <= 0 on [π + asin(1/P̂1), 2π - asin(1/P̂1)]
            g = math.asin(1.0 / self.P1)
            sep = (math.pi + g, TWO_PI - g)
        cell = min(TWO_PI, TWO_PI * self.beta) / CELLS
        self.params = np.array([self.P1, self.Q1, self.phi, self.beta, self.zeta, cell, *sep])

    def q(self, th):
        """Q̂(θ) less its mean."""
        return self.Q1 * np.sin(th + self.phi)

    def n(self, th):
        """P̂(θ) = 1 + P̂1 sin θ (negative: separated)."""
        return 1.0 + self.P1 * np.sin(th)


@dataclass
class PeriodRun:
    """One period of motion from a state (:func:`period_map`).

    Attributes
    ----------
    z, jacobian : ndarray
        The end state ``(u, u')`` and ``∂z_end/∂z``.
    J : float
        ``∫ n |u'| dθ`` over the period.
    u_min, u_max : float
        The extremes of u.
    segments : ndarray
        ``(events, 5)``: each segment's ``θa, θb, mode, u_a, u'_a``.
    """

    z: np.ndarray
    jacobian: np.ndarray
    J: float
    u_min: float
    u_max: float
    segments: np.ndarray

    @property
    def events(self) -> int:
        """The segments of the period."""
        return self.segments.shape[0]


def period_map(node: DynamicNode, z, theta0: float = 0.0) -> PeriodRun:
    """One period from ``z = (u, u')`` at ``theta0`` (module docstring).

    Raises
    ------
    SolverError
        More than :data:`~.dynamic_kernels.MAX_SEGMENTS` segments in one period (status
        ``"events"``).
    """
    from . import dynamic_kernels as kern  # numba: compiled on first use

    jac = np.empty((2, 2))
    segs = np.empty((kern.MAX_SEGMENTS, 5))
    lohi = np.empty(2)
    u, du, J, nseg, status = kern.period_map(
        node.params, float(z[0]), float(z[1]), float(theta0), jac, segs, lohi
    )
    if status:
        raise SolverError(
            f"dynamic single node: more than {kern.MAX_SEGMENTS} events in one period",
            backend="exact",
            status="events",
        )
    return PeriodRun(np.array([u, du]), jac, J, float(lohi[0]), float(lohi[1]), segs[:nseg])


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
    scale = max(1.0, node.Q1, abs(z[0]), abs(z[1]) * node.beta)
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
    else:  # Newton's method wandered on the piecewise-smooth map: the motion itself, polished
        z, run, res, extra = _settle(node, run.z, tol * scale)
        periods += extra
        if res > tol * scale:
            raise SolverError(
                f"dynamic single node: the periodic orbit not found (|Φ(z) - z| = {res:.3g} "
                f"after {max_iter} Newton iterations and {extra} periods of motion)",
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


def _settle(node: DynamicNode, z, tol: float, max_periods: int = 20_000):
    """Periods of motion from z (a stable orbit attracts them), with a Newton step tried every
    16 periods and kept where it lowers the residual: ``(z, run, residual, periods)``."""
    run = period_map(node, z)
    periods = 1
    res = float(np.max(np.abs(run.z - z)))
    while res > tol and periods < max_periods:
        if periods % 16 == 0:
            try:
                trial = z - np.linalg.solve(run.jacobian - np.eye(2), run.z - z)
                tr = period_map(node, trial)
                periods += 1
                tres = float(np.max(np.abs(tr.z - trial)))
                if tres < res:
                    z, run, res = trial, tr, tres
                    continue
            except np.linalg.LinAlgError:
                pass
        z = run.z
        run = period_map(node, z)
        periods += 1
        res = float(np.max(np.abs(run.z - z)))
    return z, run, res, periods
