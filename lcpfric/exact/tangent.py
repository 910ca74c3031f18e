"""The exact solver's tangent map: the cycle map's Jacobian ``d u(2π) / d u(0)`` propagated along
a tracked cycle (:mod:`lcpfric.exact.discrete`, "Cycles")."""

from __future__ import annotations

import numpy as np

from .triples import rate_of, value

__all__ = ["Tangent"]


class Tangent:
    """The Jacobian tracking of :class:`~lcpfric.exact.events.EventSolver` (which holds ``Kt``,
    the operator from the state to the forces (K itself, or ``K T`` in cluster coordinates), G,
    the pattern and ``Jt``)."""

    def state_triples(self):
        """The triples of the state (u itself here), whose rows the tangent tracks."""
        return self.U

    def start_tangent(self):
        """The tangent at θ = 0: each stuck node holds its own start state."""
        return np.diag((self.status == 0).astype(float))

    def tangent_stick(self, j, theta):
        """Node j (in B) sticks at theta: its held displacement ``u_j = U_j(θ)`` depends on
        the stuck displacements through ``-(G K_BS)_j``, and on the event angle through its rate
        ``U_j'(θ)``: zero when its slip stops by itself, not when it is stopped by another node
        reaching its limit at theta (then ``self.theta_row``, that angle's own sensitivity)."""
        m, p = self.m, self.pos[j]
        g = self.G[p, :m]
        nz = g.nonzero()[0]
        row = -(g[nz] @ self.Kt[self.Bidx[nz], :])
        row[self.B] = 0.0
        k = row.nonzero()[0]
        self.Jt[j] = row[k] @ self.Jt[k] if k.size else 0.0
        if self.theta_row is not None:
            rate = float(value(rate_of(self.state_triples()[j]), theta))
            self.Jt[j] += rate * self.theta_row

    def theta_sensitivity(self, j, upper, theta):
        """d(event angle)/d(start state) for stuck node j reaching its upper (or lower) limit:
        ``-(∂g/∂u_S · J_S) / g'`` with g the margin and ``∂F_j/∂u_S = K_jS - K_jB G K_BS``."""
        m = self.m
        Bi = self.Bidx[:m]
        s_row = self.Kt[j].copy()
        if m:
            kj = self.Kt[j, Bi]
            nz = kj.nonzero()[0]
            w = kj[nz] @ self.G[nz, :m]
            nw = w.nonzero()[0]
            s_row -= w[nw] @ self.Kt[Bi[nw], :]
        s_row[self.B] = 0.0
        sigma = 1.0 if upper else -1.0
        dg = float(value(self.dbt[j], theta)) - sigma * float(value(rate_of(self.Ft[j]), theta))
        if not dg < 0.0:
            return None
        k = s_row.nonzero()[0]
        return sigma * (s_row[k] @ self.Jt[k]) / dg

    def jacobian(self):
        """The cycle map's Jacobian d u(2π) / d u(0) (after a tracked cycle): stuck nodes carry
        their rows; slaved ones (B) follow the stuck ones through ``-G K_BS``."""
        J = self.Jt.copy()
        m = self.m
        if m:
            Bi = self.Bidx[:m]
            S = (~self.B).nonzero()[0]
            J[Bi] = -(self.G[:m, :m] @ self.Kt[np.ix_(Bi, S)]) @ self.Jt[S]
        return J
