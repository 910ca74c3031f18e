"""``method="exact"`` for discrete systems (event by event): the sanity links of issue 10.

* n = 1 equals the single node's closed form to 1e-12;
* a diagonal K equals the per-node single-node answers; a block-diagonal system the sum of its
  blocks; a symmetric chain loaded uniformly moves in lockstep (every event is n simultaneous
  events) and equals n single nodes;
* the explicit stepper converges to it at second order on a coupled chain with separation;
* shakedown gives W = 0; degenerate instants (re-contact exactly at θ = 0, grazing contact) and
  the event cap give the right answer or a clear error.
"""

import math

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError, SolverError
from lcpfric.exact import exact_W_hat
from lcpfric.exact.discrete import exact_system_cycle, next_entry, segment_dissipation
from lcpfric.model import ContactSystem, IndependentSprings, SingleNode, block_diagonal
from lcpfric.model.loads import Fourier, Harmonic

CASES = [
    (0.5, 1.5, 0.3),
    (1.5, 2.0, 0.6 * math.pi),
    (5.0, 5.0, 0.6 * math.pi),
    (0.5, 1.01, 0.3 * math.pi),
    (20.0, 50.0, 0.5 * math.pi),
    (1.0, 1.2, 2.0),
    (0.2, 0.3, 1.0),
]


def exact_W(system, **kw):
    return lcpfric.steady_state(system, method="exact", steps_per_cycle=64, **kw).W


def node_W(P1, Q1, phi):
    return Q1 * float(exact_W_hat(P1, Q1, phi))


def nodes_system(params, phase=0.0):
    n = len(params)
    return ContactSystem(
        np.eye(n),
        np.ones(n),
        tuple(Harmonic(0.0, q, phase + f) for _, q, f in params),
        IndependentSprings(tuple(Harmonic(1.0, p, phase) for p, _, _ in params)),
    )


@pytest.mark.parametrize("P1, Q1, phi", CASES)
def test_one_node_equals_closed_form(P1, Q1, phi):
    system = SingleNode.normalized(P1, Q1, phi).system()
    ref = node_W(P1, Q1, phi)
    assert abs(exact_W(system) - ref) <= 1e-12 * max(ref, 1.0)


def test_diagonal_K_equals_the_nodes():
    system = nodes_system(CASES)
    ref = sum(node_W(*c) for c in CASES)
    assert abs(exact_W(system) - ref) <= 1e-12 * ref


def test_block_diagonal_equals_sum_of_blocks():
    a = lcpfric.chain(3, k_coupling=10, P1=[1.5, 0.5, 2.0], Q1=[1.5, 1.0, 2.0], phi=[0.3, 1.0, 2.0])
    b = lcpfric.chain(
        4, k_coupling=2, k_ground=0.5, P1=0.4, Q1=[1.0, 0.7, 1.3, 0.2], phi=[2.0, 0.1, 1.0, 4.0]
    )
    both = block_diagonal([a, b])
    Wa, Wb = exact_W(a), exact_W(b)
    assert abs(exact_W(both) - (Wa + Wb)) <= 1e-11 * (Wa + Wb)


@pytest.mark.parametrize("P1, Q1, phi", [(0.5, 1.5, 0.3), (1.5, 2.0, 0.6 * math.pi)])
def test_symmetric_chain_moves_in_lockstep(P1, Q1, phi):
    """Uniform loads on a chain: L u = 0, every node is a single node on k_ground, and every
    event happens at n nodes at once."""
    n = 6
    system = lcpfric.chain(n, k_coupling=10.0, k_ground=1.0, P1=P1, Q1=Q1, phi=phi)
    res = lcpfric.steady_state(system, method="exact", steps_per_cycle=64)
    ref = n * node_W(P1, Q1, phi)
    assert abs(res.W - ref) <= 1e-11 * ref
    assert np.ptp(res.v, axis=1).max() <= 1e-12 * np.abs(res.v).max()


def test_sparse_and_dense_stiffness_agree():
    dense = lcpfric.chain(
        5, k_coupling=10, P1=[1.5, 0.5, 2.0, 0.3, 1.2], Q1=1.5, phi=[0.3, 1.0, 2.0, 3.0, 4.0]
    )
    sparse = lcpfric.chain(
        5,
        k_coupling=10,
        P1=[1.5, 0.5, 2.0, 0.3, 1.2],
        Q1=1.5,
        phi=[0.3, 1.0, 2.0, 3.0, 4.0],
        sparse=True,
    )
    assert exact_W(sparse) == pytest.approx(exact_W(dense), rel=1e-13)


