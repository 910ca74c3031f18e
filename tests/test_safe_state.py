"""The safe state of a discrete system (lcpfric.analysis.safe_state): the single node's closed
form node by node, a safe displacement that is safe, and Melan's theorem against ``exact``."""

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError


@pytest.mark.parametrize("seed", range(6))
def test_a_node_as_a_system_is_the_single_nodes_closed_form(seed):
    rng = np.random.default_rng(seed)
    P1, Q1, phi = rng.uniform(0, 0.95), rng.uniform(0, 2.5), rng.uniform(0, 2 * np.pi)
    node = lcpfric.SingleNode.normalized(P1, Q1, phi)
    want = lcpfric.shakedown(node)
    got = lcpfric.shakedown(node.system())
    assert got.shakedown == want.shakedown
    assert got.margin == pytest.approx(want.margin, abs=1e-10)


def _chain(P1, Q1, phi, seed=0):
    n = len(P1)
    return lcpfric.chain(
        n, k_coupling=3.0, P1=np.asarray(P1), Q1=np.asarray(Q1), phi=np.asarray(phi)
    )


def test_the_safe_displacement_is_safe():
    system = _chain([0.3, 0.5, 0.2], [0.4, 0.6, 0.3], [0.2, 2.0, 4.0])
    sd = lcpfric.shakedown(system)
    assert sd.shakedown and sd.margin > 0
    t = np.linspace(0.0, system.period, 20001)
    F = system.tangential(t) + system.dense_stiffness() @ sd.state
    limit = system.friction * system.normal.reactions(t)
    assert np.all(np.abs(F) <= limit)
    assert sd.as_dict()["state"] == pytest.approx(list(sd.state))


@pytest.mark.parametrize(
    "P1, Q1, phi, shakes",
    [
        ([0.3, 0.5, 0.2, 0.6], [0.4, 0.6, 0.3, 0.2], [0.2, 2.0, 4.0, 1.0], True),
        ([0.3, 0.5, 0.2, 0.6], [0.4, 1.9, 0.3, 0.2], [0.2, 2.0, 4.0, 1.0], False),
        ([0.8, 0.1, 0.5], [0.3, 0.2, 0.45], [3.0, 0.5, 1.6], True),
        ([0.8, 0.1, 0.5], [1.2, 0.2, 0.45], [1.5, 0.5, 1.6], False),
    ],
)
def test_melan_a_safe_state_means_no_dissipation_in_the_steady_state(P1, Q1, phi, shakes):
    """Uncoupled normal reactions: a safe state (margin > 0) and the steady W = 0 go together,
    whatever K couples the nodes."""
    system = _chain(P1, Q1, phi)
    sd = lcpfric.shakedown(system)
    W = lcpfric.steady_state(system, "exact").W
    scale = float(np.max(np.asarray(Q1)) ** 2)
    assert sd.shakedown == shakes
    if shakes:
        assert sd.margin > 0 and abs(W) <= 1e-12 * scale
    else:
        assert sd.margin < 0 and W > 1e-6 * scale


def test_a_node_that_separates_has_no_safe_state():
    system = _chain([0.3, 1.4], [0.2, 0.3], [0.5, 0.5])
    sd = lcpfric.shakedown(system)
    assert not sd.shakedown and sd.margins[1] < 0 <= sd.margins[0]
    assert sd.state is None


def test_d2_and_other_models_are_refused_by_name():
    from lcpfric.analysis.safe_state import safe_band

    with pytest.raises(InputError, match="model"):
        safe_band(lcpfric.SingleNode.normalized(0.5, 0.5, 0.0))
    d2 = lcpfric.chain(2, P1=0.5, Q1=0.4, phi=0.3, dims=2)
    with pytest.raises(InputError, match="dims"):
        lcpfric.shakedown(d2)
    with pytest.raises(InputError, match="samples"):
        safe_band(_chain([0.3], [0.2], [0.1]), samples=3)


# -- the start as an input (issue 38, item 3): exact follows it, every method checks it ----------
def test_exact_from_a_safe_start_stays_there():
    """Where the system shakes down its steady state is the start's own: from a safe
    displacement nothing slips, and ``exact`` keeps it (it ignored the start before)."""
    system = _chain([0.3, 0.5, 0.2], [0.4, 0.6, 0.3], [0.2, 2.0, 4.0])
    sd = lcpfric.shakedown(system)
    r = lcpfric.steady_state(system, "exact", u0=sd.state)
    assert r.W == 0.0
    np.testing.assert_allclose(r.v, np.broadcast_to(sd.state, r.v.shape), rtol=0, atol=1e-14)
    other = lcpfric.steady_state(system, "exact")
    assert np.max(np.abs(other.v[0] - sd.state)) > 1e-3  # another start, another steady state


