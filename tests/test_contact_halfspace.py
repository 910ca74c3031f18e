"""The 3-D half-space contact (lcpfric.model.continuum.halfspace and the newton-cg stepper):
influence coefficients, the normal problem against ContactMechanics and Hertz, the tangential
increments against the convex backends, Mindlin-Deresiewicz, the MDR model, and the properties of
the steady state."""

import math
from pathlib import Path

import numpy as np
import lcpfric
import pytest
from scipy import integrate

from lcpfric.model.continuum.closed_forms import hertz_contact, mindlin_deresiewicz_W
from lcpfric.model.continuum.halfspace import HalfSpace
from lcpfric.model.continuum.influence import Convolution, element_integrals
from lcpfric.model.continuum.normal3d import normal_contact
from support import need, halfspace_sphere as sphere
from lcpfric.errors import InputError
from lcpfric.model.loads import Harmonic

TWO_PI = 2.0 * math.pi
DATA = Path(__file__).parent / "data" / "halfspace_reference.npz"


@pytest.mark.parametrize("x, y", [(0.3, 0.0), (0.6, -0.9), (1.2, 0.3), (-0.45, 0.75)])
def test_element_integrals_against_quadrature(x, y):
    """Love's closed forms of ∬1/r, ∬x²/r³, ∬xy/r³ over a square, against adaptive
    quadrature (off the element: the integrands are smooth there)."""
    h = 0.3
    got = element_integrals(x, y, h)
    fs = (
        lambda b, a: 1 / math.hypot(a, b),
        lambda b, a: a * a / math.hypot(a, b) ** 3,
        lambda b, a: a * b / math.hypot(a, b) ** 3,
    )
    for g, f in zip(got, fs):
        ref = integrate.dblquad(f, x - h / 2, x + h / 2, y - h / 2, y + h / 2, epsabs=1e-13)[0]
        assert float(g) == pytest.approx(ref, rel=1e-9, abs=1e-13)
    # the self-term of 1/r over a square of side h: 4 h asinh(1)
    assert float(element_integrals(0.0, 0.0, h)[0]) == pytest.approx(4 * h * math.asinh(1.0))


@pytest.mark.parametrize("nu, dims", [(0.0, 1), (0.3, 1), (0.3, 2), (0.0, 2)])
def test_fft_products_equal_the_dense_matrices(nu, dims):
    """The zero-padded FFT product is the non-periodic product with the influence matrix; the
    tangential operator is symmetric positive definite (Cerruti's coupling included)."""
    N = 7
    op = Convolution(N, 0.1, 2.0, nu, dims)
    rng = np.random.default_rng(0)
    p = rng.standard_normal((N, N))
    assert np.allclose(op.normal(p).ravel(), op.dense("n") @ p.ravel(), atol=1e-14)
    if dims == 1:
        assert np.allclose(op.tangential(p).ravel(), op.dense("xx") @ p.ravel(), atol=1e-14)
        return
    q = rng.standard_normal((2, N, N))
    xy = op.dense("xy") if op.coupled else np.zeros((N * N, N * N))
    D = np.block([[op.dense("xx"), xy], [xy, op.dense("yy")]])
    assert np.allclose(op.tangential(q).reshape(-1), D @ q.reshape(-1), atol=1e-14)
    assert np.allclose(D, D.T) and np.linalg.eigvalsh(D).min() > 0
    if nu == 0.0:  # at ν = 0 the tangential kernel is the normal one (G = E*)
        assert np.allclose(op.dense("xx"), op.dense("n"), rtol=1e-14)


@pytest.mark.parametrize("case", ["a", "b"])
def test_normal_contact_against_contactmechanics(case):
    """The same discretization (uniform-pressure squares, zero-padded FFT, non-periodic) solved
    by ContactMechanics 1.8.3 (Polonsky-Keer in its FreeFFTElasticHalfSpace; stored by
    benchmarks/validation/halfspace_reference.py): pressures and approach agree to round-off."""
    ref = np.load(DATA)
    N, h, Es, P = (
        int(ref["N_" + case]),
        float(ref["h_" + case]),
        float(ref["Estar_" + case]),
        float(ref["P_" + case]),
    )
    op = Convolution(N, h, 2.0 * Es, 0.0)  # ν = 0: E* = E / 2
    sol = normal_contact(op, ref["heights_" + case], P)
    p_ref = ref["pressure_" + case]
    assert np.max(np.abs(sol.p - p_ref)) <= 1e-9 * p_ref.max()
    assert sol.d == pytest.approx(float(ref["approach_" + case]), rel=1e-10)
    assert h * h * sol.p.sum() == pytest.approx(P, rel=1e-13)


