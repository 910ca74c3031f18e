"""d = 2 Jenkins contacts in :mod:`lcpfric.steppers.newmark_system` (a mixin): each increment
problem (P) on the discs ``||T_j|| <= mu_j N_j`` by a conic backend (Clarabel or cvxpy), the
period map, and its Jacobian by central differences.

The events of a disc (a stop is a rotation of the slip direction, not a sign change) are not
located: where a contact changes between stick and slip inside an increment the step is that of
problem (P) at the increment's end, and the order of W is measured, not assumed
(``benchmarks/results/newmark-system.md``). A rigid d = 2 contact is refused (its stuck
reaction would need the mode logic of the d = 1 stepper).
"""

from __future__ import annotations

import numpy as np

from ..backends.problem import set_dofs
from ..errors import InputError

__all__ = ["Discs"]

_FD = 1e-6  # the central differences' step, relative to the state's size


class Discs:
    """The d = 2 period map (module docstring)."""

    def check_discs(self):
        """Refuse rigid d = 2 contacts, naming the way out."""
        if self.rigid.any():
            raise InputError(
                "contact_stiffness",
                "'newmark' steps d = 2 contacts with a finite contact_stiffness (Jenkins "
                "elements); a rigid d = 2 contact is not supported",
            )

    def _forces2(self, x, w, t):
        G = self.G
        T = np.repeat(self.kt, 2)[:, None] * (G.T @ x - w)
        apart = np.repeat(self.limits(t) <= self.b_floor, 2)
        T[apart] = 0.0
        return T

    def _accel2(self, t, x, v, w):
        fac = self.fac
        rhs = -(fac.C @ v) - fac.K @ x - self.G @ self._forces2(x, w, t)
        rhs[:, 0] += self.sys.forcing(t)
        return fac.constrained("mass", None, np.zeros(self.G.shape[1], dtype=bool), rhs,
                               np.zeros((0, 1)))[0]  # fmt: skip

    def _project2(self, t1, y, h):
        """Problem (P) on the discs over an increment h ending at t1."""
        x, v, a, w = y
        fac = self.fac
        c1, c2 = 4.0 / (h * h), 2.0 / h
        Z, Ceff = fac.metric(h)
        x0 = fac.solve_eff(h, self.known_side(t1, y, h))
        s = self.G.T @ x0
        b, A = self.pressed(t1)
        T = np.zeros((self.G.shape[1], 1))
        if A.size:
            dofs = set_dofs(A, 2)
            TA, _ = self.inc.solve((fac.key(h), tuple(A)), Ceff[np.ix_(dofs, dofs)],
                                   (w - s)[dofs, 0], b[A], f"ending at t = {t1:.6g}")  # fmt: skip
            T[dofs, 0] = TA
        x1 = x0 - Z @ T
        w1 = s - Ceff @ T
        apart = np.repeat(b <= 0, 2)
        w1[apart] = (self.G.T @ x1)[apart]
        return (x1, c2 * (x1 - x) - v, c1 * (x1 - x - h * v) - a, w1), T

    def _period_discs(self, z, steps, jacobian=False, record=False):
        """One period of d = 2 contacts: ``(z1, W, J, records)`` (as :meth:`period`)."""
        from .newmark_tangents import grid

        n, t = self.sys.n, grid(self.sys, steps)
        self.h_grid = self.sys.period / steps
        z = np.asarray(z, dtype=float)
        x, v = z[:n, None].copy(), z[n : 2 * n, None].copy()
        w = z[2 * n :, None].copy()
        b = np.repeat(self.limits(0.0), 2)
        T = self._forces2(x, w, 0.0)
        mag = np.repeat(np.hypot(T[0::2, 0], T[1::2, 0]), 2)
        over = mag > b
        w[over] = (self.G.T @ x)[over] - T[over] * (b[over] / mag[over])[:, None] / \
            np.repeat(self.kt, 2)[over, None]  # fmt: skip
        apart = np.zeros(w.size, dtype=bool)
        T = self._forces2(x, w, 0.0)
        y = (x, v, self._accel2(0.0, x, v, w), w)
        W = 0.0
        rec = [(y, T, None)] if record else None
        for k in range(t.size - 1):
            t0, t1 = t[k], t[k + 1]
            now = np.repeat(self.sys.normal(0.5 * (t0 + t1)) <= 0, 2)
            if not np.array_equal(now, apart):  # apart or back at t0: sliders follow, a restarts
                apart = now
                w = y[3].copy()
                w[apart] = (self.G.T @ y[0])[apart]
                T = self._forces2(y[0], w, t0)
                y = (y[0], y[1], self._accel2(t0, y[0], y[1], w), w)
            h = t1 - t0
            if abs(h - self.h_grid) <= 1e-12 * self.sys.period:
                h = self.h_grid
            self.increments += 1
            y1, T1 = self._project2(t0 + h, y, h)
            W += float(np.sum(0.5 * (T[:, 0] + T1[:, 0]) * (y1[3][:, 0] - y[3][:, 0])))
            y, T = y1, T1
            if record:
                rec.append((y, T, None))
        z1 = np.concatenate([y[0][:, 0], y[1][:, 0], y[3][:, 0]])
        J = None
        if jacobian:
            scale = max(float(np.max(np.abs(z))), 1e-300)
            J = np.empty((z.size, z.size))
            for j in range(z.size):
                e = np.zeros(z.size)
                e[j] = _FD * scale
                J[:, j] = (self._period_discs(z + e, steps)[0]
                           - self._period_discs(z - e, steps)[0]) / (2 * e[j])  # fmt: skip
        return z1, W, J, (t, rec)
