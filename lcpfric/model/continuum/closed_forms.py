r"""Closed forms of the Hertz, Cattaneo-Mindlin and Mindlin-Deresiewicz problems, and the
Ciavarella-Jäger dissipation of any uncoupled profile at constant normal load.

Two identical bodies, each of Young's modulus E and Poisson's ratio ν (G = E / (2(1 + ν))):

* composite moduli ``E* = E / (2(1 - ν²))``, ``G* = 2G / (2 - ν)``, and ``η = G*/E* =
  2(1 - ν)/(2 - ν)`` for a 3-D contact (η = 1 in plane strain);
* sphere (effective radius R): contact radius ``a = (3PR/(4E*))^(1/3)``, peak pressure
  ``p0 = 3P/(2πa²)``, approach ``d = a²/R``, initial tangential stiffness ``k_t0 = 2 a G*``;
* cylinder (plane strain, per unit length): half-width ``a = √(4PR/(πE*))``, ``p0 = 2P/(πa)``;
* Cattaneo-Mindlin stick zone at constant P under Q rising from 0, ``x = Q/(μP)``: ``c/a =
  (1 - x)^(1/3)`` (sphere), ``√(1 - x)`` (cylinder);
* Mindlin-Deresiewicz, Q cycling between ±Q* at constant P, ``x = Q*/(μP) <= 1``, per cycle:
  sphere ``W = (36/5) (μP)²/k_t0 [1 - (1 - x)^(5/3) - (5x/6)(1 + (1 - x)^(2/3))]``; cylinder
  (per unit length) ``W = 4μ²P²/(πE*) [(1 - x) ln(1 - x) + x - x²/2]``;
* any profile with normal approach C(P) (Ciavarella 1998, Jäger 1998): ``W = (8μ²/η) [∫_{P -
  Q*/μ}^{P} C(p) dp - (Q*/(2μ)) (C(P) + C(P - Q*/μ))]``, the area between C and its chord.

Every function checks its arguments and raises :class:`~lcpfric.errors.InputError` naming the
one out of range.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..._checks import positive
from ...errors import InputError

__all__ = [
    "moduli",
    "hertz_contact",
    "cylinder_contact",
    "cylinder_approach",
    "cattaneo_stick_ratio",
    "mindlin_deresiewicz_W",
    "mindlin_force",
    "cylinder_W",
    "ciavarella_jager_W",
]


def _binomial(a: float, k: int) -> float:
    """The generalized binomial coefficient (a choose k)."""
    out = 1.0
    for j in range(k):
        out *= (a - j) / (j + 1)
    return out


#: below this x = Q*/(μP) the dissipation brackets (which vanish as x³) are summed as series
_SERIES = 0.25
_TERMS = 48  # 0.25^45 < 1e-27: far below round-off
#: the Mindlin-Deresiewicz bracket 1 - (1-x)^(5/3) - (5x/6)(1 + (1-x)^(2/3)) as Σ c_k x^k
#: (the terms in 1, x and x² cancel exactly)
_MD_SERIES = [0.0, 0.0, 0.0] + [
    -((-1) ** k) * _binomial(5 / 3, k) - (5 / 6) * (-1) ** (k - 1) * _binomial(2 / 3, k - 1)
    for k in range(3, _TERMS)
]


def _poisson(nu: float) -> float:
    nu = float(nu)
    if not (math.isfinite(nu) and 0.0 <= nu < 0.5):
        raise InputError("nu", f"Poisson's ratio must be in [0, 0.5), got {nu!r}")
    return nu


def _ratio(x: float) -> float:
    x = float(x)
    if not (math.isfinite(x) and 0.0 <= x <= 1.0):
        raise InputError("Q", f"Q/(μP) must be in [0, 1] (no gross sliding), got {x!r}")
    return x


def moduli(E: float, nu: float) -> dict:
    """``{"E*", "G*", "G", "eta"}`` for two identical bodies of modulus E and ratio ν.

    Parameters
    ----------
    E : float
        Each body's Young's modulus, > 0.
    nu : float
        Each body's Poisson's ratio, ``0 <= ν < 0.5``.

    Returns
    -------
    dict
        ``"E*"``: E / (2(1 - ν²)); ``"G*"``: 2G / (2 - ν); ``"G"``: E / (2(1 + ν));
        ``"eta"``: G*/E* (floats).

    Raises
    ------
    InputError
        ``E`` or ``nu`` out of range.
    """
    E, nu = positive("E", E), _poisson(nu)
    G = E / (2.0 * (1.0 + nu))
    Es, Gs = E / (2.0 * (1.0 - nu * nu)), 2.0 * G / (2.0 - nu)
    return {"E*": Es, "G*": Gs, "G": G, "eta": Gs / Es}


def hertz_contact(P: float, R: float, E: float, nu: float) -> dict:
    """Sphere: ``{"a", "p0", "d", "k_t0"}`` at normal load P.

    Parameters
    ----------
    P : float
        Normal load, > 0.
    R : float
        Effective radius, > 0.
    E : float
        Each body's Young's modulus, > 0.
    nu : float
        Each body's Poisson's ratio, ``0 <= ν < 0.5``.

    Returns
    -------
    dict
        ``"a"``: contact radius; ``"p0"``: peak pressure; ``"d"``: approach; ``"k_t0"``:
        initial tangential stiffness of the whole contact (floats).

    Raises
    ------
    InputError
        A parameter out of range.
    """
    P, R = positive("P", P), positive("R", R)
    m = moduli(E, nu)
    a = (3.0 * P * R / (4.0 * m["E*"])) ** (1.0 / 3.0)
    return {
        "a": a,
        "p0": 3.0 * P / (2.0 * math.pi * a * a),
        "d": a * a / R,
        "k_t0": 2.0 * a * m["G*"],
    }


def cylinder_contact(P: float, R: float, E: float, nu: float) -> dict:
    """Cylinder in plane strain, P per unit length: ``{"a", "p0"}``.

    Parameters
    ----------
    P : float
        Normal load per unit length, > 0.
    R : float
        Effective radius, > 0.
    E : float
        Each body's Young's modulus, > 0.
    nu : float
        Each body's Poisson's ratio, ``0 <= ν < 0.5``.

    Returns
    -------
    dict
        ``"a"``: half-width; ``"p0"``: peak pressure (floats).

    Raises
    ------
    InputError
        A parameter out of range.
    """
    P, R = positive("P", P), positive("R", R)
    a = math.sqrt(4.0 * P * R / (math.pi * moduli(E, nu)["E*"]))
    return {"a": a, "p0": 2.0 * P / (math.pi * a)}


def cylinder_approach(P, R: float, E: float, nu: float, datum: float) -> np.ndarray:
    """Cylinder in plane strain, P per unit length: the approach of the points at distance ℓ
    (``datum``) from the contact, ``δ = (2P/(π E*)) (ln(2ℓ/a) + 1/2)`` (Hertz's pressure on
    the half-plane's logarithmic kernel measured from ℓ; cf. Johnson, Contact Mechanics, §5.6).

    Parameters
    ----------
    P : float or array_like
        Normal loads per unit length, >= 0 (0 gives 0).
    R, E, nu : float
        As for :func:`cylinder_contact`.
    datum : float
        ℓ > 0, larger than the half-width a.

    Returns
    -------
    ndarray
        δ, the shape of ``P``.

    Raises
    ------
    InputError
        A parameter out of range.
    """
    R, datum = positive("R", R), positive("datum", datum)
    Es = moduli(E, nu)["E*"]
    P = np.asarray(P, dtype=float)
    a = np.sqrt(4.0 * np.maximum(P, 0.0) * R / (math.pi * Es))
    with np.errstate(divide="ignore", invalid="ignore"):
        out = 2.0 * P / (math.pi * Es) * (np.log(2.0 * datum / a) + 0.5)
    return np.where(P > 0.0, out, 0.0)


def cattaneo_stick_ratio(x: float, geometry: str = "sphere") -> float:
    """``c/a`` of the Cattaneo-Mindlin stick zone at ``x = Q/(μP)`` (Q rising from 0).

    Parameters
    ----------
    x : float
        The load ratio Q/(μP), in [0, 1].
    geometry : {"sphere", "cylinder"}, optional
        ``(1 - x)^(1/3)`` for the sphere, ``√(1 - x)`` for the cylinder.

    Returns
    -------
    float
        The stick radius (or half-width) over the contact's.

    Raises
    ------
    InputError
        ``x`` outside [0, 1] (named ``Q``) or an unknown ``geometry``.
    """
    x = _ratio(x)
    if geometry == "sphere":
        return (1.0 - x) ** (1.0 / 3.0)
    if geometry == "cylinder":
        return math.sqrt(1.0 - x)
    raise InputError("geometry", f"must be 'sphere' or 'cylinder', got {geometry!r}")


def mindlin_force(delta, P: float, mu: float, k_t0: float) -> np.ndarray:
    """Sphere at constant P, loaded tangentially from rest to the displacement δ: Mindlin's
    force ``Q = μP [1 - (1 - δ/δ*)^(3/2)]`` for ``δ < δ* = 3μP/(2 k_t0)``, μP beyond (gross
    slip); on the first loading, and the force amplitude of a steady cycle ``±δ`` (Masing).

    Parameters
    ----------
    delta : float or array_like
        Displacements, >= 0.
    P, mu, k_t0 : float
        Normal load, friction coefficient and the initial tangential stiffness at P, > 0.

    Returns
    -------
    numpy.ndarray
        The tangential forces, the shape of ``delta``.

    Raises
    ------
    InputError
        A parameter out of range (``delta`` < 0 or not finite).
    """
    P, mu, k_t0 = positive("P", P), positive("mu", mu), positive("k_t0", k_t0)
    d = np.asarray(delta, dtype=float)
    if not np.all(np.isfinite(d)) or np.any(d < 0):
        raise InputError("delta", "must be finite and >= 0")
    star = 1.5 * mu * P / k_t0
    return mu * P * (1.0 - np.clip(1.0 - d / star, 0.0, 1.0) ** 1.5)


def mindlin_deresiewicz_W(P: float, Q_amp: float, mu: float, k_t0: float) -> float:
    """Sphere at constant P, Q between ±Q_amp: the dissipation per cycle (k_t0 at that P).

    ``W = (36/5) (μP)²/k_t0 [1 - (1 - x)^(5/3) - (5x/6)(1 + (1 - x)^(2/3))]``, ``x =
    Q_amp/(μP)``; for x < 0.25 the bracket, which vanishes as x³, is summed as a series.

    Parameters
    ----------
    P : float
        Normal load, > 0.
    Q_amp : float
        Tangential amplitude Q*, with ``0 <= Q_amp/(μP) <= 1``.
    mu : float
        Friction coefficient, > 0.
    k_t0 : float
        Initial tangential stiffness at P, > 0 (``hertz_contact(P, ...)["k_t0"]``).

    Returns
    -------
    float
        The dissipation per cycle.

    Raises
    ------
    InputError
        A parameter out of range (``Q_amp/(μP)`` outside [0, 1] is named ``Q``).
    """
    P, mu, k_t0 = positive("P", P), positive("mu", mu), positive("k_t0", k_t0)
    x = _ratio(Q_amp / (mu * P))
    if x < _SERIES:  # the bracket is (5/162) x³ (1 + 2x/3 + ...): summed, not cancelled
        bracket = sum(c * x**k for k, c in enumerate(_MD_SERIES))
    else:
        bracket = (
            1.0 - (1.0 - x) ** (5.0 / 3.0) - (5.0 * x / 6.0) * (1.0 + (1.0 - x) ** (2.0 / 3.0))
        )
    return 36.0 / 5.0 * (mu * P) ** 2 / k_t0 * bracket


def cylinder_W(P: float, Q_amp: float, mu: float, E: float, nu: float) -> float:
    """Cylinder (plane strain) at constant P, Q between ±Q_amp, per cycle and unit length.

    ``W = 4μ²P²/(πE*) [(1 - x) ln(1 - x) + x - x²/2]``, ``x = Q_amp/(μP)``; for x < 0.25
    the bracket, which vanishes as x³, is summed as a series.

    Parameters
    ----------
    P : float
        Normal load per unit length, > 0.
    Q_amp : float
        Tangential amplitude Q* per unit length, with ``0 <= Q_amp/(μP) <= 1``.
    mu : float
        Friction coefficient, > 0.
    E : float
        Each body's Young's modulus, > 0.
    nu : float
        Each body's Poisson's ratio, ``0 <= ν < 0.5``.

    Returns
    -------
    float
        The dissipation per cycle and unit length.

    Raises
    ------
    InputError
        A parameter out of range (``Q_amp/(μP)`` outside [0, 1] is named ``Q``).
    """
    P, mu = positive("P", P), positive("mu", mu)
    x = _ratio(Q_amp / (mu * P))
    Es = moduli(E, nu)["E*"]
    if x == 1.0:
        bracket = 0.5
    elif x < _SERIES:  # Σ_{k>=3} x^k / (k (k - 1)): summed, not cancelled
        bracket = sum(x**k / (k * (k - 1)) for k in range(3, _TERMS))
    else:
        bracket = (1.0 - x) * math.log1p(-x) + x - 0.5 * x * x
    return 4.0 * mu * mu * P * P / (math.pi * Es) * bracket


def ciavarella_jager_W(
    approach: Callable[[float], float], P: float, Q_amp: float, mu: float, eta: float
) -> float:
    """Any uncoupled profile at constant P, Q between ±Q_amp: the dissipation per cycle.

    ``(8μ²/η)`` times the area between the approach curve ``C(p)`` and its chord over
    ``[P - Q_amp/μ, P]``, by adaptive quadrature (:func:`scipy.integrate.quad`).

    Parameters
    ----------
    approach : callable
        ``C(p)``: the normal approach against the normal load, a scalar function.
    P : float
        Normal load, > 0.
    Q_amp : float
        Tangential amplitude Q*, with ``0 <= Q_amp/(μP) <= 1``.
    mu : float
        Friction coefficient, > 0.
    eta : float
        ``G*/E*`` (:func:`moduli`), > 0.

    Returns
    -------
    float
        The dissipation per cycle.

    Raises
    ------
    InputError
        A parameter out of range (``Q_amp/(μP)`` outside [0, 1] is named ``Q``).
    """
    from scipy.integrate import quad

    P, mu, eta = positive("P", P), positive("mu", mu), positive("eta", eta)
    x = _ratio(Q_amp / (mu * P))
    lo = P * (1.0 - x)
    area, err = quad(approach, lo, P, epsabs=0.0, epsrel=1e-13, limit=200)
    chord = 0.5 * (P - lo) * (approach(P) + approach(lo))
    return 8.0 * mu * mu / eta * (area - chord)
