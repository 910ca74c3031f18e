"""Shooting: the periodic orbit of a dynamic system as the fixed point of its period map,
by Newton's method with the map's Jacobian (issue 40, item 4), and plain cycle iteration for
comparison.

A lightly damped structure forgets its start like ``exp(-ζ Ω t)``: about ``1/(2π ζ)`` periods
an e-fold near resonance, thousands for ζ = 1e-3. Newton's method on ``Φ(z) - z = 0`` needs the
Jacobian ``∂Φ/∂z`` (propagated through the increments by the stepper) and converges in a few
periods whatever ζ. The Newton step solves ``(J - I) dz = z - Φ(z)`` in the least-squares
sense: where a slider sticks over the whole period its position is free (a family of orbits;
the step keeps the one nearest the start). A Newton step that does not lower the residual is
halved (at most ``halvings`` times), then taken as it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ShootingResult", "shoot", "iterate_cycles"]


@dataclass(frozen=True)
class ShootingResult:
    """The fixed point found: ``z``, the Jacobian at it, the residual ``max |Φ(z) - z|``
    relative to ``max |z|``, Newton's iterations, the periods computed and whether the
    tolerance was met."""

    z: np.ndarray
    jacobian: np.ndarray | None
    residual: float
    iterations: int
    periods: int
    converged: bool


def _relative(r, z) -> float:
    return float(np.max(np.abs(r))) / max(float(np.max(np.abs(z))), 1e-300)


def shoot(
    period_map,
    z0,
    tol: float,
    max_iterations: int = 30,
    halvings: int = 4,
    max_step: float = np.inf,
):
    """Newton's method on the period map.

    Parameters
    ----------
    period_map : callable
        ``period_map(z) -> (z1, J)``: the state after one period and the Jacobian.
    z0 : (p,) ndarray
        The first guess.
    tol : float
        Tolerance on ``max |Φ(z) - z| / max |z|``.
    max_iterations : int, optional
        Newton iterations at most.
    halvings : int, optional
        Step halvings at most when a step does not lower the residual.
    max_step : float, optional
        The largest step, relative to ``max |z|`` (default: no cap).

    Returns
    -------
    ShootingResult
    """
    z = np.asarray(z0, dtype=float)
    z1, J = period_map(z)
    periods = 1
    res = _relative(z1 - z, z1)
    it = 0
    while res > tol and it < max_iterations:
        it += 1
        # least squares: a sticking slider's position is a family of orbits (J - I singular)
        dz = np.linalg.lstsq(J - np.eye(z.size), -(z1 - z), rcond=1e-13)[0]
        size = float(np.max(np.abs(dz)))
        lam = min(1.0, max_step * max(float(np.max(np.abs(z))), 1e-300) / size) if size else 1.0
        for _ in range(halvings + 1):
            trial = z + lam * dz
            t1, tJ = period_map(trial)
            periods += 1
            tres = _relative(t1 - trial, t1)
            if tres < res or not math.isfinite(res):
                break
            lam *= 0.5
        z, z1, J, res = trial, t1, tJ, tres
    return ShootingResult(z, J, res, it, periods, bool(res <= tol))


def iterate_cycles(period_map, z0, tol: float, max_periods: int):
    """Plain cycle iteration ``z <- Φ(z)`` until ``max |Φ(z) - z| / max |z| <= tol``:
    ``(z, residual, periods, converged)`` (``period_map(z) -> z1``)."""
    z = np.asarray(z0, dtype=float)
    res = math.inf
    for k in range(1, max_periods + 1):
        z1 = period_map(z)
        res = _relative(z1 - z, z1)
        z = z1
        if res <= tol:
            return z, res, k, True
    return z, res, max_periods, False
