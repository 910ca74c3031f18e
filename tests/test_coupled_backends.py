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
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings
from lcpfric.scene import make_scene
from support import need_modules

need_modules("clarabel", "osqp")  # every test here runs the convex backends


def two_nodes(c=1.0):
    """The two-node system of tests/test_coupled_explicit.py."""
    return ContactSystem(
        np.array([[2.824, 0.764], [0.764, 2.740]]),
        friction=np.array([0.625, 0.407]),
        tangential_loads=(Harmonic(0.0, 1.442, 3.388), Harmonic(0.0, 1.429, 1.351)),
        normal=IndependentSprings((Harmonic(4.314, 0.951, 4.160), Harmonic(3.202, 0.334, 5.216))),
        coupling=c * np.array([[0.952, -0.096], [-0.015, -1.532]]),
    )


# a well-posed 3-node system (every K + diag(s) B a P-matrix) whose fixed point does not
# contract on the full forward slip: the spectral radius of K^-1 B there is 1.043
K3 = np.array([[2.734, -0.493, -2.086], [-0.493, 0.638, 0.419], [-2.086, 0.419, 3.676]])
B3 = np.array([[-0.096, 1.124, -0.566], [-0.086, 0.132, -0.505], [0.255, 0.855, 0.079]])


def full_slip_step(**options):
    """One increment from u = 0 whose exact end state slips every node forward to u = 0.5."""
    P = np.full(3, 10.0)
    u_end = np.full(3, 0.5)
    Q = -K3 @ u_end - (P + B3 @ u_end)  # F = -f N at the end, f = 1
    system = ContactSystem(
        K3,
        np.ones(3),
        tuple(Harmonic(q, 0.0, 0.0) for q in Q),
        IndependentSprings(tuple(Harmonic(p, 0.0, 0.0) for p in P)),
        coupling=B3,
    )
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
    s = ContactSystem(
        np.array([[2.0]]),
        np.array([0.5]),
        (Harmonic(0.0, 3.0, 0.0),),
        IndependentSprings((Harmonic(4.0, 0.5, 1.0),)),
        coupling=np.array([[-1.2]]),
    )
    W = lcpfric.steady_state(s, "exact").W
    r = lcpfric.steady_state(s, "clarabel", 400)
    assert W > 0.1
    assert r.W == pytest.approx(lcpfric.steady_state(s, "explicit", 400).W, rel=1e-12)
    assert r.W == pytest.approx(W, rel=1e-4)


def test_a_separating_node_is_named():
    s = ContactSystem(
        np.array([[2.0]]),
        np.array([0.5]),
        (Harmonic(0.0, 3.0, 0.0),),
        IndependentSprings((Harmonic(1.0, 0.0, 0.0),)),
        coupling=np.array([[-1.9]]),
    )
    with pytest.raises(InputError, match="node 0.*reaches zero at t = ") as exc:
        lcpfric.steady_state(s, "clarabel", 200)
    assert exc.value.parameter == "normal_loads"


@pytest.mark.slow
@pytest.mark.parametrize("method", ["clarabel", "osqp"])
def test_convex_order_on_a_coupled_pair(method):
    """The least-squares order over 100..6400 steps, as explicit's (measured 2.50)."""
    s = two_nodes()
    u0 = start_from_ratios(s, [-0.8, 0.0])
    W = lcpfric.steady_state(s, "exact", u0=u0).W
    ns = np.array([100, 200, 400, 800, 1600, 3200, 6400])
    err = [abs(lcpfric.steady_state(s, method, n, u0=u0, tol=1e-12).W - W) for n in ns]
    assert -np.polyfit(np.log(ns), np.log(err), 1)[0] >= 1.8
