"""A :class:`~lcpfric.model.dynamic_system.DynamicSystem`'s frequency response by shooting at
each frequency (:func:`lcpfric.analysis.frequency_response.frequency_response` calls it; its
module docstring says what is reported)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .. import _checks
from ..errors import InputError
from ..harmonic import trapezoid_coefficients
from ..periodic.newmark_steady import system_steady_state

__all__ = ["system_response", "orbit_start"]


def orbit_start(system, result) -> np.ndarray:
    """``z = (x, x', w_J)`` at t = 0 of a steady state of ``system`` (to start the next
    frequency from)."""
    dyn = result.dynamics
    fin = ~system.rigid
    w = result.v[0] - result.F[0] / np.where(fin, system.contact_stiffness, 1.0)
    return np.concatenate([dyn.displacement[0], dyn.velocity[0], w[fin]])


def system_response(system, w, dof, steps, backend) -> dict:
    """The fields of a FrequencyResponse but ``method`` and ``seconds``."""
    steps = _checks.positive_int("steps", steps, 4)
    if dof is None:
        dof = int(np.argmax(np.abs(system.G[:, 0])))
    if isinstance(dof, bool) or not isinstance(dof, (int, np.integer)) or not 0 <= dof < system.n:
        raise InputError("dof", f"a degree of freedom in [0, {system.n - 1}], got {dof!r}")
    k = int(np.argmax(np.abs(system.force)))
    rows = []
    for omega in w:
        at = replace(system, omega=float(omega))
        r = system_steady_state(at, steps, 30, None, backend)
        x = r.dynamics.displacement[:, dof]
        c = trapezoid_coefficients(r.t, x, at.period, 1)
        lag = math.atan2(system.force[k].imag, system.force[k].real) + math.atan2(c[2], c[1])
        dyn = r.dynamics
        rows.append((dyn.beta, r.W, float(dyn.amplitude[dof]), math.remainder(lag, 2 * math.pi),
                     dyn.stable, dyn.floquet, 1))  # fmt: skip
    beta, W, amp, phase, stable, mult, count = zip(*rows)
    return {
        "omega": w,
        "beta": np.array(beta),
        "W": np.array(W),
        "amplitude": np.array(amp),
        "phase": np.array(phase),
        "stable": np.array(stable, dtype=bool),
        "floquet": np.array(mult),
        "orbits": np.array(count),
    }
