"""The dynamic single node (issue 40, items 1-2): ``SingleNode(..., mass=m, damping=c)`` solved by
``exact`` event by event, its periodic orbit by Newton's method on the period map, against Den
Hartog's closed form (ζ = 0, constant N, no stops), an independent event-driven integration
(DOP853, tests/support/dynamic_reference.py) with stops, damping, a varying normal load and
separation, and the quasi-static limit β -> 0."""

import math
import warnings

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError, MultipleSteadyStates
from lcpfric.exact.dynamic import DynamicNode, period_map
from lcpfric.exact.dynamic_api import dynamic_cycle
from support.dynamic_reference import one_period


def den_hartog_W_hat(beta, Q1):
    """Ŵ = 4 X k11/Q1 = 4 sqrt(V² - (rU)²) with r = 1/Q̂1 (the notes' form; ζ = 0, P̂1 = 0)."""
    V = 1.0 / (1.0 - beta**2)
    U = math.tan(math.pi / (2 * beta)) / beta
    return 4.0 * math.sqrt(V**2 - (U / Q1) ** 2)


@pytest.mark.parametrize(
    "beta, Q1", [(0.8, 2.0), (1.5, 2.0), (0.6, 4.0), (1.2, 3.0), (0.7, 5.0), (2.5, 3.0)]
)
def test_den_hartog(beta, Q1):
    """No damping, constant N, motion without stops: W and the amplitude within 1e-9 (measured
    to 1e-13 or better)."""
    cyc = dynamic_cycle(0.0, Q1, 0.3, beta, 0.0)
    W_hat = den_hartog_W_hat(beta, Q1)
    assert cyc.W_hat == pytest.approx(W_hat, rel=1e-9, abs=1e-12)
    assert cyc.orbit.amplitude == pytest.approx(Q1 * W_hat / 4, rel=1e-9)  # W = 4 F X
    assert cyc.orbit.stable and len(cyc.orbits) == 1


CASES = [  # P̂1, Q̂1, φ, β, ζ: stops, damping, varying N, separation
    (0.5, 2.0, 0.7, 0.3, 0.05),
    (0.5, 2.0, 0.7, 1.3, 0.1),
    (1.5, 2.0, 0.4, 0.7, 0.02),
    (1.5, 1.0, 2.0, 2.0, 0.2),
    (2.5, 3.0, 5.0, 1.1, 0.05),
    (0.0, 1.2, 0.0, 3.0, 0.0),
    (0.9, 1.5, 3.5, 0.45, 0.3),
    # undamped, apart most of the cycle: Newton's method wanders, the motion settles it
    (7.425847668078969, 0.202010965564611, 4.097521069034529, 0.5762922569587907, 0.0),
]


@pytest.mark.parametrize("case", CASES)
def test_against_an_independent_integration(case):
    """The orbit's start integrated over one period by DOP853 with its own events returns to
    itself, with the same W and amplitude: within 1e-9 (measured 2e-11 or better)."""
    cyc = dynamic_cycle(*case)
    orb = cyc.orbit
    z, J, lo, hi = one_period(*case, orb.z)
    scale = max(1.0, float(np.max(np.abs(orb.z))))
    assert np.max(np.abs(z - orb.z)) <= 1e-9 * scale
    assert J == pytest.approx(orb.J, rel=1e-9, abs=1e-12)
    assert (hi - lo) / 2 == pytest.approx(orb.amplitude, rel=1e-9, abs=1e-12)
    assert orb.residual <= 1e-12 * max(1.0, case[1], scale)


def test_the_period_maps_jacobian():
    """The exact Jacobian of the period map (flows, saltations at stops and reversals) against
    central differences at a point whose events move smoothly."""
    node = DynamicNode(0.5, 2.0, 0.7, 1.3, 0.1)
    z = np.array([0.3, -0.2])
    J = period_map(node, z).jacobian
    h = 1e-6
    fd = np.column_stack(
        [
            (period_map(node, z + h * e).z - period_map(node, z - h * e).z) / (2 * h)
            for e in np.eye(2)
        ]
    )
    np.testing.assert_allclose(J, fd, rtol=1e-5, atol=1e-7)


def test_the_quasi_static_limit():
    """β -> 0: the dynamic Ŵ tends to the quasi-static exact one (measured relative differences
    6.2e-2, 4.4e-3, 1.4e-4 at β = 0.1, 0.03, 0.01 with ζ = 0.05)."""
    qs = float(lcpfric.exact_W_hat(0.5, 2.0, 0.7))
    err = [abs(dynamic_cycle(0.5, 2.0, 0.7, b, 0.05).W_hat / qs - 1) for b in (0.1, 0.03, 0.01)]
    assert err[0] > err[1] > err[2] and err[2] < 1e-3


