"""Time stepping with inertia for the dynamic single node (issue 40, item 3, the node):
``method="newmark"`` (Newmark's average acceleration, the increment the projection in the metric
of K_eff, events located inside increments, shooting) converges to ``exact`` at second order
with stops, separation and reversals (measured orders 1.97-2.44; the table:
benchmarks/validation/newmark_node.py)."""

import math

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError

CASES = {  # P̂1, Q̂1, φ, β, ζ
    "stick phases": (0.5, 2.0, 0.7, 0.3, 0.05),
    "separation": (1.5, 2.0, 0.4, 0.7, 0.02),
    "reversals": (0.5, 2.0, 0.7, 1.3, 0.1),
}


@pytest.mark.parametrize("name", list(CASES))
def test_second_order_against_exact(name):
    P1, Q1, phi, beta, zeta = CASES[name]
    node = lcpfric.SingleNode.normalized(P1, Q1, phi, beta=beta, zeta=zeta)
    exact = lcpfric.steady_state(node, "exact").W
    err = [abs(lcpfric.steady_state(node, "newmark", n).W / exact - 1) for n in (100, 200, 400)]
    orders = [math.log2(err[i] / err[i + 1]) for i in range(2)]
    assert min(orders) >= 1.8, (err, orders)
    assert err[-1] < 1e-3


def test_the_result_and_the_refusals():
    node = lcpfric.SingleNode(k11=2.0, f=0.5, P0=3.0, P1=1.0, Q1=2.5, omega=1.3, phi=0.4,
                              mass=1.5, damping=0.2)  # fmt: skip
    r = lcpfric.steady_state(node, "newmark", 400)
    e = lcpfric.steady_state(node, "exact")
    assert r.method == "newmark" and r.converged
    assert r.W == pytest.approx(e.W, rel=1e-3)
    assert r.dynamics.amplitude == pytest.approx(e.dynamics.amplitude, rel=1e-3)
    assert np.all(np.abs(r.F) <= node.f * r.N * (1 + 1e-12) + 1e-12)
    assert lcpfric.methods_for(node) == ["exact", "newmark"]
    assert "newmark" not in lcpfric.methods_for(lcpfric.SingleNode(Q1=1.0))
    with pytest.raises(InputError, match="'newmark' solves a SingleNode with a mass"):
        lcpfric.steady_state(lcpfric.SingleNode(Q1=1.0), "newmark")
    with pytest.raises(InputError, match="u0"):
        lcpfric.steady_state(node, "newmark", 100, u0=[1.0, 2.0, 3.0])
