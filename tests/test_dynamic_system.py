"""The dynamic system (issue 40, items 1, 3, 4, 5, 7): the model's checks, Newmark's increments
by every backend against the exact dynamic node, the propagated Jacobian against differences,
shooting, harmonic balance against shooting, the frequency response."""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError, SolverError
from lcpfric.methods import available_methods
from lcpfric.periodic.first_guess import equivalent_linear_start, harmonic_start
from lcpfric.periodic.shooting import iterate_cycles, shoot
from lcpfric.steppers.newmark_system import NewmarkSystem

NODES = {"stops": (0.5, 2.0, 0.3, 0.7, 0.2), "separation": (1.5, 2.0, 0.3, 0.7, 0.2)}


def chain(n=10, kt=1.0, zeta=1e-3, f=0.05, omega=0.28):
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    M = np.eye(n)
    w1 = float(np.sqrt(np.linalg.eigvalsh(K)[0]))
    force = np.zeros(n)
    force[-1] = f
    return lcpfric.DynamicSystem(mass=M, stiffness=K, damping=2 * zeta * w1 * M,
                                 contacts=[n - 1], friction=0.3, normal_load=1.0, omega=omega,
                                 force=force, contact_stiffness=kt)  # fmt: skip


def chain3():
    K = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1.5]])
    M = np.diag([1.0, 1.5, 0.8])
    Nh = [-0.6j, 1.4 * np.exp(1j * (0.7 - 0.5 * np.pi)), 0.5 * np.exp(1j * (2.0 - 0.5 * np.pi))]
    return lcpfric.DynamicSystem(
        mass=M, stiffness=K, damping=lcpfric.rayleigh(M, K, 0.05, 0.02), contacts=[0, 1, 2],
        friction=[0.3, 0.4, 0.35], normal_load=1.0, normal_amplitude=Nh, omega=0.7,
        force=[1.2 * np.exp(0.3j), 0.0, 0.9 * np.exp(-1.1j)], force_mean=[0.1, 0.0, -0.2],
    )  # fmt: skip


@pytest.mark.parametrize(
    "change, parameter",
    [
        ({"mass": [[1.0, 0], [0, -1.0]]}, "mass"),
        ({"damping": -np.eye(2)}, "damping"),
        ({"stiffness": [[1.0, 2.0], [0.0, 1.0]]}, "stiffness"),
        ({"friction": 0.0}, "friction"),
        ({"friction": [0.3, 0.3]}, "friction"),
        ({"contacts": [5]}, "contacts"),
        ({"contacts": [(1, 1)]}, "contacts"),
        ({"normal_load": -1.0}, "normal_load"),
        ({"omega": 0.0}, "omega"),
        ({"omega": np.nan}, "omega"),
        ({"force": [1.0, 2.0, 3.0]}, "force"),
        ({"contact_stiffness": -1.0}, "contact_stiffness"),
        ({"dims": 3}, "dims"),
    ],
)
def test_bad_input_is_named(change, parameter):
    base = dict(mass=np.eye(2), stiffness=[[2.0, -1], [-1, 1]], contacts=[1], friction=0.3,
                normal_load=1.0, omega=0.5, force=[0.0, 1.0])  # fmt: skip
    base.update(change)
    with pytest.raises(InputError) as err:
        lcpfric.DynamicSystem(**base)
    assert err.value.parameter == parameter


def test_rayleigh_and_sparse_matrices():
    import scipy.sparse as sp

    M, K = np.diag([1.0, 2.0]), np.array([[2.0, -1], [-1, 1]])
    assert np.allclose(lcpfric.rayleigh(M, K, 0.1, 0.2), 0.1 * M + 0.2 * K)
    C = lcpfric.rayleigh(sp.csc_matrix(M), K, 0.1, 0.2)
    assert sp.issparse(C) and np.allclose(C.toarray(), 0.1 * M + 0.2 * K)
    with pytest.raises(InputError, match="alpha"):
        lcpfric.rayleigh(M, K, -1.0, 0.0)
    s = lcpfric.DynamicSystem(mass=sp.csc_matrix(M), stiffness=sp.csc_matrix(K), damping=C,
                              contacts=[1], friction=0.3, normal_load=1.0, omega=0.5,
                              force=[0.0, 1.0], contact_stiffness=2.0)  # fmt: skip
    dense = lcpfric.DynamicSystem(mass=M, stiffness=K, damping=C.toarray(), contacts=[1],
                                  friction=0.3, normal_load=1.0, omega=0.5, force=[0.0, 1.0],
                                  contact_stiffness=2.0)  # fmt: skip
    a = lcpfric.steady_state(s, method="newmark", steps_per_cycle=100)
    b = lcpfric.steady_state(dense, method="newmark", steps_per_cycle=100)
    assert a.W == pytest.approx(b.W, rel=1e-10)