def test_frequency_and_force_units_do_not_change_W_beyond_scaling():
    base = dict(P1=[1.5, 0.5, 2.0], Q1=[1.5, 1.0, 2.0], phi=[0.3, 1.0, 2.0])
    W1 = exact_W(lcpfric.chain(3, k_coupling=10, **base))
    W3 = exact_W(lcpfric.chain(3, k_coupling=10, omega=3.0, **base))
    assert W3 == pytest.approx(W1, rel=1e-13)
    big = lcpfric.chain(
        3, k_coupling=10, P0=1e6, P1=[1.5e6, 0.5e6, 2e6], Q1=[1.5e6, 1e6, 2e6], phi=[0.3, 1.0, 2.0]
    )
    assert exact_W(big) == pytest.approx(1e12 * W1, rel=1e-12)


@pytest.mark.slow
def test_explicit_converges_to_exact_at_second_order():
    system = lcpfric.chain(
        3, k_coupling=10, P1=[1.5, 0.5, 2.0], Q1=[1.5, 1.0, 2.0], phi=[0.3, 1.0, 2.0]
    )
    ref = exact_W(system)
    steps = [400, 800, 1600]
    err = [
        abs(lcpfric.steady_state(system, method="explicit", steps_per_cycle=s).W - ref)
        for s in steps
    ]
    order = -np.polyfit(np.log(steps), np.log(err), 1)[0]
    assert order >= 1.8, (err, order)
    assert err[-1] <= 2e-6 * ref


@pytest.mark.slow
def test_coupled_dense_system_against_richardson_explicit():
    """Independent check: Richardson extrapolation of the (second-order) explicit stepper."""
    rng = np.random.default_rng(3)
    n = 4
    A = rng.standard_normal((n, n))
    K = A @ A.T / n + np.eye(n)
    P1, Q1, phi = rng.uniform(0.3, 2.0, n), rng.uniform(0.5, 2.0, n), rng.uniform(0, 6, n)
    system = ContactSystem(
        K,
        np.full(n, 0.7),
        tuple(Harmonic(0.1, Q1[i], phi[i]) for i in range(n)),
        IndependentSprings(tuple(Harmonic(1.0, P1[i]) for i in range(n))),
    )
    ref = exact_W(system)
    W = [lcpfric.steady_state(system, method="explicit", steps_per_cycle=s).W for s in (1600, 3200)]
    rich = (4 * W[1] - W[0]) / 3
    assert abs(rich - ref) <= 1e-6 * ref
    assert abs(W[1] - ref) > abs(rich - ref)  # the extrapolation did improve on the grid


def test_shakedown_gives_zero():
    system = lcpfric.chain(
        4, k_coupling=10, P1=0.2, Q1=[0.1, 0.05, 0.2, 0.1], phi=[0.0, 1.0, 2.0, 3.0]
    )
    res = lcpfric.steady_state(system, method="exact", steps_per_cycle=64)
    assert res.W == 0.0
    assert not np.any((res.state == 1) | (res.state == 2))


def test_recontact_exactly_at_the_cycle_start():
    """P = 1 + 2 sin(θ - π/6) vanishes at θ = 0: the first event is at the start."""
    params = [(2.0, 1.5, 0.7), (0.5, 1.5, 0.3)]
    system = nodes_system(params, phase=-math.pi / 6)
    ref = sum(node_W(*c) for c in params)
    assert abs(exact_W(system) - ref) <= 1e-12 * ref


@pytest.mark.parametrize("P1", [1.0, 1.0 + 1e-12, 1.0 - 1e-12])
def test_grazing_contact(P1):
    """min P = 0 exactly (a touch, no separation), or within round-off of it."""
    params = [(P1, 1.5, 0.4), (0.5, 1.0, 2.0)]
    ref = sum(node_W(*c) for c in params)
    assert abs(exact_W(nodes_system(params)) - ref) <= 1e-10 * ref


def test_event_cap_raises_naming_the_state():
    system = lcpfric.chain(3, k_coupling=10, P1=[1.5, 0.5, 2.0], Q1=1.5, phi=[0.3, 1.0, 2.0])
    with pytest.raises(SolverError, match="events in one cycle") as info:
        exact_system_cycle(system, 16, max_events=2)
    assert info.value.status == "too_many_events"
    assert "stick" in str(info.value) or "slip" in str(info.value)


