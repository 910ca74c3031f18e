"""``explicit``: an event within round-off of an increment's end finishes the increment.

A node that reaches its limit ``1.3e-15`` (in fractions of the increment) before ``t_{k+1}`` left
τ so close to 1 that the end itself was within the "same instant" tolerance ``8 eps`` of τ; with
no limit to decide there the loop retried the same τ until it raised "more than 24 state
changes in increment 199" (2-node chain, 400 steps; 100, 200, 800 and 1600 steps ran).
"""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from support import need
from lcpfric.results import State, StepState
from lcpfric.scene import make_scene
from lcpfric.steppers.explicit import ExplicitStepper


def chain():
    return lcpfric.chain(2, k_coupling=5, Q1=(2, 0.5), phi=(0, 1))


def test_event_at_the_increments_end_does_not_stall():
    """The reported case: it runs, and equals the convex backend on the same grid."""
    need("clarabel")
    s = chain()
    r = lcpfric.steady_state(s, method="explicit", steps_per_cycle=400)
    assert r.converged
    c = lcpfric.steady_state(s, method="clarabel", steps_per_cycle=400)
    assert r.W == pytest.approx(c.W, rel=1e-12)
    # the 200-step grid's points are the 400-step grid's, and its W is the same (same phase)
    r200 = lcpfric.steady_state(s, method="explicit", steps_per_cycle=200)
    assert r.W == pytest.approx(r200.W, rel=1e-12)
    assert r.W == pytest.approx(lcpfric.steady_state(s, method="exact").W, rel=2e-4)


# the state at t_199 in the run's second cycle (the one that stalled), bit for bit
U199 = ("-0x1.dfaf6dee651e3p-3", "-0x1.4c0b6e3c25e28p-4")
F199 = ("-0x1.efea6bc759f13p-1", "0x1.12b61e37c7aa8p-2")


def test_increment_199_is_one_event():
    """The increment that stalled: node 0 reaches its lower limit ~1.3e-15 before t_200, then
    the increment's end; it ends with node 0 slipping forward on its limit, as the convex
    backend's projection gives."""
    s = chain()
    scene = make_scene(s, 400)
    stepper = ExplicitStepper()
    data = stepper.init(scene).data
    u = np.array([float.fromhex(x) for x in U199])
    F = np.array([float.fromhex(x) for x in F199])
    np.testing.assert_allclose(F, scene.Q[199] + data["K"] @ u, rtol=0, atol=1e-15)
    state = StepState(u, F, np.zeros(2, dtype=np.int8), 0.0, data)
    end = stepper.step(scene, 199, state)
    assert end.data["substeps"] == 2 and end.data["events"] == 1
    assert end.F[0] == -1.0 and end.state[0] == State.FORWARD and end.state[1] == State.STICK
    assert end.u[0] - u[0] == pytest.approx(0.0, abs=1e-15)  # slipped for ~1e-15 of a step
    np.testing.assert_array_equal(end.u[1], u[1])
    assert abs(end.F[1]) < 1.0
