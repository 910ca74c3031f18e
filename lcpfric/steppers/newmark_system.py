r"""Newmark's average acceleration for a :class:`~lcpfric.model.dynamic_system.DynamicSystem`:
each increment problem (P) in the metric of the effective stiffness, solved by any convex
backend; the events located inside increments; the period map with its Jacobian propagated
through the increments (issue 40, items 3 and 4).

The increment
-------------
Over an increment h from ``(x, v, a)``, Newmark's average acceleration with the equation of
motion at its end reads ``K_eff x1 + G T1 = r`` with ``K_eff = K + (2/h) C + (4/h²) M`` and
``r = f(t1) + C((2/h) x + v) + M((4/h²)(x + h v) + a)``. Eliminating x1 and the springs,
``T = D (Gᵀ x1 - w1)``, gives ``C_eff T1 = s - w1`` with ``C_eff = D⁻¹ + Gᵀ K_eff⁻¹ G`` and
``s = Gᵀ K_eff⁻¹ r``: the quasi-static increment of :mod:`lcpfric.backends.problem` with the
compliance C_eff and the slider's start ``w_ref`` (``w`` for a Jenkins contact; for a rigid
contact, ``D⁻¹ = 0``, the start ``Gᵀ(x + h v/2)``, so that Coulomb's law holds on the velocity
at the increment's end, as for the dynamic node). Problem (P) is then

    minimize ½ Tᵀ C_eff T + (w_ref - s)ᵀ T   over ||T_j|| <= mu_j N_j(t1)   (contacts pressed)

solved by the named backend (:class:`~lcpfric.backends.metric.MetricIncrements`; one d = 1
contact: a clip), and ``x1 = K_eff⁻¹ (r - G T1)``, ``w1 = s - C_eff T1``.

Events (d = 1)
--------------
Each contact is in a mode over an increment: stick, slip forward or backward, or apart. With
the modes fixed the increment is linear (:meth:`NewmarkSystem.fixed`). Where (P)'s answer ends
in other modes than the increment started in, or a slider's velocity changes sign, the
increment is split at its first event, located by Brent's method on the fixed-mode step's
length: a slider's velocity reaching 0 (a stop: a Jenkins contact sticks; a rigid contact
sticks if its stuck reaction is within its limit, else reverses) or a stuck contact's force
reaching its limit (a release, in the direction of the force). At each event the acceleration
restarts from the equation of motion in the new modes; the separation's instants are grid
points. W is the trapezoidal rule of ``Σ T·dw`` on the (sub-)increments.

The Jacobian
------------
With the modes fixed a step is affine in the state: its tangent is the same step without
forcing. An event's instant depends on the state: ``dt* = -(∂e/∂y dy + ∂e/∂t0 dt0)/(∂e/∂t*)``
(the event function e of the fixed-mode step, its time derivatives by central differences),
so the tangent across it is exact to the differences' round-off. The period map's Jacobian is
the product over the increments (:meth:`NewmarkSystem.period`).
"""

from __future__ import annotations


import numpy as np
from scipy.optimize import brentq

from ..backends.metric import MetricIncrements
from ..errors import SolverError
from .newmark_discs import Discs
from .newmark_factors import Factors
from .newmark_tangents import Tangents

__all__ = ["NewmarkSystem", "STICK", "APART"]

STICK, APART = 0, 2


