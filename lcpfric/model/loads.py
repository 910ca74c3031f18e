"""Periodic load histories P(t) and Q(t).

The paper's loads are harmonic, Eq. (1): ``P(t) = P0 + P1 sin(ωt)``, ``Q(t) = Q0 + Q1 sin(ωt + φ)``.
:class:`Harmonic` is that form; :class:`Fourier` is any trigonometric polynomial with a common
fundamental frequency (two harmonics, say); :class:`Periodic` wraps any vectorized callable with a
known period. Every method that does not need the harmonic form (the explicit stepper, the
projection and the convex backends) accepts all three; the closed-form ``exact`` method and the
analytical shakedown test need :class:`Harmonic` loads.

All load objects are immutable, evaluate on arrays of times, and can list the instants where they
cross zero, which lcpfric places on the time grid (separation and re-contact are known before any
tangential computation in an uncoupled system).

The base class :class:`Load` and :class:`Periodic` are :mod:`.load_base`'s (re-exported here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError
from .load_base import Load, Periodic

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Load", "Harmonic", "Fourier", "Periodic", "LoadSet", "scaled_load"]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class Fourier(Load):
    """A trigonometric polynomial ``x(t) = mean + sum_k a_k sin(k ω t + ψ_k)``, k = 1..m.

    Parameters
    ----------
    mean : float
        The constant part (P0 or Q0).
    amplitudes : sequence of float
        ``a_k`` for k = 1, 2, ..., m (zeros allowed for missing harmonics). Each must be >= 0;
        a negative coefficient is expressed by a phase shift of π.
    phases : sequence of float
        ``ψ_k`` in radians, same length as ``amplitudes``.
    omega : float
        The fundamental angular frequency ω > 0; the period is 2π/ω.

    Attributes
    ----------
    mean, amplitudes, phases, omega
        As given (``amplitudes`` and ``phases`` as tuples of float); ``period`` and
        ``amplitude`` are properties (below).

    Raises
    ------
    InputError
        A value not finite, a negative amplitude, not one phase per amplitude, or ω <= 0.
    """

    mean: float = 0.0
    amplitudes: tuple = ()
    phases: tuple = ()
    omega: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "mean", _checks.finite("mean", self.mean))
        amps = tuple(
            float(a)
            for a in _checks.finite_array("amplitudes", self.amplitudes, nonneg=True).ravel()
        )
        phases = tuple(float(p) for p in _checks.finite_array("phases", self.phases).ravel())
        if len(amps) != len(phases):
            raise InputError(
                "phases", f"needs one phase per amplitude ({len(amps)}), got {len(phases)}"
            )
        object.__setattr__(self, "amplitudes", amps)
        object.__setattr__(self, "phases", phases)
        object.__setattr__(self, "omega", _checks.positive("omega", self.omega))

    @property
    def period(self) -> float:
        """The period 2π/ω."""
        return TWO_PI / self.omega

    def __call__(self, t: ArrayLike) -> float | np.ndarray:
        t = np.asarray(t, dtype=float)
        x = np.full(t.shape, self.mean)
        for k, (a, p) in enumerate(zip(self.amplitudes, self.phases), start=1):
            if a:
                x = x + a * np.sin(k * self.omega * t + p)
        return x if x.ndim else float(x)

    def derivative(self, t: ArrayLike) -> float | np.ndarray:
        """dx/dt in closed form, ``sum_k a_k k ω cos(k ω t + ψ_k)``.

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
        dx = np.zeros(t.shape)
        for k, (a, p) in enumerate(zip(self.amplitudes, self.phases), start=1):
            if a:
                dx = dx + a * k * self.omega * np.cos(k * self.omega * t + p)
        return dx if dx.ndim else float(dx)

    @property
    def amplitude(self) -> float:
        """Max over a cycle of ``|x(t) - mean|``: the one nonzero ``a_k``, else by sampling."""
        nonzero = [a for a in self.amplitudes if a]
        if not nonzero:
            return 0.0
        if len(nonzero) == 1:
            return nonzero[0]
        return Load.amplitude.fget(self)


