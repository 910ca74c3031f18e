"""The period map of :mod:`lcpfric.steppers.newmark_system` and its Jacobian, propagated
through the increments (a mixin of :class:`~lcpfric.steppers.newmark_system.NewmarkSystem`).

The unknowns of the period map are ``z = (x, x', w_J)`` at t = 0 (w_J: the Jenkins sliders; a
rigid contact's slider is its relative displacement). Its tangent is carried through every
fixed-mode step (the step without forcing), across every event with the event instant's
sensitivity and across the acceleration's restarts; the partial derivatives in time are
central differences of the steps themselves.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Tangents", "grid"]

_DT = 1e-6  # the time differences, as a share of the period


def grid(system, steps: int) -> np.ndarray:
    """The increments' instants over a period: ``steps`` equal ones and the separations'."""
    t = np.linspace(0.0, system.period, steps + 1)
    sep = system.separation_instants()
    if sep.size:
        t = np.unique(np.concatenate([t, sep]))
        keep = np.concatenate([[True], np.diff(t) > 1e-9 * system.period])
        t = t[keep]
        t[-1] = system.period
    return t


def _outer(col, row):
    return col[:, :1] * row[None, :]


class Tangents:
    """The tangents and the period map (module docstring)."""

    def _delta(self, room: float) -> float:
        return min(_DT * self.sys.period, 0.25 * room) if room > 0 else _DT * self.sys.period

    def _step_rate(self, t0, t1, y, modes, which, d):
        """``∂(step)/∂t1`` (``which=1``) or ``∂(step)/∂t0`` (``which=0``) by differences."""
        if which == 1:
            plus = self.fixed(t0, t1 + d - t0, y, modes)
            minus = self.fixed(t0, t1 - d - t0, y, modes)
        else:
            plus = self.fixed(t0 + d, t1 - t0 - d, y, modes)
            minus = self.fixed(t0 - d, t1 - t0 + d, y, modes)
        return [(p - m) / (2 * d) for p, m in zip(plus, minus)], plus, minus

    def _tangent_to(self, t0, t1, y, modes, tan, h):
        """The tangent after a fixed-mode step of length h to the grid instant t1 (fixed)."""
        Y, dt = tan
        Y1 = list(self.fixed(t0, h, Y, modes, forcing=False))
        if np.any(dt):
            rate, _, _ = self._step_rate(t0, t1, y, modes, 0, self._delta(0.5 * (t1 - t0)))
            Y1 = [Yk + _outer(rk, dt) for Yk, rk in zip(Y1, rate)]
        return tuple(Y1[:4]), np.zeros_like(dt)

    def _tangent_event(self, t0, ts, y, ys, modes, j, tan):
        """The tangent at the event of contact j at ts (its instant depends on the state)."""
        Y, dt = tan
        Yl = list(self.fixed(t0, ts - t0, Y, modes, forcing=False))
        elin = self.event_tangent(ys, Yl, modes, j)
        d = self._delta(0.5 * (ts - t0))
        r1, p1, m1 = self._step_rate(t0, ts, y, modes, 1, d)
        e_t1 = (self.event_values(ts + d, p1, modes)[j]
                - self.event_values(ts - d, m1, modes)[j]) / (2 * d)  # fmt: skip
        num = elin
        if np.any(dt):
            r0, p0, m0 = self._step_rate(t0, ts, y, modes, 0, d)
            e_t0 = (self.event_values(ts, p0, modes)[j]
                    - self.event_values(ts, m0, modes)[j]) / (2 * d)  # fmt: skip
            num = num + e_t0 * dt
            Yl = [Yk + _outer(rk, dt) for Yk, rk in zip(Yl, r0)]
        dts = -num / e_t1 if e_t1 != 0 else np.zeros_like(num)
        Ys = [Yk + _outer(rk, dts) for Yk, rk in zip(Yl, r1)]
        return tuple(Ys[:4]), dts

    def _tangent_restart(self, ts, y, modes, tan):
        """The tangent after the acceleration's restart at ts in ``modes``."""
        Y, dt = tan
        A, _ = self.accel(ts, Y, modes, forcing=False)
        if np.any(dt):
            d = _DT * self.sys.period
            rate = (self.accel(ts + d, y, modes)[0] - self.accel(ts - d, y, modes)[0]) / (2 * d)
            A = A + _outer(rate, dt)
        return (Y[0], Y[1], A, Y[3]), dt

    # -- the period map -----------------------------------------------------------------------
    def unknowns(self):
        """The size of z = (x, x', w_J)."""
        return 2 * self.sys.n + self.sys.dims * int((~self.rigid).sum())

    def period(self, z, steps, jacobian=False, record=False):
        """One period from z at t = 0: ``(z1, W, J, records)`` (J None without ``jacobian``;
        records: the grid, and per instant x, x', w, T and the modes)."""
        if self.sys.dims == 2:
            return self._period_discs(z, steps, jacobian, record)
        sys_, G, fin = self.sys, self.G, ~self.rigid
        n = sys_.n
        z = np.asarray(z, dtype=float)
        x, v = z[:n, None].copy(), z[n : 2 * n, None].copy()
        w = G.T @ x
        w[fin] = z[2 * n :, None]
        y, T, modes, projected = self.start(0.0, (x, v, None, w))
        tan = None
        if jacobian:
            p = z.size
            X, V = np.zeros((n, p)), np.zeros((n, p))
            X[:, :n] = np.eye(n)
            V[:, n : 2 * n] = np.eye(n)
            Wt = G.T @ X
            Wt[fin] = 0.0
            Wt[np.flatnonzero(fin), 2 * n + np.arange(int(fin.sum()))] = 1.0
            Wt[fin] = np.where(projected[fin, None], (G.T @ X)[fin], Wt[fin])
            A, _ = self.accel(0.0, (X, V, None, Wt), modes, forcing=False)
            tan = ((X, V, A, Wt), np.zeros(p))
        t = grid(sys_, steps)
        self.h_grid = sys_.period / steps
        W = 0.0
        rec = [(y, T, modes)] if record else None
        for k in range(t.size - 1):
            t0, t1 = t[k], t[k + 1]
            y, T, modes, tan = self._contact_changes(t0, t1, y, T, modes, tan)
            y, T, modes, dW, tan = self.advance(t0, t1, y, T, modes, tan)
            W += dW
            if record:
                rec.append((y, T, modes))
        z1 = np.concatenate([y[0][:, 0], y[1][:, 0], y[3][fin, 0]])
        J = None if tan is None else np.vstack([tan[0][0], tan[0][1], tan[0][3][fin]])
        return z1, W, J, (t, rec)

    def _contact_changes(self, t0, t1, y, T, modes, tan):
        """Contacts that come apart or back at the grid instant t0 (the increment's middle
        decides), and the acceleration's restart."""
        apart = self.sys.normal(0.5 * (t0 + t1)) <= 0
        new = modes.copy()
        new[apart] = APART_MODE
        back = ~apart & (modes == APART_MODE)
        if back.any():
            gv = self.G.T @ y[1][:, 0]
            for j in np.flatnonzero(back):
                new[j] = 0  # stick; a rigid contact in motion slips with its velocity
                if self.rigid[j] and gv[j] != 0.0:
                    new[j] = 1 if gv[j] > 0 else -1
        if np.array_equal(new, modes):
            return y, T, modes, tan
        a, T = self.accel(t0, y, new)
        if tan is not None:
            tan = self._tangent_restart(t0, y, new, tan)
        return (y[0], y[1], a, y[3]), T, new, tan


APART_MODE = 2
