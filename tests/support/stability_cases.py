"""Numerical stability on stiff and extreme cases (``benchmarks/validation/stability.py``).

Every method is run on a matrix of extreme inputs and each outcome is classified against an
exact reference: ``correct``, ``wrong`` (with the error), or ``error`` (a clear
:class:`~lcpfric.errors.LcpfricError`). A wrong number is a bug to fix; a clear error is
acceptable for a case a method cannot treat.

"Correct" means, for ``exact``, ``|value - reference| <= 1e-9 |reference| + spread`` (its stated
accuracy), where ``spread`` is the change of the exact Ŵ when one input moves by 16 units of
round-off, pinned with the reference: zero where Ŵ is well-conditioned, so that a Ŵ of 1e-20 must
be right to 1e-9 of itself. For the time-stepping methods at 4000 steps per cycle (discretization)
it means ``|value - reference| <= 1e-4 |reference| + 1e-9 scale`` with ``scale = 1 + sqrt(P̂1 Q̂1)``
the size of Ŵ for such loads: next to a zero régime Ŵ itself is 1e-12 to 1e-18 and only the
error on the scale means anything. A time-stepping method that misses its tolerance is re-run at
16 times the steps; meeting it then is a discretization error that converges (reported, with
both errors), missing it again is wrong.

The matrix:

* the normalized node: P̂1, Q̂1 each in {1e-6, 1e-3, 1, 1e3, 1e6}, φ in {0, 1e-9, π/2, π - 1e-9};
* extreme ratios Q̂1/P̂1 in {1e-20, 1e-15, 1e-10, 1e10, 1e15, 1e20} (:func:`ratio_cases`);
* the boundaries P̂1 = 1, Q̂1 = 1 and Q̂1 = P̂1 exactly;
* dimensional scales: k11 from 1e-3 to 1e12 and P0 from 1e-6 to 1e6 at fixed (P̂1, Q̂1, φ);
* multi-node: uncoupled nodes with stiffnesses spread by up to 1e8 (exact: the sum of the
  nodes' answers), and, reported separately as agreement between methods (no closed form
  exists), a coupled chain with a stiffness ratio up to 1e8;
* stiff: coupled systems with stiffness ratios 1 to 1e12 (``tests/support/stiff_cases.py``: a
  weakly grounded chain, a nearly rigid chain, a dense K = D K0 D). Their reference is not the
  continuous-time W but the discretization itself, the periodic steady state of the
  incremental projection on the case's grid, computed in mpmath
  (``tests/support/stiff_reference.py``, pinned in ``tests/support/stiff_references.py``). Only the
  methods that compute that discretization are judged (the convex backends and any method taking
  ``locate_events``, run with ``locate_events=False``, ``tol=1e-13``), at the grid's steps and
  to STIFF_RTOL = 1e-8 relative (every case's W moves by at most 6e-15 when its float64 inputs
  move by 1e-15: the tolerance asks nothing beyond float64).

References: every Ŵ comes from the independent high-precision solution
(``tests/support/exact_reference.py``, mpmath), pinned in ``tests/support/stability_references.py``
(regenerate with ``python tests/support/stability_cases.py --mp-table``), so that the stability
study needs no mpmath and the ``exact`` method is not judged against itself. Where φ = 0 the
pinned values agree with the analytical Eqs. (11)/(12) (a test checks it).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["Scenario", "scenarios", "run_scenario", "applies", "STEPPING_TOL", "STIFF_RTOL"]

PI = math.pi
EXTREMES = (1e-6, 1e-3, 1.0, 1e3, 1e6)
PHASES = (0.0, 1e-9, PI / 2, PI - 1e-9)
# relative error accepted as "correct" for a time-stepping method at the steps used here (its
# discretization error at 4000 contact steps is below 1e-5 on every benchmark case)
STEPPING_TOL = 1e-4
EXACT_RTOL = 1e-9  # lcpfric.exact's stated accuracy where Ŵ is well-conditioned
STIFF_RTOL = 1e-8  # the stiff group: the discretization itself, against its mpmath reference
# the driver's options for the stiff group: no events (the reference's discretization), a tight
# cycle test, room for the cycles a weakly contracting cycle map needs
STIFF_OPTIONS = dict(locate_events=False, tol=1e-13, max_cycles=200)


@dataclass(frozen=True)
class Scenario:
    group: str
    name: str
    build: object  # () -> model
    reference: object  # () -> (value, description)
    value: object  # result -> float
    scale: float | None = None  # size of typical values (None: the reference's own size)
    point: tuple | None = None  # (P̂1, Q̂1, φ) of a single-node scenario
    spread: float = 0.0  # change of the exact value under 16-ulp input changes (conditioning)
    steps: int | None = None  # a fixed grid whose discretization is the reference (stiff group)
    options: dict | None = None  # the driver's and the method's options (stiff group)


def _node(P1, Q1, phi):
    from lcpfric.model import SingleNode

    return SingleNode.normalized(P1, Q1, phi)


def _pinned(P1, Q1, phi):
    """(Ŵ, 16-ulp spread) from the pinned mpmath table, or None."""
    try:
        from .stability_references import MP_REFERENCE
    except ImportError:  # being regenerated
        return None
    return MP_REFERENCE.get((float(P1), float(Q1), float(phi)))


def _node_reference(P1, Q1, phi):
    """Ŵ from the pinned table of the independent mpmath solution (Eqs. (11)/(12) where φ = 0 or
    π agree with it: tests/test_stability.py); a point missing from the table falls back on
    Eqs. (11)/(12) or on the exact code, and says so."""
    pinned = _pinned(P1, Q1, phi)
    if pinned is not None:
        return pinned[0], "mpmath reference (tests/support/exact_reference.py)"
    if phi in (0.0, PI):
        from lcpfric.analysis.analytic import jang_barber

        return float(jang_barber(P1, Q1)), "Eqs. (11)/(12)"
    from lcpfric.exact import exact_W_hat

    return float(exact_W_hat(P1, Q1, phi)), "exact (not independent: point not pinned)"


def _node_scenario(group, P1, Q1, phi):
    pinned = _pinned(P1, Q1, phi)
    return Scenario(
        group,
        f"P1={P1:g} Q1={Q1:g} phi={_phi_name(phi)}",
        lambda P1=P1, Q1=Q1, phi=phi: _node(P1, Q1, phi),
        lambda P1=P1, Q1=Q1, phi=phi: _node_reference(P1, Q1, phi),
        lambda r: r.W_hat,
        1.0 + math.sqrt(P1 * Q1),
        (P1, Q1, phi),
        pinned[1] if pinned else 0.0,
    )


def scenarios(quick: bool = False) -> list[Scenario]:
    out = []
    vals = (1e-6, 1.0, 1e6) if quick else EXTREMES
    phases = (0.0, PI / 2, PI - 1e-9) if quick else PHASES
    for P1 in vals:
        for Q1 in vals:
            for phi in phases:
                out.append(_node_scenario("extreme", P1, Q1, phi))
    for P1, Q1, phi in boundary_cases():
        out.append(_node_scenario("boundary", P1, Q1, phi))
    for P1, Q1, phi in ratio_cases(quick):
        out.append(_node_scenario("ratio", P1, Q1, phi))
    k11s = (1e-3, 1e6, 1e12) if quick else (1e-3, 1.0, 1e3, 1e6, 1e9, 1e12)
    P0s = (1e-6, 1e6) if quick else (1e-6, 1e-3, 1.0, 1e3, 1e6)
    for k11 in k11s:
        for P0 in P0s:
            out.append(
                Scenario(
                    "dimensional",
                    f"k11={k11:g} P0={P0:g}",
                    lambda k11=k11, P0=P0: _dimensional(k11, P0),
                    lambda k11=k11, P0=P0: _dimensional_reference(k11, P0),
                    lambda r: r.W,
                )
            )
    for ratio in (1e4, 1e8):
        out.append(
            Scenario(
                "multi-node",
                f"uncoupled, stiffness ratio {ratio:g}",
                lambda ratio=ratio: _spread_nodes(ratio)[0],
                lambda ratio=ratio: (_spread_nodes(ratio)[1], "sum of the nodes' mpmath answers"),
                lambda r: r.W,
            )
        )
    return out + stiff_scenarios()


def stiff_scenarios() -> list[Scenario]:
    """The stiff group: every case of tests/support/stiff_cases.py with its pinned reference."""
    from .stiff_cases import stiff_cases
    from .stiff_references import STIFF_REFERENCE

    out = []
    for name, (system, steps) in stiff_cases().items():
        W, pinned_steps = STIFF_REFERENCE[name][:2]
        assert pinned_steps == steps, name  # the reference is of this grid
        out.append(
            Scenario(
                "stiff",
                name,
                lambda system=system: system,
                lambda W=W: (
                    W,
                    "mpmath reference of the discretization (tests/support/stiff_reference.py)",
                ),
                lambda r: r.W,
                steps=steps,
                options=STIFF_OPTIONS,
            )
        )
    return out


@functools.lru_cache(maxsize=None)
def _takes_locate_events(method: str) -> bool:
    from lcpfric.errors import LcpfricError, MissingDependency
    from lcpfric.methods import get_stepper

    try:
        get_stepper(method, locate_events=False)
    except MissingDependency:
        return True  # not installed here: its test runs, and skips naming the extra
    except LcpfricError:
        return False
    return True


def applies(scenario: Scenario, method: str) -> bool:
    """Whether ``method`` is judged on ``scenario``: ``exact`` has no multi-node form here, and
    the stiff group's reference is the discretization that only the methods taking
    ``locate_events`` (run with False) compute."""
    if scenario.group == "multi-node":
        return method != "exact"
    if scenario.group == "stiff":
        return _takes_locate_events(method)
    return True


def boundary_cases() -> list[tuple[float, float, float]]:
    """The régime borders P̂1 = 1, Q̂1 = 1 and Q̂1 = P̂1, exactly."""
    pairs = (
        [(1.0, q) for q in (0.5, 1.0, 2.0)]
        + [(p, 1.0) for p in (0.5, 2.0)]
        + [(x, x) for x in (0.5, 2.0, 10.0)]
    )
    return [(P1, Q1, phi) for P1, Q1 in pairs for phi in (0.0, PI / 2)]


RATIOS_SMALL = (1e-20, 1e-15, 1e-10)
RATIOS_LARGE = (1e10, 1e15, 1e20)


def ratio_cases(quick: bool = False) -> list[tuple[float, float, float]]:
    """(P̂1, Q̂1, φ) with Q̂1/P̂1 from 1e-20 to 1e20, P̂1 and Q̂1 within [1e-20, 1e20].

    Small ratios with separation (P̂1 = 2, 1e6), where Ŵ ≈ 2 Q̂1 sin²φ (1 - 1/P̂1²) comes from a
    slip of about Q̂1/P̂1 rad just before separation; large ratios at P̂1 = 0.5 and 1 (1e-3 for
    1e20), where the sticks at the extrema last about Q̂1^(-1/2) rad.
    """
    phases = (1.0,) if quick else (0.0, 1.0, PI / 2)
    out = []
    for r in RATIOS_SMALL:
        for P1 in (2.0,) if quick else (2.0, 1e6):
            out += [(P1, P1 * r, phi) for phi in phases]
    for r in RATIOS_LARGE:
        for P1 in (0.5,) if quick else ((0.5, 1.0) if r < 1e20 else (1e-3, 1.0)):
            out += [(P1, P1 * r, phi) for phi in phases]
    return out


def _phi_name(phi):
    return {0.0: "0", PI / 2: "pi/2", 1e-9: "1e-9", PI - 1e-9: "pi-1e-9"}.get(phi, f"{phi:g}")


_DIM = dict(P1_hat=1.5, Q1_hat=2.0, phi=0.6 * PI, f=0.3)


def _dimensional(k11, P0):
    from lcpfric.model import SingleNode

    f = _DIM["f"]
    return SingleNode(
        k11=k11,
        f=f,
        P0=P0,
        P1=_DIM["P1_hat"] * P0,
        Q1=_DIM["Q1_hat"] * f * P0,
        phi=_DIM["phi"],
        omega=1.0,
    )


def _dimensional_reference(k11, P0):
    f = _DIM["f"]
    Q1 = _DIM["Q1_hat"] * f * P0
    W_hat, how = _node_reference(_DIM["P1_hat"], _DIM["Q1_hat"], _DIM["phi"])
    return float(f * P0 * Q1 * W_hat / k11), f"{how}, scaled by f P0 Q1 / k11"


_SPREAD = ((0.5, 2.0, 0.0), (1.5, 2.0, 0.6 * PI), (5.0, 5.0, 0.3 * PI))


def _spread_nodes(ratio):
    """Three uncoupled nodes with stiffness 1/sqrt(ratio), 1, sqrt(ratio); f = P0 = 1."""
    from lcpfric.model import Harmonic
    from lcpfric.model import ContactSystem, IndependentSprings

    k = np.array([ratio**-0.5, 1.0, ratio**0.5])
    P, Q, F = (np.array(x) for x in zip(*_SPREAD))
    system = ContactSystem(
        stiffness=np.diag(k),
        friction=np.ones(3),
        tangential_loads=tuple(Harmonic(0.0, q, f) for q, f in zip(Q, F)),
        normal=IndependentSprings(tuple(Harmonic(1.0, p, 0.0) for p in P)),
    )
    W_hat = np.array([_node_reference(p, q, f)[0] for p, q, f in _SPREAD])
    exact = float(np.sum(Q * W_hat / k))  # W_i = f P0 Q1 Ŵ_i / k_i
    return system, exact


def _judge(method, val, ref, scale, spread=0.0, fixed_grid=False):
    """(ok, relative error or None for a zero reference, error on the scale).

    ``exact`` must be within 1e-9 relative, or within ``spread`` (the change of the exact value
    under 16-ulp input changes) where the problem is ill-conditioned; a time-stepping method
    within STEPPING_TOL relative or 1e-9 of the scale; on a ``fixed_grid`` (the stiff group,
    whose reference is the discretization) within STIFF_RTOL relative.
    """
    err = abs(val - ref)
    if fixed_grid:
        ok = err <= STIFF_RTOL * abs(ref)
    elif method == "exact":
        ok = err <= EXACT_RTOL * abs(ref) + spread
    else:
        ok = err <= STEPPING_TOL * abs(ref) + 1e-9 * scale
    return ok, (err / abs(ref) if ref else None), err / scale


def run_scenario(scenario: Scenario, method: str, steps: int = 4000, refine: int = 16) -> dict:
    """Run one method on one scenario and classify the outcome.

    A time-stepping method that misses the tolerance at ``steps`` is run again at
    ``refine * steps``: if it then meets it, the verdict is ``correct`` with a note that it needs
    more steps (a discretization error, converging); if not, ``wrong``. A scenario with its own
    ``steps`` (the stiff group) is run on that grid only, with its ``options``.
    """
    from lcpfric.errors import LcpfricError
    from lcpfric.periodic import steady_state

    ref, how = scenario.reference()
    if scenario.scale is None:
        scenario = replace(scenario, scale=abs(ref) or 1.0)
    row = dict(
        group=scenario.group,
        scenario=scenario.name,
        method=method,
        reference=ref,
        reference_from=how,
        spread=scenario.spread,
        value=None,
        rel_error=None,
        scaled_error=None,
        verdict="",
        message="",
    )
    try:
        model = scenario.build()
        fixed = scenario.steps is not None
        val = scenario.value(
            steady_state(model, method, scenario.steps or steps, **(scenario.options or {}))
        )
        if not math.isfinite(val):
            row.update(value=val, verdict="wrong", message="non-finite result")
            return row
        ok, rel, scaled = _judge(method, val, ref, scenario.scale, scenario.spread, fixed)
        row.update(value=val, rel_error=rel, scaled_error=scaled)
        if not ok and not fixed and method != "exact" and refine > 1:
            val2 = scenario.value(steady_state(model, method, steps * refine))
            ok, rel2, scaled2 = _judge(method, val2, ref, scenario.scale, scenario.spread)
            row["message"] = (
                f"error on the scale {scaled:.2e} at {steps} steps, "
                f"{scaled2:.2e} at {steps * refine}"
            )
            row.update(value=val2, rel_error=rel2, scaled_error=scaled2)
    except LcpfricError as exc:
        row.update(verdict="error", message=f"{type(exc).__name__}: {exc}")
        return row
    row["verdict"] = "correct" if ok else "wrong"
    return row


def node_points() -> list[tuple[float, float, float]]:
    """Every (P̂1, Q̂1, φ) whose Ŵ a scenario needs (single nodes, dimensional, multi-node)."""
    pts = {s.point for s in scenarios(quick=False) if s.point is not None}
    pts.add((_DIM["P1_hat"], _DIM["Q1_hat"], _DIM["phi"]))
    pts.update(_SPREAD)
    return sorted(pts)


def mp_table_source() -> str:
    """Python source of stability_references.py (needs mpmath; takes about a minute)."""
    from .exact_reference import default_dps, input_spread, reference_W_hat

    lines = [
        '"""Ŵ of the stability scenarios from the independent mpmath solution, pinned.',
        "",
        "Generated by ``python tests/support/stability_cases.py --mp-table`` with",
        "tests/support/exact_reference.py (60 + 2 x decimal exponent spread digits). Each entry",
        "is ``(P̂1, Q̂1, φ): (Ŵ, spread)``, spread being the largest change of the exact Ŵ",
        "when one input moves by 16 units of round-off (the conditioning).",
        '"""',
        "",
        "MP_REFERENCE = {",
    ]
    for P1, Q1, phi in node_points():
        W = reference_W_hat(P1, Q1, phi)
        spread = input_spread(P1, Q1, phi)
        lines.append(
            f"    ({P1!r}, {Q1!r}, {phi!r}): ({W!r}, {spread!r}),  # dps {default_dps(P1, Q1)}"
        )
    lines.append("}")
    return "\n".join(lines) + "\n"


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
    system = ContactSystem(
        stiffness=K,
        friction=np.ones(n),
        tangential_loads=tuple(Qs),
        normal=IndependentSprings(tuple(P)),
    )
    out = {}
    for m in methods:
        if m == "exact":
            continue
        try:
            out[m] = steady_state(system, m, steps, max_cycles=400).W
        except LcpfricError as exc:
            out[m] = f"{type(exc).__name__}: {exc}"
    return out


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--mp-table"]:
        sys.stdout.write(mp_table_source())
    else:
        sys.exit(
            "usage: python tests/support/stability_cases.py --mp-table > "
            "tests/support/stability_references.py"
        )