def test_exact_and_explicit_reach_the_same_state_from_one_start():
    system = _chain([0.3, 0.5, 0.2], [0.4, 0.6, 0.3], [0.2, 2.0, 4.0])
    Q0, b = system.tangential(0.0), system.friction * system.normal.reactions(0.0)
    u0 = system.solve(np.array([0.9, -0.95, 0.5]) * b - Q0)
    ex = lcpfric.steady_state(system, "exact", u0=u0)
    st = lcpfric.steady_state(system, "explicit", 4000, u0=u0)
    assert np.max(np.abs(ex.v[0] - st.v[0])) < 1e-3 * np.max(np.abs(u0))
    assert ex.W == 0.0 and abs(st.W) < 1e-12


def test_the_start_does_not_change_an_uncoupled_systems_steady_w():
    system = _chain([0.3, 0.5, 0.2, 0.6], [0.4, 1.9, 0.3, 0.2], [0.2, 2.0, 4.0, 1.0])
    Q0, b = system.tangential(0.0), system.friction * system.normal.reactions(0.0)
    u0 = system.solve(np.array([0.9, -0.95, 0.5, 0.0]) * b - Q0)
    W = lcpfric.steady_state(system, "exact").W
    assert lcpfric.steady_state(system, "exact", u0=u0).W == pytest.approx(W, rel=1e-10)


def test_the_single_node_from_a_start():
    node = lcpfric.SingleNode.normalized(0.5, 0.7, 0.3 * np.pi)  # shakes down
    safe = lcpfric.shakedown(node.system()).state
    r = lcpfric.steady_state(node, u0=safe)
    assert r.W == 0.0 and np.all(r.v == safe[0]) and r.v.shape == r.t.shape
    slipping = lcpfric.SingleNode.normalized(0.5, 1.7, 0.3 * np.pi)
    closed = lcpfric.steady_state(slipping)
    system = slipping.system()
    u0 = system.solve(0.3 * system.normal.reactions(0.0) - system.tangential(0.0))
    started = lcpfric.steady_state(slipping, u0=u0)
    assert started.W == pytest.approx(closed.W, rel=1e-12)
    assert started.W_hat == pytest.approx(closed.W_hat, rel=1e-12)


@pytest.mark.parametrize("method", ["exact", "explicit", "active-set"])
def test_a_start_the_friction_law_does_not_admit_is_refused_naming_the_nodes(method):
    system = _chain([0.3, 0.5, 0.2], [0.4, 0.6, 0.3], [0.2, 2.0, 4.0])
    with pytest.raises(InputError, match=r"u0.*node\(s\) 0 .*, 1 \("):
        lcpfric.steady_state(system, method, 200, u0=[0.0, 5.0, 0.0])
    with pytest.raises(InputError, match="u0.*needs 3"):
        lcpfric.steady_state(system, method, 200, u0=[0.0, 0.0])


@pytest.mark.parametrize("k_coupling", [3.0, 1e9])
def test_exact_started_on_its_own_steady_state_stays_there(k_coupling):
    """A start on the steady orbit is its own steady state: the same W and displacements, in
    the plain coordinates and in the stiff clusters' (k_coupling = 1e9)."""
    system = lcpfric.chain(
        4, k_coupling=k_coupling, P1=0.6, Q1=np.array([1.5, 0.4, 0.9, 1.2]), phi=1.1
    )
    ref = lcpfric.steady_state(system, "exact")
    again = lcpfric.steady_state(system, "exact", u0=ref.v[0])
    assert again.W == pytest.approx(ref.W, rel=1e-10)
    scale = np.max(np.ptp(ref.v, axis=0)) + 1e-300
    assert np.max(np.abs(again.v - ref.v)) <= 1e-9 * scale
    assert ref.solver_stats["structured"] == (k_coupling > 1e6)


def test_a_scene_given_directly_checks_its_start_too():
    from lcpfric.scene import make_scene

    system = _chain([0.3, 0.5, 0.2], [0.4, 0.6, 0.3], [0.2, 2.0, 4.0])
    scene = make_scene(system, 200)
    with pytest.raises(InputError, match="u0.*admissible"):
        lcpfric.steady_state(scene, "explicit", u0=np.array([0.0, 5.0, 0.0]))
