"""The convex backends on the paper's node: against the projection and the exact solution, their
failure paths (the typed error with the backend's own status) and their input checks."""

import numpy as np
import pytest

from lcpfric import (
    InputError,
    UndefinedQuantity,
    SingleNode,
    SolverError,
    SolverNotFound,
    available_methods,
    get_stepper,
    make_scene,
    steady_state,
)
from lcpfric.exact import exact_W_hat
from lcpfric.scene import Scene
from lcpfric.model import chain

from support import BACKENDS, FAST, REFINED, need, params
from support import CASES

SLOW_CASES = ("separation", "contact-phase")
PAIRS = [
    pytest.param(m, c, id=f"{m}-{c}")
    for m in BACKENDS
    for c in (sorted(CASES) if m in FAST else SLOW_CASES)
]


def projection(node, steps):
    return steady_state(node, "projection", steps).W_hat


@pytest.mark.parametrize("method, case", PAIRS)
def test_single_node_reproduces_projection_and_exact(method, case):
    need(method)
    P1, Q1, phi = CASES[case]
    steps = BACKENDS[method][2]
    node = SingleNode.normalized(P1, Q1, phi)
    res = steady_state(node, method, steps)
    assert res.converged and res.method == method
    ref = projection(node, steps)
    # refined on its active set, every backend gives the projection's numbers
    assert abs(res.W_hat - ref) <= REFINED * ref
    assert res.solver_stats["refined"] == res.solver_stats["solves"] > 0
    exact = exact_W_hat(P1, Q1, phi)
    assert abs(res.W_hat - exact) <= 40.0 / steps**2 * exact  # second order in the steps


@pytest.mark.parametrize("method", params())
def test_unrefined_answers_within_backend_tolerance(method):
    need(method)
    extra, tol, steps, _ = BACKENDS[method]
    node = SingleNode.normalized(*CASES["separation"])
    steps = min(steps, 400)
    res = steady_state(node, method, steps, refine=False, tol=1e-6)
    ref = projection(node, steps)
    assert abs(res.W_hat - ref) <= tol * ref
    assert res.solver_stats["refined"] == 0
    assert res.solver_stats["max_residual"] <= 1e-6


@pytest.mark.parametrize("method", params(FAST))
def test_accuracy_at_4000_steps(method):
    need(method)
    P1, Q1, phi = CASES["separation"]
    res = steady_state(SingleNode.normalized(P1, Q1, phi), method, 4000)
    exact = exact_W_hat(P1, Q1, phi)
    assert abs(res.W_hat - exact) < 2e-6 * exact


def test_single_node_through_the_general_system_is_identical():
    need("clarabel")
    node = SingleNode.normalized(*CASES["separation"])
    a = steady_state(node, "clarabel", 500)
    b = steady_state(make_scene(node.system(), 500), "clarabel")
    with pytest.raises(UndefinedQuantity, match="W_hat"):
        b.W_hat  # a general system has no Eq. (6) normalization
    assert b.W == pytest.approx(a.W_hat * node.Q1_hat, rel=1e-15) == pytest.approx(a.W, rel=1e-15)


@pytest.mark.parametrize("method", params(FAST))
@pytest.mark.parametrize("size", [1, 3])
def test_step_by_step_equals_cycle(method, size):
    need(method)
    if size == 1:
        scene = make_scene(SingleNode.normalized(*CASES["separation"]), 200)
    else:
        scene = make_scene(
            chain(3, k_coupling=0.7, P1=1.4, Q1=2.0, phi=1.0, normal_phase=[0.0, 0.4, 0.8]), 200
        )
    a, b = get_stepper(method), get_stepper(method)
    sa, sb = a.init(scene), b.init(scene)
    W = 0.0
    for k in range(scene.steps):
        sa = a.step(scene, k, sa)
        W += sa.dW
    sb, cyc = b.cycle(scene, sb)
    np.testing.assert_allclose(sa.u, cyc.u[-1], rtol=0, atol=1e-13)
    np.testing.assert_allclose(sa.F, cyc.F[-1], rtol=0, atol=1e-13)
    np.testing.assert_array_equal(sa.state, cyc.state[-1])
    assert W == pytest.approx(cyc.W, rel=1e-12)


# -- failure paths -------------------------------------------------------------------------------
@pytest.mark.parametrize("method", params())
def test_iteration_limit_raises_with_backend_status(method):
    need(method)
    settings, status = BACKENDS[method][3]
    node = SingleNode.normalized(*CASES["separation"])
    with pytest.raises(SolverError) as info:
        steady_state(node, method, 40, **settings)
    assert info.value.backend == method
    assert info.value.status.startswith(status), info.value.status
    assert "increment 0" in str(info.value)