def test_through_the_driver_and_its_units():
    """steady_state(node, "exact") on a node with a mass: W in the node's units (the normalized
    node's Ŵ), the amplitude and velocity, the series; mass 0 is the quasi-static node."""
    node = lcpfric.SingleNode(
        k11=2.0, f=0.5, P0=3.0, P1=1.0, Q1=2.5, omega=1.3, phi=0.4, Q0=0.7, mass=1.5, damping=0.2
    )
    r = lcpfric.steady_state(node, "exact", 400)
    same = lcpfric.SingleNode.normalized(
        *node.normalized_parameters(), beta=node.beta, zeta=node.zeta
    )
    assert r.W_hat == pytest.approx(lcpfric.steady_state(same, "exact").W_hat, rel=1e-12)
    assert r.W == pytest.approx(node.W(r.W_hat), rel=1e-14)
    d = r.dynamics
    assert d.beta == pytest.approx(1.3 / math.sqrt(2.0 / 1.5)) and d.stable
    assert (r.v.max() - r.v.min()) / 2 == pytest.approx(d.amplitude, rel=1e-3)
    np.testing.assert_allclose(np.gradient(r.v, r.t)[5:-5], d.velocity[5:-5], rtol=0, atol=0.05)
    # the friction force never exceeds f N; where the node slips it is f N
    assert np.all(np.abs(r.F) <= node.f * r.N + 1e-12)
    still = lcpfric.SingleNode(k11=2.0, f=0.5, P0=3.0, P1=1.0, Q1=2.5, omega=1.3, phi=0.4)
    assert not still.is_dynamic and lcpfric.steady_state(still, "exact").dynamics is None


def test_a_start_chooses_among_rest_states():
    """A cycle stuck throughout: W = 0, a neutral family of rest states (multiplier 1), reported
    stable; the start given is where it rests."""
    node = lcpfric.SingleNode.normalized(0.3, 0.5, 1.0, beta=0.5, zeta=0.01)
    r = lcpfric.steady_state(node, "exact", u0=0.2)
    assert r.W == 0.0 and r.dynamics.stable
    assert np.allclose(r.v, 0.2)


def test_bad_input():
    with pytest.raises(InputError, match="mass"):
        lcpfric.SingleNode(mass=-1.0)
    with pytest.raises(InputError, match="damping"):
        lcpfric.SingleNode(mass=1.0, damping=float("nan"))
    with pytest.raises(InputError, match="damping"):
        lcpfric.SingleNode(damping=1.0)
    with pytest.raises(InputError, match="omega.*resonance"):
        lcpfric.SingleNode(k11=4.0, mass=1.0, omega=2.0, Q1=1.0)
    with pytest.raises(InputError, match="zeta"):
        lcpfric.SingleNode.normalized(0.5, 1.0, zeta=0.1)
    node = lcpfric.SingleNode.normalized(0.5, 2.0, 0.7, beta=1.3, zeta=0.1)
    with pytest.raises(InputError, match="method.*'exact'"):
        lcpfric.steady_state(node, "explicit")
    with pytest.raises(InputError, match="u0"):
        lcpfric.steady_state(node, "exact", u0=[1.0, 2.0, 3.0])


