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
    from lcpfric.analysis.safe_state import system_shakedown

    with pytest.raises(InputError, match="model"):
        system_shakedown(lcpfric.SingleNode.normalized(0.5, 0.5, 0.0))
    d2 = lcpfric.chain(2, P1=0.5, Q1=0.4, phi=0.3, dims=2)
    with pytest.raises(InputError, match="dims"):
        lcpfric.shakedown(d2)
    with pytest.raises(InputError, match="samples"):
        system_shakedown(_chain([0.3], [0.2], [0.1]), samples=3)
