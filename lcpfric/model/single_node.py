"""The paper's single node (Fig. 2, Eqs. 1-10) and its normalization (Eq. 6).

Normalization (Eq. 6): ``P̂ = P/P0``, ``Q̂ = Q/(f P0)``, ``v̂ = k11 v / Q1``, ``F̂ = F/(f P0)`` and
``Ŵ = k11 W / (f P0 Q1)``, so Ŵ depends only on (P̂1, Q̂1, φ). Internally lcpfric advances the
single node in the units of force ``f P0`` and displacement ``f P0 / k11``: that is the general
system with ``K = [[1]]``, ``f = [1]``, ``N = max(P̂, 0)`` and ``Q = Q̂``, whose dissipation J
gives ``Ŵ = J / Q̂1`` (and the limit Ŵ = 0 at Q̂1 = 0). The conversions between W and Ŵ and the
check of the units are :mod:`.normalization`'s.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError
from .inertia import Inertia
from .loads import Harmonic, Load, scaled_load
from .normal import IndependentSprings
from .normalization import W_from_W_hat, W_hat_from_W, check_units
from .system import ContactSystem

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..results import Normalization

__all__ = ["SingleNode", "W_hat_from_W", "W_from_W_hat"]


class SingleNode(Inertia):
    """The single-node system of the paper (Fig. 2).

    Tangential spring k11, normal spring k22, Coulomb friction f, loads
    ``P(t) = P0 + P1 sin ωt`` and ``Q(t) = Q0 + Q1 sin(ωt + φ)``.

    Parameters
    ----------
    k11, k22 : float
        Tangential and normal spring stiffness, > 0. k22 does not affect the dissipation; it only
        sets the normal displacement w in separation.
    f : float
        Coefficient of friction, > 0.
    P0 : float
        Mean normal load, > 0 (the body is in contact in the absence of vibration).
    P1, Q1 : float
        Normal and tangential load amplitudes, >= 0.
    omega : float
        Angular frequency ω > 0.
    phi : float
        Phase of Q relative to P, radians.
    Q0 : float
        Mean tangential load; it shifts the displacement datum by Q0/k11 and does not affect W.
    normal_load, tangential_load : Load, optional
        Any periodic P(t) and Q(t) (two harmonics, say) in place of the harmonic ones; then
        P0 is the normal load's mean and Q1 its tangential amplitude (``max |Q - Q0|``).
    dimensional : bool, optional
        False for the dimensionless system of :meth:`normalized` (it only changes the
        ``repr``).
    k21 : float, optional
        The off-diagonal stiffness that makes the normal reaction depend on the slip
        (Klarbring's node: ``N = P + k21 v`` in contact; default 0, the paper's uncoupled node),
        ``f |k21| < k11`` (Klarbring's condition). Solved by ``exact`` and ``explicit`` through
        :meth:`system` (a coupled one-node system; a node whose reaction reaches zero is refused
        by name).
    mass, damping : float, optional
        The node's mass m and viscous damping c (default 0: the paper's quasi-static node):
        then ``m v'' + c v' + k11 v = F - Q`` (:mod:`lcpfric.model.inertia`; β = ω/Ω0,
        Ω0 = sqrt(k11/m), ζ = c / (2 sqrt(k11 m))), solved by ``exact``. Damping needs a mass;
        ζ = 0 at β = 1 (the undamped resonance) is refused.

    Attributes
    ----------
    k11, k22, f, normal_load, tangential_load, dimensional
        As given (the loads: P(t) and Q(t), harmonic ones built from P0, P1, Q0, Q1, ω, φ).
    P0, Q0, P1, Q1, period, omega, is_harmonic, phi, P1_hat, Q1_hat
        Properties (below), as are ``force_unit`` and ``displacement_unit``.

    Raises
    ------
    InputError
        A parameter out of range or not finite (P0 <= 0, a negative amplitude, ...); a load
        that is not a :class:`~lcpfric.model.loads.Load`; loads of different periods; or units
        in which the normalized quantities (f P0, f P0 / k11, P̂1, Q̂1, ω) are not finite
        normal doubles.

    Examples
    --------
    >>> node = SingleNode.normalized(P1=0.5, Q1=2.0, phi=0.0)
    >>> node.P1_hat, node.Q1_hat
    (0.5, 2.0)
    """

    #: the driver's defaults (:func:`lcpfric.steady_state`)
    default_method = "exact"
    default_steps = 2000
    default_max_cycles = 100
    default_placement = "contact"

    def __init__(
        self,
        k11: float = 1.0,
        f: float = 1.0,
        P0: float = 1.0,
        P1: float = 0.0,
        Q1: float = 0.0,
        omega: float = 1.0,
        phi: float = 0.0,
        Q0: float = 0.0,
        k22: float = 1.0,
        *,
        normal_load: Load | None = None,
        tangential_load: Load | None = None,
        dimensional: bool = True,
        k21: float = 0.0,
        mass: float = 0.0,
        damping: float = 0.0,
    ) -> None:
        self.k11 = _checks.positive("k11", k11)
        self.mass = _checks.nonnegative("mass", mass)
        self.damping = _checks.nonnegative("damping", damping)
        self.k22 = _checks.positive("k22", k22)
        self.f = _checks.positive("f", f)
        self.k21 = _checks.finite("k21", k21)
        if not self.f * abs(self.k21) < self.k11:  # Klarbring's condition for one node
            raise InputError(
                "k21",
                f"|k21| = {abs(self.k21):g} must be < k11 / f = {self.k11 / self.f:g} "
                "(Klarbring's condition: above it the evolution is not unique)",
            )
        self.dimensional = _checks.boolean("dimensional", dimensional)
        harmonic_inputs = normal_load is None and tangential_load is None
        if normal_load is None:
            P0 = _checks.finite("P0", P0)
            if P0 <= 0:
                raise InputError(
                    "P0",
                    f"must be > 0 (the paper's régime: in contact at rest; "
                    f"allowed range (0, inf)), got {P0}",
                )
            normal_load = Harmonic(
                P0, _checks.nonnegative("P1", P1), 0.0, _checks.positive("omega", omega)
            )
        elif not isinstance(normal_load, Load):
            raise InputError("normal_load", "must be a Load (Harmonic, Fourier or Periodic)")
        if tangential_load is None:
            tangential_load = Harmonic(
                _checks.finite("Q0", Q0),
                _checks.nonnegative("Q1", Q1),
                _checks.finite("phi", phi),
                normal_load.omega
                if isinstance(normal_load, Harmonic)
                else 2 * math.pi / normal_load.period,
            )
        elif not isinstance(tangential_load, Load):
            raise InputError("tangential_load", "must be a Load (Harmonic, Fourier or Periodic)")
        if normal_load.mean <= 0:
            raise InputError(
                "P0",
                f"the mean normal load must be > 0 (allowed range (0, inf)), "
                f"got {normal_load.mean}",
            )
        self.normal_load = normal_load
        self.tangential_load = tangential_load
        check_units(self, harmonic_inputs)
        periods = [ld.period for ld in (normal_load, tangential_load) if not ld.is_constant]
        if len(periods) == 2 and not math.isclose(periods[0], periods[1], rel_tol=1e-12):
            raise InputError(
                "tangential_load",
                f"must have the normal load's period {periods[0]}, got {periods[1]}",
            )
        self._system = None
        self._check_dynamics()

    @classmethod
    def normalized(
        cls, P1: float, Q1: float, phi: float = 0.0, *, beta: float = 0.0, zeta: float = 0.0
    ) -> SingleNode:
        """The dimensionless system of Eqs. (8)-(10): P̂ = 1 + P̂1 sin ωt, Q̂ = Q̂1 sin(ωt + φ).

        That is k11 = f = P0 = ω = 1, so that its W is ``Q̂1 Ŵ``; with ``beta`` > 0 the dynamic
        node of frequency ratio β = ω/Ω0 and damping ratio ζ (m = β², c = 2ζβ).

        Parameters
        ----------
        P1 : float
            Normalized normal amplitude P̂1, >= 0.
        Q1 : float
            Normalized tangential amplitude Q̂1, >= 0.
        phi : float, optional
            Phase φ of Q relative to P, radians.
        beta, zeta : float, optional
            β >= 0 (0: quasi-static) and ζ >= 0.

        Returns
        -------
        SingleNode
            The node, with ``dimensional=False``.

        Raises
        ------
        InputError
            A parameter out of range or not finite.
        """
        beta, zeta = _checks.nonnegative("beta", beta), _checks.nonnegative("zeta", zeta)
        if zeta > 0 and beta == 0:
            raise InputError("zeta", "needs beta > 0 (a massless node is quasi-static)")
        dyn = {"mass": beta * beta, "damping": 2.0 * zeta * beta}  # k11 = f = P0 = ω = 1
        return cls(1.0, 1.0, 1.0, P1, Q1, 1.0, phi, dimensional=False, **dyn)

    # -- the paper's parameters -------------------------------------------------------------------
    @property
    def P0(self) -> float:
        """The mean normal load (the normal load's mean)."""
        return self.normal_load.mean

    @property
    def Q0(self) -> float:
        """The mean tangential load."""
        return self.tangential_load.mean

    @property
    def P1(self) -> float:
        """The normal load amplitude (max over a cycle of ``|P - P0|``)."""
        return self.normal_load.amplitude

    @property
    def Q1(self) -> float:
        """The tangential load amplitude (max over a cycle of ``|Q - Q0|``)."""
        return self.tangential_load.amplitude

    @property
    def period(self) -> float:
        """The loads' period (of the first that varies; the normal load's if neither does)."""
        for ld in (self.normal_load, self.tangential_load):
            if not ld.is_constant:
                return ld.period
        return self.normal_load.period

    @property
    def omega(self) -> float:
        """The angular frequency 2π / period."""
        return 2 * math.pi / self.period

    @property
    def is_harmonic(self) -> bool:
        """True for the paper's loads (both harmonic, one frequency), which ``exact`` needs."""
        return (
            isinstance(self.normal_load, Harmonic)
            and isinstance(self.tangential_load, Harmonic)
            and (
                self.normal_load.is_constant
                or self.tangential_load.is_constant
                or math.isclose(self.normal_load.omega, self.tangential_load.omega, rel_tol=1e-12)
            )
        )

    @property
    def phi(self) -> float:
        """φ of Eq. (1): the tangential load's phase relative to the normal load's.

        Raises :class:`~lcpfric.errors.InputError` unless the loads are harmonic of one
        frequency (:attr:`is_harmonic`).
        """
        if not self.is_harmonic:
            raise InputError("phi", "is defined only for harmonic loads of one frequency")
        return self.tangential_load.phase - self.normal_load.phase

    @property
    def P1_hat(self) -> float:
        """P̂1 = P1/P0 (Eq. 6)."""
        return self.P1 / self.P0

    @property
    def Q1_hat(self) -> float:
        """Q̂1 = Q1/(f P0) (Eq. 6)."""
        return self.Q1 / (self.f * self.P0)

    def normalized_parameters(self) -> tuple[float, float, float]:
        """(P̂1, Q̂1, φ) of this (harmonic) system.

        Returns
        -------
        P1_hat, Q1_hat, phi : float
            P̂1 = P1/P0, Q̂1 = Q1/(f P0) (Eq. 6) and φ in radians.

        Raises
        ------
        InputError
            The loads are not harmonic of one frequency (φ is undefined).
        """
        return self.P1_hat, self.Q1_hat, self.phi

    # -- conversions (Eq. 6) ----------------------------------------------------------------------
    def W_hat(self, W: ArrayLike) -> float | np.ndarray:
        """Ŵ = k11 W / (f P0 Q1) (:func:`W_hat_from_W` with this node's parameters).

        Parameters
        ----------
        W : float or array_like
            Dissipation per cycle, in this node's units.

        Returns
        -------
        float or ndarray
            Ŵ (0 when Q1 = 0); a float for scalar input.
        """
        return W_hat_from_W(W, self.k11, self.f, self.P0, self.Q1)

    def W(self, W_hat: ArrayLike) -> float | np.ndarray:
        """W = f P0 Q1 Ŵ / k11 (:func:`W_from_W_hat` with this node's parameters).

        Parameters
        ----------
        W_hat : float or array_like
            Normalized dissipation per cycle Ŵ.

        Returns
        -------
        float or ndarray
            W in this node's units; a float for scalar input.
        """
        return W_from_W_hat(W_hat, self.k11, self.f, self.P0, self.Q1)

    @property
    def force_unit(self) -> float:
        """f P0: the unit of F̂ and Q̂."""
        return self.f * self.P0

    @property
    def displacement_unit(self) -> float:
        """f P0 / k11: the unit in which the solvers advance the tangential displacement."""
        return self.f * self.P0 / self.k11

    def normalization(self) -> Normalization:
        """The units of Eq. (6): W = f P0 Q1 / k11, v = Q1 / k11, F = f P0, N = P0.

        Returns
        -------
        Normalization
            The units (:class:`~lcpfric.results.Normalization`).
        """
        from ..results import Normalization

        return Normalization(
            W=self.force_unit * self.Q1 / self.k11,
            v=self.Q1 / self.k11,
            F=self.force_unit,
            N=self.P0,
        )

    def series(
        self, u: ArrayLike, F: ArrayLike, N: ArrayLike
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The model's time series (v, F, N) from the solvers' normalized ones.

        v = (f P0 u - Q0) / k11, F = f P0 F, N = P0 N.

        Parameters
        ----------
        u : array_like
            Tangential displacements in units of f P0 / k11.
        F : array_like
            Friction forces in units of f P0.
        N : array_like
            Normal reactions in units of P0.

        Returns
        -------
        v, F, N : ndarray
            The same series in this node's units.
        """
        return ((self.force_unit * u - self.Q0) / self.k11, self.force_unit * F, self.P0 * N)

    def system(self) -> ContactSystem:
        """The node as a general :class:`ContactSystem` in normalized units (K = 1, f = 1).

        Its dissipation J per cycle gives Ŵ = J / Q̂1. Built once, on first use.

        Returns
        -------
        ContactSystem
            K = [[1]], f = [1], Q = Q̂ - Q̂0 and :class:`IndependentSprings` with P̂.
        """
        if self._system is None:
            fp0 = self.force_unit
            # N = P + k21 v in contact: N/P0 = P̂ + (f k21/k11) k11 v/(f P0); a mean Q0 then
            # moves N too, so it is kept
            b = self.f * self.k21 / self.k11
            self._system = ContactSystem(
                stiffness=np.array([[1.0]]),
                friction=np.array([1.0]),
                tangential_loads=(scaled_load(self.tangential_load, 1.0 / fp0, drop_mean=not b),),
                normal=IndependentSprings((scaled_load(self.normal_load, 1.0 / self.P0),)),
                coupling=np.array([[b]]) if b else None,
            )
        return self._system

    def from_system(self, J_cycles, u, F, N) -> dict:
        """A steady state of :meth:`system` in this node's units.

        Parameters
        ----------
        J_cycles : array_like
            The dissipation of each cycle in the system's units (f P0, f P0/k11): J = Q̂1 Ŵ.
        u, F, N : array_like
            The system's series.

        Returns
        -------
        dict
            ``W``, ``W_cycles``, ``W_hat_cycles``, ``v``, ``F``, ``N`` and ``normalization``, as
            :class:`~lcpfric.results.SteadyState` takes them.
        """
        q1 = self.Q1_hat
        J = np.atleast_1d(np.asarray(J_cycles, dtype=float))
        W_hat = J / q1 if q1 > 0 else 0.0 * J
        v, F, N = self.series(u, F, N)
        v = v + self.Q0 / self.k11 if self.k21 else v  # a coupled system keeps Q's mean
        return dict(
            W=float(self.W(W_hat[-1])),
            W_cycles=np.atleast_1d(self.W(W_hat)),
            W_hat_cycles=W_hat,
            v=v,
            F=F,
            N=N,
            normalization=self.normalization(),
        )

    @property
    def coupling(self):
        """The normalized coupling ``[[f k21 / k11]]`` of the node's system, or None (k21 = 0)."""
        return self.system().coupling

    def __repr__(self) -> str:
        if self.is_harmonic:
            p1, q1, phi = self.normalized_parameters()
            core = f"P1_hat={p1:.6g}, Q1_hat={q1:.6g}, phi={phi:.6g}"
        else:
            core = f"normal_load={self.normal_load!r}, tangential_load={self.tangential_load!r}"
        if self.is_dynamic:
            core += f", beta={self.beta:.6g}, zeta={self.zeta:.6g}"
        if not self.dimensional:
            return f"SingleNode.normalized({core})"
        return (
            f"SingleNode(k11={self.k11:g}, f={self.f:g}, P0={self.P0:g}, k22={self.k22:g}, {core})"
        )
