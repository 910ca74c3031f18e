"""The dynamic single node's steady state for the driver (``steady_state(node, "exact")`` on a
node with a mass) and :func:`dynamic_cycle` on the normalized parameters.

The periodic orbit is sought from several starts (:func:`dynamic_cycle`): rest, the
frictionless linear response, and the caller's; orbits of different dissipation or amplitude
are all reported, and more than one raises a
:class:`~lcpfric.errors.MultipleSteadyStates` warning: lcpfric never picks one silently. The
result is the orbit reached from the caller's start, or else from the first start (rest).
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from .. import _checks
from ..errors import MultipleSteadyStates
from ..results import DynamicExtras, SteadyState
from .dynamic import DynamicNode, DynamicOrbit, period_map, periodic_orbit

__all__ = ["dynamic_cycle", "dynamic_steady_state", "DynamicCycle"]


class DynamicCycle:
    """The steady cycle of the normalized dynamic node (:func:`dynamic_cycle`).

    Attributes
    ----------
    W_hat : float
        Ŵ = J / Q̂1 (0 where Q̂1 = 0).
    orbit : DynamicOrbit
        The orbit chosen (:mod:`lcpfric.exact.dynamic`).
    orbits : list of (DynamicOrbit, str)
        Every distinct orbit found, with the start it came from.
    """

    def __init__(self, node, orbit, orbits):
        self.node, self.orbit, self.orbits = node, orbit, orbits
        self.W_hat = orbit.J / node.Q1 if node.Q1 > 0 else 0.0
        self._run = None

    def verify(self, samples: int = 2048) -> float:
        """Check the orbit over its cycle: every constraint at ``samples`` instants (a stuck
        force within the limit, a slip along its force, no force in separation, no contact
        force where N < 0) to 1e-9 of the loads' scale; return the largest violation.

        Raises
        ------
        SolverError
            A violation (status ``"verification"``): a wrong answer is never returned.
        """
        from ..errors import SolverError

        node = self.node
        theta = np.linspace(0.0, 2.0 * np.pi, samples, endpoint=False)
        u, du, F, st = self.sample(theta)
        n = node.n(theta)
        vscale = max(1e-300, float(np.max(np.abs(du), initial=0.0)))
        fscale = 1.0 + node.Q1 + node.P1
        over = np.zeros(theta.size)
        stick, fwd, bwd, sep = st == 0, st == 1, st == 2, st == 3
        over[stick] = np.maximum(np.abs(F[stick]) - n[stick], 0.0) / fscale
        over[fwd] = np.maximum(-du[fwd], 0.0) / vscale
        over[bwd] = np.maximum(du[bwd], 0.0) / vscale
        over[sep] = np.maximum(n[sep], 0.0) / fscale
        contact = ~sep
        over[contact] = np.maximum(over[contact], np.maximum(-n[contact], 0.0) / fscale)
        worst = float(over.max(initial=0.0))
        if worst > 1e-9:
            k = int(np.argmax(over))
            raise SolverError(
                f"dynamic single node: the orbit violates a constraint by {worst:.3g} (relative) "
                f"at θ = {theta[k]:.6g} (state {int(st[k])})",
                backend="exact",
                status="verification",
            )
        self.violation = worst
        return worst

    def sample(self, theta):
        """``(u, u', F, state)`` at the angles θ in [0, 2π] of the cycle."""
        from . import dynamic_kernels as kern

        if self._run is None:
            self._run = period_map(self.node, self.orbit.z)
        theta = np.ascontiguousarray(theta, dtype=float)
        out = np.empty((4, theta.size))
        segs = self._run.segments
        kern.sample(self.node.params, segs, segs.shape[0], theta, out)
        return out[0], out[1], out[2], out[3].astype(np.int8)


def dynamic_cycle(P1, Q1, phi, beta, zeta, *, start=None) -> DynamicCycle:
    """The exact steady cycle of the normalized dynamic node (module docstring).

    Parameters
    ----------
    P1, Q1, phi : float
        P̂1 >= 0, Q̂1 >= 0, φ.
    beta, zeta : float
        β > 0, ζ >= 0 (not ζ = 0 at β = 1).
    start : tuple of float, optional
        ``(u, u')`` at θ = 0 in the normalized units: its orbit is the one returned.

    Returns
    -------
    DynamicCycle
        Ŵ, the orbit and every orbit found.

    Raises
    ------
    InputError
        A parameter out of range.
    SolverError
        Newton's method on the period map failed from every start.
    """
    P1 = _checks.nonnegative("P1", P1)
    Q1 = _checks.nonnegative("Q1", Q1)
    phi = _checks.finite("phi", phi)
    beta = _checks.positive("beta", beta)
    zeta = _checks.nonnegative("zeta", zeta)
    node = DynamicNode(P1, Q1, phi, beta, zeta)
    from . import dynamic_kernels as kern  # numba: compiled on first use

    starts = [("rest", (0.0, 0.0)), ("linear response", kern.linear_response(node.params))]
    if start is not None:
        starts.insert(0, ("given", tuple(float(x) for x in start)))
    found: list[tuple[DynamicOrbit, str]] = []
    error = None
    for name, z in starts:
        try:
            orb = periodic_orbit(node, z)
        except Exception as exc:  # SolverError from one start: the others may succeed
            error = exc
            continue
        scale = max(1.0, abs(orb.J), orb.amplitude)
        if not any(
            abs(o.J - orb.J) <= 1e-8 * scale and abs(o.amplitude - orb.amplitude) <= 1e-8 * scale
            for o, _ in found
        ):
            found.append((orb, name))
    if not found:
        raise error
    if len(found) > 1:
        listed = "; ".join(
            f"from {name}: W_hat = {o.J / Q1 if Q1 else 0.0:.10g}, amplitude "
            f"{o.amplitude:.6g}, {'stable' if o.stable else 'unstable'}"
            for o, name in found
        )
        warnings.warn(
            f"{len(found)} periodic steady states found ({listed}); the result is the one from "
            f"{found[0][1]} (give a start to choose)",
            MultipleSteadyStates,
            stacklevel=3,
        )
    cyc = DynamicCycle(node, found[0][0], found)
    cyc.verify()
    return cyc


def dynamic_steady_state(model, samples: int, u0=None, name: str = "exact") -> SteadyState:
    """The steady state of a :class:`~lcpfric.model.SingleNode` with a mass, for the driver.

    ``u0``: a start, ``v0`` (at rest) or ``(v0, dv/dt)`` in the node's units."""
    start_time = time.perf_counter()
    P1, Q1, phi = model.normalized_parameters()
    fp0, k, w = model.force_unit, model.k11, model.omega
    start = None
    if u0 is not None:
        z = np.atleast_1d(np.asarray(u0, dtype=float)).ravel()
        if z.size not in (1, 2) or not np.all(np.isfinite(z)):
            from ..errors import InputError

            raise InputError("u0", "a node with a mass starts from v0 or (v0, dv/dt): finite")
        v0, dv0 = float(z[0]), float(z[1]) if z.size == 2 else 0.0
        start = ((k * v0 + model.Q0) / fp0, k * dv0 / (fp0 * w))
    cyc = dynamic_cycle(P1, Q1, phi, model.beta, model.zeta, start=start)
    t = np.linspace(0.0, model.period, samples + 1)
    theta = w * t + model.normal_load.phase
    u, du, F, st = cyc.sample(np.mod(theta, 2 * math.pi))
    N = np.maximum(1.0 + P1 * np.sin(theta), 0.0)
    v, F, N = model.series(u, F, N)
    orb = cyc.orbit
    W_hat = np.array([cyc.W_hat])
    orbits = tuple(
        {
            "W": float(model.W(o.J / Q1 if Q1 else 0.0)),
            "amplitude": o.amplitude * fp0 / k,
            "stable": o.stable,
            "start": name,
        }
        for o, name in cyc.orbits
    )
    extras = DynamicExtras(
        beta=model.beta,
        zeta=model.zeta,
        amplitude=orb.amplitude * fp0 / k,
        velocity=du * fp0 * w / k,
        floquet=orb.floquet,
        stable=orb.stable,
        orbits=orbits,
        newton_iterations=orb.iterations,
        periods=orb.periods,
    )
    return SteadyState(
        W=float(model.W(cyc.W_hat)),
        W_cycles=np.atleast_1d(model.W(W_hat)),
        cycles=1,
        converged=True,
        method=name,
        steps_requested=samples,
        steps_used=0,
        t=t,
        v=v,
        F=F,
        N=N,
        state=st,
        seconds=time.perf_counter() - start_time,
        change=float(orb.residual),
        message=f"exact dynamic steady state (event by event, periodic orbit by Newton's method "
        f"in {orb.iterations} iterations; {len(cyc.orbits)} orbit(s) found; series sampled at "
        f"{samples + 1} instants)",
        normalization=model.normalization(),
        W_hat_cycles=W_hat,
        dynamics=extras,
    )
