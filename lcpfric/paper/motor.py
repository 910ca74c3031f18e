"""The paper's example (Section 3.3, Figs. 8-9): a motor bolted to a foundation.

A rotor of mass M whose centre of mass is a distance δ off the axis turns at Ω. The bolts preload
the joint with P0; the out-of-balance force gives loads of the form of Eq. (1) with
``P1 = Q1 = M Ω² δ``, ``ω = Ω`` and ``φ = π/2``, so that::

    P̂1 = M Ω² δ / P0,      Q̂1 = M Ω² δ / (f P0) = P̂1 / f,

a straight line of slope 1/f on the φ = 5π/10 map of Fig. 4. The dissipation per revolution is
``W = f P0 Q1 Ŵ / k11`` (Eq. 6), with k11 the tangential stiffness of the joint. The analysis is
quasi-static: it holds for ``Ω ≪ Ω0 = sqrt(k11 / M)``.

Beyond it (issue 40, item 6), :meth:`Motor.dynamic_dissipation`: the motor's mass M on the
joint's stiffness k11 with a viscous damping ratio ζ is the dynamic single node with
``β = Ω/Ω0`` (:mod:`lcpfric.exact.dynamic`), solved exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks

__all__ = ["Motor"]


@dataclass(frozen=True)
class Motor:
    """The motor of Fig. 8, in SI units.

    Parameters
    ----------
    M : float
        Rotor mass [kg], > 0.
    delta : float
        Offset of the rotor's centre of mass from the axis [m], > 0.
    P0 : float
        Bolt preload, the normal contact force at rest [N], > 0.
    k11 : float
        Tangential stiffness of the bolted joint [N/m], > 0.

    Examples
    --------
    >>> motor = Motor(M=20.0, delta=0.5e-3, P0=2000.0, k11=5e8)
    >>> round(motor.P1_hat(motor.separation_speed()), 12)
    1.0
    """

    M: float
    delta: float
    P0: float
    k11: float

    def __post_init__(self):
        for name in ("M", "delta", "P0", "k11"):
            object.__setattr__(self, name, _checks.positive(name, getattr(self, name)))

    phi = math.pi / 2  # the out-of-balance force turns with the rotor: Q lags P by π/2

    def force(self, Omega):
        """Out-of-balance force amplitude ``M Ω² δ`` [N] (= P1 = Q1)."""
        out = self.M * np.square(np.asarray(Omega, dtype=float)) * self.delta
        return out if out.ndim else float(out)

    def P1_hat(self, Omega):
        """P̂1 = M Ω² δ / P0."""
        return self.force(Omega) / self.P0

    def Q1_hat(self, Omega, f: float):
        """Q̂1 = M Ω² δ / (f P0) = P̂1 / f."""
        return self.P1_hat(Omega) / _checks.positive("f", f)

    def dissipation(self, Omega, f: float):
        """Energy dissipated per revolution, W [J], at the speeds ``Omega`` [rad/s] (exact)."""
        from ..exact import exact_W_hat

        Omega = _checks.finite_array("Omega", Omega, nonneg=True)
        f = _checks.positive("f", f)
        W_hat = exact_W_hat(self.P1_hat(Omega), self.Q1_hat(Omega, f), self.phi)
        out = f * self.P0 * np.asarray(self.force(Omega)) * np.asarray(W_hat) / self.k11
        return out if out.ndim else float(out)

    def dynamic_dissipation(self, Omega, f: float, zeta: float = 0.05):
        """Energy dissipated per revolution, W [J], with the rotor's inertia: the dynamic node
        of mass M, damping ratio ζ and β = Ω/Ω0 (exact; module docstring).

        Parameters
        ----------
        Omega : float or array_like
            Speeds [rad/s], > 0 (ζ = 0 refuses Ω = Ω0: the undamped resonance).
        f : float
            Friction coefficient, > 0.
        zeta : float, optional
            Damping ratio, >= 0.

        Returns
        -------
        float or ndarray
            W at each speed.

        Raises
        ------
        InputError
            A speed <= 0 or not finite, f <= 0, ζ < 0, or ζ = 0 at Ω = Ω0.
        """
        from ..errors import InputError
        from ..exact.dynamic_api import dynamic_cycle

        Omega = _checks.finite_array("Omega", Omega, nonneg=True)
        f, zeta = _checks.positive("f", f), _checks.nonnegative("zeta", zeta)
        out = np.empty(Omega.shape)
        for i, Om in np.ndenumerate(Omega):
            beta = Om / self.natural_frequency()
            if not beta > 0 or (zeta == 0 and math.isclose(beta, 1.0, rel_tol=1e-9)):
                raise InputError("Omega", f"must be > 0 and not Ω0 without damping, got {Om}")
            cyc = dynamic_cycle(self.P1_hat(Om), self.Q1_hat(Om, f), self.phi, beta, zeta)
            out[i] = f * self.P0 * self.force(Om) * cyc.W_hat / self.k11
        return out if out.ndim else float(out)

    def natural_frequency(self) -> float:
        """Ω0 = sqrt(k11 / M) [rad/s]; the quasi-static analysis needs Ω ≪ Ω0."""
        return math.sqrt(self.k11 / self.M)

    def separation_speed(self) -> float:
        """The speed above which the joint opens during part of each revolution (P̂1 = 1).

        It is also the speed unit of the paper's Fig. 9 axis, ``Ω sqrt(M δ / P0)``.
        """
        return math.sqrt(self.P0 / (self.M * self.delta))

    def shakedown_speed(self, f: float) -> float:
        """The speed below which the joint shakes down (no dissipation).

        At φ = π/2 shakedown holds iff ``sqrt(P̂1² + Q̂1²) <= 1`` (``shakedown_margin`` >= 0),
        i.e. ``P̂1 sqrt(1 + 1/f²) <= 1``.
        """
        f = _checks.positive("f", f)
        return self.separation_speed() / math.sqrt(math.sqrt(1.0 + 1.0 / f**2))
