"""Quasi-static modal analysis of a jointed structure (lcpfric.analysis.modal): the closed form of
one mass with a Jenkins element, an independent return map on 2-DOF structures, invariances, the
100-DOF rod, and bad input."""

import math

import numpy as np
import pytest
import scipy.sparse as sp

from lcpfric.analysis.modal import jenkins_oscillator, modal_damping
from lcpfric.errors import InputError
from lcpfric.model.jointed import jointed_rod
from lcpfric.model.structure import JointedStructure
from support.modal_reference import return_map_cycle

# one mass m on a spring k0 with one Jenkins element (kt, Fs = mu N)
ONE = [(1.0, 1.0, 1.0, 0.5, 1.0), (2.5, 0.3, 4.0, 0.2, 3.0), (0.01, 200.0, 1e4, 0.7, 50.0)]


@pytest.mark.parametrize(("m", "k0", "kt", "mu", "N"), ONE)
def test_one_mass_matches_the_closed_form_from_stick_to_gross_slip(m, k0, kt, mu, N):
    s = JointedStructure([[m]], [[k0]], [[0, -1]], kt, mu, N)
    stick = math.sqrt(m) * mu * N / kt  # the modal amplitude where the element first slips
    a = stick * np.geomspace(0.1, 1000.0, 41)
    r = modal_damping(s, a)
    omega, zeta, W, alpha = jenkins_oscillator(a, k0, kt, mu * N, m)
    np.testing.assert_allclose(r.a, a, rtol=1e-12, atol=0)
    assert np.max(np.abs(r.omega - omega)) <= 1e-9 * r.omega0
    assert np.max(np.abs(r.zeta - zeta)) <= 1e-9
    np.testing.assert_allclose(r.W, W, rtol=1e-9, atol=1e-12 * np.max(W))
    np.testing.assert_allclose(r.alpha_max, alpha, rtol=1e-9)
    assert r.omega0 == pytest.approx(math.sqrt((k0 + kt) / m), rel=1e-14)
    np.testing.assert_array_equal(r.sticks, a <= stick)
    assert np.all(r.zeta[r.sticks] == 0) and np.all(r.omega_ratio[r.sticks] == pytest.approx(1))
    # asked as modal forces: the same cycles
    f = modal_damping(s, force=alpha)
    assert np.max(np.abs(f.omega - omega)) <= 1e-9 * r.omega0
    assert np.max(np.abs(f.zeta - zeta)) <= 1e-9


def test_the_closed_form_is_the_notes_formula_for_unit_mass():
    a = np.array([0.2, 1.0, 7.0])
    omega, zeta, W, _ = jenkins_oscillator(a, k0=2.0, kt=3.0, slip_force=0.9)
    FJ = np.minimum(3.0 * a, 0.9)
    np.testing.assert_allclose(omega**2, 2.0 + FJ / a, rtol=1e-15)
    np.testing.assert_allclose(W, np.where(a > 0.3, 4 * 0.9 * (a - 0.3), 0.0), rtol=1e-15)
    np.testing.assert_allclose(zeta, W / (2 * np.pi * omega**2 * a**2), rtol=1e-15)


M2 = np.diag([1.0, 0.5])
K2 = np.array([[3.0, -1.0], [-1.0, 1.0]])


@pytest.mark.parametrize("dofs", [[[0, 1]], [[1, -1]]], ids=["between the masses", "to ground"])
@pytest.mark.parametrize("mode", [0, 1])
def test_two_dof_matches_an_independent_return_map(dofs, mode):
    """One Jenkins element (Masing holds): the whole steady loop, W and a agree with the return
    map of the full structure."""
    s = JointedStructure(M2, K2, dofs, 3.0, 0.4, 0.5)
    _, phi = s.mode(mode)
    alphas = np.array([0.3, 1.5, 12.0])
    r = modal_damping(s, force=alphas, mode=mode, samples=40)
    for i, alpha in enumerate(alphas):
        ref = return_map_cycle(M2, K2, dofs, [3.0], [0.2], phi, alpha, steps=40, cycles=2)
        assert r.a[i] == pytest.approx(ref["a"], rel=1e-12)
        assert r.W[i] == pytest.approx(ref["W"], rel=1e-11, abs=1e-14)
        np.testing.assert_allclose(r.q[i], ref["q"], rtol=0, atol=1e-12 * ref["a"])
    assert not r.sticks[1:].any()


