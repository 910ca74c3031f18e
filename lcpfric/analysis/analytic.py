"""Analytical results: the φ = 0 dissipation of Jang and Barber (2011), Eqs. (11)-(12).

Eq. (11) is misprinted in the paper; the corrected form (``docs/paper-notes.md``) is
``Ŵ = 4 (Q̂1 - 1)(Q̂1 - P̂1²) / (Q̂1² - P̂1²)`` for ``P̂1 < 1 < Q̂1``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["jang_barber"]


def jang_barber(P1: float | np.ndarray, Q1: float | np.ndarray) -> float | np.ndarray:
    """Steady-state Ŵ at φ = 0 for P̂1, Q̂1 >= 0 (arrays broadcast).

    The four régimes of Jang and Barber (2011), Eqs. (11)-(12), Eq. (11) corrected (module
    docstring):

    ============================  ===================================================
    régime                        Ŵ
    ============================  ===================================================
    P̂1 <= 1, Q̂1 <= 1 (shakedown)  0
    P̂1 < 1 < Q̂1                    4 (Q̂1 - 1)(Q̂1 - P̂1²) / (Q̂1² - P̂1²)   (Eq. 11, corrected)
    P̂1 >= 1, Q̂1 <= P̂1              0
    P̂1 >= 1, Q̂1 > P̂1               (Q̂1 - P̂1)(1 + P̂1)² / (P̂1 (Q̂1 + P̂1))   (Eq. 12)
    ============================  ===================================================

    Parameters
    ----------
    P1 : float or array_like
        Normalized normal amplitude P̂1 = P1/P0, finite and >= 0.
    Q1 : float or array_like
        Normalized tangential amplitude Q̂1 = Q1/(f P0), finite and >= 0; broadcast against
        ``P1``.

    Returns
    -------
    float or ndarray
        Ŵ at each point (the broadcast shape of ``P1`` and ``Q1``); a float for scalar input.

    Raises
    ------
    InputError
        A negative, non-finite or non-numeric ``P1`` or ``Q1``.
    """
    from .._checks import finite_array

    P1 = finite_array("P1", P1, nonneg=True)
    Q1 = finite_array("Q1", Q1, nonneg=True)
    P1, Q1 = np.broadcast_arrays(P1, Q1)
    out = np.zeros(P1.shape)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        full = (P1 < 1) & (Q1 > 1)
        # factored so that no square of a large amplitude is formed (finite up to 1e308)
        eq11 = 4 * ((Q1 - 1) / (Q1 + P1)) * ((Q1 - P1**2) / (Q1 - P1))
        sepr = (P1 >= 1) & (Q1 > P1)
        eq12 = ((Q1 - P1) / (Q1 + P1)) * (1 + P1) * (1 + 1 / P1)
    out = np.where(full, eq11, out)
    out = np.where(sepr, eq12, out)
    return out if out.ndim else float(out)
