"""The convex backends on coupled systems (N = P + B u): per piece of an increment, a fixed point
of problem (P) on the normal reactions (lcpfric.backends.coupled), against ``explicit`` and
``exact``; the contraction bound; the typed error of a fixed point that does not converge."""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from lcpfric.analysis.starts import start_from_ratios
from lcpfric.backends.clarabel_ import ClarabelStepper
from lcpfric.errors import InputError, SolverError
from lcpfric.scene import make_scene
from support import need_modules
from support.coupled_cases import (
    pair_order,
    coupled_node,
    full_slip_system,
    separating_node,
    two_nodes,
)

need_modules("clarabel", "osqp")  # every test here runs the convex backends


def full_slip_step(**options):
    """One increment from u = 0 whose exact end state slips every node forward to u = 0.5."""
    system = full_slip_system()
    stepper = ClarabelStepper(**options)
    scene = make_scene(system, 8)
    return stepper, stepper.step(scene, 0, stepper.init(scene, np.zeros(3)))


def test_convex_backends_agree_with_explicit_and_exact():
    s = two_nodes()
    u0 = start_from_ratios(s, [-0.8, 0.0])
    ee = lcpfric.steady_state(s, "explicit", 400, u0=u0, tol=1e-12)
    W = lcpfric.steady_state(s, "exact", u0=u0).W
    for method in ("clarabel", "osqp"):
        r = lcpfric.steady_state(s, method, 400, u0=u0, tol=1e-12)
        assert r.W == pytest.approx(ee.W, rel=1e-12, abs=1e-14)  # the same piecewise-linear path
        assert r.W == pytest.approx(W, rel=2e-4)
        st = r.solver_stats
        # every piece of an increment is one fixed point: its solves are counted
        assert st["fixed_point_iterations"] == st["solves"]
        assert st["solves"] <= 3 * r.cycles * (400 + st["events"])
        assert st["fixed_point_max_ratio"] < 0.5


def test_a_start_that_shakes_down_does_so():
    s = two_nodes()
    u1 = start_from_ratios(s, [0.8, 0.0])
    assert lcpfric.steady_state(s, "clarabel", 200, u0=u1).W == pytest.approx(0.0, abs=1e-9)


def test_plain_fixed_point_contracts_within_the_bound():
    """κ = ||diag(f) B||₂ / λmin(K) < 1: every measured ratio of successive changes is below κ."""
    s = two_nodes(0.5)
    K = s.dense_stiffness()
    kappa = np.linalg.norm(s.friction[:, None] * s.coupling, 2) / np.linalg.eigvalsh(K)[0]
    assert kappa < 1
    r = lcpfric.steady_state(s, "clarabel", 200, pattern_steps=False)
    assert 0 < r.solver_stats["fixed_point_max_ratio"] <= kappa
    assert r.W == pytest.approx(lcpfric.steady_state(s, "explicit", 200).W, rel=1e-9)


def test_a_fixed_point_that_does_not_contract_raises_the_typed_error():
    with pytest.raises(SolverError, match="coupled fixed point.*measured contraction") as exc:
        full_slip_step(pattern_steps=False)
    assert exc.value.status == "coupled_fixed_point"
    assert exc.value.residuals["contraction"] > 1.0
    assert exc.value.residuals["bound"] > 1.0
    # the pattern steps reach it: two solves (the pattern's point, then its check)
    stepper, end = full_slip_step()
    assert np.allclose(end.u, 0.5, atol=1e-12)
    assert stepper.stats(end)["solves"] == 2


def test_a_coupled_single_node_against_exact():
    s = coupled_node()
    W = lcpfric.steady_state(s, "exact").W
    r = lcpfric.steady_state(s, "clarabel", 400)
    assert W > 0.1
    assert r.W == pytest.approx(lcpfric.steady_state(s, "explicit", 400).W, rel=1e-12)
    assert r.W == pytest.approx(W, rel=1e-4)


def test_a_separating_node_is_named():
    with pytest.raises(InputError, match="node 0.*reaches zero at t = ") as exc:
        lcpfric.steady_state(separating_node(), "clarabel", 200)
    assert exc.value.parameter == "normal_loads"


@pytest.mark.slow
@pytest.mark.parametrize("method", ["clarabel", "osqp"])
def test_convex_order_on_a_coupled_pair(method):
    """The least-squares order over 100..6400 steps, as explicit's (measured 2.50)."""
    assert pair_order(method) >= 1.8
