"""The real Fourier conventions of the harmonic-balance room: one copy, used by every AFT.

A periodic signal of period T = 2π/ω truncated to H harmonics is the coefficient vector

    c = [c0, a1, b1, a2, b2, ..., aH, bH]            (length K = 2H + 1)
    x(t) = c0 + Σ_{h=1..H} a_h cos(h ω t) + b_h sin(h ω t)

cosine before sine in each harmonic; the zeroth harmonic ``c0`` is the mean of x (no factor
1/2); the coefficients are amplitudes (no 1/√2, no complex pairs). In angle τ = ω t the
samples are taken at ``τ_k = 2π k / Ns`` (``t_k = k T / Ns``), k = 0 .. Ns - 1.

``E`` (Ns x K) samples: ``x_k = (E c)_k``, rows ``[1, cos τ_k, sin τ_k, ..., cos Hτ_k,
sin Hτ_k]``. ``D`` (K x Ns) is the discrete Fourier transform in the same ordering:
``c0 = mean(x_k)``, ``a_h = (2/Ns) Σ x_k cos hτ_k``, ``b_h = (2/Ns) Σ x_k sin hτ_k``. With
``Ns > 2H`` the discrete cosines and sines up to H are orthogonal, so ``D E = I`` exactly (up to
rounding) and ``E D`` is the projection of samples onto the H retained harmonics; at
``Ns = 2H`` the highest sine vanishes at every sample, hence the check ``samples > 2H``.

Alternating frequency-time (AFT): the force coefficients of a nonlinear element are
``D f(E c)``, and their Jacobian ``D (∂f/∂x_samples) E``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .._checks import positive_int
from ..errors import InputError

__all__ = [
    "FourierBasis",
    "fourier_basis",
    "check_samples",
    "harmonics_of",
    "trapezoid_coefficients",
]


@dataclass(frozen=True, eq=False)
class FourierBasis:
    """The sampling matrix and the discrete transform of H harmonics at Ns samples.

    Build it with :func:`fourier_basis` (cached); the arrays are read-only.

    Parameters
    ----------
    harmonics : int
        H, the number of harmonics (coefficient vectors have length 2H + 1).
    samples : int
        Ns, the samples per period (Ns > 2H).
    angles : numpy.ndarray
        τ_k = 2π k / Ns, shape (Ns,).
    E : numpy.ndarray
        The sampling matrix, shape (Ns, 2H + 1): samples = E @ coefficients.
    D : numpy.ndarray
        The discrete transform, shape (2H + 1, Ns): coefficients = D @ samples; D @ E = I.

    Attributes
    ----------
    harmonics : int
        H.
    samples : int
        Ns.
    angles : numpy.ndarray
        The sample angles τ_k (radians), shape (Ns,).
    E : numpy.ndarray
        The sampling matrix, shape (Ns, 2H + 1).
    D : numpy.ndarray
        The discrete transform, shape (2H + 1, Ns).
    """

    harmonics: int
    samples: int
    angles: np.ndarray
    E: np.ndarray
    D: np.ndarray

    @property
    def size(self) -> int:
        """K = 2H + 1, the length of a coefficient vector."""
        return 2 * self.harmonics + 1

    def to_samples(self, coefficients) -> np.ndarray:
        """Samples over one period of coefficient vectors along the last axis.

        Parameters
        ----------
        coefficients : array_like
            Shape (..., 2H + 1).

        Returns
        -------
        numpy.ndarray
            Shape (..., Ns): ``x(τ_k)``.
        """
        return np.asarray(coefficients, dtype=float) @ self.E.T

    def to_coefficients(self, samples) -> np.ndarray:
        """Coefficient vectors of sampled periods along the last axis (the DFT ``D``).

        Parameters
        ----------
        samples : array_like
            Shape (..., Ns).

        Returns
        -------
        numpy.ndarray
            Shape (..., 2H + 1).
        """
        return np.asarray(samples, dtype=float) @ self.D.T


def check_samples(harmonics: int, samples, name: str = "samples") -> int:
    """``samples`` as an int, checked to be > 2 ``harmonics`` (the transform's condition).

    Parameters
    ----------
    harmonics : int
        H.
    samples : int
        The requested number of samples per period.
    name : str, optional
        The parameter's name in the error message.

    Returns
    -------
    int
        ``samples``.

    Raises
    ------
    InputError
        ``samples`` is not a whole number or is <= 2H.
    """
    ns = positive_int(name, samples, minimum=1)
    if ns <= 2 * harmonics:
        raise InputError(
            name,
            f"must be > 2H = {2 * harmonics} for H = {harmonics} harmonics (the discrete "
            f"transform needs at least 2H + 1 samples per period), got {ns}",
        )
    return ns


def harmonics_of(length: int, name: str = "tangential") -> int:
    """H from a coefficient vector's length 2H + 1 (odd, >= 3).

    Parameters
    ----------
    length : int
        The length of the coefficient axis.
    name : str, optional
        The parameter's name in the error message.

    Returns
    -------
    int
        H >= 1.

    Raises
    ------
    InputError
        ``length`` is even or smaller than 3.
    """
    if length < 3 or length % 2 == 0:
        raise InputError(
            name,
            "the last axis must hold 2H + 1 coefficients [c0, a1, b1, ..., aH, bH] with "
            f"H >= 1 (an odd length >= 3), got length {length}",
        )
    return (length - 1) // 2


@functools.lru_cache(maxsize=32)
def fourier_basis(harmonics: int, samples: int) -> FourierBasis:
    """The (cached) basis of ``harmonics`` harmonics sampled ``samples`` times per period.

    Parameters
    ----------
    harmonics : int
        H >= 1.
    samples : int
        Ns > 2H.

    Returns
    -------
    FourierBasis
        E, D and the angles, read-only.
    """
    H = positive_int("harmonics", harmonics, minimum=1)
    ns = check_samples(H, samples)
    k = np.arange(ns)
    tau = 2.0 * np.pi * k / ns
    h = np.arange(1, H + 1)
    # h k mod Ns keeps the angle in [0, 2π): cos and sin of it are then exact to rounding for
    # every h, not degraded for high harmonics
    ang = 2.0 * np.pi * ((np.outer(k, h) % ns) / ns)
    E = np.empty((ns, 2 * H + 1))
    E[:, 0] = 1.0
    E[:, 1::2] = np.cos(ang)
    E[:, 2::2] = np.sin(ang)
    D = E.T * (2.0 / ns)
    D[0] = 1.0 / ns
    for a in (tau, E, D):
        a.setflags(write=False)
    return FourierBasis(H, ns, tau, E, D)


def trapezoid_coefficients(t, x, period: float, harmonics: int) -> np.ndarray:
    """The coefficients ``[c0, a1, b1, ..., aH, bH]`` (module docstring) of a periodic signal
    known at records ``(t_j, x_j)`` of any spacing (a cycle's records with its events), by the
    trapezoidal rule of ``x cos hωt`` and ``x sin hωt``: on a uniform grid this is the discrete
    transform ``D`` (spectrally accurate for a smooth signal), on any grid second order.

    Parameters
    ----------
    t : array_like
        Increasing instants ``t_0 .. t_n`` with ``t_n = t_0 + period``.
    x : array_like
        The values at them.
    period : float
        The period.
    harmonics : int
        H >= 1.

    Returns
    -------
    ndarray
        ``(2H + 1,)`` coefficients.
    """
    t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    H = positive_int("harmonics", harmonics, minimum=1)
    w = np.zeros(t.size)  # the trapezoidal weights
    dt = np.diff(t)
    w[:-1] += 0.5 * dt
    w[1:] += 0.5 * dt
    wx = w * x / period
    # the angle reduced to [0, 2π) before the harmonics multiply it
    tau = 2.0 * np.pi * (((t - t[0]) / period) % 1.0) + 2.0 * np.pi * (t[0] / period)
    out = np.empty(2 * H + 1)
    out[0] = wx.sum()
    for h in range(1, H + 1):
        out[2 * h - 1] = 2.0 * np.dot(wx, np.cos(h * tau))
        out[2 * h] = 2.0 * np.dot(wx, np.sin(h * tau))
    return out
