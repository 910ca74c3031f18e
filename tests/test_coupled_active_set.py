"""``active-set`` on coupled systems (N = P + B u): the coupled pattern iteration
(lcpfric.steppers.active_set_coupled), one linear solve per pattern, along the convex backends'
path; against ``explicit`` (the same piecewise-linear path, so the same W to round-off) and
``exact``."""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from lcpfric.analysis.starts import start_from_ratios
from lcpfric.errors import InputError
from lcpfric.model import ContactSystem
from lcpfric.scene import make_scene
from lcpfric.steppers.active_set import ActiveSetStepper
from support.coupled_cases import (
    pair_order,
    B3,
    coupled_node,
    full_slip_system,
    separating_node,
    two_nodes,
)


def chain3():
    """The 3-node chain of benchmarks/validation/coupled.py (its order case)."""
    c = lcpfric.chain(
        3,
        k_coupling=2.0,
        P1=np.array([0.3, 0.5, 0.2]),
        Q1=np.array([0.8, 1.2, 0.6]),
        phi=np.array([0.2, 2.0, 4.0]),
    )
    B = 0.3 * np.array([[0.5, -0.4, 0.1], [0.3, 0.2, -0.5], [-0.2, 0.4, 0.3]])
    return ContactSystem(c.stiffness, c.friction, c.tangential_loads, c.normal, coupling=B)


@pytest.mark.parametrize("ratios", [[-0.8, 0.0], [0.3, -0.5], [0.8, 0.0]])
def test_active_set_follows_explicit_and_converges_to_exact(ratios):
    s = two_nodes()
    u0 = start_from_ratios(s, ratios)
    W = lcpfric.steady_state(s, "exact", u0=u0).W
    for n in (200, 800):
        ee = lcpfric.steady_state(s, "explicit", n, u0=u0, tol=1e-12)
        r = lcpfric.steady_state(s, "active-set", n, u0=u0, tol=1e-12)
        assert r.W == pytest.approx(ee.W, rel=1e-12, abs=1e-14)
        assert r.W == pytest.approx(W, rel=1e-3, abs=1e-12)
        st = r.solver_stats
        # a warm-started pattern is right at once: one linear solve per piece of an increment
        assert st["iterations"] <= 1.05 * st["solves"]
        assert st["solves"] <= 1.1 * r.cycles * n + 2 * st["events"]
        assert np.allclose(r.N[-1], r.N[0])  # N = P + B v is periodic with v


def test_active_set_on_a_coupled_chain():
    s = chain3()
    W = lcpfric.steady_state(s, "exact").W
    ee = lcpfric.steady_state(s, "explicit", 400, tol=1e-12)
    r = lcpfric.steady_state(s, "active-set", 400, tol=1e-12)
    assert W > 0.1
    assert r.W == pytest.approx(ee.W, rel=1e-11)
    assert r.W == pytest.approx(W, rel=1e-3)


def test_a_step_where_the_fixed_point_on_N_does_not_contract():
    """The well-posed 3-node system on which the convex backends' plain fixed point on N does
    not contract (tests/test_coupled_backends.py): the pattern iteration solves its coupled box
    LCP directly."""
    system = full_slip_system()
    stepper = ActiveSetStepper()
    scene = make_scene(system, 8)
    end = stepper.step(scene, 0, stepper.init(scene, np.zeros(3)))
    assert np.allclose(end.u, 0.5, atol=1e-12)
    N = 10.0 + B3 @ end.u
    assert np.allclose(end.F, -N, atol=1e-12)  # every node on its lower limit, f = 1
    assert stepper.stats(end)["iterations"] <= 3


def test_a_coupled_single_node_against_exact():
    s = coupled_node()
    W = lcpfric.steady_state(s, "exact").W
    r = lcpfric.steady_state(s, "active-set", 400)
    assert r.W == pytest.approx(lcpfric.steady_state(s, "explicit", 400).W, rel=1e-12)
    assert r.W == pytest.approx(W, rel=1e-4)


def test_active_set_names_a_separating_node():
    with pytest.raises(InputError, match="node 0.*reaches zero at t = ") as exc:
        lcpfric.steady_state(separating_node(), "active-set", 200)
    assert exc.value.parameter == "normal_loads"


def test_zero_coupling_is_the_uncoupled_active_set_bit_for_bit():
    s = two_nodes(0.0)  # B = 0: no coupling block, the uncoupled increments
    assert s.coupling is None
    plain = ContactSystem(s.stiffness, s.friction, s.tangential_loads, s.normal)
    a = lcpfric.steady_state(plain, "active-set", 300)
    assert a.W > 0
    assert lcpfric.steady_state(s, "active-set", 300).W == a.W


@pytest.mark.slow
def test_active_set_order_on_a_coupled_pair():
    """The least-squares order over 100..6400 steps, as explicit's (measured 2.50)."""
    assert pair_order("active-set") >= 1.8
