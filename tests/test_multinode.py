"""Multi-node systems: chains with coupled stiffness (n = 2, 10, 100, with and without
separation), block-diagonal stacks of single nodes, d = 2; every method against the others and
against the explicit stepper."""

import numpy as np
import pytest

from lcpfric import InputError, SingleNode, make_scene, steady_state
from lcpfric.exact import exact_W_hat
from lcpfric.model import block_diagonal, chain, chain_stiffness

from support import need
from support import CASES, fitted_order

CONVEX = ("clarabel", "osqp", "qpsolvers:proxqp")


def make_chain(n, separation, dims=1):
    """A chain whose nodes are loaded out of phase; P̂1 = 1.5 separates every node in turn."""
    return chain(
        n,
        k_coupling=0.5,
        P1=1.5 if separation else 0.5,
        Q1=np.linspace(1.5, 2.5, n),
        phi=0.6 * np.pi,
        normal_phase=np.linspace(0.0, 1.0, n),
        dims=dims,
    )


def run_all(system, steps, methods):
    scene = make_scene(system, steps)
    out = {}
    for method in methods:
        need(method) if method not in ("explicit", "projection") else None
        out[method] = steady_state(scene, method, tol=1e-9)
    return scene, out


@pytest.mark.slow
@pytest.mark.parametrize(
    "n, steps",
    [
        pytest.param(2, 200, id="n=2"),
        pytest.param(10, 400, id="n=10", marks=pytest.mark.slow),
        pytest.param(100, 100, id="n=100", marks=pytest.mark.slow),
    ],
)
@pytest.mark.parametrize("separation", [False, True], ids=["contact", "separation"])
def test_chain_methods_agree(n, steps, separation):
    methods = ("explicit",) + CONVEX + (("cvxpy:CLARABEL",) if n == 2 else ())
    scene, res = run_all(make_chain(n, separation), steps, methods)
    ref = res["clarabel"]
    span = float(np.ptp(ref.v))
    assert (scene.N == 0).any() == separation
    for method, r in res.items():
        assert r.converged, method
        if method == "explicit":
            # the incremental problem and the event-located explicit stepper differ by the
            # time discretization only (measured: 3e-5 relative at 400 steps, 7e-4 at 100)
            assert abs(r.W - ref.W) <= 20.0 / steps**2 * ref.W
            assert float(np.max(np.abs(r.v - ref.v))) <= 0.8 / steps * span
        else:  # every convex backend solves the same problems: the same numbers
            assert abs(r.W - ref.W) <= 1e-11 * ref.W, method
            assert float(np.max(np.abs(r.v - ref.v))) <= 1e-10 * span, method
            np.testing.assert_array_equal(r.state, ref.state)
    if separation:
        assert (ref.state == 3).any() and (res["explicit"].state == 3).any()


@pytest.mark.slow
@pytest.mark.parametrize("separation", [False, True], ids=["contact", "separation"])
def test_chain_convex_and_explicit_converge_together(separation):
    need("osqp")
    system = make_chain(10, separation)
    steps = [100, 400, 1600]
    W = {m: [steady_state(system, m, s, tol=1e-9).W for s in steps] for m in ("explicit", "osqp")}
    diff = np.abs(np.subtract(W["explicit"], W["osqp"])) / W["explicit"][-1]
    # the convex backends locate the events inside an increment (lcpfric.steppers.rates):
    # they solve the same piecewise-linear problem as the explicit stepper (measured: equal to
    # round-off from 400 steps on; 2.4e-5 apart at 100 steps with separation)
    assert np.all(diff[1:] < 1e-9) and diff[0] < 1e-4, diff
    # each method is self-consistent at second order
    for m in W:
        assert abs(W[m][1] - W[m][2]) < abs(W[m][0] - W[m][1]) / 4


@pytest.mark.slow
def test_block_diagonal_reproduces_the_sum_of_single_nodes():
    cases = [CASES[c] for c in sorted(CASES)]
    nodes = [SingleNode.normalized(*c) for c in cases]
    system = block_diagonal(nodes)
    assert system.n == len(nodes) and system.is_diagonal()
    # the stacked nodes are normalized (K = 1, f = 1): J = Σ Q̂1_i Ŵ_i
    exact = sum(q1 * exact_W_hat(p1, q1, phi) for p1, q1, phi in cases)
    steps = 2000
    methods = ["projection", "explicit", "clarabel", "osqp"]
    for method in methods:
        if method in ("clarabel", "osqp"):
            need(method)
        r = steady_state(system, method, steps, tol=1e-9)
        assert abs(r.W - exact) <= 40.0 / steps**2 * exact, method


