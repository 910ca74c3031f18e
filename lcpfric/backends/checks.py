"""Checking every answer: the residuals of a candidate solution of problem (P), and the
acceptance of a solver's answer (:func:`lcpfric.backends.refine.accept`: refined on its
active set, or as it is).

Checking every answer
---------------------
A solver's status flag is not trusted alone (OSQP, for one, can report success on a poor answer).
After every step lcpfric computes, from the returned forces only, with the slip
``Δu_A = P F_A + q`` (the gradient of (P)), relative to the scene's force scale ``s_F`` and
compliance scale ``c = max C_ii``:

``cone``
    ``max_i (||F_i|| - f_i N_i)_+ / s_F``: primal feasibility;
``complementarity``
    ``max_i (F_i·Δu_i + f_i N_i ||Δu_i||) / (c s_F²)``: >= 0 always, and 0 iff the slip
    opposes the force and vanishes below the limit;
``stationarity``
    ``max_i ||F_i - Π_i(F_i - Δu_i / c)|| / s_F``, the natural-map residual of (P) (Π_i the
    projection on node i's interval or disc): zero iff F solves (P);
``equilibrium``
    ``max |Q + K u - F| / s_F`` with ``u = C (F - Q)``, which catches a compliance that is
    not K⁻¹.

A step whose status is not "solved", or whose largest residual exceeds ``check_tol``, raises
:class:`~lcpfric.errors.SolverError` with the backend's own status and the residuals.

The array form :func:`residuals` and the scalar form :func:`scalar_residuals` (for the single
node's fast path) compute the same quantities; the tests check them equal on random data.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["residuals", "scalar_residuals", "scalar_worst", "worst", "separating_slips_agree"]

#: a wrong-way slip of a separating node up to this (times ``c s_F``) is round-off
SLIP_TOL = 1e-10


def residuals(
    F: np.ndarray, g: np.ndarray, b: np.ndarray, dims: int, fscale: float, cscale: float
) -> dict[str, float]:
    """The residuals of a candidate answer of (P) (see the module docstring).

    Parameters
    ----------
    F : (a·d,) ndarray
        Friction forces of the nodes in contact.
    g : (a·d,) ndarray
        Their slip ``Δu = P F + q``.
    b : (a,) ndarray
        Their friction limits f_i N_i.
    dims : int
        d, the tangential directions per node: 1 (intervals) or 2 (discs).
    fscale, cscale : float
        Force and compliance scales (``s_F`` and ``c = max C_ii``), both > 0.

    Returns
    -------
    dict
        ``cone``, ``complementarity`` and ``stationarity`` (floats, relative as in the module
        docstring; all 0 for an empty set). NaN in ``F`` or ``g`` gives a NaN residual, which
        fails any tolerance.
    """
    if F.size == 0:
        return {"cone": 0.0, "complementarity": 0.0, "stationarity": 0.0}
    if dims == 1:
        normF, normg = np.abs(F), np.abs(g)
        proj = np.minimum(np.maximum(F - g / cscale, -b), b)
        dot = F * g
        stat = np.abs(F - proj)
    else:
        F2, g2 = F.reshape(-1, 2), g.reshape(-1, 2)
        normF, normg = np.hypot(F2[:, 0], F2[:, 1]), np.hypot(g2[:, 0], g2[:, 1])
        t2 = F2 - g2 / cscale
        nt = np.hypot(t2[:, 0], t2[:, 1])
        scale = np.where(nt > b, b / np.where(nt > 0, nt, 1.0), 1.0)
        dot = np.einsum("ij,ij->i", F2, g2)
        diff = F2 - t2 * scale[:, None]
        stat = np.hypot(diff[:, 0], diff[:, 1])
    return {
        "cone": max(float((normF - b).max()), 0.0) / fscale,
        "complementarity": float(np.abs(dot + b * normg).max()) / (cscale * fscale * fscale),
        "stationarity": float(stat.max()) / fscale,
    }


def worst(res: dict) -> float:
    """The largest residual (NaN if any is NaN)."""
    worst = 0.0
    for v in res.values():
        if v != v:
            return math.nan
        if v > worst:
            worst = v
    return worst


def scalar_residuals(F, g, b, c, scale) -> dict:
    """:func:`residuals` of one unknown (d = 1) in Python floats; ``scale = (s_F, c s_F²)``."""
    fs, cfs2 = scale
    t = F - g / c
    return {
        "cone": max(abs(F) - b, 0.0) / fs,
        "complementarity": abs(F * g + b * abs(g)) / cfs2,
        "stationarity": abs(F - min(max(t, -b), b)) / fs,
    }


def scalar_worst(F, g, b, c, scale) -> float:
    """max of :func:`scalar_residuals` without building the dict (NaN propagates)."""
    fs, cfs2 = scale
    t = F - g / c
    r1 = (abs(F) - b) / fs
    r2 = abs(F * g + b * abs(g)) / cfs2
    r3 = abs(F - min(max(t, -b), b)) / fs
    if r1 != r1 or r2 != r2 or r3 != r3:
        return math.nan
    return max(r1, r2, r3)


def separating_slips_agree(
    F_start: np.ndarray,
    du: np.ndarray,
    separating: np.ndarray | None,
    fscale: float,
    cscale: float,
) -> bool:
    """Whether the nodes that separate at the end of a (sub-)increment slip against their force
    at its start (d = 1): the part of the straight path's admissibility that
    :func:`~lcpfric.steppers.rates.path_is_exact` does not see.

    A node that separates at t_{k+1} leaves problem (P): its force is zero at the end and its
    displacement free. On the straight path its force goes from the limit it is on at the start,
    ``F_i = ±f_i N_i``, to zero along that limit (``f_i N_i`` is linear too), which is
    admissible only if the node slips the other way all along, ``F_i Δu_i <= 0``. When its slip
    reverses inside the increment (the node stops, then crosses to its other limit as ``N_i``
    goes to zero, and a neighbour's slip rate jumps with it), the projection's end state is not
    the exact one: the neighbours' slips before the reversal are missed.

    Parameters
    ----------
    F_start : (n,) ndarray
        The forces at the start of the (sub-)increment.
    du : (n,) ndarray
        The slips over it, as the projection returned them.
    separating : (n,) bool ndarray or None
        The nodes that separate at its end (None: none).
    fscale, cscale : float
        Force and compliance scales (``s_F`` and ``c``): a wrong-way slip up to
        :data:`SLIP_TOL` ``c s_F`` is taken for round-off.

    Returns
    -------
    bool
        True when every separating node slips against its start force (or does not slip).
    """
    if separating is None or not separating.any():
        return True
    wrong = np.sign(F_start[separating]) * du[separating]
    return bool(np.all(wrong <= SLIP_TOL * cscale * fscale))
