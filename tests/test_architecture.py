"""The architecture's contracts: one registry, explicit state, immutable results, one copy of each
formula, the normal-model protocol, and the recipe of docs/architecture.md for a new backend
followed end to end."""

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

import lcpfric
from lcpfric import (
    InputError,
    SingleNode,
    State,
    UndefinedQuantity,
    get_stepper,
    make_scene,
    steady_state,
)
from lcpfric.backends import ConvexStepper, IncrementProblem, residuals
from lcpfric.backends.checks import scalar_residuals, scalar_worst
from lcpfric.methods import (
    CLOSED_FORM,
    TIME_STEPPER,
    Method,
    available_methods,
    get_method,
    register,
    unregister,
)
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings, chain
from lcpfric.steppers import Stepper
from lcpfric.steppers.dissipation import increment_dissipation, node_shares, scalar_share

from support import need
from support import CASES

RNG = np.random.default_rng(8)


# -- one registry ----------------------------------------------------------------------------
def test_exact_is_in_the_registry():
    solver = get_stepper("exact")
    assert solver.kind == CLOSED_FORM and get_method("exact")[0].kind == CLOSED_FORM
    node = SingleNode.normalized(*CASES["separation"])
    assert steady_state(node, solver).W_hat == steady_state(node, "exact").W_hat
    assert get_stepper("explicit").kind == TIME_STEPPER


def test_every_listed_method_resolves():
    for name in available_methods():
        entry, _ = get_method(name)
        assert entry.kind in (CLOSED_FORM, TIME_STEPPER)