def test_hertz_radius_and_pressure():
    """The discrete contact's radius (of its area) and peak pressure approach Hertz's as the
    grid is refined."""
    errs = []
    for grid in (20, 40):
        m = sphere(grid=grid, Q1=0.0)
        p = m.pressure(1.0)
        hz = hertz_contact(1.0, 1.0, 1.0, 0.0)
        a = math.sqrt(np.count_nonzero(p) * m.h**2 / math.pi)
        errs.append((abs(a / hz["a"] - 1), abs(p.max() / hz["p0"] - 1)))
        assert m.h**2 * p.sum() == pytest.approx(1.0, rel=1e-13)
    assert errs[1][0] < 0.02 and errs[1][1] < 0.005
    assert errs[1][1] < errs[0][1]


def _increments(m, steps=100):
    """The newton-cg stepper's increments on the model's scene: ``(stepper, its context,
    the virgin contact's state)``."""
    from lcpfric.steppers.newton_cg import NewtonCGStepper

    stepper = NewtonCGStepper()
    scene = lcpfric.make_scene(m, steps)
    context = stepper.context(scene)
    return stepper, context, stepper.start(scene, context)


def _restarted(stepper, context, state):
    """The state restarted at its own slips (the driver's acceleration's path)."""
    from lcpfric.results import StepState
    from lcpfric.steppers.continuum import ContinuumData

    step = StepState(state.v, state.F, None, data=ContinuumData(state, context))
    return stepper.restart(None, step, state.v).data.tangential


def test_cattaneo_stick_radius():
    """Q rising from 0 to 0.9 μP at constant P: the stick zone's radius (of its area) over the
    contact's is (1 - Q/(μP))^(1/3), within a little more than an element."""
    Q = Harmonic(0.0, 0.45, 0.0, TWO_PI)  # quarter cycle: 0 -> 0.9 μP
    m = HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, 1.0, Q, grid=28)
    steps = 100
    b = m.normal_solution(np.zeros(1))[0][0]
    stepper, context, state = _increments(m)
    t = np.linspace(0.0, 0.25 * TWO_PI / TWO_PI, steps + 1)
    a = math.sqrt(np.count_nonzero(b) * m.h**2 / math.pi)
    checked = 0
    for j in range(1, steps + 1):
        state, F, dv = stepper.increment(context, state, b, float(Q(t[j])))
        x = float(Q(t[j])) / (0.5 * 1.0)
        if x > 0.3 and j % 10 == 0:
            stick = (b > 0) & (dv == 0.0)
            c = math.sqrt(np.count_nonzero(stick) * m.h**2 / math.pi)
            assert abs(c / a - (1 - x) ** (1 / 3)) < 1.5 * m.h / a, x
            checked += 1
    assert checked >= 5


@pytest.mark.parametrize("x", [0.5])
def test_mindlin_deresiewicz_at_constant_load(x):
    """ν = 0, d = 1, Q cycling at constant P: W within 2.5 % of Mindlin-Deresiewicz on a coarse
    grid (316 nodes in contact) and closer on a finer one (the benchmark's 1272 nodes: 0.6 %)."""
    ref = mindlin_deresiewicz_W(1.0, x * 0.5, 0.5, hertz_contact(1.0, 1.0, 1.0, 0.0)["k_t0"])
    errs = []
    for grid in (20, 28):
        r = lcpfric.steady_state(sphere(Q1=x * 0.5, grid=grid), steps_per_cycle=100)
        assert r.converged and r.cycles == 3
        errs.append(abs(r.W / ref - 1))
    assert errs[0] < 0.025 and errs[1] < errs[0]