def test_sparse_and_dense_agree_and_a_mode_given_as_a_vector_is_the_same():
    s = JointedStructure(M2, K2, [[0, 1]], 3.0, 0.4, 0.5)
    t = JointedStructure(sp.csr_matrix(M2), sp.csc_matrix(K2), [[0, 1]], 3.0, 0.4, 0.5)
    assert t.sparse and not s.sparse
    r, q = modal_damping(s, [0.1, 1.0, 10.0]), modal_damping(t, [0.1, 1.0, 10.0])
    np.testing.assert_allclose(q.zeta, r.zeta, rtol=1e-12)
    np.testing.assert_allclose(q.omega, r.omega, rtol=1e-12)
    v = modal_damping(s, [0.1, 1.0, 10.0], mode=-3.0 * r.phi)  # any scale and sign
    np.testing.assert_allclose(v.zeta, r.zeta, rtol=1e-12)
    assert v.mode_index is None and r.mode_index == 0


def test_scaling_the_mass_and_the_stiffness():
    """M -> s M: ω -> ω/√s at a -> √s a, ζ unchanged; K, kt, N -> s (·): ω -> √s ω, a and ζ
    unchanged at α -> s α."""
    dofs, alphas = [[0, 1], [1, -1]], np.array([0.4, 2.0, 9.0])
    base = modal_damping(JointedStructure(M2, K2, dofs, [3.0, 1.0], 0.4, [0.5, 0.3]), force=alphas)
    scale = 7.0
    heavy = JointedStructure(scale * M2, K2, dofs, [3.0, 1.0], 0.4, [0.5, 0.3])
    h = modal_damping(heavy, force=alphas / math.sqrt(scale))
    np.testing.assert_allclose(h.a, base.a * math.sqrt(scale), rtol=1e-12)
    np.testing.assert_allclose(h.omega, base.omega / math.sqrt(scale), rtol=1e-12)
    np.testing.assert_allclose(h.zeta, base.zeta, rtol=1e-11, atol=1e-15)
    stiff = JointedStructure(
        M2, scale * K2, dofs, [3.0 * scale, scale], 0.4, [0.5 * scale, 0.3 * scale]
    )
    k = modal_damping(stiff, force=alphas * scale)
    np.testing.assert_allclose(k.a, base.a, rtol=1e-12)
    np.testing.assert_allclose(k.omega, base.omega * math.sqrt(scale), rtol=1e-12)
    np.testing.assert_allclose(k.zeta, base.zeta, rtol=1e-11, atol=1e-15)


def test_a_frictionless_contact_only_stiffens_the_stuck_mode():
    s = JointedStructure([[2.0]], [[1.0]], [[0, -1]], 3.0, 0.0, 1.0)
    r = modal_damping(s, [0.01, 1.0, 100.0])
    np.testing.assert_allclose(r.omega, math.sqrt(1.0 / 2.0), rtol=1e-14)
    assert np.all(r.W == 0) and r.stats["solves"] == 0 and r.stats["contacts"] == 0


