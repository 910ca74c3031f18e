"""Events inside an increment on coupled systems (lcpfric.steppers.rates): the convex backends
split an increment where a node starts to slip, so that on coupled d = 1 systems they are second
order (one projection per step is first order there) and reproduce the event-located explicit
stepper on the same grid."""

import numpy as np
import pytest

from lcpfric import make_scene, steady_state
from lcpfric.model import chain

from support import need
from support import fitted_order


def coupled_chain():
    """3 nodes, coupling 10, separation: once per cycle a slipping node stops inside a step
    when its neighbour starts to slip (the case one projection per step gets wrong by O(h))."""
    return chain(
        3,
        k_coupling=10.0,
        P1=1.5,
        Q1=np.linspace(1.5, 2.5, 3),
        phi=0.6 * np.pi,
        normal_phase=np.linspace(0.0, 1.0, 3),
    )


@pytest.mark.parametrize("method", ["osqp", "clarabel"])
def test_split_increments_reproduce_the_explicit_stepper(method):
    need(method)
    scene = make_scene(coupled_chain(), 400)
    ref = steady_state(scene, "explicit", tol=1e-12).W
    split = steady_state(scene, method, tol=1e-12)
    assert split.solver_stats["events"] > 0
    assert abs(split.W - ref) <= 1e-10 * ref
    # without the split the single projection misses the slip before the event
    single = steady_state(scene, method, tol=1e-12, locate_events=False)
    assert single.solver_stats["events"] == 0
    assert abs(single.W - ref) > 1e-5 * ref


def test_convex_order_on_a_coupled_chain():
    """Judged against the exact steady state (lcpfric.exact.discrete), not another grid."""
    need("osqp")
    system = coupled_chain()
    ref = steady_state(system, "exact").W
    steps = [200, 400, 800, 1600]
    W = [steady_state(system, "osqp", s, tol=1e-12).W for s in steps]
    errors = np.abs(np.asarray(W) - ref)
    assert fitted_order(steps, errors) >= 1.8, errors
    assert errors[-1] <= 1e-5 * ref
