"""Axisymmetric bodies for the method of dimensionality reduction (:class:`~.mdr.MDRSphere`): each
gives the 1-D profile ``g(x)`` of the MDR (Popov and Heß), its integral, and the contact radius
at a load.

``Sphere``        ``f = r²/(2R)``: ``g = x²/R``
``PowerLaw``      ``f = c r^n``: ``g = κ_n c |x|^n``, ``κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)``
``Axisymmetric``  any slope ``f'``: ``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ`` by quadrature
"""

from __future__ import annotations

import math

import numpy as np

from ... import _checks
from ...errors import InputError

__all__ = ["Sphere", "PowerLaw", "Axisymmetric"]


class Sphere:
    """The sphere ``f = r²/(2R)``: ``g = x²/R``."""

    def __init__(self, R):
        self.R = _checks.positive("R", R)

    def g(self, x):
        return np.asarray(x) ** 2 / self.R

    def G(self, x):
        """``∫_0^x g``."""
        x = np.asarray(x)
        return x * x * x / (3.0 * self.R)

    def radius(self, P, Estar):
        return (3.0 * np.maximum(P, 0.0) * self.R / (4.0 * Estar)) ** (1.0 / 3.0)


class PowerLaw:
    """``f = c r^n`` (n > 0; n = 2, c = 1/(2R) is the sphere): ``g = κ_n c |x|^n``."""

    def __init__(self, c, n):
        self.c = _checks.positive("c", c)
        self.n = _checks.positive("n", n)
        self.kappa = math.sqrt(math.pi) * math.gamma(self.n / 2 + 1) / math.gamma(self.n / 2
                                                                                  + 0.5)

    def g(self, x):
        return self.kappa * self.c * np.abs(np.asarray(x)) ** self.n

    def G(self, x):
        x = np.asarray(x)
        return self.kappa * self.c * x ** (self.n + 1) / (self.n + 1)

    def radius(self, P, Estar):
        k = 2.0 * Estar * self.kappa * self.c * self.n / (self.n + 1)
        return (np.maximum(P, 0.0) / k) ** (1.0 / (self.n + 1))


class Axisymmetric:
    """Any axisymmetric body by its slope ``f'(r)`` (vectorized, ``f'(0) = 0``, increasing
    enough that the contact is one disc): the MDR transform by 64-point Gauss-Legendre
    quadrature on a table of 4097 points, interpolated by a cubic spline (its antiderivative
    gives ``∫ g``), the table widened when asked beyond it; the contact radius by bisection."""

    _POINTS = 4097

    def __init__(self, slope):
        if not callable(slope):
            raise InputError("profile", "Axisymmetric needs the slope f'(r) as a callable")
        self.slope = slope
        self._t, self._w = np.polynomial.legendre.leggauss(64)
        self._X = 0.0

    def transform(self, x):
        """``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ`` by quadrature (no table)."""
        x = np.abs(np.asarray(x, dtype=float))
        theta = 0.25 * math.pi * (self._t + 1.0)                # [0, π/2]
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

    def g(self, x):
        self._table(x)
        return self._g(np.abs(np.asarray(x, dtype=float)))

    def G(self, x):
        self._table(x)
        return self._G(np.asarray(x, dtype=float))

    def radius(self, P, Estar):
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
