r"""The frequency response of the dynamic single node (issue 40, item 7): its exact steady orbit
(:mod:`lcpfric.exact.dynamic`) at each forcing frequency ω, with the dissipation per cycle W, the
amplitude ``(max v - min v)/2``, the phase of the response and the orbit's stability.

The **phase** is the lag of the displacement's first harmonic behind ``-Q``'s (lcpfric's sign
convention ``m v'' + c v' + k11 v = F - Q`` makes the stuck or slow node move against Q): 0 in the
quasi-static limit, about π/2 at resonance, towards π above it. With ``v1(t) = a1 cos ωt + b1 sin
ωt`` (the first harmonic of the steady cycle, by the trapezoidal rule on the sampled cycle) and
``Q(t) - Q0 = Q1 sin(ωt + φ)``, the phase is ``φ + π - atan2(a1, b1)`` reduced to (-π, π].

Every frequency is solved independently (no continuation is needed: the exact orbit is found by
Newton's method on the period map from rest and from the linear response); an orbit that is
not unique is reported (``orbits`` > 1, and a :class:`~lcpfric.errors.MultipleSteadyStates`
warning).

A :class:`~lcpfric.model.dynamic_system.DynamicSystem` is solved by the ``newmark`` method
(shooting, :mod:`lcpfric.periodic.newmark_steady`) at each frequency, started from the
equivalent linear response (measured: fewer Newton iterations than from the neighbouring
frequency's orbit near a contact's stick-slip threshold, ``benchmarks/results/newmark-system.md``);
where the response folds it finds one of the orbits (to follow a branch, give each point's
start: :func:`lcpfric.periodic.newmark_steady.system_steady_state` takes ``u0``). The amplitude
and phase are those of one degree of freedom ``dof`` (default: the first contact's); the phase
is the lag of its first harmonic behind the forcing's first harmonic at the most forced degree
of freedom (for ``DynamicSystem.from_node`` the node's phase above).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["FrequencyResponse", "frequency_response"]


@dataclass(frozen=True)
class FrequencyResponse:
    """The steady response against the forcing frequency (:func:`frequency_response`).

    Parameters
    ----------
    omega, beta, W, amplitude, phase, stable, floquet, orbits, method, seconds
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    omega, beta : ndarray
        The forcing frequencies ω and ω/Ω0, (m,).
    W : ndarray
        Dissipation per cycle, (m,).
    amplitude : ndarray
        ``(max v - min v)/2`` over the steady cycle, (m,).
    phase : ndarray
        The lag of the displacement's first harmonic behind ``-Q``'s (module docstring), (m,).
    stable : ndarray
        The orbit's stability (its Floquet multipliers inside the unit circle), (m,) bool.
    floquet : ndarray
        The Floquet multipliers, (m, 2) complex (a DynamicSystem: (m, p), p its unknowns).
    orbits : ndarray
        The distinct orbits found at each frequency (more than 1: a warning was issued), (m,).
    method : str
        ``"exact"`` (the node) or ``"newmark"`` (a DynamicSystem).
    seconds : float
        Wall time.
    """

    omega: np.ndarray
    beta: np.ndarray
    W: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    stable: np.ndarray
    floquet: np.ndarray
    orbits: np.ndarray
    method: str
    seconds: float


def frequency_response(
    node, omegas, *, samples: int = 256, dof=None, steps: int = 400, backend=None
) -> FrequencyResponse:
    """The dynamic node's, or a dynamic system's, steady response at each forcing frequency
    (module docstring).

    Parameters
    ----------
    node : SingleNode or DynamicSystem
        A node with a mass (its own ω is replaced by each of ``omegas``; P1, Q1, φ, the mass
        and the damping are kept), or a DynamicSystem (its ω replaced likewise).
    omegas : float or array_like
        Forcing frequencies ω > 0 (not Ω0 if the node has no damping).
    samples : int, optional
        Samples of the cycle for the phase's first harmonic, >= 16 (the node).
    dof : int, optional
        A DynamicSystem's degree of freedom whose amplitude and phase are reported.
    steps : int, optional
        A DynamicSystem's increments per period (>= 4).
    backend : str, optional
        A DynamicSystem's convex backend for its increments (``newmark``'s option).

    Returns
    -------
    FrequencyResponse
        W, the amplitude, the phase and the stability per frequency.

    Raises
    ------
    InputError
        A node without a mass or with non-harmonic loads (named ``node``), a frequency <= 0,
        not finite, or at the undamped resonance (named ``omega``), ``samples`` < 16.
    SolverError
        The orbit was not found at some frequency.
    """
    from ..exact.dynamic_api import dynamic_cycle
    from ..harmonic import trapezoid_coefficients
    from ..model import SingleNode

    start = time.perf_counter()
    if hasattr(node, "dynamic_methods"):  # a DynamicSystem
        from .frequency_response_system import system_response

        return FrequencyResponse(
            **system_response(node, _omegas(omegas), dof, steps, backend),
            method="newmark",
            seconds=time.perf_counter() - start,
        )
    if not isinstance(node, SingleNode) or not node.is_dynamic:
        raise InputError(
            "node",
            "a frequency response needs a SingleNode with a mass (mass > 0): the quasi-static "
            "node's W does not depend on ω",
        )
    if not node.is_harmonic:
        raise InputError("node", "needs harmonic loads P0 + P1 sin ωt, Q0 + Q1 sin(ωt + φ)")
    w = _omegas(omegas)
    samples = _checks.positive_int("samples", samples, 16)
    P1, Q1, phi = node.normalized_parameters()
    keep = {k: getattr(node, k) for k in ("k11", "f", "P0", "P1", "Q1", "phi", "Q0", "k22")}
    theta = np.linspace(0.0, 2.0 * math.pi, samples + 1)
    rows = []
    for omega in w:
        at = SingleNode(**keep, omega=float(omega), mass=node.mass, damping=node.damping)
        cyc = dynamic_cycle(P1, Q1, phi, at.beta, at.zeta)
        u = cyc.sample(theta[:-1])[0]
        c = trapezoid_coefficients(theta, np.append(u, u[0]), 2.0 * math.pi, 1)
        lag = phi + math.pi - math.atan2(c[1], c[2])
        rows.append(
            (
                at.beta,
                float(at.W(cyc.W_hat)),
                cyc.orbit.amplitude * at.force_unit / at.k11,
                math.remainder(lag, 2.0 * math.pi),
                cyc.orbit.stable,
                cyc.orbit.floquet,
                len(cyc.orbits),
            )
        )
    beta, W, amp, phase, stable, mult, count = zip(*rows)
    return FrequencyResponse(
        omega=w,
        beta=np.array(beta),
        W=np.array(W),
        amplitude=np.array(amp),
        phase=np.array(phase),
        stable=np.array(stable, dtype=bool),
        floquet=np.array(mult),
        orbits=np.array(count),
        method="exact",
        seconds=time.perf_counter() - start,
    )


def _omegas(omegas) -> np.ndarray:
    w = np.atleast_1d(_checks.finite_array("omega", omegas)).astype(float)
    if w.ndim != 1 or w.size == 0 or np.any(w <= 0):
        raise InputError("omega", "every frequency must be finite and > 0")
    return w