def test_several_steady_states_are_never_picked_silently(monkeypatch):
    """Orbits of different W from different starts: a MultipleSteadyStates warning naming them,
    and every orbit in the result (the starts' orbits forced apart here: of 1499 random extreme
    inputs none had two, benchmarks/results/dynamic-node.md, section 2c)."""
    import lcpfric.exact.dynamic as dyn
    import lcpfric.exact.dynamic_api as api

    node = lcpfric.SingleNode.normalized(0.0, 3.0, 0.0, beta=0.8, zeta=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", MultipleSteadyStates)
        r = lcpfric.steady_state(node, "exact")  # one orbit: no warning
    assert len(r.dynamics.orbits) == 1
    true = dyn.periodic_orbit

    def shifted(nd, start, **kw):  # the second start "finds" an orbit of twice the W
        orb = true(nd, start, **kw)
        if start[0] != 0.0 or start[1] != 0.0:
            from dataclasses import replace

            orb = replace(orb, J=2 * orb.J, stable=False)
        return orb

    monkeypatch.setattr(api, "periodic_orbit", shifted)
    with pytest.warns(MultipleSteadyStates, match="2 periodic steady states.*unstable"):
        r = lcpfric.steady_state(node, "exact")
    assert len(r.dynamics.orbits) == 2
    assert r.dynamics.orbits[0]["start"] == "rest" and r.W == r.dynamics.orbits[0]["W"]
    assert r.dynamics.orbits[1]["W"] == pytest.approx(2 * r.W)


def test_the_motor_with_its_inertia():
    """The paper's motor as the dynamic node (M on k11, ζ): W tends to the quasi-static W as the
    joint stiffens (Ω/Ω0 -> 0 at fixed speed; measured 4.2e-5 at Ω/Ω0 = 1e-2, f = 0.3, 3 times
    the separation speed), and resonance is refused without damping."""
    from lcpfric.paper.motor import Motor

    base = Motor(M=20.0, delta=0.5e-3, P0=2000.0, k11=5e8)
    Om = 3.0 * base.separation_speed()
    stiff = Motor(M=20.0, delta=0.5e-3, P0=2000.0, k11=20.0 * (Om / 1e-2) ** 2)
    assert Om / stiff.natural_frequency() == pytest.approx(1e-2)
    W, Wqs = stiff.dynamic_dissipation(Om, 0.3), stiff.dissipation(Om, 0.3)
    assert W == pytest.approx(Wqs, rel=1e-4)
    assert W != Wqs
    with pytest.raises(InputError, match="Omega"):
        base.dynamic_dissipation(base.natural_frequency(), 0.3, zeta=0.0)


def test_the_frequency_response_of_a_nearly_frictionless_node():
    """f -> 0: the linear oscillator's amplitude Q1/k / sqrt((1-β²)² + (2ζβ)²) and lag
    atan2(2ζβ, 1 - β²) (within the friction's 1e-4 of the load)."""
    from lcpfric.analysis.frequency_response import frequency_response

    node = lcpfric.SingleNode(k11=1.0, f=1e-4, P0=1.0, Q1=1.0, omega=1.0, mass=1.0, damping=0.2)
    w = np.array([0.3, 0.9, 1.0, 1.2, 2.0])
    r = frequency_response(node, w)
    lin = 1.0 / np.sqrt((1 - w**2) ** 2 + (0.2 * w) ** 2)
    np.testing.assert_allclose(r.amplitude, lin, rtol=5e-4)
    np.testing.assert_allclose(r.phase, np.arctan2(0.2 * w, 1 - w**2), atol=5e-4)
    assert np.all(r.stable) and np.all(r.orbits == 1) and r.method == "exact"
    np.testing.assert_allclose(r.beta, w)
    with pytest.raises(InputError, match="node"):
        frequency_response(lcpfric.SingleNode(Q1=1.0), [1.0])
    with pytest.raises(InputError, match="omega"):
        frequency_response(node, [1.0, -1.0])


def test_the_dynamic_figures(tmp_path):
    """The three figures are drawn (their content: benchmarks/validation/dynamic_node.py and
    motor_dynamic.py)."""
    from support import need_modules

    need_modules("matplotlib")
    from lcpfric.analysis.frequency_response import frequency_response
    from lcpfric.figures.dynamic import (
        figure_dynamic_node,
        figure_frequency_response,
        figure_motor_dynamic,
    )

    node = lcpfric.SingleNode.normalized(0.5, 2.0, 0.7, beta=1.0, zeta=0.1)
    r = frequency_response(node, np.linspace(0.5, 1.5, 5))
    figure_frequency_response(r).savefig(tmp_path / "frf.png")
    b = np.array([0.5, 1.0, 2.0])
    figure_dynamic_node(b, [("z", b + 1, b)], 1.5, (b, b + 1, b)).savefig(tmp_path / "d.pdf")
    figure_motor_dynamic(b, [(0.3, b, 1.1 * b)], 0.05).savefig(tmp_path / "m.png")
    assert all((tmp_path / n).stat().st_size > 0 for n in ("frf.png", "d.pdf", "m.png"))


def test_a_node_with_a_mass_under_other_periodic_loads_is_refused_by_name():
    from lcpfric.model import Fourier

    q = Fourier(0.0, (1.0, 0.3), (0.0, 0.5))
    node = lcpfric.SingleNode(tangential_load=q, mass=0.5, damping=0.1)
    with pytest.raises(InputError, match="harmonic loads only"):
        lcpfric.steady_state(node, "exact")
    with pytest.raises(InputError, match="'explicit' or 'projection'"):
        lcpfric.steady_state(lcpfric.SingleNode(tangential_load=q), "exact")
