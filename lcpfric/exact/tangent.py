"""The exact solver's tangent map: the cycle map's Jacobian ``d u(2π) / d u(0)`` propagated along
a tracked cycle (:mod:`lcpfric.exact.discrete`, "Cycles")."""

from __future__ import annotations

import numpy as np


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
        reaching its limit at theta (then that angle's own sensitivity, computed at the event:
        :func:`lcpfric.exact.kernels.theta_sensitivity`)."""
        lin, tri, _flg, tan, wk = self.bundles()
        self.kernels.tangent_stick(j, theta, lin, tri, tan, wk, self.ints, self.fl)

    def resolve_trow(self):
        """Complete a pending event-angle sensitivity before the tangent's rows change outside
        the kernels (:func:`lcpfric.exact.kernels.resolve_trow`)."""
        if self.Jt is not None:
            self.kernels.resolve_trow(self.bundles()[3], self.ints, self.fl)

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
