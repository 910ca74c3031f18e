"""The normalization of Eq. (6): the conversions between the dissipation W and its normalized
Ŵ, and the check that a single node's units and normalized amplitudes are representable.

``Ŵ = k11 W / (f P0 Q1)``; the units of force ``f P0`` and of displacement ``f P0 / k11`` in
which lcpfric advances a :class:`~lcpfric.model.single_node.SingleNode` must be finite normal
doubles, as must the normalized amplitudes ``P̂1 = P1/P0`` and ``Q̂1 = Q1/(f P0)``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["W_hat_from_W", "W_from_W_hat", "check_units"]

_TINY = float(np.finfo(float).tiny)  # the smallest normal double, 2.2e-308
_HUGE = float(np.finfo(float).max)


def W_hat_from_W(
    W: ArrayLike, k11: float, f: float, P0: float, Q1: ArrayLike
) -> float | np.ndarray:
    """Ŵ = k11 W / (f P0 Q1) (Eq. 6); zero where Q1 = 0 (the limit, since W = O(Q1²)).

    Parameters
    ----------
    W : float or array_like
        Dissipation per cycle, in the units of force x displacement.
    k11 : float
        Tangential spring stiffness.
    f : float
        Coefficient of friction.
    P0 : float
        Mean normal load.
    Q1 : float or array_like
        Tangential load amplitude (broadcast against ``W``).

    Returns
    -------
    float or ndarray
        Ŵ (0 where ``f P0 Q1 <= 0``); a float for scalar input.
    """
    W = np.asarray(W, dtype=float)
    denom = f * P0 * np.asarray(Q1, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(denom > 0, k11 * W / np.where(denom > 0, denom, 1.0), 0.0)
    return out if out.ndim else float(out)


def W_from_W_hat(
    W_hat: ArrayLike, k11: float, f: float, P0: float, Q1: ArrayLike
) -> float | np.ndarray:
    """W = f P0 Q1 Ŵ / k11, the inverse of :func:`W_hat_from_W`.

    Parameters
    ----------
    W_hat : float or array_like
        Normalized dissipation per cycle Ŵ.
    k11 : float
        Tangential spring stiffness.
    f : float
        Coefficient of friction.
    P0 : float
        Mean normal load.
    Q1 : float or array_like
        Tangential load amplitude (broadcast against ``W_hat``).

    Returns
    -------
    float or ndarray
        W, in the units of force x displacement; a float for scalar input.
    """
    out = f * P0 * np.asarray(Q1, dtype=float) * np.asarray(W_hat, dtype=float) / k11
    return out if out.ndim else float(out)


def check_units(node, harmonic_inputs: bool) -> None:
    """P0, f P0 and the normalized amplitudes P̂1 = P1/P0, Q̂1 = Q1/(f P0) must be finite
    normal doubles (no overflow to inf, no underflow to 0 or to subnormals).

    Parameters
    ----------
    node : SingleNode
        The node (:class:`~lcpfric.model.single_node.SingleNode`), its loads and springs set.
    harmonic_inputs : bool
        Whether the loads were given as P0, P1, Q0, Q1 (the errors name those) rather than as
        ``normal_load`` and ``tangential_load``.

    Raises
    ------
    InputError
        A unit or normalized amplitude that is not a finite normal double.
    """
    P0, f = node.normal_load.mean, node.f
    p_name = "P1" if harmonic_inputs else "normal_load"
    q_name = "Q1" if harmonic_inputs else "tangential_load"
    if not _TINY <= P0 <= _HUGE:
        raise InputError(
            "P0",
            f"must be in [{_TINY:.4g}, {_HUGE:.4g}] (the loads are divided by P0), got {P0!r}",
        )
    fp0 = f * P0
    if not _TINY <= fp0 <= _HUGE:
        raise InputError(
            "f",
            f"the force unit f·P0 = {fp0:.4g} must be in [{_TINY:.4g}, "
            f"{_HUGE:.4g}] (f = {f!r}, P0 = {P0!r})",
        )
    for name, k in (("k11", node.k11), ("k22", node.k22)):
        if k < _TINY:
            raise InputError(name, f"must be >= {_TINY:.4g} (a normal double), got {k!r}")
    unit = fp0 / node.k11
    if not _TINY <= unit <= _HUGE:
        raise InputError(
            "k11",
            f"the displacement unit f·P0/k11 = {unit:.4g} must be in "
            f"[{_TINY:.4g}, {_HUGE:.4g}] (f·P0 = {fp0!r}, "
            f"k11 = {node.k11!r})",
        )
    omega = 2 * math.pi / node.period
    if not (_TINY <= omega and math.isfinite(node.period)):
        raise InputError(
            "omega", f"must be >= {_TINY:.4g} (the period 2π/ω must be finite), got {omega!r}"
        )
    for name, amp, unit, what in (
        (p_name, node.normal_load.amplitude, P0, "P1/P0"),
        (q_name, node.tangential_load.amplitude, fp0, "Q1/(f·P0)"),
    ):
        ratio = amp / unit
        if not math.isfinite(ratio) or (amp > 0 and ratio < _TINY):
            raise InputError(
                name,
                f"the normalized amplitude {what} = {ratio:.4g} is not "
                f"representable (allowed {what} = 0 or in "
                f"[{_TINY:.4g}, {_HUGE:.4g}]); got amplitude {amp!r} "
                f"for the unit {unit!r}",
            )