@pytest.mark.slow
def test_two_directions_at_nu_zero_equal_one():
    """At ν = 0 Cerruti has no coupling and d = 2 gives d = 1's answer (no transverse traction);
    with ν > 0 the transverse tractions appear and W differs by a few percent."""
    r1 = lcpfric.steady_state(sphere(P1=0.5, Q1=0.2, phi=0.7, grid=12), steps_per_cycle=60)
    r2 = lcpfric.steady_state(sphere(P1=0.5, Q1=0.2, phi=0.7, grid=12, dims=2), steps_per_cycle=60)
    assert r2.W == pytest.approx(r1.W, rel=1e-9)
    r3 = lcpfric.steady_state(
        sphere(P1=0.5, Q1=0.2, phi=0.7, grid=12, nu=0.3, dims=2), steps_per_cycle=60
    )
    r4 = lcpfric.steady_state(sphere(P1=0.5, Q1=0.2, phi=0.7, grid=12, nu=0.3), steps_per_cycle=60)
    assert 1e-5 < abs(r3.W / r4.W - 1) < 0.05
    assert np.max(np.abs(r3.F[:, 1::2])) > 1e-3 * np.max(np.abs(r3.F[:, 0::2]))


@pytest.mark.slow
@pytest.mark.parametrize("dims, nu", [(1, 0.0), (2, 0.3)])
def test_against_the_convex_backends(dims, nu):
    """Held by a support, the half-space is an lcpfric ContactSystem (its compliance the FFT
    product; the elements' exact entry loads as its normal model's transitions): Clarabel
    (second-order cones for d = 2) and active-set (d = 1, matrix-free) give the model's W on
    the same scene."""
    need("clarabel")
    import lcpfric
    from lcpfric.scene import make_scene

    m = sphere(P1=0.5, Q1=0.3, phi=0.7, nu=nu, grid=10, dims=dims, k_support=2.0)
    system = m.system()
    assert system.matrix_free  # the FFT product; C⁻¹ B by CG
    scene = make_scene(system, 80)
    # d = 2: the cycles repeat to the increments' own accuracy (about 1e-11), not to 1e-12
    ref = lcpfric.steady_state(
        lcpfric.make_scene(m, grid=scene.t), tol=1e-12 if dims == 1 else 1e-10
    ).W
    # Clarabel's answers on the cones pass its own tolerance but not always lcpfric's 1e-6
    # stationarity check; the dissipation agrees to 1e-10 regardless
    opts = {"check_tol": 1e-4} if dims == 2 else {}
    r = lcpfric.steady_state(scene, "clarabel", tol=1e-12, locate_events=False, **opts)
    assert r.W == pytest.approx(ref, rel=1e-9)
    if dims == 1:
        r = lcpfric.steady_state(scene, "active-set", tol=1e-12, locate_events=False)
        assert r.W == pytest.approx(ref, rel=1e-9)


def test_against_mdr_with_varying_load():
    """ν = 0, P and Q varying with a phase: the half-space agrees with the axisymmetric (MDR)
    model within 3 % on a coarse grid, and closer on a finer one."""
    from lcpfric.model.continuum import MDRSphere

    P, Q = Harmonic(1.0, 0.5, 0.0, TWO_PI), Harmonic(0.0, 0.2, 0.7, TWO_PI)
    ref = lcpfric.steady_state(
        MDRSphere(1.0, 1.0, 0.0, 0.5, P, Q, nodes=2000), steps_per_cycle=100
    ).W
    errs = [
        abs(
            lcpfric.steady_state(
                HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, P, Q, grid=g), steps_per_cycle=100
            ).W
            / ref
            - 1
        )
        for g in (16, 24)
    ]
    assert errs[0] < 0.03 and errs[1] < errs[0]


def test_in_phase_and_half_period_shift():
    """In phase (Q1 <= μ P1, P1 < P0) nothing is dissipated up to the discretization; W(φ + π)
    = W(φ)."""
    w0 = lcpfric.steady_state(
        sphere(P1=0.5, Q1=0.2, phi=0.0, grid=14), steps_per_cycle=80
    ).W_normalized
    w1 = lcpfric.steady_state(
        sphere(P1=0.5, Q1=0.2, phi=0.8, grid=14), steps_per_cycle=80
    ).W_normalized
    w2 = lcpfric.steady_state(
        sphere(P1=0.5, Q1=0.2, phi=0.8 + math.pi, grid=14), steps_per_cycle=80
    ).W_normalized
    assert w0 < 0.05 * w1
    assert w2 == pytest.approx(w1, rel=1e-9)


