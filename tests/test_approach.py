"""A continuum contact under a prescribed normal approach (issue 39, item 1: the normal side as a
normal displacement): the grid's exact load-approach relation, the cylinder's closed-form
approach, separation, and the describing functions of the driven contact."""

import numpy as np
import pytest

from lcpfric.errors import InputError
from lcpfric.harmonic import trapezoid_coefficients
from lcpfric.model.continuum.approach import ApproachTable
from lcpfric.model.continuum.closed_forms import cylinder_approach, moduli
from lcpfric.model.continuum.halfplane import HalfPlaneCylinder
from lcpfric.model.continuum.halfspace import HalfSpace
from lcpfric.model.continuum.normal3d import normal_contact
from lcpfric.model.loads import Harmonic


def _approach_of(model, P):
    """The half-plane's approach under the load P, from its own normal solve."""
    p = model.normal_problem().pressure(float(P))
    on = p > 0
    return float(np.mean((model.h + model.A @ p)[on]))


def test_the_cylinders_approach_closed_form_and_its_order():
    """The discrete half-plane's approach under Hertz's load against ``(2P/πE*)(ln(2ℓ/a) +
    1/2)``: second order in the element width (measured 4.6e-6, 1.2e-6, 2.9e-7 at 100, 200,
    400 elements)."""
    errors = []
    for n in (100, 200, 400):
        m = HalfPlaneCylinder(1.0, 1.0, 0.3, 0.3, 1e-3, 0.0, nodes=n, datum=50.0)
        errors.append(abs(_approach_of(m, 1e-3) / cylinder_approach(1e-3, 1.0, 1.0, 0.3, 50.0) - 1))
    orders = np.log2(np.array(errors[:-1]) / errors[1:])
    assert errors[-1] < 1e-6
    assert np.all(orders > 1.9), orders
    assert cylinder_approach(0.0, 1.0, 1.0, 0.3, 50.0) == 0.0


def test_the_half_plane_under_an_approach_reproduces_it_and_separates():
    """P(t) from the grid's table: the normal solve at P(t) has the approach d(t) to round-off;
    where d(t) < 0 the bodies are apart (P = 0)."""
    d = Harmonic(0.02, 0.01, 0.3)
    m = HalfPlaneCylinder.under_approach(1.0, 1.0, 0.3, 0.3, d, datum=50.0, nodes=100)
    t = np.linspace(0.0, m.period, 13)[:-1]
    for tt in t:
        assert _approach_of(m, m.P(tt)) == pytest.approx(d(tt), rel=1e-12)
    # the derivative is the table's slope times d'(t)
    h = 1e-6 * m.period
    fd = (m.P(t + h) - m.P(t - h)) / (2 * h)
    np.testing.assert_allclose(m.P.derivative(t), fd, rtol=1e-4)
    apart = HalfPlaneCylinder.under_approach(
        1.0, 1.0, 0.3, 0.3, Harmonic(0.01, 0.02, 0.0), datum=50.0, nodes=100
    )
    P = apart.P(t)
    assert P.min() == 0.0 and P.max() > 0.0
    assert np.all(apart.normal_solution(t[P == 0.0])[0] == 0.0)


def test_the_half_space_sphere_under_an_approach():
    """The normal solve (constrained CG) at the table's P(t) finds the approach d(t) to
    round-off; P(d) tends to Hertz's 4/3 E* √R d^(3/2) with the grid (measured 1.9 % at grid 16,
    0.93 % at 24)."""
    d = Harmonic(1e-2, 0.5e-2, 0.0)
    Es = moduli(1.0, 0.3)["E*"]
    t = np.linspace(0.0, 2 * np.pi, 7)[:-1]
    err = []
    for grid in (16, 24):
        m = HalfSpace.under_approach(1.0, 0.3, 0.3, d, R=1.0, grid=grid)
        P = m.P(t)
        for tt, PP in zip(t, P):
            assert normal_contact(m.op, m.g0, PP).d == pytest.approx(d(tt), rel=1e-11)
        err.append(np.max(np.abs(P / (4 / 3 * Es * d(t) ** 1.5) - 1)))
        assert m.R == 1.0 and m.geometry == "sphere"
    assert err[1] < 0.6 * err[0] and err[1] < 0.01


