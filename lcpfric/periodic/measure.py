"""How far a cycle is from repeating: the one convergence measure of every cycle loop (the driver,
the batched loop, the exact solver's cycle Newton).

A cycle's change is ``max(du / s_v, |dW| / s_W)`` (:func:`cycle_change`), with ``du`` the largest
change of the compared displacements, in one of two forms (:func:`displacement_change`):

``"cycles"``
    the cycle's recorded instants against the previous cycle's (discrete systems: the whole
    cycle, or its first and last instants without the history; the batched single nodes compare
    the cycles' starts, the clamp being non-expansive);
``"map"``
    the cycle's end against its start, the cycle map's residual, on the unknowns that are the
    state (a continuum contact's nodes in contact at the cycle's start); the exact solver's
    cycle Newton compares the start displacements this way, with no W term (its successive
    cycles start from Newton's iterates).
"""

from __future__ import annotations

import numpy as np

from dataclasses import replace

from ..scene import Scene, column_reduce

__all__ = ["cycle_change", "displacement_change", "load_scales", "unit_scaled", "MEASURES"]

MEASURES = ("cycles", "map")


def cycle_change(
    du: float | np.ndarray,
    v_span: float | np.ndarray,
    dW: float | np.ndarray,
    W: float | np.ndarray,
    load_span: tuple[float | np.ndarray, float | np.ndarray],
) -> float | np.ndarray:
    """The convergence measure of a cycle (the one criterion of every cycle loop).

    ``max(du / s_v, |dW| / s_W)`` with the scales

    * ``s_v = max(v_span, load_span)``: the cycle's range of the displacements, or the loads'
      displacement scale (the range of the tangential loads times the compliance), whichever is
      larger. It does not vanish when the system shakes down or slips very little, so such a
      steady state is confirmed like any other;
    * ``s_W = max(|W|, s_u · s_F)``, the same for the dissipation, with ``s_u`` the loads'
      displacement scale and ``s_F`` the largest friction limit f N: the dissipating forces
      never exceed it (the tangential load itself may be far larger).

    Parameters
    ----------
    du : float or ndarray
        ``max |v_c - v_{c-1}|`` over the grid (per point of a batch).
    v_span : float or ndarray
        The cycle's range of v.
    dW, W : float or ndarray
        ``W_c - W_{c-1}`` and ``W_c`` (``dW = 0``: the displacements alone decide).
    load_span : tuple (displacement, force) of floats or ndarrays
        The loads' scales: the range of Q times the compliance, and the largest friction
        limit f N.

    Returns
    -------
    float or ndarray
        The relative change (>= 0; a float when every input is scalar, else per point).
        Where a scale is 0 a nonzero change is ``inf`` and a zero change 0.
    """
    u_scale, f_scale = (np.asarray(x, dtype=float) for x in load_span)
    s_v = np.maximum(np.asarray(v_span, dtype=float), u_scale)
    s_W = np.maximum(np.abs(np.asarray(W, dtype=float)), u_scale * f_scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(
            s_v > 0,
            np.abs(du) / np.where(s_v > 0, s_v, 1.0),
            np.where(np.asarray(du) == 0, 0.0, np.inf),
        )
        b = np.where(
            s_W > 0,
            np.abs(dW) / np.where(s_W > 0, s_W, 1.0),
            np.where(np.asarray(dW) == 0, 0.0, np.inf),
        )
    out = np.maximum(a, b)
    return out if out.ndim else float(out)


def displacement_change(form: str, cyc, prev, held=None) -> float:
    """``du`` of :func:`cycle_change` for a :class:`~lcpfric.results.CycleResult` ``cyc`` after
    ``prev``, in the form ``"cycles"`` or ``"map"`` (module docstring; ``held``: the unknowns
    the map form compares, all by default)."""
    if form == "map":
        d = np.abs(cyc.u[-1] - cyc.u[0])
        return float(np.max(d if held is None else d[held], initial=0.0))
    return float(np.max(np.abs(cyc.u - prev.u)))


def load_scales(scene, compliance) -> tuple[float, float]:
    """The loads' displacement and force scales of a discrete system's scene: ``(c r, b)`` with
    r the largest range of a tangential load over the cycle, c the largest diagonal compliance
    and b the largest friction limit f N."""
    parts = column_reduce(scene.Q, lambda x: (np.min(x, axis=0), np.max(x, axis=0)))
    lo = np.min([p[0] for p in parts], axis=0)
    hi = np.max([p[1] for p in parts], axis=0)
    r = float(np.max(hi - lo, initial=0.0))
    return compliance * r, largest_limit(scene)


def largest_limit(scene) -> float:
    """The largest friction limit f N over a discrete system's scene (chunk by chunk: Q and N
    may be :class:`~lcpfric.scene.Rows`)."""
    f = scene.system.friction
    return float(max(column_reduce(scene.N, lambda x: float(np.max(x * f, initial=0.0)))))


def unit_scaled(scene: Scene) -> tuple[Scene, float]:
    """A discrete system's scene with forces divided by s, a power of two near the largest
    friction limit (a continuum contact's steppers scale their own tolerances: unchanged).

    Steppers then see forces of order one whatever the units (loads of 1e6, or 1e-6): the
    convex solvers' tolerances are absolute, and at P̂1 = Q̂1 = 1e6 Clarabel otherwise stops
    "DualInfeasible". Q, f N and so u and F scale by 1/s and W by 1/s². Dividing by a power of
    two is exact in floating point, so the closed-form steppers give the same bits either way.
    """
    if scene.system is None or getattr(scene.system, "coupling", None) is not None:
        return scene, 1.0  # (a coupled system's steppers read P(t) from the system itself)
    # the answer F lies within ±f N: its size is the largest friction limit
    size = largest_limit(scene)
    if not np.isfinite(size) or size == 0.0:
        return scene, 1.0
    scale = float(2.0 ** np.round(np.log2(size)))
    if scale == 1.0:
        return scene, 1.0
    return replace(
        scene, Q=scene.Q / scale, N=scene.N / scale, _cache={"contact": scene.contact}
    ), scale  # contact is scale-free
