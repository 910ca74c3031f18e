"""The per-node memory of a cycle's starting slips (lcpfric.cycle_memory): the d = 2
preconditioner of the contact steady-state driver."""

import numpy as np
import lcpfric
import pytest

from lcpfric.steppers.slip_memory import MAX_GAIN, SlipMemory
from support import halfspace_sphere as sphere


def _return_mapping(s0, deltas, c, b):
    """One node on a spring of compliance c with a circular limit b, its support moved
    through ``deltas``: the slips of each increment and the final slip (lcpfric's signs:
    ``s = δ + c F``, the slip opposes F)."""
    s, slips = np.array(s0, dtype=float), []
    for d in deltas:
        Ft = (s - d) / c
        norm = np.hypot(*Ft)
        s1 = s.copy() if norm <= b else d + c * Ft * (b / norm)
        slips.append(s1 - s)
        s = s1
    return np.array(slips), s


def test_memory_is_the_single_node_jacobian_of_the_cycle():
    """For one node the memory is exact: R equals the finite-difference Jacobian of the final
    slip with respect to the starting one, over a path that sticks, slips and turns."""
    c, b = 0.7, 1.3
    corners = np.array([[0.0, 0.0], [2.0, 0.5], [-2.0, 0.3], [0.5, -0.4]])
    deltas = np.concatenate(
        [
            a + np.linspace(0.0, 1.0, 15)[1:, None] * (z - a)
            for a, z in zip(corners[:-1], corners[1:])
        ]
    )
    s0 = np.array([0.2, -0.1])
    slips, _ = _return_mapping(s0, deltas, c, b)
    assert np.sum(np.hypot(*slips.T) > 0) > 10 and np.sum(np.hypot(*slips.T) == 0) > 3
    mem = SlipMemory(c, 1)
    R = mem.start()
    for ds in slips:
        mem.update(R, ds, np.array([b]))
    eps = 1e-7
    J = np.empty((2, 2))
    for k in range(2):
        e = np.zeros(2)
        e[k] = eps
        J[:, k] = (
            _return_mapping(s0 + e, deltas, c, b)[1] - _return_mapping(s0 - e, deltas, c, b)[1]
        ) / (2 * eps)
    assert np.abs(R[0]).max() > 1e-3  # something is remembered
    assert R[0] == pytest.approx(J, abs=1e-7)


def test_memory_step_is_a_floored_newton_step():
    """A node that sticks all cycle remembers everything (its start repeats whatever it is:
    the step is its change, round-off); one that slips along x keeps r of y only (the step is
    capped at MAX_GAIN times the change when r is near 1); one that separates (b = 0) keeps
    nothing."""
    mem = SlipMemory(np.array([1.0, 2.0, 1.0]), 3)
    R = mem.start()
    mem.update(R, np.array([0.0, 0.0, 0.5, 0.0, 0.1, 0.2]), np.array([1.0, 1.0, 0.0]))
    r = 2.0 / (2.0 + 0.5)
    assert R[0] == pytest.approx(np.eye(2))
    assert R[1] == pytest.approx(np.diag([0.0, r]))
    assert R[2] == pytest.approx(np.zeros((2, 2)))
    f = np.array([1e-3, 2e-3, 1.0, 1.0, 3.0, -4.0])
    step = mem.step(R, f).reshape(3, 2)
    assert step[0] == pytest.approx(f[:2])
    assert step[1] == pytest.approx([1.0, 1.0 / (1.0 - r)])
    assert step[2] == pytest.approx([3.0, -4.0])
    R[1] = np.diag([0.0, 1.0 - 1e-6])  # nearly all remembered
    assert mem.step(R, f).reshape(3, 2)[1] == pytest.approx([1.0, MAX_GAIN])


@pytest.mark.slow
def test_memory_cuts_the_cycles_to_the_same_steady_state(monkeypatch):
    """d = 2, ν = 0.3, the cycles not accelerated otherwise: scaling each cycle's change by
    the memory reaches the steady state in a few cycles (14 in a run of this test), where the
    plain cycles still change by more than 1e-9 after 40, towards the same W."""
    from lcpfric.periodic import acceleration

    class Plain:  # no Anderson: the memory's own effect
        def __call__(self, x, g):
            return None

    monkeypatch.setattr(acceleration, "Anderson", Plain)
    m = sphere(Q1=0.3, grid=16, nu=0.3, dims=2)
    r1 = lcpfric.steady_state(m, steps_per_cycle=40, max_cycles=40)
    r0 = lcpfric.steady_state(
        m, "newton-cg", 40, max_cycles=40, on_nonconvergence="ignore", slip_memory=False
    )
    assert r1.converged and r1.cycles <= 20
    assert r1.changes.size == r1.cycles - 1 and r1.changes[-1] == r1.change
    assert not r0.converged and r0.change > 1e-9  # still far from repeating
    assert r1.W == pytest.approx(r0.W, rel=1e-9)  # toward the same W
    from lcpfric.steppers.newton_cg import NewtonCGStepper

    d1 = lcpfric.make_scene(sphere(grid=16), 8)
    assert NewtonCGStepper().memory(d1) is None  # d = 1 forgets by slipping


def _d2_chain(n, coupling):
    import math

    import lcpfric

    return lcpfric.chain(
        n,
        k_coupling=coupling,
        dims=2,
        P1=0.5,
        Q1=[[1.2, 0.9], [1.0, 1.1], [0.8, 1.3]][:n],
        phi=[[0.6 * math.pi, 0.1 * math.pi], [0.3, 1.2], [2.0, 0.4]][:n],
    )


@pytest.mark.parametrize(
    "n, coupling, method, most",
    [
        (1, 0.0, "projection", 6),  # uncoupled: the memory is the cycle map's Jacobian
        pytest.param(
            3,
            10.0,
            "clarabel",
            10,
            marks=pytest.mark.skipif(
                __import__("importlib").util.find_spec("clarabel") is None,
                reason="clarabel is not installed (pip install lcpfric[clarabel])",
            ),
        ),
    ],
)
@pytest.mark.slow
def test_discrete_d2_driver_uses_the_memory(monkeypatch, n, coupling, method, most):
    """The discrete driver with d = 2: the same steady state (W to 1e-9) as with Aitken's
    jumps alone, in fewer cycles (a single node: 5 against 9; a coupled 3-node chain, with
    Anderson's acceleration for the coupling: 9 against 13)."""
    import lcpfric
    from lcpfric.periodic import acceleration, driver

    fast = lcpfric.steady_state(_d2_chain(n, coupling), method, 200, tol=1e-10)
    monkeypatch.setattr(
        driver,
        "choose",
        lambda scene, stepper, history, start: acceleration.Acceleration(aitken=True, first=start),
    )
    slow = lcpfric.steady_state(_d2_chain(n, coupling), method, 200, tol=1e-10)
    assert fast.converged and slow.converged
    assert fast.W == pytest.approx(slow.W, rel=1e-9)
    assert fast.cycles <= most < slow.cycles