def test_a_surface_under_an_approach_and_bad_input():
    """A height map under a constant approach is the model under the table's constant load; bad
    input is named."""
    g = (np.arange(20) - 9.5) * 0.1
    heights = (g[:, None] ** 2 + g[None, :] ** 2) / 2.0
    m = HalfSpace.under_approach(1.0, 0.3, 0.3, 0.2, heights=heights, spacing=0.1)
    assert isinstance(m.P.mean, float) and m.P.is_constant
    assert normal_contact(m.op, m.g0, m.P0).d == pytest.approx(0.2, rel=1e-11)
    with pytest.raises(InputError, match="R"):
        HalfSpace.under_approach(1.0, 0.3, 0.3, 0.2, R=1.0, heights=heights, spacing=0.1)
    with pytest.raises(InputError, match="approach"):
        HalfSpace.under_approach(1.0, 0.3, 0.3, Harmonic(-1e-3, 1e-2, 0.0), R=1.0)
    with pytest.raises(InputError, match="grid"):
        HalfSpace.under_approach(1.0, 0.3, 0.3, 1e-2, R=1.0, grid=60)
    with pytest.raises(InputError, match="datum"):
        HalfPlaneCylinder.under_approach(1.0, 1.0, 0.3, 0.3, 0.02, datum=0.1, nodes=100)
    with pytest.raises(InputError, match="datum"):
        HalfPlaneCylinder(1.0, 1.0, 0.3, 0.3, 1e-3, 0.0, nodes=100, datum=float("nan"))


def test_the_table_is_exact_between_its_breakpoints():
    """With the contact set fixed the pressures are affine in the approach: the table's line
    between two breakpoints is the solve's load at the midpoint."""
    m = HalfPlaneCylinder(1.0, 1.0, 0.3, 0.3, 1e-3, 0.0, nodes=60, datum=50.0)
    table = ApproachTable(m.A, m.h, m.dx, 0.01)
    assert np.all(np.diff(table.d) > 0) and np.all(np.diff(table.P) > 0)
    mid = 0.5 * (table.d[3] + table.d[4])
    P = float(table(mid))
    assert _approach_of(m, P) == pytest.approx(mid, rel=1e-12)
    assert table(table.d[0] - 1.0) == 0.0 and table.slope(table.d[0] - 1.0) == 0.0


def test_trapezoid_coefficients():
    """On a uniform grid the discrete transform; on records of any spacing the trapezoidal rule,
    second order (measured on random refinements of a grid)."""
    from lcpfric.harmonic import fourier_basis

    T = 2.0
    n = 64
    t = np.arange(n + 1) * T / n
    x = 0.5 + np.cos(np.pi * t) - 0.25 * np.sin(2 * np.pi * t) + 0.1 * np.cos(3 * np.pi * t) ** 3
    np.testing.assert_allclose(
        trapezoid_coefficients(t, x, T, 4), fourier_basis(4, n).to_coefficients(x[:-1]), atol=1e-15
    )
    rng = np.random.default_rng(3)
    errors = []
    for m in (50, 100, 200, 400):
        tt = np.sort(np.r_[np.linspace(0.0, T, m + 1), rng.uniform(0, T, m // 4)])
        y = 0.5 + np.cos(np.pi * tt) - 0.25 * np.sin(2 * np.pi * tt)
        c = trapezoid_coefficients(tt, y, T, 2)
        errors.append(np.max(np.abs(c - [0.5, 1.0, 0.0, 0.0, -0.25])))
    orders = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(orders > 1.5), orders


def test_describing_functions_under_an_approach():
    """The half-space sphere under an oscillating approach against the MDR sphere under the
    same approach (the describing functions of a varying normal load): within 1 % at grid 16
    (measured 0.25-0.45 % in W, 0.37-0.50 % in k_eq; benchmarks/validation/approach.py)."""
    from lcpfric.analysis.describing_contact import contact_describing_functions
    from lcpfric.model.continuum.mdr import MDRSphere

    d = Harmonic(1e-2, 0.5e-2, 0.3)
    a = np.array([1e-4, 1e-3])
    mdr = contact_describing_functions(
        MDRSphere.under_approach(1.0, 1.0, 0.3, 0.3, d, nodes=1000), a, samples=1024
    )
    hs = contact_describing_functions(
        HalfSpace.under_approach(1.0, 0.3, 0.3, d, R=1.0, grid=16), a, steps=200
    )
    np.testing.assert_allclose(hs.W, mdr.W, rtol=1e-2)
    np.testing.assert_allclose(hs.k_eq, mdr.k_eq, rtol=1e-2)