@pytest.mark.slow
def test_in_phase_with_fine_steps():
    """In phase on grid 32 with 400 steps: the increments are large against the tolerance
    (the forces change a lot, the slips hardly), the case where an inconsistent start product
    (C F carried over the increments by linearity, tried and reverted) left a d = 1 increment
    unable to reach its tolerance. It repeats in 3 cycles, W → 0 (the benchmark's 5.7e-7)."""
    r = lcpfric.steady_state(
        HalfSpace.sphere(
            10.0,
            200e3,
            0.0,
            0.5,
            Harmonic(100.0, 50.0, 0.0, TWO_PI),
            Harmonic(0.0, 20.0, 0.0, TWO_PI),
            grid=32,
        ),
        steps_per_cycle=400,
    )
    assert r.converged and r.cycles <= 4
    assert 0.0 <= r.W_normalized < 2e-6


def _md(grid):
    return HalfSpace.sphere(
        10.0,
        200e3,
        0.0,
        0.5,
        Harmonic(100.0, 0.0, 0.0, TWO_PI),
        Harmonic(0.0, 25.0, 0.0, TWO_PI),
        grid=grid,
    )


@pytest.mark.slow
def test_d1_large_increments_on_a_fine_grid(monkeypatch):
    """8 steps per cycle on grid 64: an increment changes the state of thousands of nodes, the
    active-set patterns stall, and Murty's rule (one node per iteration) ran out of iterations
    (SolverError after 3312 Newton steps, residual 0.047). d = 1 then turns to the damped
    Newton steps of d = 2: it converges. On grid 40, where both work, the damped steps alone
    (from every increment's first iteration) give the patterns' W to 1e-12.

    Finer grids: the damped steps start from the previous increment's forces, not from the
    stalled iterate, and where every node slips, as many nodes stick as can carry the load
    (not one). Either old rule made the line search crawl at steps of 2^-12, with the same W
    in the end: 4153 Newton steps on grid 120 at constant P, 2962 on grid 96 with varying P
    (171 and 172 now)."""
    from lcpfric.steppers import newton_increment

    r = lcpfric.steady_state(_md(64), steps_per_cycle=8)
    assert r.converged and r.W > 0
    for m in (_md(120), sphere(P1=0.5, Q1=0.2, phi=0.5 * np.pi, grid=96)):
        r = lcpfric.steady_state(m, steps_per_cycle=8)
        st = r.solver_stats
        assert r.converged and st["stalled"] > 0 and st["newton"] < 400
    w = lcpfric.steady_state(_md(40), steps_per_cycle=8).W
    monkeypatch.setattr(newton_increment, "_SINGLE_MAX", -1)
    assert lcpfric.steady_state(_md(40), steps_per_cycle=8).W == pytest.approx(w, rel=1e-12)


def test_d2_residual_hovering_about_the_tolerance():
    """Large increments with phases of gross sliding (the support holds the body): the damped
    steps' linear solves, stopped at 0.9 of the tolerance, left one increment's residual
    hovering between 0.5 and 1.02 of it until the Newton iterations ran out (SolverError,
    residual 1.27e-11 above 1.24e-11). Steps that begin near the tolerance and do not end the
    increment now solve ten times tighter each. (The hovering depends on round-off: this case
    showed it on the development machine.)"""

    def model(ks):
        return HalfSpace.sphere(
            10.0,
            200e3,
            0.3,
            0.5,
            Harmonic(100.0, 50.0, 0.0, TWO_PI),
            Harmonic(0.0, 45.0, np.pi, TWO_PI),
            grid=32,
            dims=2,
            k_support=ks,
        )

    m = model(model(1.0).k_t0)
    r = lcpfric.steady_state(m, steps_per_cycle=8)
    assert r.converged and r.solver_stats["newton"] < 200


