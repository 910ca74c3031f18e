"""The Jenkins element: a spring kt in series with a Coulomb slider, driven by a prescribed
displacement (``shared/dynamics/NOTES.md``, the Jenkins element; issue 39).

The tangential force is ``T = kt (x - w)``: x(t) the prescribed displacement, w the slider, which
moves only when ``|T| = μ N`` (and then in the direction of T). The normal side is either a
prescribed normal load or a normal spring kn with a preload N0 and a prescribed normal
displacement u_n(t), ``N = max(0, N0 + kn u_n)``; for a harmonic u_n that is the clipped harmonic
normal load ``N0 + kn b cos(ωt + φ)``.

The element *is* the paper's single node (:class:`~lcpfric.model.SingleNode`, ``F = Q + k11 v``,
``|F| <= f N``) with

    k11 = kt,   f = μ,   P(t) = N0 + N1 cos(ωt + φ),   Q(t) = -kt x(t),   v = w,   F = -T,

so that the node's forward slip (v increasing, ``F = -f N``) is the slider moving in +x with
``T = +μ N``, and the states of :class:`~lcpfric.results.State` keep their codes:
:meth:`JenkinsElement.single_node` builds that node, and the exact single node gives the element's
steady cycle (:mod:`lcpfric.exact.jenkins_node`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _checks
from ..errors import InputError
from .loads import Fourier, Harmonic
from .single_node import SingleNode

__all__ = ["JenkinsElement", "jenkins_closed_form", "amplitudes_checked"]

HALF_PI = 0.5 * math.pi


class JenkinsElement:
    """A Jenkins element (spring kt in series with a Coulomb slider) with its normal side.

    Tangential: ``T = kt (x - w)``, ``|T| <= μ N``, the slider w moves only where ``|T| = μ N``.
    Normal, for a motion of angular frequency ω: ``N(t) = max(0, N0 + N1 cos(ωt + φ))`` (a
    prescribed load), or ``N(t) = max(0, N0 + kn u_n(t))`` with ``u_n = un1 cos(ωt + φ)`` (a normal
    spring with preload N0 and a prescribed normal displacement); φ is the phase of the normal
    side relative to the motion ``x = x0 + a cos ωt``.

    Parameters
    ----------
    kt : float
        Tangential stiffness, > 0.
    mu : float
        Coefficient of friction, >= 0 (0: no force at all).
    N0 : float
        Mean normal load, or the preload with ``kn``; > 0.
    N1 : float, optional
        Amplitude of the prescribed normal load, >= 0 (N1 > N0: the element separates, T = 0
        while N = 0). Not with ``un1``.
    phi : float, optional
        Phase φ of the normal side relative to the motion, radians.
    kn : float, optional
        Normal stiffness, > 0: the normal load is then ``N0 + kn u_n``.
    un1 : float, optional
        Amplitude of the prescribed normal displacement, >= 0 (needs ``kn``; ``N1 = kn un1``).

    Attributes
    ----------
    kt, mu, N0, phi, kn, un1
        As given (``kn`` and ``un1`` None without a normal spring).
    N1 : float
        The normal load amplitude: as given, or ``kn un1``.
    slip_limit : float
        ``μ N0 / kt``: the displacement amplitude above which the element slips under constant N.

    Raises
    ------
    InputError
        Naming the parameter: kt <= 0, mu < 0, N0 <= 0, a negative amplitude, kn <= 0, un1
        without kn, N1 and un1 together, or a value that is not finite.

    Examples
    --------
    >>> el = JenkinsElement(kt=2.0, mu=0.3, N0=5.0)
    >>> el.slip_limit
    0.75
    >>> node = el.single_node(amplitude=3.0)
    >>> node.normalized_parameters()[:2]
    (0.0, 4.0)
    """

    def __init__(
        self,
        kt: float,
        mu: float,
        N0: float,
        N1: float = 0.0,
        phi: float = 0.0,
        *,
        kn: float | None = None,
        un1: float | None = None,
    ) -> None:
        self.kt = _checks.positive("kt", kt)
        self.mu = _checks.nonnegative("mu", mu)
        self.N0 = _checks.positive("N0", N0)
        N1 = _checks.nonnegative("N1", N1)
        self.phi = _checks.finite("phi", phi)
        self.kn = None if kn is None else _checks.positive("kn", kn)
        self.un1 = None if un1 is None else _checks.nonnegative("un1", un1)
        if self.un1 is not None:
            if self.kn is None:
                raise InputError("un1", "a normal displacement needs the normal stiffness kn (> 0)")
            if N1:
                raise InputError(
                    "un1",
                    "give either N1 (a prescribed normal load) or kn and un1 (a prescribed "
                    "normal displacement, N1 = kn un1), not both",
                )
            N1 = self.kn * self.un1
            if not math.isfinite(N1):
                raise InputError("un1", f"kn un1 = {N1} is not a finite normal load amplitude")
        self.N1 = N1

    def __repr__(self) -> str:
        normal = (
            f"kn={self.kn!r}, un1={self.un1!r}"
            if self.un1 is not None
            else f"N1={self.N1!r}" + (f", kn={self.kn!r}" if self.kn is not None else "")
        )
        return (
            f"JenkinsElement(kt={self.kt!r}, mu={self.mu!r}, N0={self.N0!r}, {normal}, "
            f"phi={self.phi!r})"
        )

    @property
    def slip_limit(self) -> float:
        """``μ N0 / kt``: the amplitude above which the element slips under constant N."""
        return self.mu * self.N0 / self.kt

    @property
    def separates(self) -> bool:
        """True where the harmonic normal load reaches zero over a cycle (N1 > N0)."""
        return self.N1 > self.N0

    def normal_load(self, omega: float = 1.0, normal: Fourier | None = None) -> Fourier:
        """The normal load before clipping, ``N = max(0, this)``, as a load of time.

        Parameters
        ----------
        omega : float, optional
            Angular frequency ω > 0 of the motion.
        normal : Fourier, optional
            A periodic normal side in place of the harmonic one: with ``kn``, the normal
            displacement u_n(t) (the load is ``N0 + kn u_n``); else the normal load itself,
            whose mean must be > 0.

        Returns
        -------
        Fourier
            ``N0 + N1 cos(ωt + φ)`` (a :class:`~lcpfric.model.Harmonic`), or the load from
            ``normal``.

        Raises
        ------
        InputError
            ``omega`` <= 0, ``normal`` not a Fourier load, or a mean normal load <= 0.
        """
        omega = _checks.positive("omega", omega)
        if normal is None:
            return Harmonic(self.N0, self.N1, self.phi + HALF_PI, omega)
        if not isinstance(normal, Fourier):
            raise InputError(
                "normal", "must be a Fourier load (Harmonic or Fourier: a trigonometric polynomial)"
            )
        if self.kn is None:
            load = normal
        else:
            kn = self.kn
            load = Fourier(
                self.N0 + kn * normal.mean,
                tuple(kn * a for a in normal.amplitudes),
                normal.phases,
                normal.omega,
            )
        if load.mean <= 0:
            raise InputError(
                "normal",
                f"the mean normal load must be > 0 (in contact on average), got {load.mean}",
            )
        return load

    def motion(
        self, amplitude: float, omega: float = 1.0, x0: float = 0.0, phase: float = 0.0
    ) -> Harmonic:
        """The harmonic motion ``x(t) = x0 + a cos(ωt + phase)`` as a load of time.

        Parameters
        ----------
        amplitude : float
            The displacement amplitude a, > 0.
        omega : float, optional
            Angular frequency ω > 0.
        x0 : float, optional
            The mean displacement.
        phase : float, optional
            The phase of the motion, radians (the normal side keeps its φ relative to t).

        Returns
        -------
        Harmonic
            ``x0 + a sin(ωt + phase + π/2)``.

        Raises
        ------
        InputError
            amplitude <= 0, omega <= 0, or a value that is not finite.
        """
        a = _checks.positive("amplitude", amplitude)
        return Harmonic(
            _checks.finite("x0", x0),
            a,
            _checks.finite("phase", phase) + HALF_PI,
            _checks.positive("omega", omega),
        )

    def single_node(
        self, amplitude: float, omega: float = 1.0, x0: float = 0.0, phase: float = 0.0
    ) -> SingleNode:
        """The paper's single node that is this element under the motion
        ``x = x0 + a cos(ωt + phase)``.

        ``k11 = kt``, ``f = μ``, ``P(t) = N0 + N1 cos(ωt + φ)``, ``Q(t) = -kt x(t)``; its
        displacement v is the slider w and its friction force F is ``-T``.

        Parameters
        ----------
        amplitude : float
            The displacement amplitude a, > 0.
        omega : float, optional
            Angular frequency ω > 0.
        x0 : float, optional
            The mean displacement (the node's ``Q0 = -kt x0``).
        phase : float, optional
            The phase of the motion, radians.

        Returns
        -------
        SingleNode
            The node, with harmonic loads of one frequency (``exact`` solves it).

        Raises
        ------
        InputError
            The motion's parameters out of range, or mu = 0 (the node needs f > 0; the element
            then carries no force at all).
        """
        x = self.motion(amplitude, omega, x0, phase)
        if self.mu == 0.0:
            raise InputError(
                "mu", "must be > 0 for the single node (with mu = 0 the element carries no force)"
            )
        return SingleNode(
            k11=self.kt,
            f=self.mu,
            normal_load=self.normal_load(omega),
            tangential_load=Harmonic(-self.kt * x.mean, self.kt * x.amplitude, x.phase - math.pi,
                                     x.omega),
        )  # fmt: skip


def _x_minus_sin(x):
    """``x - sin x`` without cancellation for small x (Taylor series below 0.5)."""
    x = np.asarray(x, dtype=float)
    x2 = x * x
    inner = 1 - x2 / 110 * (1 - x2 / 156 * (1 - x2 / 210))  # truncation < 1e-17 relative
    series = x * x2 / 6.0 * (1 - x2 / 20 * (1 - x2 / 42 * (1 - x2 / 72 * inner)))
    return np.where(np.abs(x) < 0.5, series, x - np.sin(x))


def jenkins_closed_form(kt: float, mu: float, N: float, amplitudes) -> dict:
    """The notes' closed forms of a Jenkins element under constant N and ``x = a cos ωt``.

    With ``Fs = μN`` and, for ``a > Fs/kt``, ``cos τ* = 1 - 2 Fs/(kt a)``::

        k_eq   = (kt/π) (τ* - sin(2τ*)/2)
        ω c_eq = (4 Fs/(π a)) (1 - Fs/(kt a))
        W      = 4 Fs (a - Fs/kt)

    and ``k_eq = kt``, ``c_eq = W = 0`` for ``a <= Fs/kt``. Written to keep their digits at
    large amplitudes: ``τ* = 2 asin(sqrt(Fs/(kt a)))`` and ``2τ - sin 2τ`` by its series.

    Parameters
    ----------
    kt, mu, N : float
        Stiffness (> 0), friction coefficient (>= 0) and the constant normal load (> 0).
    amplitudes : array_like
        Motion amplitudes a > 0.

    Returns
    -------
    dict
        ``k_eq``, ``c_eq_omega``, ``W``, ``loss_factor`` and ``force_amplitude``
        (``min(kt a, Fs)``), arrays of the amplitudes' shape.

    Raises
    ------
    InputError
        A parameter out of range.
    """
    kt = _checks.positive("kt", kt)
    Fs = _checks.nonnegative("mu", mu) * _checks.positive("N", N)
    a = amplitudes_checked(amplitudes)
    r = Fs / (kt * a)
    slips = r < 1.0
    rs = np.where(slips, r, 0.5)
    tau = 2.0 * np.arcsin(np.sqrt(rs))
    k_eq = np.where(slips, kt / (2.0 * math.pi) * _x_minus_sin(2.0 * tau), kt)
    c = np.where(slips, 4.0 * Fs / (math.pi * a) * (1.0 - rs), 0.0)
    W = np.where(slips, 4.0 * Fs * (a - Fs / kt), 0.0)
    return {
        "k_eq": k_eq,
        "c_eq_omega": c,
        "W": W,
        "loss_factor": c / k_eq,
        "force_amplitude": np.minimum(kt * a, Fs),
    }


def amplitudes_checked(amplitudes) -> np.ndarray:
    """Motion amplitudes as a flat float array, every one finite and > 0 (else InputError)."""
    a = _checks.finite_array("amplitude", amplitudes)
    if a.size == 0 or np.any(a <= 0):
        raise InputError(
            "amplitude", "every amplitude must be > 0 (allowed range (0, inf)); got none or <= 0"
        )
    return a.ravel()