def inconsistent_scene():
    """A node marked in contact with a negative normal reaction: the step is infeasible."""
    scene = make_scene(SingleNode.normalized(0.5, 2.0, 0.6 * np.pi), 50)
    N = scene.N.copy()
    N[10] = -0.5
    return Scene(
        scene.system,
        scene.model,
        scene.t,
        scene.Q,
        N,
        scene.transitions,
        scene.placement,
        _cache={"contact": np.ones_like(N, dtype=bool)},
    )


@pytest.mark.parametrize(
    "method, status",
    [
        ("clarabel", "PrimalInfeasible"),
        ("osqp", "solved"),
        ("qpsolvers:clarabel", "PrimalInfeasible"),
        ("cvxpy:CLARABEL", "infeasible"),
    ],
)
def test_inconsistent_data_raises_with_backend_status(method, status):
    need(method)
    with pytest.raises(SolverError) as info:
        steady_state(inconsistent_scene(), method)
    assert info.value.status == status
    assert "increment 9" in str(info.value)
    if status == "solved":
        # OSQP refuses the update (lower bound above upper) and "solves" the old problem:
        # only the residual check sees it
        assert info.value.residuals["cone"] > 1e-3


@pytest.mark.parametrize(
    "method, loose",
    [
        ("osqp", {"eps_abs": 1e-3, "eps_rel": 1e-3}),  # OSQP's own defaults: off by ~2e-3
        ("clarabel", {"tol_gap_abs": 1e-8, "tol_gap_rel": 1e-8, "tol_feas": 1e-8}),  # ~2e-5
    ],
)
def test_poor_answer_reported_solved_is_caught_and_refinement_repairs_it(method, loose):
    need(method)
    node = SingleNode.normalized(*CASES["separation"])
    with pytest.raises(SolverError) as info:
        steady_state(node, method, 200, refine=False, **loose)
    assert info.value.status in ("solved", "Solved")
    assert max(info.value.residuals.values()) > 1e-6
    assert "residual check" in str(info.value)
    res = steady_state(node, method, 200, **loose)
    assert abs(res.W_hat - projection(node, 200)) <= REFINED * res.W_hat


def test_nan_loads_are_input_errors():
    need("clarabel")
    scene = make_scene(SingleNode.normalized(0.5, 2.0, 0.0), 20)
    Q = scene.Q.copy()
    Q[3] = np.nan
    bad = Scene(scene.system, scene.model, scene.t, Q, scene.N, scene.transitions, scene.placement)
    with pytest.raises(InputError, match="finite"):
        steady_state(bad, "clarabel")


@pytest.mark.parametrize(
    "method, options, match",
    [
        ("clarabel", {"no_such_setting": 1}, "no_such_setting"),
        ("osqp", {"no_such_setting": 1}, "no_such_setting"),
        ("clarabel", {"check_tol": -1.0}, "check_tol"),
        ("qpsolvers", {}, "qpsolvers:<solver>"),
        ("cvxpy:GLPK", {}, "GLPK"),
    ],
)
def test_bad_options_are_input_errors(method, options, match):
    need(
        method if method in BACKENDS else "qpsolvers:proxqp" if "qp" in method else "cvxpy:CLARABEL"
    )
    node = SingleNode.normalized(0.5, 2.0, 0.0)
    with pytest.raises(InputError, match=match):
        steady_state(node, method, 20, **options)


def test_unknown_qpsolvers_solver_lists_the_installed_ones():
    need("qpsolvers:proxqp")
    with pytest.raises(InputError, match="nosuchsolver.*installed: .*proxqp"):
        get_stepper("qpsolvers:nosuchsolver")


def test_a_missing_solver_package_names_the_package():
    """cvxpy:ECOS without ecos: `pip install ecos` helps, not the cvxpy extra."""
    from lcpfric.methods import get_method

    entry, _ = get_method("cvxpy:ECOS")
    if "ECOS" in entry.installed_solvers():
        pytest.skip("ecos is installed here")
    with pytest.raises(SolverNotFound, match="pip install ecos"):
        get_stepper("cvxpy:ECOS")


@pytest.mark.parametrize("method", ["osqp", "qpsolvers:proxqp", "cvxpy:OSQP"])
def test_qp_backends_refuse_the_d2_cone(method):
    need(method)
    system = chain(2, dims=2, P1=0.5, Q1=1.5, phi=0.3)
    with pytest.raises(InputError, match="clarabel"):
        steady_state(system, method, 20)


def test_registry_lists_the_installed_backends():
    import importlib.util

    names = available_methods()
    for method in BACKENDS:
        if method in names:
            assert get_stepper(method).label == method
    # a backend is listed exactly when its package is installed
    for name, package in (("clarabel", "clarabel"), ("osqp", "osqp")):
        assert (name in names) == (importlib.util.find_spec(package) is not None)