@pytest.mark.parametrize(
    "P1, Q1, phi", [(0.9, 0.8, 0.2), (0.3, 1.5, 0.7), (1.3, 0.6, 0.5), (0.5, 0.9, 1.0)]
)
@pytest.mark.parametrize("dims, nu", [(1, 0.0), (2, 0.3)])
def test_large_increments_across_the_loads(P1, Q1, phi, dims, nu):
    """8 steps per cycle, the support k_t0 holding the body: near separation, gross sliding
    (Q1 = 1.5 μP0), complete separation (P1 = 1.3) and opposite phases all reach a steady
    state. (Sweeps of these loads on grids 32 to 120, 8 to 40 steps, spheres, the punch and a
    rough surface, found the crawl and the hovering that the two tests above guard.)"""

    def model(ks):
        return HalfSpace.sphere(
            10.0,
            200e3,
            nu,
            0.5,
            Harmonic(100.0, 100.0 * P1, 0.0, TWO_PI),
            Harmonic(0.0, 50.0 * Q1, phi * np.pi, TWO_PI),
            grid=32,
            dims=dims,
            k_support=ks,
        )

    r = lcpfric.steady_state(model(model(1.0).k_t0), steps_per_cycle=8)
    assert r.converged and r.W > 0


def test_d2_preconditioner_scaled_on_the_slipping_nodes():
    """d = 2 under gross sliding held by a support (most nodes slip): the Newton steps'
    unknowns are mostly the slipping nodes' tangential forces, whose operator adds a diagonal
    term to C. With the preconditioner (C's inverse) scaled on them by sqrt(c / (c + term))
    this case takes 1928 FFT products on the development machine; unscaled it took 5988."""

    def model(ks):
        return HalfSpace.sphere(
            10.0,
            200e3,
            0.3,
            0.5,
            Harmonic(100.0, 30.0, 0.0, TWO_PI),
            Harmonic(0.0, 75.0, 0.7 * np.pi, TWO_PI),
            grid=32,
            dims=2,
            k_support=ks,
        )

    m = model(model(1.0).k_t0)
    r = lcpfric.steady_state(m, steps_per_cycle=8)
    assert r.converged and r.solver_stats["tangential_products"] < 3000


@pytest.mark.parametrize("dims, nu", [(1, 0.0), (2, 0.3)])
def test_small_tangential_loads_reach_the_steady_state(dims, nu):
    """Q1 = 1e-4 μP0: the increments' tolerance follows the loads' displacement scale (the
    cycle criterion's), not only the largest limit; with the latter the cycles' change hovered
    at the increments' errors (1.7e-9 for d = 1, 2e-4 for d = 2, never below 1e-10). Nothing
    slips, so the slips of the nodes in contact repeat at once: d = 2 is confirmed in 3 cycles
    (6 when the nodes out of contact counted, their v following the loosely solved forces)."""
    from lcpfric.errors import ResolutionWarning

    m = sphere(Q1=0.5e-4, grid=16, dims=dims, nu=nu)
    # no element slips at this load: the slip annulus (about x/3 of the radius in Mindlin's
    # solution, x = 1e-4) is far thinner than an element, and the result says so
    with pytest.warns(ResolutionWarning, match="no element slipped"):
        r = lcpfric.steady_state(m, steps_per_cycle=100, max_cycles=30)
    assert r.converged and r.change <= 1e-10 and r.W == 0.0
    assert r.cycles <= 3


@pytest.mark.parametrize("dims, nu", [(1, 0.0), (2, 0.3)])
def test_carried_products_stay_those_of_the_forces(dims, nu):
    """The state carries ``C F`` and each increment's ``C ΔF`` (an increment's start then
    costs no product): over two cycles with varying P (nodes enter and leave the contact) and
    each increment started from the previous cycle's, they stay the products of the state's
    forces and changes to round-off, and the increments' forces satisfy their limits."""
    m = sphere(P1=0.5, Q1=0.3, phi=0.5 * math.pi, nu=nu, grid=14, dims=dims)
    steps = 24
    stepper, context, state = _increments(m, steps)
    t = np.linspace(0.0, m.period, steps + 1)
    b, Q = m.normal_solution(t)[0], m.Q(t)
    guesses = None
    scale = float(np.max(np.abs(context.compliance(np.ones((m.nodes, dims)) * b.max()))))
    for _ in range(2):
        new = []
        for j in range(steps):
            state, F, _ = stepper.increment(
                context, state, b[j + 1], Q[j + 1], guesses[j] if guesses else None
            )
            new.append(stepper.guess(state))
            F_nodes = state.F.reshape(-1, dims)
            assert np.max(np.abs(state.CF - context.compliance(F_nodes))) <= 1e-12 * scale
            dF = state.dF.reshape(-1, dims)
            assert np.max(np.abs(state.CdF - context.compliance(dF))) <= 1e-12 * scale
            norms = (
                np.abs(F.reshape(-1, dims)) if dims == 1 else np.hypot(*F.reshape(-1, 2).T)[:, None]
            )
            assert np.all(norms[:, 0] <= b[j + 1] * (1 + 1e-12))
        guesses = new
        state = _restarted(stepper, context, state)


