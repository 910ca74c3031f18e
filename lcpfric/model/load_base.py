"""The base of the periodic loads: :class:`Load`, whose amplitude, extrema and zero crossings
are found by sampling and polishing, and :class:`Periodic`, any vectorized callable with a known
period (the load a scaled one becomes).

The closed-form loads (:class:`~lcpfric.model.loads.Fourier`,
:class:`~lcpfric.model.loads.Harmonic`) and the evaluation of many loads together are
:mod:`lcpfric.model.loads`'s, which re-exports both classes here.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np

from .. import _checks
from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Load", "Periodic"]


class Load:
    """Base class of a periodic load history ``x(t)``.

    Subclasses define ``period``, ``mean``, ``__call__`` (vectorized over ``t``) and
    ``derivative``; the base class provides the amplitude, zero crossings and extrema by sampling
    and root polishing, which subclasses with closed forms override.

    Called with times, a load returns its values in their shape (a float for a scalar time).

    Attributes
    ----------
    period, mean : float
        The period T > 0 and the constant part (P0 or Q0 of Eq. 1).
    amplitude, is_constant
        Properties (below).
    """

    period: float
    mean: float
    _samples = 4096  # samples per period for the numerical searches; smooth loads need no more

    def __call__(self, t: ArrayLike) -> float | np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def derivative(self, t: ArrayLike) -> float | np.ndarray:
        """dx/dt; by central differences unless a subclass knows it in closed form.

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        float or ndarray
            dx/dt at each time, the shape of ``t``.
        """
        t = np.asarray(t, dtype=float)
        h = 1e-6 * self.period
        return (self(t + h) - self(t - h)) / (2 * h)

    @property
    def is_constant(self) -> bool:
        """Whether the load does not vary: its amplitude is zero."""
        return self.amplitude == 0.0

    @property
    def amplitude(self) -> float:
        """Max over a cycle of ``|x(t) - mean|``: the normalization amplitude (Q1, P1 for Eq. 1)."""
        t = np.linspace(0.0, self.period, self._samples, endpoint=False)
        return float(np.max(np.abs(self(t) - self.mean)))

    def extrema(self) -> tuple[float, float]:
        """(min, max) of x over a cycle, polished with a bounded scalar search.

        Returns
        -------
        min, max : float
            The smallest and largest value of x over a cycle (the best of 4096 samples per
            period, polished by :func:`scipy.optimize.minimize_scalar` around it).
        """
        from scipy.optimize import minimize_scalar

        t = np.linspace(0.0, self.period, self._samples, endpoint=False)
        x = self(t)
        h = self.period / self._samples
        out = []
        for sign, k in ((1.0, int(np.argmin(x))), (-1.0, int(np.argmax(x)))):
            res = minimize_scalar(
                lambda s: sign * float(self(s)),
                bounds=(t[k] - h, t[k] + h),
                method="bounded",
                options={"xatol": 1e-14 * self.period},
            )
            best = min(sign * x[k], float(res.fun)) if res.success else sign * x[k]
            out.append(sign * best)
        return float(out[0]), float(out[1])

    def zeros(self, t0: float, t1: float) -> np.ndarray:
        """Instants in (t0, t1) where x changes sign, sorted, to machine precision.

        Parameters
        ----------
        t0, t1 : float
            The open interval searched, ``t0 < t1``.

        Returns
        -------
        ndarray
            The sorted instants, 1-D (sampled, 4096 per period, and polished by Brent's method
            :func:`scipy.optimize.brentq`; empty when x keeps its sign).
        """
        n = max(16, int(math.ceil(self._samples * (t1 - t0) / self.period)))
        t = np.linspace(t0, t1, n + 1)
        x = self(t)
        roots = []
        from scipy.optimize import brentq  # here: importing lcpfric stays free of scipy

        for k in np.nonzero(np.signbit(x[:-1]) != np.signbit(x[1:]))[0]:
            a, b = t[k], t[k + 1]
            if x[k] == 0.0:
                if t0 < a < t1:
                    roots.append(a)
                continue
            roots.append(
                brentq(
                    lambda s: float(self(s)),
                    a,
                    b,
                    xtol=1e-15 * max(1.0, abs(b)),
                    rtol=4 * np.finfo(float).eps,
                )
            )
        return np.asarray(sorted(r for r in roots if t0 < r < t1), dtype=float)

    def scaled(self, factor: float) -> Load:
        """The load ``factor * x(t)``.

        Parameters
        ----------
        factor : float
            The scale factor.

        Returns
        -------
        Periodic
            ``factor * x(t)``, with mean ``factor * mean`` and derivative ``factor * dx/dt``.
        """
        return Periodic(
            lambda t, f=self, c=factor: c * f(t),
            self.period,
            mean=factor * self.mean,
            derivative=lambda t, f=self, c=factor: c * f.derivative(t),
        )


class Periodic(Load):
    """Any periodic load given as a vectorized callable ``func(t)`` with a known ``period``.

    Parameters
    ----------
    func : callable
        ``func(t)`` for an array ``t`` returns an array of the same shape.
    period : float
        The period T > 0; ``func(t + T) == func(t)`` is the caller's promise.
    mean : float, optional
        The constant part used for normalization (P0 of a normal load). Computed as the cycle
        average when omitted.
    derivative : callable, optional
        ``dfunc/dt``; central differences are used when omitted.

    Attributes
    ----------
    func, period, mean, derivative_func
        As given (``derivative_func``: the ``derivative``; ``mean`` computed when omitted).

    Raises
    ------
    InputError
        ``func`` not callable or (when ``mean`` is omitted) not returning finite values of the
        shape of its argument; ``period`` <= 0; ``mean`` not finite.
    """

    def __init__(
        self,
        func: Callable,
        period: float,
        mean: float | None = None,
        derivative: Callable | None = None,
    ) -> None:
        if not callable(func):
            raise InputError("func", "must be a callable func(t) returning an array")
        self.func = func
        self.period = _checks.positive("period", period)
        self.derivative_func = derivative
        if mean is None:
            t = np.linspace(0.0, self.period, self._samples, endpoint=False)
            vals = np.asarray(func(t), dtype=float)
            if vals.shape != t.shape or not np.all(np.isfinite(vals)):
                raise InputError(
                    "func", "must return finite values, one per time, for an array of times"
                )
            mean = float(np.mean(vals))
        self.mean = _checks.finite("mean", mean)

    def __repr__(self) -> str:
        return f"Periodic({self.func!r}, period={self.period!r}, mean={self.mean!r})"

    def __call__(self, t: ArrayLike) -> float | np.ndarray:
        t = np.asarray(t, dtype=float)
        x = np.asarray(self.func(t), dtype=float)
        return x if x.ndim else float(x)

    def derivative(self, t: ArrayLike) -> float | np.ndarray:
        """dx/dt: the ``derivative`` given, else central differences.

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        float or ndarray
            dx/dt at each time, the shape of ``t``.
        """
        if self.derivative_func is not None:
            return np.asarray(self.derivative_func(np.asarray(t, dtype=float)), dtype=float)
        return Load.derivative(self, t)
