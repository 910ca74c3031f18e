r"""The MDR sphere's increment (``method="mdr-bar"``): the bar's equation, solved exactly.

The increment to ``t_{j+1}`` is problem (P) of the other backends, the maximum-dissipation
projection of the trial state, for this system: given the bar's displacement u the springs are
independent, and each one's answer is its return mapping ``F_i(u) = clip(k_i (v_i - u), -b_i,
b_i)``, ``b_i = μ N_i(t_{j+1})`` (lcpfric's sign: ``F_i = k_i (v_i - u)`` is the friction force, and
the slip opposes it). The bar's equilibrium ``h(u) = Σ F_i(u) - k_support u + Q = 0`` is one
monotone piecewise-linear equation in u, solved exactly (:func:`bar_root`: a safeguarded Newton
iteration from the previous u, exact once a step keeps every spring on its side of its breakpoints
``v_i ∓ b_i/k_i``; usually two or three O(n) passes); the rank-one coupling of the springs through
the bar is never formed as a matrix. With ``k_support = 0`` the equation has a root only when
``|Q| <= μ P`` (else the whole contact slides): such loads are refused before any work, naming
the instants and the fix (a support stiffness).

The model (:class:`~lcpfric.model.continuum.mdr.MDRSphere`) gives the springs (``k_i``) and the
friction limits; :func:`bar_increment` advances many bars at once (the maps of
:mod:`lcpfric.analysis.contact_maps` advance every point of a map with it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.continuum.mdr import MDRSphere
from .continuum import ContinuumStepper

__all__ = ["MDRBarStepper", "bar_increment", "bar_root"]


class MDRBarStepper(ContinuumStepper):
    """The MDR sphere's exact increment (module docstring)."""

    name = "mdr-bar"
    model_type = MDRSphere

    def start(self, scene, context) -> "_Bar":
        return _Bar(np.zeros(scene.model.nodes), 0.0)

    def increment(self, context, state, b, Q, guess=None, tol=None):
        """The exact increment to the next instant (module docstring): ``(state, F, dv)``."""
        model = context
        v, u = state.v, state.u
        if model.k_support == 0.0 and abs(Q) > float(b.sum()) * (1.0 + 1e-12):
            _no_root(Q, b)
        u1, F, v1 = bar_increment(
            v[None], np.array([u]), model.k[None], b[None], np.array([Q]), model.k_support
        )
        v1 = v1[0]
        return _Bar(v1, float(u1[0])), F[0], v1 - state.v

    def context(self, scene):
        return scene.model


def bar_increment(v, u, k, b, Q, ks):
    """The increment of m bars at once (rows of the ``(m, n)`` arrays v, k, b; u and Q of
    length m): the bar displacements (:func:`bar_root`), then each spring's return mapping.
    Returns ``(u, F, v)``."""
    u1 = bar_root(v, u, k, b, Q, ks)
    trial = k * (v - u1[:, None])
    F = np.minimum(np.maximum(trial, -b), b)
    return u1, F, np.where(np.abs(trial) <= b, v, u1[:, None] + F / k)


def bar_root(v, u, k, b, Q, ks):
    """The bar displacement of every row: the root of ``h(u) = Σ clip(k (v - u), -b, b) - ks
    u + Q`` (decreasing in u), by a safeguarded Newton iteration from the previous u. h is
    linear between the breakpoints ``v ∓ b/k``, so a step that keeps every spring's stick/slip
    side lands on the root exactly; a bracket keeps the iteration inside. Under pure load
    control with |Q| beyond every limit there is no root: the caller checks."""
    lo = np.min(v - b / k, axis=1)  # below: every spring at +b
    hi = np.max(v + b / k, axis=1)  # above: every spring at -b
    total = b.sum(axis=1)
    h_lo = total - ks * lo + Q
    h_hi = -total - ks * hi + Q
    out = np.empty_like(u)
    below, above = h_lo <= 0.0, h_hi >= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        out[below] = np.where(ks > 0, lo[below] + h_lo[below] / ks, lo[below])
        out[above] = np.where(ks > 0, hi[above] + h_hi[above] / ks, hi[above])
    inside = ~(below | above)
    if not inside.any():
        return out
    i = np.flatnonzero(inside)
    every = i.size == u.size
    vv, kk, bb, qq = (v, k, b, Q) if every else (v[i], k[i], b[i], Q[i])
    L, H = lo[i].copy(), hi[i].copy()
    x = np.clip(u[i], L, H)
    todo = None  # None: every point (no gathering on the first, usually last, iteration)
    eps = 4 * np.finfo(float).eps
    for _ in range(200):
        if todo is None:
            xv, Vv, Kv, Bv, qv, Lt, Ht = x, vv, kk, bb, qq, L, H
        else:
            xv, Vv, Kv, Bv, qv = x[todo], vv[todo], kk[todo], bb[todo], qq[todo]
            Lt, Ht = L[todo], H[todo]
        t = Kv * (Vv - xv[:, None])
        c = np.minimum(np.maximum(t, -Bv), Bv)
        side = np.sign(c - t)  # 0: sticking; ±1: at -b / +b
        h = c.sum(axis=1) - ks * xv + qv
        slope = -(Kv * (side == 0)).sum(axis=1) - ks
        Lt = np.where(h > 0.0, xv, Lt)
        Ht = np.where(h < 0.0, xv, Ht)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(slope < 0.0, xv - h / slope, 0.5 * (Lt + Ht))
        step = np.where((step >= Lt) & (step <= Ht), step, 0.5 * (Lt + Ht))
        new = np.where(h == 0.0, xv, step)
        t2 = Kv * (Vv - new[:, None])
        same = np.all(np.sign(np.minimum(np.maximum(t2, -Bv), Bv) - t2) == side, axis=1)
        finished = (
            (h == 0.0)
            | (same & (slope < 0.0))
            | (new == xv)
            | (Ht - Lt <= eps * np.maximum(np.abs(Lt), np.abs(Ht)))
        )
        if todo is None:
            x, L, H = new, Lt, Ht
            todo = np.flatnonzero(~finished)
        else:
            x[todo], L[todo], H[todo] = new, Lt, Ht
            todo = todo[~finished]
        if not todo.size:
            break
    out[i] = x
    return out


@dataclass
class _Bar:
    """The tangential state: the springs' slips v and the bar's displacement u."""

    v: np.ndarray
    u: float


def _no_root(Q, b):
    raise InputError(
        "k_support",
        f"is 0 and |Q| = {abs(Q):.6g} exceeds the friction limit "
        f"μP = {float(np.sum(b)):.6g} of the whole contact at an "
        f"increment: gross sliding has no equilibrium under pure load "
        f"control; give k_support > 0",
    )