def test_block_diagonal_equals_its_nodes_on_the_same_grid():
    need("clarabel")
    nodes = [SingleNode.normalized(*CASES[c]) for c in ("separation", "contact-phase")]
    scene = make_scene(block_diagonal(nodes), 500)
    r = steady_state(scene, "clarabel", tol=1e-12)
    # each node of the stack, alone on the stack's grid
    parts = []
    for i, node in enumerate(nodes):
        sub = type(scene)(
            node.system(),
            None,
            scene.t,
            scene.Q[:, [i]],
            scene.N[:, [i]],
            scene.transitions,
            scene.placement,
        )
        parts.append(steady_state(sub, "clarabel", tol=1e-12).W)
    assert r.W == pytest.approx(sum(parts), rel=1e-12)


@pytest.mark.slow
def test_explicit_multinode_second_order_with_separation():
    system = make_chain(4, True)
    steps = [100, 200, 400, 800]
    W = [steady_state(system, "explicit", s, tol=1e-10).W for s in steps]
    ref = steady_state(system, "explicit", 3200, tol=1e-10).W
    errors = np.maximum(np.abs(np.asarray(W) - ref) / ref, 1e-16)
    assert fitted_order(steps, errors) > 1.5, errors


@pytest.mark.slow
def test_d2_chain_conic_backends_agree():
    need("clarabel")
    system = chain(
        3,
        k_coupling=0.5,
        dims=2,
        P1=[0.5, 1.5, 0.8],
        Q1=[[1.5, 1.0], [2.0, 0.5], [1.2, 1.2]],
        phi=[[0.6 * np.pi, 0.1], [0.3, 1.0], [0.0, 0.5 * np.pi]],
        normal_phase=[0.0, 0.5, 1.0],
    )
    scene = make_scene(system, 60)
    ref = steady_state(scene, "clarabel", tol=1e-10)
    assert ref.solver_stats["refined"] == ref.solver_stats["solves"]
    for method in ("cvxpy:CLARABEL", "cvxpy:SCS"):
        need(method)
        r = steady_state(scene, method, tol=1e-10)
        assert abs(r.W - ref.W) <= 1e-11 * ref.W, method
        np.testing.assert_allclose(r.v, ref.v, rtol=0, atol=1e-11)


def test_d2_uncoupled_equals_projection():
    need("clarabel")
    system = chain(
        3,
        k_coupling=0.0,
        dims=2,
        P1=[0.5, 1.5, 0.8],
        Q1=[[1.5, 1.0], [2.0, 0.5], [1.2, 1.2]],
        phi=[[0.6 * np.pi, 0.1], [0.3, 1.0], [0.0, 0.5 * np.pi]],
    )
    scene = make_scene(system, 200)
    a = steady_state(scene, "clarabel", tol=1e-10)
    b = steady_state(scene, "projection", tol=1e-10)
    assert a.W == pytest.approx(b.W, rel=1e-12)
    np.testing.assert_allclose(a.v, b.v, rtol=0, atol=1e-12)


def test_chain_stiffness_is_spd_and_sparse_on_request():
    K = chain_stiffness(5, 2.0, 0.5)
    assert np.allclose(K, K.T) and np.all(np.linalg.eigvalsh(K) > 0)
    assert K[0, 0] == 2.5 and K[1, 1] == 4.5 and K[0, 1] == -2.0
    Ks = chain_stiffness(5, 2.0, 0.5, dims=2, sparse=True)
    assert Ks.shape == (10, 10) and np.allclose(Ks.toarray()[::2, ::2], K)
    sys_sparse = chain(5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=1.0, sparse=True)
    sys_dense = chain(5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=1.0)
    a = steady_state(sys_sparse, "explicit", 100)
    b = steady_state(sys_dense, "explicit", 100)
    assert a.W == pytest.approx(b.W, rel=1e-13)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n": 0}, "n"),
        ({"n": 3, "k_ground": 0.0}, "k_ground"),
        ({"n": 3, "dims": 3}, "dims"),
        ({"n": 3, "P1": [1.0, 2.0]}, "P1"),
        ({"n": 3, "Q1": -1.0}, "Q1"),
        ({"n": 2, "dims": 2, "phi": np.zeros((3, 2))}, "phi"),
    ],
)
def test_chain_bad_input(kwargs, match):
    with pytest.raises(InputError, match=match):
        chain(**kwargs)


def test_block_diagonal_bad_input():
    with pytest.raises(InputError, match="nodes"):
        block_diagonal([])
    with pytest.raises(InputError, match="same d"):
        block_diagonal([chain(1, dims=1, Q1=1.0), chain(1, dims=2, Q1=1.0)])