def test_listing_methods_imports_no_solver_package():
    code = (
        "import sys, lcpfric; lcpfric.available_methods(); "
        "print([m for m in ('clarabel', 'osqp', 'qpsolvers', 'cvxpy', 'scipy') "
        "if m in sys.modules])"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.strip()
    assert out == "[]"


def test_unknown_names_and_options_are_input_errors():
    node = SingleNode.normalized(0.5, 2.0, 0.0)
    with pytest.raises(InputError, match="max_cycle.*did you mean 'max_cycles'") as info:
        steady_state(node, "explicit", 100, max_cycle=5)
    assert info.value.parameter == "max_cycle"
    with pytest.raises(InputError, match="exact"):
        steady_state(node, "exact", refine=True)
    with pytest.raises(InputError, match="did you mean 'explicit'"):
        get_stepper("explicti")
    with pytest.raises(InputError, match="takes no ':<solver>'"):
        get_stepper("explicit:foo")


def test_register_refuses_duplicates():
    with pytest.raises(InputError, match="registered already"):
        register(Method("exact", CLOSED_FORM, "x", "lcpfric.closed_form:ExactSolver"))


# -- explicit state, immutable results ---------------------------------------------------------
@pytest.mark.parametrize("method", ["explicit", "projection", "clarabel", "osqp"])
def test_one_stepper_serves_two_scenes(method):
    if method in ("clarabel", "osqp"):
        need(method)
    stepper = get_stepper(method)
    s1 = make_scene(chain(3, k_coupling=0.0, P1=1.4, Q1=2.0, phi=1.0), 100)
    s2 = make_scene(SingleNode.normalized(*CASES["separation"]), 150)
    a, b = stepper.init(s1), stepper.init(s2)
    a1 = stepper.step(s1, 0, a)  # the first scene after the second was initialised
    b1 = stepper.step(s2, 0, b)
    fresh = get_stepper(method)
    assert np.array_equal(a1.u, fresh.step(s1, 0, fresh.init(s1)).u)
    assert np.array_equal(b1.u, fresh.step(s2, 0, fresh.init(s2)).u)
    assert stepper.stats(a) == stepper.stats(stepper.init(s1))  # the old state is unchanged


def test_results_are_immutable():
    r = steady_state(SingleNode.normalized(0.5, 2.0, 0.0), "projection", 100)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.W = 0.0
    scene = make_scene(SingleNode.normalized(0.5, 2.0, 0.0), 50)
    stepper = get_stepper("projection")
    state, cyc = stepper.cycle(scene, stepper.init(scene))
    with pytest.raises(dataclasses.FrozenInstanceError):
        cyc.W = 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        state.u = None


def test_results_mean_one_thing():
    """W is the dissipation in the model's units for every input; Ŵ exists for a node only."""
    node = SingleNode.normalized(*CASES["separation"])
    as_node = steady_state(node, "projection", 400)
    as_system = steady_state(node.system(), "projection", 400)
    assert as_node.W == pytest.approx(as_system.W, rel=1e-14)
    assert as_node.W == pytest.approx(node.Q1_hat * as_node.W_hat, rel=1e-15)
    with pytest.raises(UndefinedQuantity):
        as_system.W_hat
    with pytest.raises(AttributeError):  # UndefinedQuantity is an AttributeError too
        as_system.v_hat
    assert as_node.steps_requested == 400 and as_node.steps_used == 401  # separation added
    ex = steady_state(node, "exact", 400)
    assert ex.steps_used == 0 and ex.steps_requested == 400 and ex.t.size == 401


# -- one copy of each formula -------------------------------------------------------------------
@pytest.mark.parametrize("method", ["explicit", "projection"])
def test_scalar_fast_path_equals_step_by_step(method):
    """The single node's whole-cycle scalar loops are separate code: they must agree with the
    generic step-by-step loop."""
    for case in ("separation", "contact-phase", "near-shakedown"):
        scene = make_scene(SingleNode.normalized(*CASES[case]), 300)
        stepper = get_stepper(method)
        state = stepper.init(scene, [0.3])
        _, fast = stepper.cycle(scene, state)
        _, slow = Stepper.cycle(stepper, scene, state)
        np.testing.assert_allclose(fast.u, slow.u, rtol=0, atol=1e-13)
        np.testing.assert_allclose(fast.F, slow.F, rtol=0, atol=1e-13)
        np.testing.assert_array_equal(fast.state, slow.state)
        assert fast.W == pytest.approx(slow.W, rel=1e-12)


def test_dissipation_forms_agree():
    F0, F1, du = RNG.normal(size=(3, 500))
    shares = node_shares(F0[:, None], F1[:, None], du[:, None])[:, 0]
    assert np.array_equal(shares, [scalar_share(a, b, c) for a, b, c in zip(F0, F1, du)])
    assert increment_dissipation(F0, F1, du) == pytest.approx(shares.sum(), rel=1e-15)
    assert np.all(shares >= 0.0)
    two = node_shares(F0[:4], F1[:4], du[:4], dims=2)  # two nodes, d = 2: summed per node
    assert two.shape == (2,)


def test_residual_forms_agree():
    c, fs = 0.7, 2.0
    for _ in range(300):
        F, g = RNG.normal(size=2)
        b = abs(RNG.normal()) + 0.1
        F = float(np.clip(F, -b, b)) if RNG.random() < 0.5 else F
        arr = residuals(np.array([F]), np.array([g]), np.array([b]), 1, fs, c)
        sca = scalar_residuals(F, g, b, c, (fs, c * fs * fs))
        assert arr == pytest.approx(sca, rel=1e-15, abs=1e-300)
        assert scalar_worst(F, g, b, c, (fs, c * fs * fs)) == pytest.approx(max(sca.values()))


def test_node_states_are_one_enum():
    from lcpfric import exact

    r = steady_state(SingleNode.normalized(*CASES["separation"]), "explicit", 400)
    assert set(np.unique(r.state)) <= {int(s) for s in State}
    assert State.SEPARATION in set(r.state.tolist())
    for name in ("STICK", "FORWARD", "BACKWARD", "SEPARATION"):
        assert getattr(exact, name) == getattr(State, name)
    assert State.FORWARD.label == "forward slip"


# -- the normal-model protocol -------------------------------------------------------------------
class DelegatingNormal:
    """A normal model that is not IndependentSprings: it provides the protocol's members only."""

    def __init__(self, loads):
        self._inner = IndependentSprings(loads)
        self.n = self._inner.n
        self.period = self._inner.period

    def reactions(self, t):
        return self._inner.reactions(t)

    def transitions(self, t0, t1):
        return self._inner.transitions(t0, t1)

    def scale(self, t):
        return self._inner.scale(t)

    def always_in_contact(self):
        return self._inner.always_in_contact()


def test_any_normal_model_with_the_protocol_works():
    loads = (Harmonic(1.0, 1.5, 0.0), Harmonic(1.0, 0.5, 0.4))
    tang = (Harmonic(0.0, 2.0, 1.0), Harmonic(0.0, 1.0, 0.2))
    K = np.array([[2.0, -0.5], [-0.5, 1.5]])
    a = ContactSystem(K, [1.0, 0.8], tang, IndependentSprings(loads))
    b = ContactSystem(K, [1.0, 0.8], tang, DelegatingNormal(loads))
    assert steady_state(a, "explicit", 300).W == steady_state(b, "explicit", 300).W
    with pytest.raises(InputError, match="normal model"):
        ContactSystem(K, [1.0, 0.8], tang, object())


def test_supplied_compliance_is_checked():
    loads = (Harmonic(1.0, 0.5, 0.0),) * 2
    tang = (Harmonic(0.0, 1.0, 1.0),) * 2
    K = np.array([[2.0, -0.5], [-0.5, 1.5]])
    ok = ContactSystem(K, [1.0, 1.0], tang, IndependentSprings(loads), compliance=np.linalg.inv(K))
    assert np.allclose(ok.compliance_matrix() @ K, np.eye(2))
    with pytest.raises(InputError, match="compliance.*inverse"):
        ContactSystem(K, [1.0, 1.0], tang, IndependentSprings(loads), compliance=np.eye(2))


# -- recipe 1 of docs/architecture.md, followed: a new backend -----------------------------------
class BVLSStepper(ConvexStepper):
    """Problem (P), d = 1, by scipy's bounded-variable least squares (a toy backend).

    With P = L Lᵀ, ½ Fᵀ P F + qᵀ F = ½ ||Lᵀ F + L⁻¹ q||² + const, a bounded least-squares
    problem."""

    name = "scipy-bvls"
    can_soc = False
    # scipy's lsq_linear statuses: 1-3 converged (gtol, ftol, xtol), 0 iteration limit
    STATUS_MAP = {"1": "solved", "2": "solved", "3": "solved", "0": "max_iter", "-1": "numerical"}

    def build(self, prob: IncrementProblem, settings: dict):
        P = prob.P.toarray() if hasattr(prob.P, "toarray") else np.asarray(prob.P)
        L = np.linalg.cholesky(P)
        return L

    def solve(self, prob, q, bdata):
        from scipy.optimize import lsq_linear

        L = prob.handle
        rhs = -np.linalg.solve(L, q)
        res = lsq_linear(L.T, rhs, bounds=bdata, method="bvls", tol=1e-14)
        return res.x, str(res.status), res.status in (1, 2, 3)


@pytest.fixture
def bvls_backend():
    register(
        Method("scipy-bvls", TIME_STEPPER, "toy backend", BVLSStepper, dims=(1,), requires="scipy")
    )
    yield
    unregister("scipy-bvls")


def test_recipe_new_backend_end_to_end(bvls_backend):
    need("clarabel")
    assert "scipy-bvls" in available_methods()
    system = chain(3, k_coupling=0.7, P1=1.4, Q1=2.0, phi=1.0, normal_phase=[0.0, 0.4, 0.8])
    ours = steady_state(system, "scipy-bvls", 300)
    ref = steady_state(system, "clarabel", 300)
    assert ours.method == "scipy-bvls" and ours.converged
    assert ours.W == pytest.approx(ref.W, rel=1e-12)
    node = SingleNode.normalized(*CASES["separation"])  # the scalar fast path too
    assert steady_state(node, "scipy-bvls", 300).W_hat == pytest.approx(
        steady_state(node, "projection", 300).W_hat, rel=1e-12
    )
    with pytest.raises(InputError, match="cannot express the d = 2"):
        steady_state(chain(2, dims=2, P1=0.5, Q1=1.0), "scipy-bvls", 50)


def test_public_names_are_lazy_and_complete():
    for name in lcpfric.__all__:
        assert getattr(lcpfric, name) is not None
    code = "import sys, lcpfric; print('scipy' in sys.modules, 'lcpfric.periodic' in sys.modules)"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.split()
    assert out == ["False", "False"]