@pytest.mark.parametrize("case", sorted(NODES))
def test_node_as_a_system_against_exact_second_order(case):
    p = NODES[case]
    node = lcpfric.SingleNode.normalized(P1=p[0], Q1=p[1], phi=p[2], beta=p[3], zeta=p[4])
    ref = lcpfric.steady_state(node, method="exact")
    system = lcpfric.DynamicSystem.from_node(node)
    errs = []
    for steps in (200, 800):
        r = lcpfric.steady_state(system, method="newmark", steps_per_cycle=steps)
        errs.append(abs(r.W / ref.W - 1))
        assert r.converged and r.method == "newmark"
    assert errs[1] < 1e-4
    assert np.log(errs[0] / errs[1]) / np.log(4) >= 1.8
    amp = r.dynamics.amplitude[0]
    assert amp == pytest.approx(ref.dynamics.amplitude, rel=1e-4)


def test_every_backend_gives_the_same_increments():
    node = lcpfric.SingleNode.normalized(P1=1.5, Q1=2.0, phi=0.3, beta=0.7, zeta=0.2)
    system = lcpfric.DynamicSystem.from_node(node)
    clip = lcpfric.steady_state(system, method="newmark", steps_per_cycle=200)
    assert clip.solver_stats["closed_form"] > 0
    installed = set(available_methods())
    for b in ("clarabel", "osqp", "qpsolvers:proxqp", "cvxpy"):
        if b not in installed:
            continue
        r = lcpfric.steady_state(system, method="newmark", steps_per_cycle=200, backend=b)
        assert r.solver_stats["closed_form"] == 0 and r.solver_stats["refined"] > 0
        assert r.W == pytest.approx(clip.W, rel=1e-9), b


def test_coupled_chain_converges_at_second_order():
    pytest.importorskip("clarabel")
    s = chain3()
    W = [lcpfric.steady_state(s, method="newmark", steps_per_cycle=n).W for n in (200, 400, 800)]
    p = np.log2(abs(W[0] - W[1]) / abs(W[1] - W[2]))
    assert p >= 1.8


@pytest.mark.parametrize("kt", [1.0, np.inf])
def test_jacobian_against_differences(kt):
    s = chain(n=4, kt=kt, f=0.5, omega=0.5 if kt == 1.0 else 0.6, zeta=0.02)
    path = NewmarkSystem(s)
    z = np.zeros(path.unknowns())
    for _ in range(20):
        z = path.period(z, 200)[0]
    _, _, J, _ = path.period(z, 200, jacobian=True)
    assert path.events > 0
    Jfd = np.zeros_like(J)
    for k in range(z.size):
        e = np.zeros(z.size)
        e[k] = 1e-5
        Jfd[:, k] = (path.period(z + e, 200)[0] - path.period(z - e, 200)[0]) / 2e-5
    assert np.max(np.abs(J - Jfd)) / np.max(np.abs(Jfd)) < 1e-5


def test_shooting_lightly_damped_chain_in_few_iterations():
    s = chain(omega=0.282)
    r = lcpfric.steady_state(s, method="newmark", steps_per_cycle=200)
    assert r.dynamics.newton_iterations <= 10 and r.W > 0
    assert r.v.shape == (r.t.size, 1) and r.dynamics.displacement.shape == (r.t.size, 10)
    assert set(np.unique(r.state)) <= {0, 1, 2}


def test_shooting_agrees_with_cycles():
    s = chain(n=4, f=0.5, omega=0.6, zeta=0.05)
    path = NewmarkSystem(s)
    z0 = equivalent_linear_start(s)
    r = shoot(lambda z: path.period(z, 200, jacobian=True)[::2], z0, 1e-11)
    zc, res, periods, conv = iterate_cycles(lambda z: path.period(z, 200)[0], z0, 1e-11, 5000)
    assert r.converged and conv and periods > 5 * r.periods
    assert np.max(np.abs(zc - r.z)) <= 1e-8 * np.max(np.abs(r.z))


