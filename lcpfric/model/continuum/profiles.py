"""Axisymmetric bodies for the method of dimensionality reduction (:class:`~.mdr.MDRSphere`): each
gives the 1-D profile ``g(x)`` of the MDR (Popov and Heß), its integral, and the contact radius
at a load.

``Sphere``        ``f = r²/(2R)``: ``g = x²/R``
``PowerLaw``      ``f = c r^n``: ``g = κ_n c |x|^n``, ``κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)``
``Axisymmetric``  any slope ``f'``: ``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ`` by quadrature
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np

from ... import _checks
from ...errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Sphere", "PowerLaw", "Axisymmetric"]


class Sphere:
    """The sphere ``f = r²/(2R)``: ``g = x²/R``.

    Parameters
    ----------
    R : float
        Effective radius, > 0.

    Attributes
    ----------
    R : float
        As given.

    Raises
    ------
    InputError
        ``R`` <= 0 or not finite.
    """

    def __init__(self, R: float) -> None:
        self.R = _checks.positive("R", R)

    def g(self, x: ArrayLike) -> np.ndarray:
        """The 1-D profile ``g(x) = x²/R``.

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``g(x)``, the shape of ``x``.
        """
        return np.asarray(x) ** 2 / self.R

    def G(self, x: ArrayLike) -> np.ndarray:
        """``∫_0^x g``, ``= x³/(3R)``.

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``∫_0^x g`` at each position, the shape of ``x``.
        """
        x = np.asarray(x)
        return x * x * x / (3.0 * self.R)

    def radius(self, P: ArrayLike, Estar: float) -> float | np.ndarray:
        """Hertz's contact radius ``(3PR/(4E*))^(1/3)`` at the normal load P (0 for P <= 0).

        Parameters
        ----------
        P : float or array_like
            Normal loads.
        Estar : float
            The composite modulus E*.

        Returns
        -------
        float or ndarray
            The contact radius a, the shape of ``P``.
        """
        return (3.0 * np.maximum(P, 0.0) * self.R / (4.0 * Estar)) ** (1.0 / 3.0)


class PowerLaw:
    """``f = c r^n`` (n > 0; n = 2, c = 1/(2R) is the sphere): ``g = κ_n c |x|^n``.

    ``κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)``.

    Parameters
    ----------
    c : float
        The coefficient, > 0.
    n : float
        The exponent, > 0.

    Attributes
    ----------
    c, n : float
        As given.
    kappa : float
        κ_n.

    Raises
    ------
    InputError
        ``c`` or ``n`` <= 0 or not finite.
    """

    def __init__(self, c: float, n: float) -> None:
        self.c = _checks.positive("c", c)
        self.n = _checks.positive("n", n)
        self.kappa = math.sqrt(math.pi) * math.gamma(self.n / 2 + 1) / math.gamma(self.n / 2 + 0.5)

    def g(self, x: ArrayLike) -> np.ndarray:
        """The 1-D profile ``g(x) = κ_n c |x|^n``.

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``g(x)``, the shape of ``x``.
        """
        return self.kappa * self.c * np.abs(np.asarray(x)) ** self.n

    def G(self, x: ArrayLike) -> np.ndarray:
        """``∫_0^x g``, ``= κ_n c x^(n+1) / (n + 1)`` (x >= 0).

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``∫_0^x g`` at each position, the shape of ``x``.
        """
        x = np.asarray(x)
        return self.kappa * self.c * x ** (self.n + 1) / (self.n + 1)

    def radius(self, P: ArrayLike, Estar: float) -> float | np.ndarray:
        """The contact radius at the normal load P (0 for P <= 0), in closed form.

        Parameters
        ----------
        P : float or array_like
            Normal loads.
        Estar : float
            The composite modulus E*.

        Returns
        -------
        float or ndarray
            The contact radius a, the shape of ``P``.
        """
        k = 2.0 * Estar * self.kappa * self.c * self.n / (self.n + 1)
        return (np.maximum(P, 0.0) / k) ** (1.0 / (self.n + 1))


class Axisymmetric:
    """Any axisymmetric body by its slope ``f'(r)``.

    The slope is vectorized, ``f'(0) = 0``, increasing enough that the contact is one disc.
    The MDR transform by 64-point Gauss-Legendre quadrature on a table of 4097 points,
    interpolated by a cubic spline (its antiderivative gives ``∫ g``), the table widened when
    asked beyond it; the contact radius by bisection.

    Parameters
    ----------
    slope : callable
        ``f'(r)``, vectorized over arrays of radii.

    Attributes
    ----------
    slope : callable
        As given.

    Raises
    ------
    InputError
        ``slope`` not callable (named ``profile``).
    """

    _POINTS = 4097

    def __init__(self, slope: Callable) -> None:
        if not callable(slope):
            raise InputError("profile", "Axisymmetric needs the slope f'(r) as a callable")
        self.slope = slope
        self._t, self._w = np.polynomial.legendre.leggauss(64)
        self._X = 0.0

    def transform(self, x: ArrayLike) -> np.ndarray:
        """``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ`` by quadrature (no table).

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``g(x)``, the shape of ``x``.
        """
        x = np.abs(np.asarray(x, dtype=float))
        theta = 0.25 * math.pi * (self._t + 1.0)  # [0, π/2]
        vals = np.asarray(self.slope(x[..., None] * np.sin(theta)), dtype=float)
        return x * (vals @ self._w) * 0.25 * math.pi

    def _table(self, x):
        top = float(np.max(np.abs(x), initial=0.0))
        if top <= self._X:
            return
        from scipy.interpolate import CubicSpline

        X = max(top, 2.0 * self._X)
        xs = np.linspace(0.0, X, self._POINTS)
        gs = self.transform(xs)
        if not np.all(np.isfinite(gs)):
            raise InputError("profile", "the slope f'(r) gave non-finite values")
        self._g = CubicSpline(xs, gs)
        self._G = self._g.antiderivative()
        self._X = X

    def g(self, x: ArrayLike) -> np.ndarray:
        """The 1-D profile ``g(x)``, interpolated in the table (widened as needed).

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``g(x)``, the shape of ``x``.

        Raises
        ------
        InputError
            The slope gave non-finite values while the table was built (named ``profile``).
        """
        self._table(x)
        return self._g(np.abs(np.asarray(x, dtype=float)))

    def G(self, x: ArrayLike) -> np.ndarray:
        """``∫_0^x g``, the antiderivative of the table's spline.

        Parameters
        ----------
        x : float or array_like
            Positions.

        Returns
        -------
        ndarray
            ``∫_0^x g`` at each position, the shape of ``x``.

        Raises
        ------
        InputError
            The slope gave non-finite values while the table was built (named ``profile``).
        """
        self._table(x)
        return self._G(np.asarray(x, dtype=float))

    def radius(self, P: ArrayLike, Estar: float) -> np.ndarray:
        """The contact radius at the normal load P (0 for P <= 0), by bisection.

        Parameters
        ----------
        P : float or array_like
            Normal loads.
        Estar : float
            The composite modulus E*.

        Returns
        -------
        ndarray
            The contact radius a, the shape of ``P`` (at least 1-D).

        Raises
        ------
        InputError
            The slope gave non-finite values while the table was built (named ``profile``).
        """
        P = np.atleast_1d(np.maximum(np.asarray(P, dtype=float), 0.0))
        lo, hi = np.zeros_like(P), np.ones_like(P)

        def load(a):
            return 2.0 * Estar * (a * self.g(a) - self.G(a))

        for _ in range(200):  # grow the bracket
            short = load(hi) < P
            if not short.any():
                break
            hi = np.where(short, 2.0 * hi, hi)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            below = load(mid) < P
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        return np.where(P > 0, 0.5 * (lo + hi), 0.0)
