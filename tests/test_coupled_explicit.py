"""``explicit`` on coupled systems (N = P + B u): the rate LCP with ``K + diag(s f) B``, the
normal reactions moving with the slips inside an increment, against ``exact``."""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from lcpfric.analysis.starts import start_from_ratios
from lcpfric.errors import InputError
from support.coupled_cases import pair_order, separating_node, two_nodes


def test_explicit_converges_to_exact_from_a_start():
    s = two_nodes()
    u0 = start_from_ratios(s, [-0.8, 0.0])
    ex = lcpfric.steady_state(s, "exact", u0=u0)
    assert ex.W > 0.2
    ee = lcpfric.steady_state(s, "explicit", 6400, u0=u0, tol=1e-12)
    assert ee.W == pytest.approx(ex.W, rel=1e-7)  # measured 1.9e-8
    # a start that shakes down does so in both
    u1 = start_from_ratios(s, [0.8, 0.0])
    assert lcpfric.steady_state(s, "explicit", 400, u0=u1).W == pytest.approx(0.0, abs=1e-9)
    assert lcpfric.steady_state(s, "exact", u0=u1).W == 0.0


def test_both_methods_share_the_default_start():
    s = two_nodes(0.5)
    ex = lcpfric.steady_state(s, "exact")
    ee = lcpfric.steady_state(s, "explicit", 3200, tol=1e-12)
    assert np.allclose(ee.v[0], ex.v[0], atol=1e-6)
    assert ee.W == pytest.approx(ex.W, rel=1e-5)


def test_explicit_names_a_separating_node():
    with pytest.raises(InputError, match="node 0.*reaches zero at t = ") as exc:
        lcpfric.steady_state(separating_node(), "explicit", 200)
    assert exc.value.parameter == "normal_loads"


@pytest.mark.slow
def test_explicit_order_on_a_coupled_pair():
    """The least-squares order over 100..6400 steps (measured 2.50)."""
    assert pair_order("explicit") >= 1.8


def test_series_and_approach_of_a_coupled_steady_state():
    s = two_nodes()
    u0 = start_from_ratios(s, [-0.8, 0.0])
    e = lcpfric.steady_state(s, "explicit", 400, u0=u0)
    P = s.normal.loads_at(e.t)
    assert np.allclose(e.N, P + e.v @ s.coupling.T, atol=1e-12)  # N = P + B v, not P
    assert {"ratio", "remaining"} <= set(e.solver_stats)
    ex = lcpfric.steady_state(s, "exact", 400, u0=u0)
    assert np.max(np.abs(ex.N - e.N)) < 1e-4
    node = lcpfric.SingleNode(k11=2.0, f=0.5, P0=3.0, P1=1.0, Q1=2.5, phi=0.7, Q0=0.4, k21=0.5)
    a, b = lcpfric.steady_state(node, "exact", 400), lcpfric.steady_state(node, "explicit", 400)
    assert np.max(np.abs(a.v - b.v)) < 1e-4 and np.max(np.abs(a.N - b.N)) < 1e-4
