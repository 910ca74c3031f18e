"""One world: every model (the single node, discrete systems, the continuum contacts) goes
through the one driver to the one result type, its methods named by the one registry; a model
holds no solver state, so a solve leaves it as it was and solving it again gives the same
bits; a method that cannot solve a model says which can."""

import math

import numpy as np
import pytest

import lcpfric
from lcpfric import InputError, SteadyState, UndefinedQuantity
from lcpfric.model import Harmonic

TWO_PI = 2.0 * math.pi


def _models():
    return {
        "node": lcpfric.SingleNode.normalized(1.5, 2.0, 0.6 * math.pi),
        "chain": lcpfric.chain(3, k_coupling=1.0, P1=0.5, Q1=1.2, phi=0.4),
        "mdr": lcpfric.MDRSphere(
            1.0, 1.0, 0.0, 0.5, Harmonic(1.0, 0.5), Harmonic(0.0, 0.2, 0.7), nodes=60
        ),
        "halfplane": lcpfric.HalfPlaneCylinder(
            1.0, 1.0, 0.0, 0.5, Harmonic(1.0, 0.5), Harmonic(0.0, 0.2, 0.7), nodes=40
        ),
        "halfspace": lcpfric.HalfSpace.sphere(
            1.0,
            1.0,
            0.3,
            0.5,
            Harmonic(1.0, 0.5, 0.0, TWO_PI),
            Harmonic(0.0, 0.2, 0.7, TWO_PI),
            grid=12,
            dims=2,
        ),
    }


@pytest.mark.parametrize("name", ["node", "chain", "mdr", "halfplane", "halfspace"])
def test_every_model_through_the_one_driver(name):
    model = _models()[name]
    r = lcpfric.steady_state(model, steps_per_cycle=60)
    assert isinstance(r, SteadyState) and r.converged and r.W > 0
    assert r.method == model.default_method
    assert r.method in lcpfric.methods_for(model)
    if r.method != "exact":  # the closed form takes no steps: its series are samples
        assert r.changes.size == r.cycles - 1 and r.changes[-1] == r.change
        assert r.t.size == r.steps_used + 1
    assert r.v.shape[0] == r.t.size
    if name in ("mdr", "halfplane", "halfspace"):
        assert r.W_normalized == r.contact.W_normalized > 0
        assert r.contact.nodes == model.nodes and r.stick_size().shape == r.t.shape
        with pytest.raises(UndefinedQuantity):
            r.W_hat
    else:
        with pytest.raises(UndefinedQuantity):
            r.W_normalized


@pytest.mark.parametrize("name", ["mdr", "halfplane", "halfspace"])
def test_a_solve_leaves_the_model_as_it_was(name):
    """No statistics, caches or warm starts on the model: its attributes are the same objects
    with the same values after a solve, and a second solve gives the same bits."""
    model = _models()[name]

    def snapshot():
        return {
            k: (id(v), v.copy() if isinstance(v, np.ndarray) else v) for k, v in vars(model).items()
        }

    before = snapshot()
    first = lcpfric.steady_state(model, steps_per_cycle=40)
    after = snapshot()
    assert before.keys() == after.keys()
    for key, (ident, value) in before.items():
        assert after[key][0] == ident, key
        if isinstance(value, np.ndarray):
            assert np.array_equal(after[key][1], value), key
    second = lcpfric.steady_state(model, steps_per_cycle=40)
    assert second.W == first.W and second.cycles == first.cycles
    assert first.solver_stats and "normal_solves" in first.solver_stats or name == "mdr"


def test_the_history_off_keeps_the_ends():
    r = lcpfric.steady_state(_models()["mdr"], steps_per_cycle=40, history=False)
    full = lcpfric.steady_state(_models()["mdr"], steps_per_cycle=40)
    assert r.t.size == 2 and r.state.shape[0] == 2 and r.W == full.W
    with pytest.raises(InputError, match="history"):
        r.stick_size()


@pytest.mark.parametrize(
    "name, method, right",
    [
        ("mdr", "active-set", "mdr-bar"),
        ("halfspace", "exact", "newton-cg"),
        ("node", "mdr-bar", "exact"),
        ("halfplane", "newton-cg", "halfplane-pdas"),
    ],
)
def test_a_method_that_cannot_solve_a_model_names_those_that_can(name, method, right):
    with pytest.raises(InputError, match=right) as info:
        lcpfric.steady_state(_models()[name], method, 40)
    assert info.value.parameter == "method"


def test_a_contact_as_a_system_is_solved_by_the_discrete_methods():
    """The contact held by a support, as a matrix-free ContactSystem (model.system()): the
    discrete methods solve it through the same driver, and agree with the model's own
    stepper on the same grid."""
    m = lcpfric.MDRSphere(
        1.0, 1.0, 0.0, 0.5, Harmonic(1.0, 0.3), Harmonic(0.0, 0.2, 0.7), nodes=40, k_support=0.5
    )
    scene = lcpfric.make_scene(m.system(), 80)
    own = lcpfric.steady_state(lcpfric.make_scene(m, grid=scene.t), tol=1e-12)
    other = lcpfric.steady_state(scene, "active-set", tol=1e-12, locate_events=False)
    assert other.W == pytest.approx(own.W, rel=1e-9)


def test_contact_scenes_share_their_normal_problem():
    """A contact's scene under another tangential load keeps the friction limits (solved once)
    and has the new load's scales; its steady state equals that of a model built with it."""
    P = Harmonic(1.0, 0.5, 0.0, TWO_PI)
    base = lcpfric.HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, P, 0.0, grid=12)
    scene = lcpfric.make_scene(base, 40)
    Q = Harmonic(0.0, 0.15, 0.4, TWO_PI)
    shared = lcpfric.with_tangential_load(scene, Q)
    assert shared.limits is scene.limits and shared.scales != scene.scales
    direct = lcpfric.HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, P, Q, grid=12)
    assert lcpfric.steady_state(shared).W == lcpfric.steady_state(direct, steps_per_cycle=40).W
    with pytest.raises(InputError, match="k_support"):  # |Q| > μ P: refused, as a model
        lcpfric.with_tangential_load(scene, Harmonic(0.0, 0.6, 0.0, TWO_PI))


def test_the_contacts_own_options_are_the_steppers():
    m = _models()["halfspace"]
    with pytest.raises(InputError, match="increment_tol"):
        lcpfric.steady_state(m, "newton-cg", 40, increment_tol=-1.0)
    with pytest.raises(InputError, match="valid options"):
        lcpfric.steady_state(m, "newton-cg", 40, refine=True)
    with pytest.raises(InputError, match="placement"):
        lcpfric.steady_state(m, steps_per_cycle=40, placement="contact")
    with pytest.raises(InputError, match="u0"):
        lcpfric.steady_state(m, steps_per_cycle=40, u0=np.zeros(m.nodes * 2))