class Harmonic(Fourier):
    """The harmonic load of Eq. (1): ``x(t) = mean + amplitude sin(ω t + phase)``.

    Parameters
    ----------
    mean : float, optional
        The constant part (P0 or Q0), finite.
    amplitude : float, optional
        The amplitude (P1 or Q1), >= 0.
    phase : float, optional
        The phase in radians (φ for Q of Eq. 1), finite.
    omega : float, optional
        The angular frequency ω > 0; the period is 2π/ω.

    Attributes
    ----------
    mean, amplitude, phase, omega, period : float
        As given (``period`` = 2π/ω).

    Raises
    ------
    InputError
        A parameter out of range or not finite.
    """

    def __init__(
        self, mean: float = 0.0, amplitude: float = 0.0, phase: float = 0.0, omega: float = 1.0
    ) -> None:
        amplitude = _checks.nonnegative("amplitude", amplitude)
        super().__init__(
            mean=mean,
            amplitudes=(amplitude,),
            phases=(_checks.finite("phase", phase),),
            omega=omega,
        )

    @property
    def phase(self) -> float:
        """The phase ψ in radians."""
        return self.phases[0]

    @property
    def amplitude(self) -> float:
        """The amplitude (P1 or Q1)."""
        return self.amplitudes[0]

    def __repr__(self) -> str:
        return (
            f"Harmonic(mean={self.mean!r}, amplitude={self.amplitude!r}, "
            f"phase={self.phase!r}, omega={self.omega!r})"
        )

    def extrema(self) -> tuple[float, float]:
        """(min, max) of x over a cycle, in closed form.

        Returns
        -------
        min, max : float
            ``mean - amplitude`` and ``mean + amplitude``.
        """
        return self.mean - self.amplitude, self.mean + self.amplitude

    def zeros(self, t0: float, t1: float) -> np.ndarray:
        """Closed-form sign changes: mean + a sin(ωt + ψ) = 0 (a tangency is not one).

        Parameters
        ----------
        t0, t1 : float
            The open interval searched, ``t0 < t1``.

        Returns
        -------
        ndarray
            The sorted instants in (t0, t1), 1-D (empty when x keeps its sign).
        """
        a, m = self.amplitude, self.mean
        if a == 0.0 or abs(m) >= a:
            return np.empty(0)  # no crossing (a tangency at |m| == a is not a sign change)
        base = math.asin(-m / a)
        out = []
        for root in (base, math.pi - base):
            s = (root - self.phase) / self.omega
            k0 = math.ceil((t0 - s) / self.period) - 1
            for k in range(k0, k0 + int((t1 - t0) / self.period) + 3):
                tk = s + k * self.period
                if t0 < tk < t1:
                    out.append(tk)
        return np.asarray(sorted(out), dtype=float)


class LoadSet:
    """Many loads evaluated together: ``x(t)`` with shape ``t.shape + (L,)``.

    The :class:`Fourier` loads (:class:`Harmonic` among them) of one fundamental frequency are
    evaluated as one array expression, ``mean + Σ_k (a_k cos ψ_k) sin(kωt) + (a_k sin ψ_k)
    cos(kωt)``: two products per harmonic and node, and the sines and cosines of the instants
    only, so that 1e5 nodes take a few array operations, not 1e5 calls or 1e5 sines (the
    values agree with each load's own ``__call__`` to a few units of round-off of its
    amplitude). Any other load is evaluated by its own call.
    """

    def __init__(self, loads):
        self.loads = tuple(loads)
        groups: dict[float, list[int]] = {}
        self.others = []
        for i, load in enumerate(self.loads):
            if isinstance(load, Fourier):
                groups.setdefault(load.omega, []).append(i)
            else:
                self.others.append(i)
        self.groups = []
        for omega, idx in groups.items():
            members = [self.loads[i] for i in idx]
            h = max(len(p.amplitudes) for p in members)
            amps = np.zeros((h, len(idx)))
            phases = np.zeros((h, len(idx)))
            for col, p in enumerate(members):
                amps[: len(p.amplitudes), col] = p.amplitudes
                phases[: len(p.phases), col] = p.phases
            mean = np.array([p.mean for p in members])
            self.groups.append(
                (
                    np.asarray(idx, dtype=np.intp),
                    omega,
                    mean,
                    amps * np.cos(phases),
                    amps * np.sin(phases),
                )
            )

    def __len__(self) -> int:
        return len(self.loads)

    def __call__(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        out = np.empty(t.shape + (len(self.loads),))
        tt = t[..., None]
        for idx, omega, mean, sin_coef, cos_coef in self.groups:
            whole = idx.size == len(self.loads)  # one group in order: write in place
            x = out if whole else np.empty(t.shape + mean.shape)
            x[...] = mean
            tmp = np.empty_like(x)
            for k in range(sin_coef.shape[0]):
                angle = (k + 1) * omega * tt
                x += np.multiply(sin_coef[k], np.sin(angle), out=tmp)
                x += np.multiply(cos_coef[k], np.cos(angle), out=tmp)
            if not whole:
                out[..., idx] = x
        for i in self.others:
            out[..., i] = self.loads[i](t)
        return out


def scaled_load(load: Load, factor: float, drop_mean: bool = False) -> Load:
    """``factor * (load - mean if drop_mean)``, keeping a harmonic load harmonic.

    Parameters
    ----------
    load : Load
        The load.
    factor : float
        The factor.
    drop_mean : bool, optional
        Subtract the load's mean first.

    Returns
    -------
    Load
        A :class:`Harmonic`, :class:`Fourier` or :class:`Periodic` load.
    """
    shift = load.mean if drop_mean else 0.0
    if isinstance(load, Harmonic):
        return Harmonic(
            factor * (load.mean - shift), factor * load.amplitude, load.phase, load.omega
        )
    if isinstance(load, Fourier):
        return Fourier(
            factor * (load.mean - shift),
            tuple(factor * a for a in load.amplitudes),
            load.phases,
            load.omega,
        )
    return Periodic(
        lambda t: factor * (load(t) - shift),
        load.period,
        mean=factor * (load.mean - shift),
        derivative=lambda t: factor * load.derivative(t),
    )
