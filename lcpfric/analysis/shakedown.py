"""Shakedown: does a constant slip displacement exist under which the node sticks for ever?

Section 3.2: shakedown happens if and only if some constant shift c gives ``|Q̂(t) - c| <= P̂(t)``
for all t, i.e. the load ellipse of Fig. 1, shifted along Q, fits between the lines Q = ±P. That is
``max_t (Q̂ - P̂) <= c <= min_t (Q̂ + P̂)``. For harmonic loads both extrema are closed form::

    max (Q̂ - P̂) = R_hi - 1,   R_hi = |Q̂1 e^{iφ} - P̂1|
    min (Q̂ + P̂) = 1 - R_lo,   R_lo = |Q̂1 e^{iφ} + P̂1|

so shakedown holds iff ``R_lo + R_hi <= 2`` (the sum of the distances from Q̂1 e^{iφ} to ±P̂1 is at
most 2: the load point lies in an ellipse with foci ±P̂1). For other periodic loads the extrema
are found by sampling and polishing (:meth:`lcpfric.model.loads.Load.extrema`).
"""

from __future__ import annotations

from dataclasses import dataclass

from typing import TYPE_CHECKING

import numpy as np

from .. import _checks

if TYPE_CHECKING:  # for the annotations only: lcpfric.model is imported on first use
    from ..model import SingleNode

__all__ = ["Shakedown", "shakedown", "shakedown_margin"]


@dataclass(frozen=True)
class Shakedown:
    """Outcome of the shakedown test (:func:`shakedown`).

    The parameters are kept as the attributes of the same names.

    Parameters
    ----------
    shakedown : bool
        True when a constant shift keeps the node in stick for the whole cycle (then Ŵ = 0).
    shift : float or None
        A valid shift c in units of f P0 (the middle of the admissible range), or None.
    margin : float
        ``min(Q̂ + P̂) - max(Q̂ - P̂)``: the width of the admissible range of c (< 0: no shakedown).
    state : ndarray or None, optional
        For a discrete system (:func:`~lcpfric.analysis.safe_state.safe_band`): a safe
        displacement, or None.
    margins : ndarray or None, optional
        For a discrete system: every node's margin.

    Attributes
    ----------
    shakedown : bool
        True when a constant shift keeps the node in stick for the whole cycle (then Ŵ = 0).
    shift : float or None
        A valid shift c in units of f P0 (the middle of the admissible range), or None.
    margin : float
        ``min(Q̂ + P̂) - max(Q̂ - P̂)``: the width of the admissible range of c (< 0: no shakedown).
    state : ndarray or None
        A discrete system's safe displacement, or None.
    margins : ndarray or None
        A discrete system's margins, node by node.
    """

    shakedown: bool
    shift: float | None
    margin: float
    state: np.ndarray | None = None
    margins: np.ndarray | None = None

    def as_dict(self) -> dict:
        """The outcome as a JSON-serializable dict.

        Returns
        -------
        dict
            ``{"shakedown": bool, "shift": float or None, "margin": float}``, and for a
            discrete system ``"state"`` and ``"margins"`` (lists).
        """
        out = {"shakedown": self.shakedown, "shift": self.shift, "margin": self.margin}
        if self.margins is not None:
            out["state"] = None if self.state is None else [float(x) for x in self.state]
            out["margins"] = [float(x) for x in self.margins]
        return out


def shakedown_margin(P1, Q1, phi):
    """``2 - R_lo - R_hi`` for arrays of (P̂1, Q̂1, φ): >= 0 exactly in the shakedown region."""
    P1, Q1, phi = (np.asarray(x, dtype=float) for x in (P1, Q1, phi))
    z = Q1 * np.exp(1j * phi)
    out = 2.0 - np.abs(z + P1) - np.abs(z - P1)
    return out if out.ndim else float(out)


def shakedown(
    P1: float | SingleNode | None = None,
    Q1: float | None = None,
    phi: float = 0.0,
    *,
    model: SingleNode | None = None,
) -> Shakedown:
    """Decide shakedown exactly.

    Call as ``shakedown(P1, Q1, phi)`` with normalized parameters, or ``shakedown(model=node)``
    (or ``shakedown(node)``) for a :class:`~lcpfric.model.SingleNode` with any periodic loads,
    or ``shakedown(system)`` for a :class:`~lcpfric.model.ContactSystem` (d = 1: the safe
    state node by node, :func:`lcpfric.analysis.safe_state.safe_band`).
    Harmonic loads of one frequency are decided in closed form (module docstring); other
    periodic loads by the extrema of ``Q̂ - P̂`` and ``Q̂ + P̂`` over a cycle, sampled and
    polished (:meth:`lcpfric.model.loads.Load.extrema`).

    Parameters
    ----------
    P1 : float, SingleNode or ContactSystem, optional
        Normalized normal amplitude P̂1 = P1/P0, >= 0; or the node (or system) itself, as
        ``model``.
    Q1 : float, optional
        Normalized tangential amplitude Q̂1 = Q1/(f P0), >= 0.
    phi : float, optional
        Phase φ of Q relative to P, radians (finite).
    model : SingleNode or ContactSystem, optional
        The node (or system) to decide; its parameters replace ``P1``, ``Q1`` and ``phi``.

    Returns
    -------
    Shakedown
        Whether shakedown happens, a valid shift and the margin.

    Raises
    ------
    InputError
        Without a model: ``P1`` or ``Q1`` missing, negative, not finite or over 1e300
        (:data:`~lcpfric.exact.MAX_AMPLITUDE`), or ``phi`` not finite.
    """
    from ..model import ContactSystem, SingleNode

    if isinstance(P1, (SingleNode, ContactSystem)):
        model, P1 = P1, None
    if isinstance(model, ContactSystem):
        from .safe_state import safe_band

        ok, margin, state, margins = safe_band(model)
        return Shakedown(ok, None, margin, state=state, margins=margins)
    if model is not None:
        if model.is_harmonic:
            P1, Q1, phi = model.normalized_parameters()
        else:
            fp0 = model.f * model.P0
            Pn, Qn = model.normal_load, model.tangential_load
            from ..model.loads import Periodic

            minus = Periodic(
                lambda t: (Qn(t) - Qn.mean) / fp0 - Pn(t) / model.P0, model.period, mean=0.0
            )
            plus = Periodic(
                lambda t: (Qn(t) - Qn.mean) / fp0 + Pn(t) / model.P0, model.period, mean=0.0
            )
            lo = minus.extrema()[1]
            hi = plus.extrema()[0]
            ok = lo <= hi
            return Shakedown(bool(ok), 0.5 * (lo + hi) if ok else None, float(hi - lo))
    from ..exact.formulas import MAX_AMPLITUDE

    P1 = _checks.amplitude("P1", P1, MAX_AMPLITUDE)
    Q1 = _checks.amplitude("Q1", Q1, MAX_AMPLITUDE)
    phi = _checks.finite("phi", phi)
    z = Q1 * np.exp(1j * phi)
    r_lo, r_hi = abs(z + P1), abs(z - P1)
    lo, hi = r_hi - 1.0, 1.0 - r_lo
    ok = lo <= hi
    return Shakedown(bool(ok), 0.5 * (lo + hi) if ok else None, float(hi - lo))
