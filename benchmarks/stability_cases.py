"""Numerical stability on stiff and extreme cases (``benchmarks/stability.py``).

Every method is run on a matrix of extreme inputs and each outcome is classified against an
exact reference: ``correct``, ``wrong`` (with the error), or ``error`` (a clear
:class:`~lcpfric.errors.LcpfricError`). A wrong number is a bug to fix; a clear error is
acceptable for a case a method cannot treat.

"Correct" means ``|value - reference| <= rtol |reference| + atol scale``: rtol = 1e-10 and
atol = 1e-14 for ``exact`` (round-off), rtol = 1e-4 and atol = 1e-9 for the time-stepping methods
at 4000 steps per cycle (discretization), where ``scale = 1 + sqrt(P̂1 Q̂1)`` is the size of Ŵ for
such loads: next to a zero régime Ŵ itself is 1e-12 to 1e-18 and only the error on the scale
means anything. A time-stepping method that misses its tolerance is re-run at 16 times the
steps; meeting it then is a discretization error that converges (reported, with both errors),
missing it again is wrong.

The matrix:

* the normalized node: P̂1, Q̂1 each in {1e-6, 1e-3, 1, 1e3, 1e6}, φ in {0, 1e-9, π/2, π - 1e-9};
* the boundaries P̂1 = 1, Q̂1 = 1 and Q̂1 = P̂1 exactly;
* dimensional scales: k11 from 1e-3 to 1e12 and P0 from 1e-6 to 1e6 at fixed (P̂1, Q̂1, φ);
* multi-node: uncoupled nodes with stiffnesses spread by up to 1e8 (exact: the sum of the
  nodes' exact answers), and, reported separately as agreement between methods (no closed form
  exists), a coupled chain with a stiffness ratio up to 1e8.

References: for φ = 0 and φ = π the analytical Eqs. (11)/(12) (independent of the exact code);
otherwise the exact event-by-event solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["Scenario", "scenarios", "run_scenario", "STEPPING_TOL"]

PI = math.pi
EXTREMES = (1e-6, 1e-3, 1.0, 1e3, 1e6)
PHASES = (0.0, 1e-9, PI / 2, PI - 1e-9)
# relative error accepted as "correct" for a time-stepping method at the steps used here (its
# discretization error at 4000 contact steps is below 1e-5 on every benchmark case)
STEPPING_TOL = 1e-4


@dataclass(frozen=True)
class Scenario:
    group: str
    name: str
    build: object          # () -> model
    reference: object      # () -> (value, description)
    value: object          # result -> float
    scale: float | None = None  # size of typical values (None: the reference's own size)


def _node(P1, Q1, phi):
    from lcpfric.model import SingleNode

    return SingleNode.normalized(P1, Q1, phi)


def _node_reference(P1, Q1, phi):
    from lcpfric.analysis.analytic import jang_barber
    from lcpfric.exact import exact_W_hat

    if phi in (0.0, PI):
        return float(jang_barber(P1, Q1)), "Eqs. (11)/(12)"
    return float(exact_W_hat(P1, Q1, phi)), "exact"


def scenarios(quick: bool = False) -> list[Scenario]:
    out = []
    vals = (1e-6, 1.0, 1e6) if quick else EXTREMES
    phases = (0.0, PI / 2, PI - 1e-9) if quick else PHASES
    for P1 in vals:
        for Q1 in vals:
            for phi in phases:
                out.append(Scenario(
                    "extreme", f"P1={P1:g} Q1={Q1:g} phi={_phi_name(phi)}",
                    lambda P1=P1, Q1=Q1, phi=phi: _node(P1, Q1, phi),
                    lambda P1=P1, Q1=Q1, phi=phi: _node_reference(P1, Q1, phi),
                    lambda r: r.W_hat, 1.0 + math.sqrt(P1 * Q1)))
    boundary = [(1.0, q) for q in (0.5, 1.0, 2.0)] + [(p, 1.0) for p in (0.5, 2.0)] + \
               [(x, x) for x in (0.5, 2.0, 10.0)]
    for P1, Q1 in boundary:
        for phi in (0.0, PI / 2):
            out.append(Scenario(
                "boundary", f"P1={P1:g} Q1={Q1:g} phi={_phi_name(phi)}",
                lambda P1=P1, Q1=Q1, phi=phi: _node(P1, Q1, phi),
                lambda P1=P1, Q1=Q1, phi=phi: _node_reference(P1, Q1, phi),
                lambda r: r.W_hat, 1.0 + math.sqrt(P1 * Q1)))
    k11s = (1e-3, 1e6, 1e12) if quick else (1e-3, 1.0, 1e3, 1e6, 1e9, 1e12)
    P0s = (1e-6, 1e6) if quick else (1e-6, 1e-3, 1.0, 1e3, 1e6)
    for k11 in k11s:
        for P0 in P0s:
            out.append(Scenario(
                "dimensional", f"k11={k11:g} P0={P0:g}",
                lambda k11=k11, P0=P0: _dimensional(k11, P0),
                lambda k11=k11, P0=P0: _dimensional_reference(k11, P0),
                lambda r: r.W))
    for ratio in (1e4, 1e8):
        out.append(Scenario(
            "multi-node", f"uncoupled, stiffness ratio {ratio:g}",
            lambda ratio=ratio: _spread_nodes(ratio)[0],
            lambda ratio=ratio: (_spread_nodes(ratio)[1], "sum of exact node answers"),
            lambda r: r.W))
    return out


def _phi_name(phi):
    return {0.0: "0", PI / 2: "pi/2", 1e-9: "1e-9", PI - 1e-9: "pi-1e-9"}.get(phi, f"{phi:g}")


_DIM = dict(P1_hat=1.5, Q1_hat=2.0, phi=0.6 * PI, f=0.3)


def _dimensional(k11, P0):
    from lcpfric.model import SingleNode

    f = _DIM["f"]
    return SingleNode(k11=k11, f=f, P0=P0, P1=_DIM["P1_hat"] * P0, Q1=_DIM["Q1_hat"] * f * P0,
                      phi=_DIM["phi"], omega=1.0)


def _dimensional_reference(k11, P0):
    from lcpfric.exact import exact_W_hat

    f = _DIM["f"]
    Q1 = _DIM["Q1_hat"] * f * P0
    return float(f * P0 * Q1 * exact_W_hat(_DIM["P1_hat"], _DIM["Q1_hat"], _DIM["phi"]) / k11), \
        "exact Ŵ scaled by f P0 Q1 / k11"


_SPREAD = ((0.5, 2.0, 0.0), (1.5, 2.0, 0.6 * PI), (5.0, 5.0, 0.3 * PI))


def _spread_nodes(ratio):
    """Three uncoupled nodes with stiffness 1/sqrt(ratio), 1, sqrt(ratio); f = P0 = 1."""
    from lcpfric.exact import exact_W_hat
    from lcpfric.model import Harmonic
    from lcpfric.model import ContactSystem, IndependentSprings

    k = np.array([ratio ** -0.5, 1.0, ratio ** 0.5])
    P, Q, F = (np.array(x) for x in zip(*_SPREAD))
    system = ContactSystem(stiffness=np.diag(k), friction=np.ones(3),
                           tangential_loads=tuple(Harmonic(0.0, q, f) for q, f in zip(Q, F)),
                           normal=IndependentSprings(tuple(Harmonic(1.0, p, 0.0) for p in P)))
    exact = float(np.sum(Q * exact_W_hat(P, Q, F) / k))  # W_i = f P0 Q1 Ŵ_i / k_i
    return system, exact


def _judge(method, val, ref, scale):
    """(ok, relative error or None for a zero reference, error on the scale)."""
    rtol, atol = (1e-10, 1e-14) if method == "exact" else (STEPPING_TOL, 1e-9)
    err = abs(val - ref)
    ok = err <= rtol * abs(ref) + atol * scale
    return ok, (err / abs(ref) if ref else None), err / scale


def run_scenario(scenario: Scenario, method: str, steps: int = 4000, refine: int = 16) -> dict:
    """Run one method on one scenario and classify the outcome.

    A time-stepping method that misses the tolerance at ``steps`` is run again at
    ``refine * steps``: if it then meets it, the verdict is ``correct`` with a note that it needs
    more steps (a discretization error, converging); if not, ``wrong``.
    """
    from lcpfric.errors import LcpfricError
    from lcpfric.periodic import steady_state

    ref, how = scenario.reference()
    if scenario.scale is None:
        scenario = replace(scenario, scale=abs(ref) or 1.0)
    row = dict(group=scenario.group, scenario=scenario.name, method=method, reference=ref,
               reference_from=how, value=None, rel_error=None, scaled_error=None, verdict="",
               message="")
    try:
        model = scenario.build()
        val = scenario.value(steady_state(model, method, steps))
        if not math.isfinite(val):
            row.update(value=val, verdict="wrong", message="non-finite result")
            return row
        ok, rel, scaled = _judge(method, val, ref, scenario.scale)
        row.update(value=val, rel_error=rel, scaled_error=scaled)
        if not ok and method != "exact" and refine > 1:
            val2 = scenario.value(steady_state(model, method, steps * refine))
            ok, rel2, scaled2 = _judge(method, val2, ref, scenario.scale)
            row["message"] = (f"error on the scale {scaled:.2e} at {steps} steps, "
                              f"{scaled2:.2e} at {steps * refine}")
            row.update(value=val2, rel_error=rel2, scaled_error=scaled2)
    except LcpfricError as exc:
        row.update(verdict="error", message=f"{type(exc).__name__}: {exc}")
        return row
    row["verdict"] = "correct" if ok else "wrong"
    return row


def coupled_agreement(methods, ratio: float, steps: int = 2000) -> dict:
    """Spread of W across methods on a coupled chain with stiffness ratio ``ratio`` (no exact
    solution exists; this measures agreement, reported as such)."""
    from lcpfric.errors import LcpfricError
    from lcpfric.model import Harmonic
    from lcpfric.model import ContactSystem, IndependentSprings
    from lcpfric.periodic import steady_state

    n = 4
    kc, kg = 1.0, 1.0 / ratio
    K = np.diag(np.full(n, 2 * kc + kg)) - kc * (np.eye(n, k=1) + np.eye(n, k=-1))
    K[0, 0] = K[-1, -1] = kc + kg
    P = [Harmonic(1.0, p, 0.0) for p in (0.5, 1.5, 0.8, 2.0)]
    Qs = [Harmonic(0.0, q, f) for q, f in ((2.0, 0.3), (1.0, 1.9), (1.5, 1.0), (2.5, 2.2))]
    system = ContactSystem(stiffness=K, friction=np.ones(n), tangential_loads=tuple(Qs),
                           normal=IndependentSprings(tuple(P)))
    out = {}
    for m in methods:
        if m == "exact":
            continue
        try:
            out[m] = steady_state(system, m, steps, max_cycles=400).W
        except LcpfricError as exc:
            out[m] = f"{type(exc).__name__}: {exc}"
    return out
