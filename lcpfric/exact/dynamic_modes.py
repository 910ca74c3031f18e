r"""The closed-form modes of the dynamic single node (issue 40): between events its motion is a
damped oscillator under constant plus harmonic forcing.

In the node's normalized units (displacement ``u = k11 v / (f P0)``, force ``f P0``, angle
``θ = ωt``) the equation of motion is

    β² u'' + 2ζβ u' + u = F(θ) - q(θ),     β = ω/Ω0 = ω sqrt(m/k11),  ζ = c / (2 sqrt(k11 m)),

with ``q = Q̂1 sin(θ + φ)`` (the mean only shifts u) and the friction force F: ``F = -s n(θ)`` in
slip of direction ``s = sign u'``, ``n = 1 + P̂1 sin θ``; ``F = 0`` in separation (n <= 0);
``F = u + q`` in stick (``|u + q| <= n``, u constant). This is lcpfric's quasi-static sign
convention (``k11 v = F - Q``) with inertia and damping added: as β -> 0 it is the paper's node.

So every mode's forcing is ``g(θ) = g0 + gc cos θ + gs sin θ``; its solution is the particular
``u_p = g0 + A cos θ + B sin θ`` (``(1-β²) A + 2ζβ B = gc``, ``(1-β²) B - 2ζβ A = gs``) plus the
homogeneous motion ``y_h(θ) = E(θ - θa) y_h(θa)`` of ``y = (u, u')``, ``E(s) = exp(s M)`` with
``M = [[0, 1], [-1/β², -2ζ/β]]`` in closed form for every damping (under-, critically and
over-damped). The particular solution needs ``(1-β²)² + (2ζβ)² > 0``: ζ = 0 at β = 1 is the
undamped resonance, refused by the model.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Oscillator", "Segment", "slip_forcing", "free_forcing"]


class Oscillator:
    """``β² u'' + 2ζβ u' + u = g(θ)`` (module docstring).

    Parameters
    ----------
    beta, zeta : float
        β > 0, ζ >= 0, not (ζ = 0 and β = 1).
    """

    def __init__(self, beta: float, zeta: float) -> None:
        self.beta, self.zeta = float(beta), float(zeta)
        b = self.beta
        self.b2 = b * b
        self.damp = 2.0 * self.zeta * b  # the coefficient of u'
        self.M = np.array([[0.0, 1.0], [-1.0 / self.b2, -2.0 * self.zeta / b]])
        self.mu = -self.zeta / b
        self.nu2 = (self.zeta * self.zeta - 1.0) / self.b2
        a = 1.0 - self.b2
        self.det = a * a + self.damp * self.damp
        self.a = a
        #: the natural period in θ (the scan's time scale)
        self.natural = 2.0 * math.pi * b

    def particular(self, g0: float, gc: float, gs: float) -> tuple[float, float, float]:
        """``(g0, A, B)`` of the particular solution of the forcing ``g0 + gc cos + gs sin``."""
        a, d = self.a, self.damp
        return g0, (a * gc - d * gs) / self.det, (a * gs + d * gc) / self.det

    def propagator(self, s) -> np.ndarray:
        """``E(s) = exp(s M)`` for the array s: ``(..., 2, 2)``."""
        s = np.asarray(s, dtype=float)
        mu, nu2 = self.mu, self.nu2
        N = self.M - mu * np.eye(2)
        if nu2 < 0.0:
            w = math.sqrt(-nu2)
            C, S = np.cos(w * s), np.sin(w * s) / w
        elif nu2 > 0.0:
            nu = math.sqrt(nu2)
            if nu * max(1.0, float(np.max(np.abs(s), initial=0.0))) > 1e-3:
                # exponentials, not cosh and sinh: no overflow for an over-damped long segment
                e1, e2 = np.exp((mu + nu) * s), np.exp((mu - nu) * s)
                eye = np.eye(2)
                return 0.5 * (
                    e1[..., None, None] * (eye + N / nu) + e2[..., None, None] * (eye - N / nu)
                )
            C, S = np.cosh(nu * s), np.sinh(nu * s) / nu
        else:
            C, S = np.ones_like(s), s.copy()
        e = np.exp(mu * s)
        return e[..., None, None] * (C[..., None, None] * np.eye(2) + S[..., None, None] * N)


    def propagator1(self, s: float) -> tuple[float, float, float, float]:
        """``E(s)`` for a scalar s, as ``(E00, E01, E10, E11)`` (scalar arithmetic: the event
        searches' many single evaluations)."""
        mu, nu2, b = self.mu, self.nu2, self.beta
        n00, n10, n11 = -mu, -1.0 / self.b2, -2.0 * self.zeta / b - mu  # N = M - μ I; N01 = 1
        if nu2 < 0.0:
            w = math.sqrt(-nu2)
            C, S = math.cos(w * s), math.sin(w * s) / w
        elif nu2 > 0.0:
            nu = math.sqrt(nu2)
            if nu * max(1.0, abs(s)) > 1e-3:
                e1, e2 = math.exp((mu + nu) * s), math.exp((mu - nu) * s)
                p, m = 0.5 * (e1 + e2), 0.5 * (e1 - e2) / nu
                return p + m * n00, m, m * n10, p + m * n11
            C, S = math.cosh(nu * s), math.sinh(nu * s) / nu
        else:
            C, S = 1.0, s
        e = math.exp(mu * s)
        return e * (C + S * n00), e * S, e * S * n10, e * (C + S * n11)


def slip_forcing(s: int, P1: float, Q1: float, phi: float) -> tuple[float, float, float]:
    """The forcing ``-s n(θ) - q(θ)`` of slip in the direction s."""
    return -float(s), -Q1 * math.sin(phi), -s * P1 - Q1 * math.cos(phi)


def free_forcing(Q1: float, phi: float) -> tuple[float, float, float]:
    """The forcing ``-q(θ)`` of separation."""
    return 0.0, -Q1 * math.sin(phi), -Q1 * math.cos(phi)


class Segment:
    """A mode's motion from ``(θa, ya)``: ``y(θ) = y_p(θ) + E(θ - θa) (ya - y_p(θa))``.

    Parameters
    ----------
    osc : Oscillator
        The oscillator.
    forcing : tuple of float
        ``(g0, gc, gs)``.
    theta_a : float
        The segment's start.
    y_a : array_like
        ``(u, u')`` there.
    """

    def __init__(self, osc: Oscillator, forcing, theta_a: float, y_a) -> None:
        self.osc = osc
        self.g = forcing
        self.p0, self.A, self.B = osc.particular(*forcing)
        self.theta_a = float(theta_a)
        ya = np.asarray(y_a, dtype=float)
        self.h0 = ya - self._particular(self.theta_a)
        self.h0 = (float(self.h0[0]), float(self.h0[1]))

    def _particular(self, theta):
        c, s = np.cos(theta), np.sin(theta)
        return np.array([self.p0 + self.A * c + self.B * s, -self.A * s + self.B * c])

    def state(self, theta) -> np.ndarray:
        """``(u, u')`` at θ (scalar or array: ``(2,)`` or ``(2, n)``)."""
        theta = np.asarray(theta, dtype=float)
        E = self.osc.propagator(theta - self.theta_a)
        return self._particular(theta) + np.moveaxis(E @ np.asarray(self.h0), -1, 0)

    def state1(self, theta: float) -> tuple[float, float]:
        """``(u, u')`` at a scalar θ (scalar arithmetic)."""
        c, s = math.cos(theta), math.sin(theta)
        e00, e01, e10, e11 = self.osc.propagator1(theta - self.theta_a)
        h0, h1 = self.h0[0], self.h0[1]
        return (
            self.p0 + self.A * c + self.B * s + e00 * h0 + e01 * h1,
            -self.A * s + self.B * c + e10 * h0 + e11 * h1,
        )

    def acceleration1(self, theta: float, u: float, du: float) -> float:
        """u'' at a scalar θ in the state ``(u, u')``."""
        g0, gc, gs = self.g
        g = g0 + gc * math.cos(theta) + gs * math.sin(theta)
        return (g - self.osc.damp * du - u) / self.osc.b2

    def acceleration(self, theta, y=None) -> np.ndarray:
        """u'' at θ from the equation of motion."""
        theta = np.asarray(theta, dtype=float)
        if y is None:
            y = self.state(theta)
        g0, gc, gs = self.g
        g = g0 + gc * np.cos(theta) + gs * np.sin(theta)
        return (g - self.osc.damp * y[1] - y[0]) / self.osc.b2

    def velocity_scale(self) -> float:
        """The size of the terms whose sum is u' (its round-off's scale)."""
        return abs(self.A) + abs(self.B) + abs(self.h0[1]) + abs(self.h0[0]) / self.osc.beta