def test_what_exact_cannot_solve_is_refused_clearly():
    two_d = lcpfric.chain(2, Q1=1.0, dims=2)
    with pytest.raises(InputError, match="d = 1"):
        exact_W(two_d)
    rich = ContactSystem(
        np.eye(1),
        [1.0],
        (Fourier(0.0, (1.0, 0.5), (0.0, 0.0)),),
        IndependentSprings((Harmonic(1.0, 0.5),)),
    )
    with pytest.raises(InputError, match="higher harmonics") as info:
        exact_W(rich)
    assert info.value.parameter == "tangential_loads"


def test_result_series_are_consistent():
    system = lcpfric.chain(
        3, k_coupling=10, P1=[1.5, 0.5, 2.0], Q1=[1.5, 1.0, 2.0], phi=[0.3, 1.0, 2.0]
    )
    res = lcpfric.steady_state(system, method="exact", steps_per_cycle=200)
    Q = system.tangential(res.t)
    assert np.max(np.abs(res.F - (Q + res.v @ system.dense_stiffness()))) <= 1e-12 * 3
    bound = res.N * system.friction
    assert np.all(np.abs(res.F) <= bound * (1 + 1e-12) + 1e-14)
    assert np.allclose(res.v[0], res.v[-1], atol=1e-11)  # periodic
    assert res.solver_stats["events_per_cycle"] > 0
    assert res.W_cycles[-1] == res.W


