"""The plane contact by half-plane boundary elements (lcpfric.model.continuum.halfplane and the
halfplane-pdas stepper): the Hertz pressure, Cattaneo's stick half-width, the plane
Mindlin-Deresiewicz dissipation, the in-phase condition, W(φ + π) = W(φ), and separation held by a
support."""

import numpy as np
import lcpfric
import pytest

from support import need

from lcpfric.model.continuum import cattaneo_stick_ratio, cylinder_contact, cylinder_W
from lcpfric.model.continuum.halfplane import HalfPlaneCylinder
from lcpfric.errors import InputError
from lcpfric.model import Harmonic

R, E, NU, MU, P0 = 10.0, 200e3, 0.3, 0.5, 100.0


def cylinder(P1=0.0, Q1=0.25, phi=0.0, **kw):
    """Q1 in units of μ P0."""
    return HalfPlaneCylinder(
        R, E, NU, MU, Harmonic(P0, P1 * P0), Harmonic(0.0, Q1 * MU * P0, phi), **kw
    )


def test_hertz_pressure_and_half_width():
    m = cylinder(nodes=400)
    p = m.pressure(P0)
    ref = cylinder_contact(P0, R, E, NU)
    assert p.sum() * m.dx == pytest.approx(P0, rel=1e-12)
    assert m.normal_solution([0.0])[1][0] == pytest.approx(ref["a"], abs=m.dx)
    exact = ref["p0"] * np.sqrt(np.maximum(0.0, 1 - (m.x / ref["a"]) ** 2))
    assert np.max(np.abs(p - exact)) < 0.01 * ref["p0"]  # the edge element: 0.6 %


@pytest.mark.parametrize("x", [0.2, 0.5, pytest.param(0.9, marks=pytest.mark.slow)])
def test_plane_mindlin_deresiewicz(x):
    r = lcpfric.steady_state(cylinder(Q1=x, nodes=400), steps_per_cycle=400)
    ref = cylinder_W(P0, x * MU * P0, MU, E, NU)
    assert r.converged and r.W == pytest.approx(ref, rel=5e-3)  # the goal: 0.5 %
    assert r.contact.normalization == "W pi E*/(mu^2 P0^2)"


def test_cattaneo_stick_half_width():
    steps, m = 400, cylinder(Q1=0.9, nodes=400)
    r = lcpfric.steady_state(m, steps_per_cycle=steps, max_cycles=1, on_nonconvergence="ignore")
    c = r.stick_size()
    for j in (20, 50, 80, 100):
        x = 0.9 * np.sin(2 * np.pi * j / steps)
        assert c[j] / r.contact.size[j] == pytest.approx(
            cattaneo_stick_ratio(x, "cylinder"), abs=2 * m.dx / r.contact.size[j]
        )


@pytest.mark.slow
def test_in_phase_and_half_period():
    W0 = lcpfric.steady_state(cylinder(P1=0.5, Q1=0.4, nodes=200), steps_per_cycle=200).W_normalized
    Wa = lcpfric.steady_state(
        cylinder(P1=0.5, Q1=0.4, phi=0.5, nodes=200), steps_per_cycle=200
    ).W_normalized
    Wb = lcpfric.steady_state(
        cylinder(P1=0.5, Q1=0.4, phi=0.5 + np.pi, nodes=200), steps_per_cycle=200
    ).W_normalized
    assert W0 < 1e-3 * Wa and Wa > 1e-3
    assert Wb == pytest.approx(Wa, rel=1e-9)


def test_separation_held_by_a_support_and_refusals():
    m = cylinder(P1=1.5, Q1=0.6, phi=0.3, nodes=100, k_support=1e3)
    r = lcpfric.steady_state(m, steps_per_cycle=200)
    assert r.converged and r.W > 0 and r.contact.size.min() == 0.0
    with pytest.raises(InputError) as err:
        lcpfric.steady_state(cylinder(P1=1.5, Q1=0.6, phi=0.3, nodes=100), steps_per_cycle=200)
    assert err.value.parameter == "k_support"
    with pytest.raises(InputError) as err:
        cylinder(nodes=10**5)
    assert err.value.parameter == "nodes"


def test_as_an_lcpfric_system():
    """Held by a support, the plane contact is an lcpfric ContactSystem (compliance C + 1 1ᵀ/k_s,
    the elements' entry loads as its normal model's transitions, exact for the discrete
    problem): the backends give the same W on the same scene."""
    need("clarabel")
    import lcpfric
    from lcpfric.scene import make_scene

    m = cylinder(P1=1.5, Q1=0.6, phi=1.0, nodes=40, k_support=2e3)
    levels = m.entry_loads()
    for i in np.flatnonzero(np.isfinite(levels) & (levels > 0))[:4]:
        assert m.pressure(levels[i] * (1 - 1e-6))[i] == 0.0 < m.pressure(levels[i] * (1 + 1e-6))[i]
    scene = make_scene(m.system(), 150)
    ref = lcpfric.steady_state(lcpfric.make_scene(m, grid=scene.t), tol=1e-12).W
    for method in ("active-set", "clarabel"):
        r = lcpfric.steady_state(scene, method, tol=1e-12, locate_events=False)
        assert r.W == pytest.approx(ref, rel=1e-9), method
    with pytest.raises(InputError):
        cylinder(nodes=20).system()


@pytest.mark.parametrize(
    "P1, Q1, phi, steps",
    [
        pytest.param(0.3, 1.5, 0.7, 100, marks=pytest.mark.slow),
        pytest.param(0.9, 0.8, 0.2, 8, marks=pytest.mark.slow),
        (0.5, 0.9, 1.0, 8),
    ],
)
def test_gross_sliding_held_by_a_support(P1, Q1, phi, steps):
    """Phases of gross sliding (|Q| > μP) with a support: the stick/slip patterns could cycle
    there (a node flipping between its bounds) and ran out of iterations (SolverError after
    400); the increment then falls back to bounded-variable least squares, which ends."""
    m = cylinder(P1, Q1, phi * np.pi, nodes=400, k_support=1e4)
    r = lcpfric.steady_state(m, steps_per_cycle=steps)
    assert r.converged and r.W > 0


def test_bounded_least_squares_is_the_increment():
    """The fallback (BVLS on min ½ Fᵀ(C + 1 1ᵀ/k_s)F + (Q/k_s − s0)ᵀF over |F| <= b) gives the
    active set's W, increment for increment, to 1e-12."""
    a = cylinder(0.5, 0.4, 0.5 * np.pi, nodes=100, k_support=1e4)
    b = cylinder(0.5, 0.4, 0.5 * np.pi, nodes=100, k_support=1e4)
    b.increment = lambda state, lim, Q: b._bounded(state, lim, Q, lim > 1e-10 * b._force_scale)
    assert lcpfric.steady_state(b, steps_per_cycle=40).W == pytest.approx(
        lcpfric.steady_state(a, steps_per_cycle=40).W, rel=1e-12
    )
