"""The Hertz contact by dimensionality reduction (lcpfric.model.continuum.mdr and the mdr-bar
stepper) against the classical closed forms: Mindlin-Deresiewicz at constant P, Cattaneo's stick
radius, Mindlin and Deresiewicz's in-phase condition, W(φ + π) = W(φ), and the single node (one
spring)."""

import numpy as np
import pytest

from support import need

import lcpfric
from lcpfric.model.continuum import cattaneo_stick_ratio, mindlin_deresiewicz_W
from lcpfric.model.continuum import MDRSphere
from lcpfric.errors import InputError
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings

R, E, MU, P0 = 10.0, 200e3, 0.5, 100.0


def sphere(P1=0.0, Q1=0.25, phi=0.0, nu=0.0, **kw):
    """Q1 in units of μ P0."""
    return MDRSphere(R, E, nu, MU, Harmonic(P0, P1 * P0), Harmonic(0.0, Q1 * MU * P0, phi), **kw)


@pytest.mark.parametrize("nu", [0.0, 0.3])
@pytest.mark.parametrize("x", [0.2, 0.5, 0.9])
def test_mindlin_deresiewicz_at_constant_load(x, nu):
    r = lcpfric.steady_state(sphere(Q1=x, nu=nu, nodes=2000), steps_per_cycle=400)
    ref = mindlin_deresiewicz_W(P0, x * MU * P0, MU, r.contact.k_t0)
    assert r.converged and r.W == pytest.approx(ref, rel=2e-4)  # the goal: 0.2 %
    assert r.W_normalized == pytest.approx(r.W * r.contact.k_t0 / (MU * P0) ** 2)


def test_second_order_in_the_steps():
    """At constant P the error halves twice per halving of the step (measured order 2)."""
    errs = []
    for steps in (100, 200, 400):
        r = lcpfric.steady_state(sphere(Q1=0.5, nodes=4000), steps_per_cycle=steps)
        errs.append(abs(r.W / mindlin_deresiewicz_W(P0, 0.5 * MU * P0, MU, r.contact.k_t0) - 1))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 1.8) & (orders < 2.2)), orders


def test_cattaneo_stick_radius_on_first_loading():
    """From the virgin state, Q rising at constant P: c/a = (1 - Q/(μP))^(1/3), to a cell."""
    steps, m = 400, sphere(Q1=0.9, nodes=2000)
    r = lcpfric.steady_state(m, steps_per_cycle=steps, max_cycles=1, on_nonconvergence="ignore")
    c = r.stick_size()
    for j in (20, 50, 80, 100):  # Q(t_j) rises to 0.9 μ P0 at j = steps / 4
        x = 0.9 * np.sin(2 * np.pi * j / steps)
        assert c[j] / r.contact.size[j] == pytest.approx(
            cattaneo_stick_ratio(x), abs=2 * m.dx / r.contact.size[j]
        )


@pytest.mark.slow
def test_in_phase_dissipates_nothing_and_half_period_symmetry():
    """φ = 0, Q1 <= μ P1, P1 < P0: no dissipation in the steady state (to the discretization:
    it falls with the steps), while φ = 0.5 dissipates; W(φ + π) = W(φ)."""
    W0 = [
        lcpfric.steady_state(sphere(P1=0.5, Q1=0.4, nodes=2000), steps_per_cycle=s).W_normalized
        for s in (200, 400)
    ]
    assert W0[1] < W0[0] < 1e-5
    Wa = lcpfric.steady_state(
        sphere(P1=0.5, Q1=0.4, phi=0.5, nodes=500), steps_per_cycle=200
    ).W_normalized
    Wb = lcpfric.steady_state(
        sphere(P1=0.5, Q1=0.4, phi=0.5 + np.pi, nodes=500), steps_per_cycle=200
    ).W_normalized
    assert Wa > 1e-3 and Wb == pytest.approx(Wa, rel=1e-12)


def test_too_few_springs_are_refused():
    """Fewer than 10 springs across the contact do not resolve it (W 8 % off at 3): refused,
    naming the parameter, by the model and so by every caller."""
    with pytest.raises(InputError, match="nodes: 3 nodes are too coarse.*at least 10"):
        MDRSphere(R, E, 0.3, MU, P0, 0.0, nodes=3)
    with pytest.raises(InputError, match="at least 10"):
        lcpfric.HalfPlaneCylinder(R, E, 0.3, MU, P0, 0.0, nodes=9)


@pytest.mark.filterwarnings("ignore::lcpfric.errors.ResolutionWarning")  # W = 0: one spring
def test_one_spring_is_the_single_node():
    """One spring of stiffness k1 on the bar held by k_s: the paper's node with k11 = k1 k_s /
    (k1 + k_s) under -k1/(k1 + k_s) Q, N = P: the same increments as lcpfric's projection."""
    ks = 3e3

    class OneSpring(MDRSphere):  # below the resolution the model asks for, on purpose
        min_nodes = 1

    m = OneSpring(
        R,
        E,
        0.0,
        MU,
        Harmonic(P0, 0.6 * P0),
        Harmonic(0.0, 0.5 * MU * P0, 0.7),
        nodes=1,
        k_support=ks,
    )
    r = lcpfric.steady_state(m, steps_per_cycle=300, tol=1e-12)
    k1 = m.k[0]
    node = ContactSystem(
        [[k1 * ks / (k1 + ks)]],
        [MU],
        (Harmonic(0.0, k1 / (k1 + ks) * 0.5 * MU * P0, 0.7 + np.pi),),
        IndependentSprings((Harmonic(P0, 0.6 * P0),)),
    )
    ref = lcpfric.steady_state(node, "projection", 300, tol=1e-12, placement="uniform")
    assert r.W == pytest.approx(ref.W, rel=1e-10)


