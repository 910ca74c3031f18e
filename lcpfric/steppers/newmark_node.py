r"""Time stepping with inertia for the dynamic single node (issue 40, item 3, for the node):
Newmark's average acceleration, its increment the maximum-dissipation projection in the metric
of the effective stiffness, the events located inside increments; the periodic orbit by
shooting (method ``"newmark"``).

In the node's normalized units (:mod:`lcpfric.exact.dynamic`) the equation is
``β² u'' + 2ζβ u' + u = F - q(θ)``. Newmark's average acceleration over an increment h,
``u1 = u + h v + h²/4 (a + a1)``, ``v1 = v + h/2 (a + a1)``, with the equation at its end gives
``F1 = K_eff u1 - R`` with ``K_eff = 4β²/h² + 4ζβ/h + 1`` and R from the known state and
``q(θ1)``; since ``v1 = (2/h)(u1 - ũ)`` with ``ũ = u + h v / 2``, Coulomb's law on the
velocity at the increment's end is problem (P) of the quasi-static steppers from the start ũ:
the trial force ``F_tr = K_eff ũ - R`` projected on ``[-n1, n1]`` (in closed form for one node:
no solver where a closed form serves). ``|F_tr| <= n1``: stick (``u1 = ũ``, ``v1 = 0``); else
slip with ``F1 = sign(F_tr) n1``.

**Events inside increments.** With the mode of the increment's start fixed the step is linear;
where its end contradicts the mode the increment is split at the event: a slip whose velocity
changes sign is cut where the fixed-mode step's velocity vanishes (Brent's method on the step
length), and the stop decides stick (``|u + q| <= n``) or a reversal; a stick whose force
reaches the limit (scanned on 16 sub-points, refined by Brent) releases there into slip from
rest; the separation's instants are grid points. At each event the acceleration restarts from
the equation of motion in the new mode, so that the scheme stays second order (measured:
:mod:`tests.test_newmark_node`, ``benchmarks/validation/newmark_node.py``). W is the trapezoidal
rule of ``-F du`` on the (sub-)increments.

**Shooting.** The period map of ``(u, u')`` at θ = 0 is solved by Newton's method with its
Jacobian by central differences (two periods per column), after two periods of motion; where
a Newton step does not lower the residual, a period of motion is taken instead. The orbit is
periodic to ``max(1e-12, 256 eps · steps)`` of the loads' scale (the period map's own round-off
grows with its increments).
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.optimize import brentq

from .. import _checks
from ..errors import InputError, SolverError
from ..results import DynamicExtras, State, SteadyState

__all__ = ["NewmarkNode", "NewmarkPath"]

TWO_PI = 2.0 * math.pi
STICK, SEPARATION = 0, 2


class NewmarkPath:
    """Newmark's average acceleration for the normalized node (module docstring).

    Parameters
    ----------
    P1, Q1, phi, beta, zeta : float
        The normalized node (β > 0).
    """

    def __init__(self, P1, Q1, phi, beta, zeta):
        self.P1, self.Q1, self.phi = float(P1), float(Q1), float(phi)
        self.b2, self.d = beta * beta, 2.0 * zeta * beta
        self.sep = None
        if self.P1 > 1.0:
            g = math.asin(1.0 / self.P1)
            self.sep = (math.pi + g, TWO_PI - g)

    def q(self, t):
        return self.Q1 * math.sin(t + self.phi)

    def n(self, t):
        return 1.0 + self.P1 * math.sin(t)

    def accel(self, t, u, v, F):
        return (F - self.q(t) - self.d * v - u) / self.b2

    def fixed(self, t0, u, v, a, h, mode):
        """One Newmark step of length h with the mode fixed: ``(u1, v1, a1, F1)``."""
        c1, c2 = 4.0 / (h * h), 2.0 / h
        K = self.b2 * c1 + self.d * c2 + 1.0
        R = -self.q(t0 + h) + self.b2 * (c1 * u + 2.0 * c2 * v + a) + self.d * (c2 * u + v)
        if mode == STICK:
            u1 = u + 0.5 * h * v
            F1 = K * u1 - R
        else:
            F1 = 0.0 if mode == SEPARATION else -mode * self.n(t0 + h)
            u1 = (F1 + R) / K
        return u1, c2 * (u1 - u) - v, c1 * (u1 - u) - 2.0 * c2 * v - a, F1

    def grid(self, steps):
        """The increments' instants: ``steps`` equal ones and the separation's ends."""
        t = np.linspace(0.0, TWO_PI, steps + 1)
        if self.sep is not None:
            t = np.unique(np.concatenate([t, self.sep]))
        return t

    def start_mode(self, t, u, v):
        if self.sep is not None and self.sep[0] < t < self.sep[1]:
            return SEPARATION
        if v != 0.0:
            return 1 if v > 0 else -1
        F = u + self.q(t)
        return STICK if abs(F) <= self.n(t) else (-1 if F > 0 else 1)

    def force(self, t, u, mode):
        if mode == STICK:
            return u + self.q(t)
        return 0.0 if mode == SEPARATION else -mode * self.n(t)

    def advance(self, t0, t1, u, v, a, F, mode):
        """From t0 to t1 (events inside located): ``(u, v, a, F, mode, W)``."""
        W = 0.0
        for _ in range(64):
            h = t1 - t0
            if h <= 1e-15 * TWO_PI:
                break
            if mode == SEPARATION:
                u1, v1, a1, F1 = self.fixed(t0, u, v, a, h, SEPARATION)
                return u1, v1, a1, F1, mode, W
            if mode == STICK:
                ts = np.linspace(t0, t1, 17)
                g = [abs(u + self.q(t)) - self.n(t) for t in ts]
                over = [i for i in range(1, 17) if g[i] > 0.0]
                if not over:
                    return u, 0.0, 0.0, u + self.q(t1), STICK, W
                k = over[0]
                tr = brentq(lambda t: abs(u + self.q(t)) - self.n(t), ts[k - 1], ts[k],
                            xtol=1e-15)  # fmt: skip
                mode = -1 if u + self.q(tr) > 0 else 1
                F = -mode * self.n(tr)
                t0, v, a = tr, 0.0, self.accel(tr, u, 0.0, F)
                continue
            s = mode
            u1, v1, a1, F1 = self.fixed(t0, u, v, a, h, s)
            if s * v1 > 0.0:
                return u1, v1, a1, F1, mode, W - 0.5 * (F + F1) * (u1 - u)

            def speed(tau, s=s, t0=t0, u=u, v=v, a=a):
                return s * v if tau == 0.0 else s * self.fixed(t0, u, v, a, tau, s)[1]

            lo = 0.0
            if s * v <= 0.0:  # from rest: the first length at which it moves
                lo = h
                while lo > 1e-12 * h and speed(lo) <= 0.0:
                    lo *= 0.5
                lo = lo if (speed(lo) > 0.0 and lo < h) else None
            if lo is None:  # no motion: it stops at once
                tau, us = 0.0, u
            else:
                tau = brentq(speed, lo, h, xtol=1e-15)
                us, _, _, Fs = self.fixed(t0, u, v, a, tau, s)
                W -= 0.5 * (F + Fs) * (us - u)
            t0, u, v = t0 + tau, us, 0.0
            Fst = u + self.q(t0)
            if abs(Fst) <= self.n(t0):
                mode, F, a = STICK, Fst, 0.0
            else:  # a reversal
                mode = -1 if Fst > 0 else 1
                F = -mode * self.n(t0)
                a = self.accel(t0, u, 0.0, F)
        return u, v, a, F, mode, W

    def period(self, z, steps, record=False):
        """One period from ``z = (u, u')`` at θ = 0: ``(z_end, W, records)``."""
        t = self.grid(steps)
        u, v = float(z[0]), float(z[1])
        mode = self.start_mode(0.0, u, v)
        if mode == STICK:
            v = 0.0
        F = self.force(0.0, u, mode)
        a = 0.0 if mode == STICK else self.accel(0.0, u, v, F)
        W = 0.0
        rec = [(u, v, F, mode)] if record else None
        for k in range(t.size - 1):
            t0, t1 = t[k], t[k + 1]
            inside = self.sep is not None and self.sep[0] - 1e-13 <= t0 < self.sep[1] - 1e-13
            if inside and mode != SEPARATION:
                mode, F = SEPARATION, 0.0
                a = self.accel(t0, u, v, 0.0)
            elif not inside and mode == SEPARATION:  # re-contact at t0
                mode = 1 if v > 0 else (-1 if v < 0 else self.start_mode(t0, u, 0.0))
                F = self.force(t0, u, mode)
                a = self.accel(t0, u, v, F)
            u, v, a, F, mode, dW = self.advance(t0, t1, u, v, a, F, mode)
            W += dW
            if record:
                rec.append((u, v, F, mode))
        return np.array([u, v]), W, (t, rec)


class NewmarkNode:
    """The ``newmark`` method: the dynamic single node by Newmark's average acceleration with
    events located and shooting (module docstring); a
    :class:`~lcpfric.model.dynamic_system.DynamicSystem` by
    :func:`~lcpfric.periodic.newmark_steady.system_steady_state` (the driver calls it).
    Quasi-static models are refused.

    Parameters
    ----------
    backend : str, optional
        A DynamicSystem's convex backend for its increments (``"clarabel"``, ``"osqp"``,
        ``"qpsolvers:<solver>"``, ``"cvxpy"``; default: a clip for one contact, else
        ``"clarabel"``). The node's increment is always its closed form.
    **options
        The backend's options (tolerances, solver settings).
    """

    name = "newmark"
    label = "newmark"
    kind = "time-stepper"
    cycle_measure = "cycles"

    def __init__(self, backend=None, **options):
        if backend is not None and not isinstance(backend, str):
            raise InputError("backend", f"a backend's registry name, got {backend!r}")
        self.backend = backend
        self.options = options

    def check(self, scene):
        """Refuse every scene: ``newmark`` solves a node with a mass, through
        :meth:`steady_state` (the driver calls it for a dynamic node)."""
        raise InputError(
            "method",
            "'newmark' solves a SingleNode with a mass (the dynamic node); for quasi-static "
            "models use 'exact', 'explicit', 'projection' or a convex backend",
        )

    def cycle(self, scene, state, history=True):  # pragma: no cover - refused by check
        """Not used: the dynamic node goes through :meth:`steady_state`."""
        self.check(scene)

    def steady_state(self, model, steps_per_cycle=2000, max_cycles=100, u0=None) -> SteadyState:
        """The periodic steady state of a dynamic :class:`~lcpfric.model.SingleNode` by
        shooting on the Newmark period map; ``u0``: ``v0`` or ``(v0, dv/dt)`` (the first
        guess; default rest); ``max_cycles`` caps the periods of motion."""
        start = time.perf_counter()
        if self.backend is not None or self.options:
            raise InputError(
                "backend",
                "the dynamic node's increment is a closed form (no backend); to step it with a "
                "backend, give DynamicSystem.from_node(node)",
            )
        if not getattr(model, "is_dynamic", False) or not model.is_harmonic:
            raise InputError(
                "method",
                "'newmark' solves a SingleNode with a mass under harmonic loads",
            )
        steps = _checks.positive_int("steps_per_cycle", steps_per_cycle, 4)
        P1, Q1, phi = model.normalized_parameters()
        fp0, k, w = model.force_unit, model.k11, model.omega
        path = NewmarkPath(P1, Q1, phi, model.beta, model.zeta)
        z = np.zeros(2)
        if u0 is not None:
            z0 = np.atleast_1d(np.asarray(u0, dtype=float)).ravel()
            if z0.size not in (1, 2) or not np.all(np.isfinite(z0)):
                raise InputError("u0", "a node with a mass starts from v0 or (v0, dv/dt): finite")
            z = np.array([(k * z0[0] + model.Q0) / fp0, k * (z0[1] if z0.size == 2 else 0.0)
                          / (fp0 * w)])  # fmt: skip
        z, jac, res, its, periods, converged = _shoot(path, z, steps, max_cycles)
        if not converged:
            raise SolverError(
                f"newmark: the periodic orbit not found by shooting (|Φ(z) - z| = {res:.3g} "
                f"after {its} Newton iterations, {periods} periods)",
                backend="newmark",
                status="shooting",
            )
        z_end, W, (theta, rec) = path.period(z, steps, record=True)
        u, du, F, mode = (np.array(x) for x in zip(*rec))
        n = np.maximum(1.0 + P1 * np.sin(theta), 0.0)
        states = np.select(
            [mode == STICK, mode == SEPARATION, mode == 1],
            [State.STICK, State.SEPARATION, State.FORWARD],
            State.BACKWARD,
        ).astype(np.int8)
        v, Fm, N = model.series(u, F, n)
        mult = np.linalg.eigvals(jac)
        W_hat = W / Q1 if Q1 > 0 else 0.0
        amp = 0.5 * float(v.max() - v.min())
        extras = DynamicExtras(
            beta=model.beta,
            zeta=model.zeta,
            amplitude=amp,
            velocity=du * fp0 * w / k,
            floquet=mult,
            stable=bool(np.all(np.abs(mult) < 1.0 - 1e-9)),
            orbits=(
                {
                    "W": float(model.W(W_hat)),
                    "amplitude": amp,
                    "stable": None,
                    "start": "given" if u0 is not None else "rest",
                },
            ),  # fmt: skip
            newton_iterations=its,
            periods=periods,
        )
        return SteadyState(
            W=float(model.W(W_hat)),
            W_cycles=np.atleast_1d(model.W(W_hat)),
            cycles=periods,
            converged=converged,
            method=self.name,
            steps_requested=steps,
            steps_used=int(theta.size - 1),
            t=theta / w,
            v=v,
            F=Fm,
            N=N,
            state=states,
            seconds=time.perf_counter() - start,
            change=res,
            message=f"newmark (average acceleration, events located): periodic orbit by shooting "
            f"in {its} Newton iterations, {periods} periods",
            normalization=model.normalization(),
            W_hat_cycles=np.array([W_hat]),
            dynamics=extras,
        )


def _shoot(path, z, steps, max_cycles, tol=1e-12):
    """Newton's method on the period map (central-difference Jacobian): ``(z, J, residual,
    iterations, periods, converged)``."""
    periods = 0
    for _ in range(2):
        z = path.period(z, steps)[0]
        periods += 1
    # the period map holds its own round-off, about eps per increment: the tolerance follows it
    scale = max(1.0, path.Q1) * max(1.0, 256 * np.finfo(float).eps * steps / tol)
    jac = np.eye(2)
    res = math.inf
    for it in range(1, max_cycles + 1):
        z1 = path.period(z, steps)[0]
        periods += 1
        r = z1 - z
        res = float(np.max(np.abs(r)))
        cols = []
        for j in range(2):
            e = np.zeros(2)
            e[j] = 1e-7 * max(1.0, abs(z[j]))
            cols.append((path.period(z + e, steps)[0] - path.period(z - e, steps)[0]) / (2 * e[j]))
            periods += 2
        jac = np.column_stack(cols)
        if res <= tol * scale:
            return z, jac, res, it, periods, True
        try:
            trial = z - np.linalg.solve(jac - np.eye(2), r)
        except np.linalg.LinAlgError:
            trial = z1
        tr = path.period(trial, steps)[0]
        periods += 1
        z = trial if float(np.max(np.abs(tr - trial))) < res else z1
        if periods >= 20 * max_cycles:
            break
    return z, jac, res, it, periods, False