def test_the_rod_from_stick_to_macroslip():
    """The 100-DOF rod with 10 contacts: ω falls from ω0 to the secant of the structure alone
    (``ω² -> 1/(φᵀ M K⁻¹ M φ)``), ζ rises from 0 and falls again, each loop's extremes are at
    the load's."""
    rod = jointed_rod()
    r = modal_damping(rod, force=np.geomspace(1e-3, 1e4, 30), samples=8)
    assert r.sticks[0] and not r.sticks[-1]
    assert np.all(np.diff(r.omega) <= 1e-12 * r.omega0)
    assert np.all(r.zeta >= 0) and 0.05 < r.zeta.max() < 1 and r.zeta[-1] < 0.01 * r.zeta.max()
    Mphi = rod.mass @ r.phi
    from scipy.sparse.linalg import spsolve

    free = 1.0 / math.sqrt(Mphi @ spsolve(rod.stiffness, Mphi))
    assert r.omega[-1] == pytest.approx(free, rel=1e-3) and r.omega[-1] > free
    assert np.all(np.argmax(r.q, axis=1) == 2) and np.all(np.argmin(r.q, axis=1) == 6)
    assert r.stats["solves"] == np.count_nonzero(~r.sticks)  # the stuck ones need none


def test_a_structure_held_only_by_its_contacts_is_refused_for_the_cycle():
    # the second mass hangs on the joint only: K is singular, K + the joint's spring is not
    K = np.array([[1.0, 0.0], [0.0, 0.0]])
    s = JointedStructure(np.eye(2), K, [[0, 1]], 2.0, 0.5, 1.0)
    with pytest.raises(InputError) as e:
        modal_damping(s, [1.0])
    assert e.value.parameter == "stiffness"
    t = JointedStructure(sp.identity(2, format="csc"), sp.csc_matrix(K), [[0, 1]], 2.0, 0.5, 1.0)
    with pytest.raises(InputError, match="stiffness"):
        modal_damping(t, [1.0])


GOOD = dict(mass=[[1.0]], stiffness=[[1.0]], contact_dofs=[[0, -1]], contact_stiffness=1.0,
            friction=0.5, normal_load=1.0)  # fmt: skip
BAD = [
    (dict(mass=[[1.0, 0.0]]), "mass"),
    (dict(mass=[[-1.0]]), "mass"),
    (dict(mass=[[np.nan]]), "mass"),
    (dict(stiffness=[[1.0, 0.0], [0.0, 1.0]]), "stiffness"),
    (dict(stiffness=[[-1.0]]), "stiffness"),
    (dict(mass=np.eye(2), stiffness=[[1.0, 0.5], [0.0, 1.0]], contact_dofs=[0]), "stiffness"),
    (dict(mass=np.eye(2), stiffness=np.zeros((2, 2)), contact_dofs=[[0, 1]]), "stiffness"),
    (dict(contact_dofs=[[1, -1]]), "contact_dofs"),
    (dict(contact_dofs=[[0, 0]]), "contact_dofs"),
    (dict(contact_dofs=[[-1, -1]]), "contact_dofs"),
    (dict(contact_dofs=[[0.5, -1]]), "contact_dofs"),
    (dict(contact_dofs=[]), "contact_dofs"),
    (dict(contact_stiffness=0.0), "contact_stiffness"),
    (dict(contact_stiffness=-2.0), "contact_stiffness"),
    (dict(friction=-0.1), "friction"),
    (dict(friction=np.inf), "friction"),
    (dict(normal_load=0.0), "normal_load"),
    (dict(normal_load=[1.0, 2.0]), "normal_load"),
]


@pytest.mark.parametrize(("change", "named"), BAD, ids=[f"{b[1]}-{i}" for i, b in enumerate(BAD)])
def test_bad_structures_are_refused_naming_the_parameter(change, named):
    with pytest.raises(InputError) as e:
        JointedStructure(**dict(GOOD, **change))
    assert e.value.parameter == named


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        (dict(amplitude=[0.0]), "amplitude"),
        (dict(amplitude=[1.0, -1.0]), "amplitude"),
        (dict(amplitude=[np.nan]), "amplitude"),
        (dict(force=[np.inf]), "force"),
        (dict(amplitude=[1.0], force=[1.0]), "amplitude"),
        (dict(), "amplitude"),
        (dict(amplitude=[1.0], samples=6), "samples"),
        (dict(amplitude=[1.0], samples=2), "samples"),
        (dict(amplitude=[1.0], mode=2), "mode"),
        (dict(amplitude=[1.0], mode=-1), "mode"),
        (dict(amplitude=[1.0], mode=[1.0, 1.0]), "mode"),  # not a mode
        (dict(amplitude=[1.0], mode=[1.0, 0.0, 0.0]), "mode"),
        (dict(amplitude=[1.0], mode=[0.0, 0.0]), "mode"),
    ],
)
def test_bad_requests_are_refused_naming_the_parameter(kwargs, named):
    s = JointedStructure(M2, K2, [[0, 1]], 3.0, 0.4, 0.5)
    with pytest.raises(InputError) as e:
        modal_damping(s, **kwargs)
    assert e.value.parameter == named