def test_harmonic_balance_against_shooting():
    from lcpfric.harmonic import forced_response

    s = chain(omega=0.3)
    f = np.zeros(10)
    f[-1] = 0.05
    hb = forced_response(s.mass, s.damping, s.stiffness, f, (0.285, 0.29), contacts=(9,),
                         kt=1.0, mu=0.3, normal_load=1.0, harmonics=15, samples=120)  # fmt: skip
    i = int(np.argmin(np.abs(hb.omega - 0.2874)))
    at = chain(omega=float(hb.omega[i]))
    r = lcpfric.steady_state(
        at,
        method="newmark",
        steps_per_cycle=1600,
        u0=harmonic_start(at, hb.coefficients[i], hb.contact_force[i]),
    )
    t, x = r.t[:-1], r.dynamics.displacement[:-1]
    c = (2 / t.size) * np.stack([x.T @ np.cos(at.omega * t), x.T @ np.sin(at.omega * t)], 1)
    hbc = hb.coefficients[i][:, 1:3]
    assert np.max(np.hypot(*(hbc - c).T)) / np.max(np.hypot(*hbc.T)) < 1e-3


def test_frequency_response_of_a_system_matches_the_node():
    from lcpfric.analysis.frequency_response import frequency_response

    node = lcpfric.SingleNode.normalized(P1=0.5, Q1=3.0, phi=0.3, beta=0.7, zeta=0.1)
    om = [0.6, 1.0, 1.4]
    a = frequency_response(node, om)
    b = frequency_response(lcpfric.DynamicSystem.from_node(node), om, steps=800)
    assert b.method == "newmark"
    np.testing.assert_allclose(b.W, a.W, rtol=1e-4)
    np.testing.assert_allclose(b.amplitude, a.amplitude, rtol=1e-4)
    np.testing.assert_allclose(b.phase, a.phase, atol=1e-4)
    with pytest.raises(InputError, match="dof"):
        frequency_response(lcpfric.DynamicSystem.from_node(node), om, dof=3)


def test_refusals_name_the_way_out():
    s = chain(n=3)
    with pytest.raises(InputError, match="newmark"):
        lcpfric.steady_state(s, method="exact")
    assert lcpfric.methods_for(s) == ["newmark"]
    node = lcpfric.SingleNode.normalized(P1=0.5, Q1=2.0, phi=0.3, beta=0.7, zeta=0.2)
    with pytest.raises(InputError, match="from_node"):
        lcpfric.steady_state(node, method="newmark", backend="osqp")
    d2 = lcpfric.DynamicSystem(mass=np.eye(2), stiffness=np.eye(2), contacts=[(0, 1)],
                               friction=0.3, normal_load=1.0, omega=0.5, dims=2,
                               force=[1.0, 0.5j])  # fmt: skip
    with pytest.raises(InputError, match="rigid d = 2"):
        lcpfric.steady_state(d2, method="newmark")
    with pytest.raises(InputError, match="u0"):
        lcpfric.steady_state(s, method="newmark", u0=[1.0, 2.0])


def test_shooting_that_does_not_converge_raises_with_status():
    with pytest.raises(SolverError) as err:
        lcpfric.steady_state(chain(omega=0.282), method="newmark", steps_per_cycle=100,
                             max_cycles=1)  # fmt: skip
    assert err.value.status == "shooting"


def test_d2_contact_under_collinear_loads_is_the_d1_contact():
    pytest.importorskip("clarabel")
    K = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1.5]])
    M = np.diag([1.0, 1.5, 0.8])
    C = lcpfric.rayleigh(M, K, 0.05, 0.02)
    common = dict(friction=0.3, normal_load=1.0, normal_amplitude=-0.6j, omega=0.7,
                  contact_stiffness=2.0)  # fmt: skip
    one = lcpfric.DynamicSystem(mass=M, stiffness=K, damping=C, contacts=[2],
                                force=[0, 0, 1.0], **common)  # fmt: skip
    two = lcpfric.DynamicSystem(mass=np.kron(np.eye(2), M), stiffness=np.kron(np.eye(2), K),
                                damping=np.kron(np.eye(2), C), contacts=[(2, 5)], dims=2,
                                force=[0, 0, 1.0, 0, 0, 0], **common)  # fmt: skip
    W1 = lcpfric.steady_state(one, "newmark", 100).W
    r2 = lcpfric.steady_state(two, "newmark", 100)
    assert r2.converged and r2.F.shape == (r2.t.size, 2)
    assert r2.W == pytest.approx(W1, rel=2e-4)