def test_normal_forces_carry_the_load_and_separation_with_support():
    m = sphere(P1=1.5, Q1=0.6, phi=0.3, nodes=300, k_support=2e3)
    t = np.linspace(0, 2 * np.pi, 50)
    np.testing.assert_allclose(
        m.normal_forces(t).sum(axis=1), np.maximum(m.P(t), 0), rtol=1e-12, atol=1e-12 * P0
    )
    r = lcpfric.steady_state(m, steps_per_cycle=200)
    assert r.converged and r.W > 0 and r.contact.size.min() == 0.0


def test_refusals():
    with pytest.raises(InputError) as err:
        lcpfric.steady_state(sphere(P1=1.5, Q1=0.6, phi=0.3, nodes=100), steps_per_cycle=100)
    assert err.value.parameter == "k_support" and "|Q(t)| > μ P(t)" in str(err.value)
    for kw, name in (
        (dict(nu=0.5), "nu"),
        (dict(nodes=0), "nodes"),
        (dict(nodes=10**7), "nodes"),
        (dict(k_support=-1.0), "k_support"),
    ):
        with pytest.raises(InputError) as err:
            sphere(**kw)
        assert err.value.parameter == name
    with pytest.raises(InputError) as err:
        MDRSphere(R, E, 0.0, MU, Harmonic(-1.0, 0.5), 0.0)
    assert err.value.parameter == "P"


@pytest.mark.parametrize("x", [0.3, 0.8])
def test_any_profile_against_ciavarella_jager(x):
    """A power-law body f = r⁴ (in closed form, and through the numerical MDR transform of its
    slope): W at constant P is the Ciavarella-Jäger chord area of its approach curve C(P)."""
    from lcpfric.model.continuum import ciavarella_jager_W, moduli
    from lcpfric.model.continuum import Axisymmetric, PowerLaw

    eta = moduli(E, 0.3)["eta"]
    runs = []
    for profile in (PowerLaw(1.0, 4), Axisymmetric(lambda r: 4.0 * r**3)):
        m = MDRSphere(
            None,
            E,
            0.3,
            MU,
            Harmonic(P0, 0.0),
            Harmonic(0.0, x * MU * P0),
            nodes=2000,
            profile=profile,
        )
        runs.append(lcpfric.steady_state(m, steps_per_cycle=400).W)
        ref = ciavarella_jager_W(m.approach, P0, x * MU * P0, MU, eta)
        assert runs[-1] == pytest.approx(ref, rel=2e-4)
    assert runs[1] == pytest.approx(runs[0], rel=1e-9)


def test_inverse_transform_gives_hertz_pressure_and_cattaneo_traction():
    """The inverse MDR transform of the spring forces: Hertz's pressure from the normal forces,
    Cattaneo's shear traction from the tangential ones (away from the edge cells)."""
    from lcpfric.model.continuum import hertz_contact

    m = sphere(Q1=0.95, nodes=2000)
    h = hertz_contact(P0, R, E, 0.0)
    rr = m.x / h["a"]
    inner = rr < 0.9
    p = m.tractions(m.normal_forces([0.0])[0])
    np.testing.assert_allclose(p[inner] / h["p0"], np.sqrt(1 - rr[inner] ** 2), atol=1e-3)
    r = lcpfric.steady_state(m, steps_per_cycle=400, max_cycles=1, on_nonconvergence="ignore")
    j = 40  # Q = 0.95 sin(2π 40/400) μ P0 on first loading
    x = 0.95 * np.sin(2 * np.pi * j / 400)
    c = cattaneo_stick_ratio(x)
    tau = -m.tractions(r.F[j]) / (MU * h["p0"])
    exact = np.sqrt(1 - rr**2) - c * np.sqrt(np.clip(1 - (rr / c) ** 2, 0, None))
    err = np.abs(tau - exact)[inner]
    assert np.median(err) < 1e-3 and err.max() < 0.05  # the largest: at the stick edge


def test_as_an_lcpfric_system():
    """With a support, the MDR contact is an lcpfric ContactSystem (matrix-free compliance
    ``diag(1/k) + 1 1ᵀ/k_s``, its own normal model): the backends give the same W on the same
    scene; under pure load control it is refused (a singular stiffness)."""
    need("clarabel")
    import lcpfric
    from lcpfric.scene import make_scene

    m = sphere(P1=1.5, Q1=0.6, phi=1.0, nu=0.3, nodes=60, k_support=2e4)
    system = m.system()
    assert system.matrix_free and system.n == 60
    scene = make_scene(system, 150)
    assert scene.steps > 150  # the springs' contact instants are on the grid
    ref = lcpfric.steady_state(lcpfric.make_scene(m, grid=scene.t), tol=1e-12).W
    for method in ("active-set", "clarabel"):
        r = lcpfric.steady_state(scene, method, tol=1e-12, locate_events=False)
        assert r.W == pytest.approx(ref, rel=1e-9), method
    with pytest.raises(InputError) as err:
        sphere(nodes=10).system()
    assert err.value.parameter == "k_support"