def test_punch_and_height_map():
    """A flat punch with rounded edges and a user height map run; the punch's contact covers
    the flat; the height map of a sphere given by hand equals the sphere."""
    P, Q = Harmonic(1.0, 0.3, 0.0, TWO_PI), Harmonic(0.0, 0.2, 0.5, TWO_PI)
    punch = HalfSpace.punch(1.0, 0.5, 1.0, 0.0, 0.5, P, Q, grid=16)
    r = lcpfric.steady_state(punch, steps_per_cycle=40)
    assert r.converged and r.W > 0 and r.contact.contact_size_max > 0.5
    s = HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, P, Q, grid=12)
    hm = HalfSpace(1.0, 0.0, 0.5, P, Q, heights=s.g0 * 1.0, spacing=s.h)
    assert lcpfric.steady_state(hm, steps_per_cycle=40).W == pytest.approx(
        lcpfric.steady_state(s, steps_per_cycle=40).W, rel=1e-12
    )


def test_bad_input_is_refused_before_work():
    P, Q = Harmonic(1.0, 0.3, 0.0, TWO_PI), Harmonic(0.0, 0.2, 0.5, TWO_PI)
    with pytest.raises(InputError, match="grid"):
        HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, P, Q, grid=6)
    with pytest.raises(InputError, match="too coarse"):
        HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, Harmonic(1.0, 0.9, 0, TWO_PI), Q, grid=9)
    with pytest.raises(InputError, match="heights"):
        HalfSpace(1.0, 0.0, 0.5, P, Q, heights=np.zeros((5, 6)), spacing=0.1)
    with pytest.raises(InputError, match="heights"):
        HalfSpace(1.0, 0.0, 0.5, P, Q, heights=np.full((8, 8), np.nan), spacing=0.1)
    with pytest.raises(InputError, match="dims"):
        sphere(dims=3)
    with pytest.raises(InputError, match="spacing"):
        HalfSpace(1.0, 0.0, 0.5, P, Q, heights=np.zeros((8, 8)), spacing=-1.0)
    with pytest.raises(InputError, match="heights"):  # beyond the largest grid
        HalfSpace(1.0, 0.0, 0.5, P, Q, heights=np.zeros((4096, 4096)), spacing=0.1)
    from lcpfric import memory

    with memory.limit(4 << 30, "a test's limit"):
        with pytest.raises(InputError, match=r"heights.*d = 2 \(its arrays\) needs about 6\.\d"):
            HalfSpace(1.0, 0.3, 0.5, P, Q, heights=np.zeros((1800, 1800)), spacing=0.1, dims=2)
    with pytest.raises(InputError, match="edge"):  # contact reaches the grid's edge
        g = np.linspace(-1, 1, 24)
        HalfSpace(
            1.0,
            0.0,
            0.5,
            50.0,
            0.0,
            heights=(g[:, None] ** 2 + g[None, :] ** 2) / 2,
            spacing=g[1] - g[0],
        )


@pytest.mark.parametrize("dims", [1, 2])
def test_memory_estimate_bounds_the_measured_peak(dims):
    """The estimate behind the memory refusal bounds the peak that tracemalloc measures over
    the setup and a short solve (grid 40, 8 steps; the scene's limits and the cycle's history
    besides, lcpfric.memory.continuum_bytes, twice: the scene's normal forces and the cycle's
    records), and is not more than twice it."""
    import tracemalloc

    import lcpfric.periodic.driver  # noqa: F401  (the modules a solve imports: not its arrays)
    import lcpfric.steppers.newton_cg  # noqa: F401
    from lcpfric import memory

    tracemalloc.start()
    try:
        m = HalfSpace.sphere(
            10.0,
            200e3,
            0.3 * (dims - 1),
            0.5,
            Harmonic(100.0, 30.0, 0.0, TWO_PI),
            Harmonic(0.0, 20.0, 0.5, TWO_PI),
            grid=40,
            dims=dims,
        )
        lcpfric.steady_state(m, steps_per_cycle=8, max_cycles=2, on_nonconvergence="ignore")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    records = 2 * memory.continuum_bytes(m.nodes, dims, 8, True)
    assert peak <= m.memory_estimate() + records
    assert m.memory_estimate() <= 2 * peak