def test_event_search_and_segment_integral():
    # g = 0.5 + sin θ dips below 0 on (7π/6, 11π/6)
    t = next_entry(np.array([[0.5, 1.0, 0.0]]), 0.0, 1e-12)
    assert t[0] == pytest.approx(7 * math.pi / 6, abs=1e-14)
    # a touch (min exactly 0) is no entry
    assert np.isinf(next_entry(np.array([[1.0, 1.0, 0.0]]), 0.0, 1e-12)[0])
    # ∫ b du for b = 2 + sin θ, u = cos θ over (0, π/2) vs quadrature
    a, e = 0.0, math.pi / 2
    x = np.linspace(a, e, 200001)
    f = (2 + np.sin(x)) * (-np.sin(x))
    quad = float(np.sum((f[1:] + f[:-1]) * np.diff(x)) / 2)
    got = segment_dissipation(
        np.array([[2.0, 1.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]), np.array([1.0]), a, e
    )
    assert got == pytest.approx(quad, rel=1e-9)


def test_memory_is_checked_before_any_work(monkeypatch):
    monkeypatch.setenv("LCPFRIC_MAX_MEMORY", "1MB")
    system = lcpfric.chain(400, k_coupling=10, P1=0.5, Q1=1.0, sparse=True)
    with pytest.raises(InputError, match="memory") as info:
        exact_system_cycle(system, 16)
    assert info.value.parameter == "model"


def test_a_constant_tangential_load_does_not_change_W():
    """Q0 shifts the equilibrium by K⁻¹ Q0 and nothing else (d = 1, uncoupled normal loads)."""
    kw = dict(k_coupling=10, P1=[1.5, 0.5, 2.0], Q1=[1.5, 1.0, 2.0], phi=[0.3, 1.0, 2.0])
    base = lcpfric.chain(3, **kw)
    loads = tuple(
        Harmonic(q0, q.amplitude, q.phase) for q0, q in zip((0.7, -0.4, 0.2), base.tangential_loads)
    )
    shifted = ContactSystem(base.stiffness, base.friction, loads, base.normal)
    assert exact_W(shifted) == pytest.approx(exact_W(base), rel=1e-12)


def test_projection_converges_to_exact_on_uncoupled_nodes():
    system = nodes_system([(1.5, 2.0, 0.6 * math.pi), (0.5, 1.5, 0.3)])
    ref = exact_W(system)
    steps = [400, 800, 1600]
    err = [
        abs(lcpfric.steady_state(system, method="projection", steps_per_cycle=s).W - ref)
        for s in steps
    ]
    assert -np.polyfit(np.log(steps), np.log(err), 1)[0] >= 1.8, err


# -- found by benchmarks/validation/exact_discrete_audit.py ------------------------------------
def test_stiff_pair_converges_without_drift():
    """k_coupling = 1e4: correcting the start through K⁻¹ moved the pair along its soft mode by
    round-off / λmin every cycle (2e-9), and the periodicity test never passed."""
    K = np.array([[1 + 1e4, -1e4], [-1e4, 1 + 1e4]])
    system = ContactSystem(
        K,
        np.ones(2),
        (Harmonic(0, 1, 0.3), Harmonic(0, 2, 2.0)),
        IndependentSprings((Harmonic(1, 0.5, 0), Harmonic(1, 0.5, 1.0))),
    )
    res = lcpfric.steady_state(system, method="exact")
    assert res.cycles <= 4 and res.W > 0


def test_weakly_coupled_systems_converge_in_few_cycles():
    slow = lcpfric.chain(
        2, k_coupling=100.0, k_ground=0.1, P1=0.5, Q1=1.0, phi=[0.0, 1.0], normal_phase=[0.0, 0.5]
    )
    assert lcpfric.steady_state(slow, method="exact").cycles <= 10  # plain iteration: 145


def test_damped_newton_on_a_weakly_grounded_chain():
    """Undamped Newton cycled among four states here (for 183 of 401 phase shifts)."""
    f = [0.596, 0.934, 0.447, 0.618, 0.402]
    P0, P1 = [0.876, 1.417, 1.230, 1.196, 1.490], [0.600, 2.245, 0.087, 2.269, 0.494]
    psi = [2.804, 4.455, 1.212, 5.440, 5.546]
    Q0, Q1 = [0.098, 1.054, -0.417, -0.256, 0.395], [2.083, 0.888, 1.131, 1.740, 2.619]
    qph = [3.469, 6.061, 1.149, 0.489, 4.826]
    W = []
    for shift in (0.0, -10.0, 3.3):
        system = lcpfric.chain(
            5,
            k_coupling=0.526,
            k_ground=0.012,
            friction=f,
            normal_loads=[Harmonic(P0[i], P1[i], psi[i] + shift) for i in range(5)],
            tangential_loads=[Harmonic(Q0[i], Q1[i], qph[i] + shift) for i in range(5)],
        )
        W.append(exact_W(system))
    assert np.ptp(W) <= 1e-9 * W[0]


def test_stiff_lockstep_chain_equals_single_nodes():
    """k_coupling = 1e6 (cond K ~ 4e6): the tolerances grow with the conditioning."""
    system = lcpfric.chain(
        5,
        k_coupling=1e6,
        k_ground=1.0,
        friction=0.7,
        P0=1.2,
        P1=1.5,
        Q1=1.0,
        phi=1.2,
        normal_phase=0.1,
    )
    ref = 5 * 0.7 * 1.2 * 1.0 * float(exact_W_hat(1.5 / 1.2, 1.0 / (0.7 * 1.2), 1.2))
    assert exact_W(system) == pytest.approx(ref, rel=1e-9)


def test_tiny_tangential_amplitude_is_resolved():
    """Q1 = 1e-8 f P0 on top of Q0 ~ f P0: the periodicity test once stopped 3.6e-5 short of the
    orbit (W invariant to a phase shift only to 3.6e-5)."""
    import json

    s = json.loads(
        '{"K": ["dense", [[4.416599343127213, -2.2624455004156565, 1.1118017987240811, 1.2254533267659693], [-2.2624455004156565, 2.0101020741878237, -0.8467364692155653, -0.853045485655723], [1.1118017987240811, -0.8467364692155653, 0.9752959068078093, 0.3889253286690564], [1.2254533267659693, -0.853045485655723, 0.3889253286690564, 1.142126070640437]]], "f": [0.531558151871436, 0.10652470225439042, 0.8548123464074138, 0.2156492853488356], "P0": [0.6242153499857771, 1.7259032660504021, 0.6097131727425642, 1.4465943829899528], "P1": [2.0539802641427256, 2.498738131803606, 1.169042643459838, 2.5001908009351337], "psi": [1.5960134581748686, 0.9169961311725444, 5.322746101988275, 4.297628178607945], "Q0": [-0.04050928492129153, 0.1017763291705658, -0.200066050616187, -0.12548803323528293], "Q1": [3.3180675780822126e-09, 2.3900673099666878e-09, 8.33904556524128e-09, 5.9271838527470385e-09], "qph": [3.2718987992522925, 0.08900184331447107, 2.938657837082162, 5.187666954926775], "omega": 1.0}'  # noqa: E501 (the audit case, as printed)
    )
    n = len(s["f"])
    K = (
        lcpfric.chain(n, k_coupling=s["K"][2], k_ground=s["K"][3]).stiffness
        if s["K"][0] == "chain"
        else np.array(s["K"][1])
    )
    W = []
    for a in (0.0, 1.1):
        system = ContactSystem(
            K,
            s["f"],
            tuple(Harmonic(s["Q0"][i], s["Q1"][i], s["qph"][i] + a) for i in range(n)),
            IndependentSprings(
                tuple(Harmonic(s["P0"][i], s["P1"][i], s["psi"][i] + a) for i in range(n))
            ),
        )
        W.append(exact_W(system))
    assert W[1] == pytest.approx(W[0], rel=1e-6)