class NewmarkSystem(Tangents, Discs):
    """The Newmark path of a dynamic system (module docstring; d = 2 contacts:
    :mod:`~lcpfric.steppers.newmark_discs`).

    The state is ``y = (x, v, a, w)``, columns of shape (n, p) and (n_c, p): column 0 the
    motion, the others (``forcing=False``) its tangents.

    Parameters
    ----------
    system : DynamicSystem
        The structure, its contacts and loads.
    backend : str or None
        The convex backend of the increments (None: a clip for one contact, else Clarabel).
    options : dict, optional
        The backend's options.
    """

    def __init__(self, system, backend=None, options=None):
        self.sys = system
        self.fac = Factors(system)
        self.inc = MetricIncrements(backend, system.dims, options)
        self.mu = system.friction
        self.kt = system.contact_stiffness
        self.rigid = system.rigid
        self.G = system.G
        self.nc = system.n_contacts
        self.events = 0
        self.increments = 0
        self.h_grid = None  # the grid's equal increments' length (set by the period map)
        self.b_floor = 1e-13 * self.mu * (system.normal_load + np.abs(system.normal_amplitude))

    # -- the modes' equations -----------------------------------------------------------------
    def limits(self, t):
        """mu_j N_j(t)."""
        return self.mu * self.sys.normal(t)

    def accel(self, t, y, modes, forcing=True):
        """The acceleration from the equation of motion in ``modes`` (a rigid stuck contact
        holds its relative acceleration at 0) and the contacts' forces: ``(a, T)``."""
        x, v, _, w = y
        p = x.shape[1]
        T = np.zeros((self.nc, p))
        fin = ~self.rigid
        T[fin] = self.kt[fin, None] * (self.G[:, fin].T @ x - w[fin])
        slip = (modes == 1) | (modes == -1)
        T[slip] = 0.0
        if forcing:
            T[slip, 0] = modes[slip] * self.limits(t)[slip]
        T[modes == APART] = 0.0
        held = (modes == STICK) & self.rigid
        rhs = -(self.fac.C @ v) - self.fac.K @ x - self.G[:, ~held] @ T[~held]
        if forcing:
            rhs[:, 0] += self.sys.forcing(t)
        a, TR = self.fac.constrained("mass", None, held, rhs, np.zeros((int(held.sum()), p)))
        T[held] = TR
        return a, T

    def known_side(self, t1, y, h, forcing=True):
        """``r = f(t1) + C((2/h) x + v) + M((4/h²)(x + h v) + a)``, the known side of an
        increment of length h ending at t1 (without ``forcing``: its tangent)."""
        x, v, a, _ = y
        c1, c2 = 4.0 / (h * h), 2.0 / h
        r = self.fac.C @ (c2 * x + v) + self.fac.M @ (c1 * (x + h * v) + a)
        if forcing:
            r[:, 0] += self.sys.forcing(t1)
        return r

    def pressed(self, t1):
        """The limits mu_j N_j(t1) (0 where apart, to round-off) and the contacts pressed."""
        b = self.limits(t1)
        b[b <= self.b_floor] = 0.0  # a separation instant's load, zero to round-off
        return b, np.flatnonzero(b > 0)

    def fixed(self, t0, h, y, modes, forcing=True):
        """One Newmark step of length h in fixed modes: ``(x1, v1, a1, w1, T1)``."""
        x, v, a, w = y
        t1 = t0 + h
        c1, c2 = 4.0 / (h * h), 2.0 / h
        fac = self.fac
        rhs = self.known_side(t1, y, h, forcing)
        slip = (modes == 1) | (modes == -1)
        T = np.zeros((self.nc, x.shape[1]))
        if forcing:
            T[slip, 0] = modes[slip] * self.limits(t1)[slip]
        rhs -= self.G[:, slip] @ T[slip]
        sf = (modes == STICK) & ~self.rigid
        rhs += self.G[:, sf] @ (self.kt[sf, None] * w[sf])
        held = (modes == STICK) & self.rigid
        x1, TR = fac.constrained(h, sf, held, rhs, self.G[:, held].T @ (x + 0.5 * h * v))
        T[held] = TR
        T[sf] = self.kt[sf, None] * (self.G[:, sf].T @ x1 - w[sf])
        w1 = self.G.T @ x1
        fs = slip & ~self.rigid
        w1[fs] -= T[fs] / self.kt[fs, None]
        w1[sf] = w[sf]
        return x1, c2 * (x1 - x) - v, c1 * (x1 - x - h * v) - a, w1, T

    def event_values(self, t, y1, modes):
        """The event functions after a fixed-mode step (>= 0 while the modes hold): a
        slider's velocity times its direction; a stuck contact's margin to its limit."""
        e = np.full(self.nc, np.inf)
        slip = (modes == 1) | (modes == -1)
        if slip.any():
            e[slip] = modes[slip] * self._slider_speed(t, y1[1][:, 0], slip, modes)
        st = modes == STICK
        e[st] = self.limits(t)[st] - np.abs(y1[4][st, 0])
        return e

    def _slider_speed(self, t, v, which, modes):
        wd = self.G[:, which].T @ v
        fin = ~self.rigid[which]
        if fin.any():
            idx = np.flatnonzero(which)[fin]
            wd[fin] -= modes[idx] * self.mu[idx] * self.sys.normal(t, rate=True)[idx] / self.kt[idx]
        return wd

    def event_tangent(self, y1, Y1, modes, j):
        """The linear part of event function j on the tangents ``Y1`` of a fixed-mode step."""
        if modes[j] == STICK:
            return -np.sign(y1[4][j, 0]) * Y1[4][j]
        return modes[j] * (self.G[:, j] @ Y1[1])

    # -- the increment ------------------------------------------------------------------------
    def project(self, t0, t1, y, h):
        """Problem (P) over ``[t0, t1]`` (of length h) from ``y``: ``(x1, v1, a1, w1, T1)`` and
        the end's modes."""
        x, v, a, w = y
        fac = self.fac
        c1, c2 = 4.0 / (h * h), 2.0 / h
        Z, Ceff = fac.metric(h)
        x0 = fac.solve_eff(h, self.known_side(t1, y, h))
        s = self.G.T @ x0
        wref = w.copy()
        wref[self.rigid] = self.G[:, self.rigid].T @ (x + 0.5 * h * v)
        b, A = self.pressed(t1)
        T = np.zeros((self.nc, 1))
        end = np.full(self.nc, APART)
        if A.size:
            P = Ceff[np.ix_(A, A)]
            TA, stick = self.inc.solve(
                (fac.key(h), tuple(A)), P, (wref - s)[A, 0], b[A], f"ending at t = {t1:.6g}"
            )
            T[A, 0] = TA
            if stick is None:
                stick = np.abs(TA) < b[A] * (1.0 - 1e-9)
            end[A] = np.where(stick, STICK, np.where(TA > 0, 1, -1))
        x1 = x0 - Z @ T
        w1 = s - Ceff @ T
        w1[b <= 0] = (self.G.T @ x1)[b <= 0]
        held = (end == STICK) & ~self.rigid
        w1[held] = w[held]  # a stuck slider stays where it is, exactly
        return (x1, c2 * (x1 - x) - v, c1 * (x1 - x - h * v) - a, w1, T), end

    def advance(self, t0, t1, y, T, modes, tan=None):
        """From t0 to t1, the events located: ``(y, T, modes, W, tan)``. ``tan`` is None or
        ``(Y, dt)``: the tangents of the state and of the current instant."""
        self.increments += 1
        W = 0.0
        h = t1 - t0
        if self.h_grid is not None and abs(h - self.h_grid) <= 1e-12 * self.sys.period:
            h = self.h_grid  # one length, one factorization, for the equal increments
            t1 = t0 + h
        y1, end = self.project(t0, t1, y, h)
        if np.array_equal(end, modes) and not np.any(self.event_values(t1, y1, modes) < 0):
            if tan is not None:
                tan = self._tangent_to(t0, t1, y, modes, tan, h)
            return y1[:4], y1[4], modes, self._work(y, T, y1), tan
        for k in range(16 * self.nc + 16):
            h = h if k == 0 else t1 - t0  # the grid's length until an event splits it
            if h <= 1e-13 * self.sys.period:  # the increment's end reached by an event
                return y, T, modes, W, (None if tan is None else (tan[0], np.zeros_like(tan[1])))
            y1 = self.fixed(t0, h, y, modes)
            bad = np.flatnonzero(self.event_values(t1, y1, modes) < 0)
            if bad.size == 0:
                if tan is not None:
                    tan = self._tangent_to(t0, t1, y, modes, tan, h)
                return y1[:4], y1[4], modes, W + self._work(y, T, y1), tan
            ts, j = self._first_event(t0, t1, y, modes, bad)
            self.events += 1
            if ts > t0:
                ys = self.fixed(t0, ts - t0, y, modes)
                if tan is not None:
                    tan = self._tangent_event(t0, ts, y, ys, modes, j, tan)
                W += self._work(y, T, ys)
                y = ys[:4]
            modes = self._switch(ts, y, modes, j)
            a, T = self.accel(ts, y, modes)
            if tan is not None:
                tan = self._tangent_restart(ts, y, modes, tan)
            y = (y[0], y[1], a, y[3])
            t0 = ts
        raise SolverError(
            f"newmark: the events of the increment ending at t = {t1:.6g} did not settle",
            backend="newmark",
            status="events",
        )

    @staticmethod
    def _work(y, T, y1):
        """The trapezoid of ``Σ T·dw`` over a (sub-)increment."""
        return float(np.sum(0.5 * (T[:, 0] + y1[4][:, 0]) * (y1[3][:, 0] - y[3][:, 0])))

    def _first_event(self, t0, t1, y, modes, bad):
        """The first event among the contacts ``bad`` (violated at t1): ``(instant, j)``."""
        best = (t1, int(bad[0]))
        h = t1 - t0
        for j in bad:

            def g(t, j=j):
                if t <= t0:
                    if modes[j] == STICK:
                        return 0.0
                    sel = np.zeros(self.nc, dtype=bool)
                    sel[j] = True
                    return float(modes[j] * self._slider_speed(t0, y[1][:, 0], sel, modes)[0])
                return self.event_values(t, self.fixed(t0, t - t0, y, modes), modes)[j]

            lo = t0
            if g(lo) <= 0.0:  # from rest (or at the limit): the first length the mode holds
                lo = t0 + 0.5 * h
                while lo - t0 > 1e-12 * h and g(lo) <= 0.0:
                    lo = t0 + 0.5 * (lo - t0)
                if g(lo) <= 0.0:
                    return t0, int(j)
            ts = brentq(g, lo, t1, xtol=1e-15 * self.sys.period, rtol=4 * np.finfo(float).eps)
            if ts < best[0]:
                best = (ts, int(j))
        return best

    def _switch(self, t, y, modes, j):
        """The modes after contact j's event at t."""
        modes = modes.copy()
        if modes[j] == STICK:  # a release, in the direction of the force
            _, T = self.accel(t, y, modes)
            modes[j] = 1 if T[j, 0] > 0 else -1
            return modes
        if not self.rigid[j]:  # a Jenkins slider stops: it sticks
            modes[j] = STICK
            return modes
        trial = modes.copy()
        trial[j] = STICK
        _, T = self.accel(t, y, trial)
        if abs(T[j, 0]) <= self.limits(t)[j]:
            return trial
        modes[j] = 1 if T[j, 0] > 0 else -1  # a reversal
        return modes

    def start(self, t, y):
        """The modes at t of a state (a Jenkins force beyond its limit is brought to it) and
        the state with its acceleration: ``(y, T, modes, projected)``."""
        x, v, _, w = y
        w = w.copy()
        b = self.limits(t)
        modes = np.full(self.nc, STICK)
        projected = np.zeros(self.nc, dtype=bool)
        gv = self.G.T @ v[:, :1]
        gx = self.G.T @ x[:, :1]
        for j in range(self.nc):
            if b[j] <= 0:
                modes[j] = APART
                w[j] = gx[j]
            elif not self.rigid[j]:
                Tj = self.kt[j] * (gx[j, 0] - w[j, 0])
                if abs(Tj) >= b[j]:
                    modes[j] = 1 if Tj > 0 else -1
                    w[j] = gx[j] - modes[j] * b[j] / self.kt[j]
                    projected[j] = True
            elif abs(gv[j, 0]) > 1e-13 * max(1.0, float(np.max(np.abs(v[:, 0])))):
                modes[j] = 1 if gv[j, 0] > 0 else -1
        y = (x, v, None, w)
        for j in np.flatnonzero((modes == STICK) & self.rigid):
            _, T = self.accel(t, y, modes)
            if abs(T[j, 0]) > b[j]:
                modes[j] = 1 if T[j, 0] > 0 else -1
        a, T = self.accel(t, y, modes)
        return (x, v, a, w), T, modes, projected