def test_a_mode_that_is_not_a_mode_says_how_far_it_is():
    s = JointedStructure(M2, K2, [[0, 1]], 3.0, 0.4, 0.5)
    _, phi = s.mode(0)
    s.mode(phi * (1 + 1e-9 * np.array([1.0, -1.0])))  # within MODE_TOL
    with pytest.raises(InputError, match=r"not a mode of the stuck structure.*λ ="):
        s.mode(phi + 1e-3 * np.array([1.0, -1.0]))
    with pytest.raises(InputError, match="structure"):
        modal_damping("not a structure", [1.0])


def test_the_rod_matches_an_independent_return_map():
    """Ten coupled contacts that slip one after the other: a and W of the full structure's
    return map (no condensation) agree."""
    rod = jointed_rod(sparse=False)
    alphas = np.array([0.45, 2.0])
    r = modal_damping(rod, force=alphas, samples=8)
    for i, alpha in enumerate(alphas):
        ref = return_map_cycle(rod.mass, rod.stiffness, rod.contact_dofs, rod.contact_stiffness,
                               rod.friction * rod.normal_load, r.phi, alpha, steps=200,
                               cycles=3, tol=1e-14)  # fmt: skip
        assert r.a[i] == pytest.approx(ref["a"], rel=1e-11)
        assert r.W[i] == pytest.approx(ref["W"], rel=1e-10)


def test_the_figure(tmp_path):
    pytest.importorskip("matplotlib")
    from support import texts

    from lcpfric.figures.modal import figure_modal_damping
    from lcpfric.figures.style import COLUMN_WIDTH, MIN_FONT_SIZE

    s = JointedStructure([[1.0]], [[1.0]], [[0, -1]], 3.0, 0.5, 1.0)
    r = modal_damping(s, np.geomspace(0.01, 100.0, 9))
    x = np.geomspace(0.1, 1000.0, 50)
    omega, zeta, _, _ = jenkins_oscillator(x * r.a_slip, 1.0, 3.0, 0.5)
    fig = figure_modal_damping([("one mass", r)], closed_form=(x, omega / r.omega0, zeta))
    assert r.a_slip == pytest.approx(0.5 / 3.0, rel=1e-14)
    assert fig.get_figwidth() <= COLUMN_WIDTH + 1e-9 and len(fig.axes) == 2
    assert fig.axes[0].get_xscale() == "log"
    assert min(t.get_fontsize() for t in texts(fig)) >= MIN_FONT_SIZE
    fig.savefig(tmp_path / "f.pdf")
    pdf = (tmp_path / "f.pdf").read_bytes()
    assert b"/Type3" not in pdf and (b"/CIDFontType2" in pdf or b"/TrueType" in pdf)
    loop_alpha, loop_q = r.loop(8)
    assert loop_alpha.max() == pytest.approx(r.alpha_max[8]) and loop_q.max() == pytest.approx(
        r.a[8]
    )
    assert r.backbone[0] is r.a


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        (dict(n=3), "n"),
        (dict(contacts=60), "contacts"),
        (dict(slip_forces=(0.2, 0.1)), "slip_forces"),
        (dict(joint_stiffness=0.0), "joint_stiffness"),
        (dict(friction=-1.0), "friction"),
    ],
)
def test_the_rod_builder_refuses_bad_input(kwargs, named):
    with pytest.raises(InputError) as e:
        jointed_rod(**kwargs)
    assert e.value.parameter == named