@pytest.mark.slow
def test_loose_steps_for_new_patterns_keep_the_answer(monkeypatch):
    """d = 1 on a wavy surface (contact islands, where the first patterns are often wrong):
    Newton steps whose pattern is new are solved loosely, a repeated pattern to full accuracy;
    the same W (1e-10) for fewer conjugate-gradient iterations than with every step solved
    to full accuracy."""
    import lcpfric.steppers.newton_increment as hs

    g = (np.arange(64) - 31.5) / 64 * 2.4
    X, Y = np.meshgrid(g, g, indexing="ij")
    wavy = (X**2 + Y**2) / 2 + 0.03 * (np.cos(14 * X) * np.cos(11 * Y) + 1)

    def run():
        m = HalfSpace(
            1.0,
            0.0,
            0.5,
            Harmonic(0.05, 0.025, 0.0, TWO_PI),
            Harmonic(0.0, 0.01, 0.5, TWO_PI),
            heights=wavy,
            spacing=g[1] - g[0],
        )
        r = lcpfric.steady_state(m, steps_per_cycle=40)
        return r, r.solver_stats["cg"]

    (loose, cg_loose) = run()
    monkeypatch.setattr(hs, "_ETA1", 0.0)
    (tight, cg_tight) = run()
    assert loose.converged and tight.converged
    assert loose.W == pytest.approx(tight.W, rel=1e-10)
    assert cg_loose < 0.8 * cg_tight


def test_d2_at_the_gross_sliding_limit_is_refused():
    """d = 2 with |Q| reaching μP under pure load control: nothing holds the body across the
    load (its transverse slip drifts, no cycle repeats), so it is refused before any work, in
    a solve and as a map's point (NaN); d = 1 there has its steady state."""
    from lcpfric.analysis.contact_maps import halfspace_W_normalized

    with pytest.raises(InputError, match=r"k_support.*reaches μ P.*transverse slip drifts"):
        lcpfric.steady_state(sphere(Q1=0.5, grid=12, dims=2), steps_per_cycle=40)
    assert lcpfric.steady_state(sphere(Q1=0.5, grid=12, dims=1), steps_per_cycle=40).converged
    out = halfspace_W_normalized(
        np.array([0.0, 0.0]),
        np.array([1.0, 0.0]),
        np.array([0.0, 0.0]),
        grid=12,
        dims=2,
        steps_per_cycle=20,
    )
    assert np.isnan(out[0]) and out[1] == 0.0


def test_near_gross_sliding_failure_says_so():
    """d = 2 within 0.02 % of gross sliding on a coarse grid (a stick zone of about two
    elements): the increment does not converge, and the typed error says why and what to do
    (0.1 % from it converges on this grid)."""
    from lcpfric.errors import SolverError

    with pytest.raises(SolverError, match="close to gross sliding.*refine the grid"):
        lcpfric.steady_state(sphere(Q1=0.4999, grid=16, nu=0.3, dims=2), steps_per_cycle=60)


def test_recorded_cycle_starts_where_it_ends():
    """The recorded states of the steady cycle's first instant are those of its last (the
    previous cycle's last increment), not a blank 'stick'."""
    r = lcpfric.steady_state(sphere(Q1=0.25, grid=12), steps_per_cycle=40)
    assert np.array_equal(r.state[0], r.state[-1])
    assert np.any((r.state[0] == 1) | (r.state[0] == 2))  # the edge slips at t = 0


