"""A separating node that reverses inside an increment (issue 38, item 2): on a coupled 3-node
chain, a neighbour starts to slip just before the middle node separates; the middle node stops,
crosses from its upper to its lower limit as its normal reaction goes to zero, and the third
node's slip rate jumps (it stops). The single projection to the separation instant lets the
separating node slip the wrong way and misses the third node's slip before it stopped: the
convex backends and ``active-set`` stayed ~2.5e-6 off ``exact`` from 1600 steps on (order 1.2
over 100 to 12800 steps) until the separating node's slip direction was checked
(:func:`lcpfric.backends.checks.separating_slips_agree`) and the reversal located as an event.
"""

import numpy as np
import pytest

import lcpfric.backends.increments as increments
from lcpfric import make_scene, steady_state
from lcpfric.backends.checks import separating_slips_agree
from lcpfric.model import chain

from support import fitted_order, need

STEPS = (400, 1600)


def reversal_chain():
    """The case (benchmarks/perf/comparison.py, ``separation-reversal``): node 0's phase puts
    its stick-slip event about 1e-4 of a cycle before node 1 separates."""
    return chain(
        3,
        k_coupling=19.00222,
        friction=(0.393073, 0.687262, 0.843258),
        P1=(0.770597, 1.446758, 0.565331),
        Q1=(1.963212, 1.552373, 1.410178),
        phi=(5.486, 0.560708, 3.784577),
    )


@pytest.fixture(scope="module")
def reference():
    model = reversal_chain()
    scenes = {n: make_scene(model, n) for n in STEPS}
    explicit = steady_state(scenes[STEPS[-1]], "explicit").W
    return steady_state(model, "exact").W, scenes, explicit


@pytest.mark.parametrize("method", ["clarabel", "osqp", "active-set"])
def test_every_method_is_second_order_through_the_reversal(reference, method):
    if method != "active-set":
        need(method)
    exact, scenes, explicit = reference
    W = [steady_state(scenes[n], method).W for n in STEPS]
    errors = [abs(w - exact) / exact for w in W]
    assert fitted_order(STEPS, errors) >= 1.8
    # the same discrete solution as the event-located explicit stepper
    assert abs(W[-1] - explicit) <= 1e-9 * exact


def test_without_the_check_the_projection_misses_the_reversal(reference, monkeypatch):
    need("clarabel")
    exact, scenes, explicit = reference
    monkeypatch.setattr(increments, "separating_slips_agree", lambda *args: True)
    W = steady_state(scenes[STEPS[-1]], "clarabel").W
    assert abs(W - explicit) > 1e-6 * exact


def test_separating_slips_agree():
    F = np.array([0.5, -0.2, 0.1])
    sep = np.array([True, True, False])
    assert separating_slips_agree(F, np.array([-1e-3, 2e-3, 5.0]), sep, 1.0, 1.0)
    assert not separating_slips_agree(F, np.array([1e-3, 2e-3, 0.0]), sep, 1.0, 1.0)
    assert not separating_slips_agree(F, np.array([-1e-3, -2e-3, 0.0]), sep, 1.0, 1.0)
    # round-off of a wrong-way slip, and no separating node
    assert separating_slips_agree(F, np.array([1e-12, 0.0, 0.0]), sep, 1.0, 1.0)
    assert separating_slips_agree(F, np.ones(3), None, 1.0, 1.0)
    assert separating_slips_agree(F, np.ones(3), np.zeros(3, dtype=bool), 1.0, 1.0)
