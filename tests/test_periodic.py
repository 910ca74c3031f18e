"""The periodic driver: convergence judged on scales that do not vanish, shakedown reported as
converged with W = 0, and a time grid that does not depend on ω through round-off."""

import numpy as np
import pytest

from lcpfric import SingleNode, steady_state
from lcpfric.model import chain
from lcpfric.periodic import cycle_change

from support import need


def test_cycle_change_scales():
    # a cycle that barely moves is judged against the loads' scale, not its own range
    assert cycle_change(1e-12, 1e-11, 0.0, 0.0, (2.0, 2.0)) == pytest.approx(5e-13)
    # W judged against W where it is the larger scale
    assert cycle_change(0.0, 1.0, 1e-3, 10.0, (1.0, 1.0)) == pytest.approx(1e-4)
    assert cycle_change(0.0, 0.0, 0.0, 0.0, (0.0, 0.0)) == 0.0
    assert cycle_change(1.0, 0.0, 0.0, 0.0, (0.0, 0.0)) == np.inf
    arr = cycle_change(
        np.array([0.0, 1e-3]), np.ones(2), np.zeros(2), np.ones(2), (np.ones(2), np.ones(2))
    )
    assert arr.shape == (2,) and arr[1] == pytest.approx(1e-3)


def test_single_node_that_barely_slips_converges():
    """(P̂1, Q̂1, φ) = (1e-6, 1, 0): the range of v tends to zero as it shakes down (issue 9)."""
    r = steady_state(SingleNode.normalized(1e-6, 1.0, 0.0), "explicit", 400)
    assert r.converged and r.cycles < 100
    assert r.W_hat == pytest.approx(0.0, abs=1e-5)


def test_shakedown_is_converged_with_W_zero():
    # on the shakedown boundary (Q̂1 = 1 at φ = 0): the nodes touch their limits, W is round-off
    sys_sparse = chain(5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=1.0, sparse=True)
    sys_dense = chain(5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=1.0)
    for system in (sys_sparse, sys_dense):
        r = steady_state(system, "explicit", 100)
        assert r.converged and abs(r.W) < 1e-12
    inside = chain(5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=0.8)
    node = SingleNode.normalized(0.5, 0.7, 0.3 * np.pi)  # inside the shakedown region
    for model, methods in ((inside, ("explicit",)), (node, ("explicit", "projection"))):
        for method in methods:
            r = steady_state(model, method, 200)
            assert r.converged and r.W == 0.0 and "shakedown" in r.message


def test_tiny_dissipation_under_large_limits_is_kept():
    """Ŵ = 2e-6 at P̂1 = 1e6, Q̂1 = 1e-6: small against the friction limits, but resolved."""
    node = SingleNode.normalized(1e6, 1e-6, np.pi / 2)
    for method in ("explicit", "projection"):
        r = steady_state(node, method, 4000)
        assert r.W_hat == pytest.approx(2e-6, rel=1e-3) and "shakedown" not in r.message


@pytest.mark.slow
@pytest.mark.parametrize("method", ["explicit", "osqp", "clarabel"])
def test_stiff_chain_that_slips_little_converges(method):
    """The 5-node chain of issue 9 (relative change 2e-7 to 3e-8 after 100 cycles before)."""
    if method != "explicit":
        need(method)
    system = chain(
        5,
        k_coupling=100.0,
        k_ground=1.0,
        friction=0.4,
        P0=1.0,
        P1=0.6,
        normal_phase=[0.0, 0.4, 0.9, 1.3, 2.0],
        Q1=[0.3, 0.5, 0.2, 0.6, 0.4],
        phi=[1.0, 1.5, 0.8, 2.0, 1.2],
    )
    r = steady_state(system, method, 2000)
    assert r.converged and r.cycles < 100 and r.W >= 0.0


def test_time_grid_does_not_depend_on_omega():
    """A ceiling saw 400.00000000000006 and added a step at some ω (issue 9)."""
    kw = dict(
        k11=0.012201058565709777,
        f=0.030050234381531534,
        P0=3881.647934869681,
        P1=156694.69867660385,
        Q1=2.217107930761032,
        phi=-5.55106807724441,
    )
    a = steady_state(SingleNode(omega=1.0, **kw), "projection", 400)
    b = steady_state(SingleNode(omega=3918.7748195993795, **kw), "projection", 400)
    assert a.steps_used == b.steps_used == 401  # 400 in contact, one over the separation
    assert a.W_hat == pytest.approx(b.W_hat, rel=1e-13)


def test_anderson_reaches_the_fixed_point_of_an_affine_map():
    """A contraction with slow modes (ratios 0.99 to 0.1): the plain iteration needs thousands
    of steps for 1e-10, Anderson's acceleration a dozen (depth 5 and the default 10); a
    growing residual drops the history."""
    from lcpfric.periodic.acceleration import Anderson

    rng = np.random.default_rng(3)
    Qm, _ = np.linalg.qr(rng.standard_normal((40, 40)))
    ratios = np.r_[0.99, 0.95, 0.8, 0.5, np.full(36, 0.1)]
    A = (Qm * ratios) @ Qm.T
    c = rng.standard_normal(40)
    fixed = np.linalg.solve(np.eye(40) - A, c)
    for acc in (Anderson(5), Anderson()):
        x = np.zeros(40)
        for k in range(30):
            g = A @ x + c
            if np.linalg.norm(g - x) <= 1e-10 * np.linalg.norm(fixed):
                break
            nxt = acc(x, g)
            x = g if nxt is None else nxt
        assert k <= 15 and np.allclose(x, fixed, rtol=0, atol=1e-8 * np.linalg.norm(fixed))
    acc(np.zeros(40), np.ones(40))  # a residual larger than the last: a fresh start
    assert len(acc.x) == 1 and acc(np.ones(40), np.ones(40) * 2) is not None


def test_anderson_falls_back_to_aitken_where_it_stalls():
    """Residuals that shrink by less than a tenth three cycles running switch the accelerator to
    the plain iteration, which Aitken's jump then takes to the fixed point of one slow mode."""
    from lcpfric.periodic.acceleration import Anderson

    acc = Anderson(5)
    x = np.array([1.0, 0.0])
    for norm in (1.0, 0.95, 0.93, 0.92):  # stalled: no jump is trusted any more
        acc(x, x + np.array([0.0, norm]))
    assert acc.starts is not None
    fixed, rho = np.array([2.0, -1.0]), 0.9
    x, jump = fixed + np.array([1.0, 1.0]), None
    for _ in range(6):
        g = fixed + rho * (x - fixed)  # one slow mode
        jump = acc(x, g)
        if jump is not None:
            break
        x = g
    assert jump is not None and np.allclose(jump, fixed, atol=1e-12)