@pytest.mark.slow
def test_accelerated_cycles_reach_the_plain_iterations_steady_state():
    """d = 2 with ν > 0: the transverse tractions settle over many cycles (35 here without
    acceleration). Anderson's acceleration of the cycles' starts reaches the same steady state
    (W to 1e-9) in a few cycles, and the previous cycle's increments as starts cut the
    products per cycle once the cycles nearly repeat."""
    m = sphere(Q1=0.25, grid=12, nu=0.3, dims=2)
    r0 = lcpfric.steady_state(m, "newton-cg", 60, max_cycles=60, accelerate=False)
    r1 = lcpfric.steady_state(m, "newton-cg", 60, max_cycles=60)
    assert r0.converged and r1.converged
    assert r0.cycles >= 25 and r1.cycles <= 12 and r1.solver_stats["extrapolations"] >= 3
    assert r1.W == pytest.approx(r0.W, rel=1e-9)
    cold = lcpfric.steady_state(m, "newton-cg", 60, max_cycles=60, warm_start=False)
    per = [r.solver_stats["tangential_products"] / r.solver_stats["increments"] for r in (r1, cold)]
    assert per[0] < 0.6 * per[1]


@pytest.mark.slow
def test_loose_early_cycles_reach_the_same_steady_state(monkeypatch):
    """d = 2 solves its early cycles' increments loosely (to a hundredth of the last cycle's
    change) and only a cycle at full accuracy ends the iteration: the same W (1e-9) for fewer
    products than with every increment at full accuracy, on a case that settles slowly."""
    m = sphere(Q1=0.25, grid=12, nu=0.3, dims=2)
    r1 = lcpfric.steady_state(m, steps_per_cycle=60)
    r0 = lcpfric.steady_state(m, "newton-cg", 60, loose_cycles=False)
    assert r0.converged and r1.converged
    assert r1.W == pytest.approx(r0.W, rel=1e-9)
    assert r1.solver_stats["tangential_products"] < 0.85 * r0.solver_stats["tangential_products"]


def test_unsettled_cycles_raise_with_the_smallest_change(monkeypatch):
    """Too few cycles for d = 2 to settle: ConvergenceError (never a silent W), naming the last
    and the smallest change reached at full accuracy."""
    from lcpfric.errors import ConvergenceError
    from lcpfric.periodic import driver as steady

    with pytest.raises(ConvergenceError, match=r"after 3 cycles \(relative change [^;]*\)"):
        lcpfric.steady_state(
            sphere(Q1=0.25, grid=12, nu=0.3, dims=2), steps_per_cycle=40, max_cycles=3
        )
    # the last cycles' increments solved only to their own tol 1e-10 (as before 0.1 x the cycle
    # tolerance was the rule) hold the cycles to about 6e-12 here: the floor is named
    with monkeypatch.context() as patch:
        patch.setattr(steady, "_FINAL", 1e3)
        with pytest.raises(ConvergenceError, match=r"the smallest at full accuracy \d.*e-1[0-3]"):
            lcpfric.steady_state(
                sphere(Q1=0.25, grid=12, nu=0.3, dims=2),
                steps_per_cycle=40,
                tol=1.1e-12,
                max_cycles=30,
            )


@pytest.mark.slow
def test_tight_cycle_tolerances_settle_or_are_refused():
    """d = 2 solves its last cycles' increments to a tenth of the cycle tolerance (tighter than
    their own tol 1e-10): a cycle tolerance of 1.1e-12, which the increments at 1e-10 could not
    reach in 30 cycles, settles in 10 to 12 (12 since the linear solves stop at 0.9 of the
    increments' tolerance, not 0.1: so near the floor, their errors slow the last cycles), to
    the W of the default tolerance; under 1e-12 (the increments would go below the 1e-13 they
    hold) it is refused before any work."""
    base = lcpfric.steady_state(sphere(Q1=0.25, grid=12, nu=0.3, dims=2), steps_per_cycle=40)
    tight = lcpfric.steady_state(
        sphere(Q1=0.25, grid=12, nu=0.3, dims=2), steps_per_cycle=40, tol=1.1e-12, max_cycles=15
    )
    assert tight.converged and tight.change <= 1.1e-12 and tight.cycles <= 14
    assert tight.W == pytest.approx(base.W, rel=1e-9)
    with pytest.raises(InputError, match=r"tol.*below what the increments can hold.*1e-12"):
        lcpfric.steady_state(
            sphere(Q1=0.25, grid=12, nu=0.3, dims=2), steps_per_cycle=40, tol=9e-13
        )
    lcpfric.steady_state(
        sphere(Q1=0.25, grid=12, nu=0.3, dims=1),
        steps_per_cycle=8,
        tol=1e-15,
        max_cycles=3,
        on_nonconvergence="ignore",
    )  # d = 1: exact
