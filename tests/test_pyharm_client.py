"""A real client (issue 39, item 5): lcpfric's Jenkins element inside pyHarm's forced-response
computation, against pyHarm's own Jenkins element and the notes' closed forms; and the minimal
harmonic-balance loop (``lcpfric.harmonic.balance``) that drives lcpfric's AFT without pyHarm.

The pyHarm tests skip without it (``pip install pyharm-os``) through the ``pyharm`` fixture's
``pytest.importorskip("pyHarm")``; the harmonic-balance loop's and the missing-pyHarm tests
run without it.
"""

import logging
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from lcpfric.analysis.describing import jenkins_closed_form
from lcpfric.errors import InputError
from lcpfric.harmonic.balance import forced_response, harmonic_residual
from lcpfric.harmonic.pyharm import pyharm_element_class, pyharm_harmonic_index
from support import fitted_order

# importing pyHarm writes .pyHarm/context.json into the working directory unless told otherwise
os.environ.setdefault(
    "PYHARM_CONTEXT_FILE", str(Path(tempfile.gettempdir()) / "lcpfric-pyharm" / "context.json")
)

ROOT = Path(__file__).resolve().parents[1]
# the oscillator: m x'' + c x' + k x + T(x) = F cos ωt, T a Jenkins element to ground
M, C, K, KT, MU, N, F = 1.0, 0.02, 1.0, 1.0, 0.3, 1.0, 0.3
FS = MU * N
H, NS = 5, 128
BAND = (0.5, 2.0)
#: the closed form's error bound at Ns samples per period: SAMPLING * μN / Ns², the trapezoidal
#: DFT across the slip onset's kink (measured: at most 15 μN / Ns² over 64 to 1024 samples,
#: amplitudes 1.5 to 10 slip limits, phases 0 to 1)
SAMPLING = 20.0


def closed(a):
    """(k_eq a, -ω c_eq a): the first harmonic of the force for x = a cos τ."""
    cf = jenkins_closed_form(KT, MU, N, [a])
    return float(cf["k_eq"][0]) * a, -float(cf["c_eq_omega"][0]) * a


def in_phase(c1, s1, phase):
    """A first harmonic (c1, s1) in the frame of a motion cos(τ - phase): (in phase, quadrature)."""
    return c1 * np.cos(phase) + s1 * np.sin(phase), -c1 * np.sin(phase) + s1 * np.cos(phase)


@pytest.fixture(scope="module")
def pyharm():
    return pytest.importorskip("pyHarm", reason="pyHarm is not installed: pip install pyharm-os")


def element(cls, nh, samples, dirs=(0,), data=None):
    """A pyHarm element on one node of a substructure (to ground), its dof table by hand."""
    import pandas as pd
    from pyHarm.CoordinateSystem import GlobalCoordinateSystem

    d = len(dirs)
    spec = {"connect": {"sub": [0]}, "dirs": list(dirs), "mu": MU, "N0": N, "k": KT}
    e = cls(nh, samples, "jenkins", dict(spec, **(data or {})), GlobalCoordinateSystem(d))
    harm = list(range(nh + 1)) if isinstance(nh, int) else sorted(nh)
    blocks = [(h, cs) for h in harm for cs in (("c",) if h == 0 else ("c", "s"))]
    rows = [(h, cs, j) for h, cs in blocks for j in range(d)]
    edf = pd.DataFrame(
        {"sub": "sub", "node_num": 0, "harm": [r[0] for r in rows], "cs": [r[1] for r in rows],
         "dof_num": [r[2] for r in rows]}
    )  # fmt: skip
    e.generateIndices(edf)
    return e


def pyharm_jenkins():
    from pyHarm.Elements.NodeToNodeElements.Jenkins import Jenkins

    return Jenkins


def solve_at(q, omega, samples):
    """Newton on lcpfric's harmonic-balance equations at fixed ω from q: the curve's point."""
    kw = dict(kt=KT, mu=MU, normal_load=N, samples=samples)
    for _ in range(20):
        r, J, _ = harmonic_residual(q, omega, M, C, K, F, **kw)
        if np.linalg.norm(r) <= 1e-13 * F:
            return q
        q = q - np.linalg.solve(J, r.ravel()).reshape(q.shape)
    raise AssertionError(f"no convergence at ω = {omega}")


# ---- the mapping ----------------------------------------------------------------------------


def test_harmonic_index_without_pyharm():
    assert pyharm_harmonic_index(3).tolist() == list(range(7))
    assert pyharm_harmonic_index([1, 3]).tolist() == [1, 2, 5, 6]
    assert pyharm_harmonic_index([2, 0]).tolist() == [0, 3, 4]
    for bad in ([0], [1, 1], [-1, 2], 0):
        with pytest.raises(InputError, match="nh"):
            pyharm_harmonic_index(bad)


@pytest.mark.parametrize("nh", [3, [1, 3], [0, 1, 2]])
def test_pure_cosine_and_sine(pyharm, nh):
    """x = a cos τ gives the closed form's (k_eq a, -ω c_eq a) to the sampling order, and
    x = a sin τ (Ns a multiple of 4: the same samples a quarter period later) its rotation
    (ω c_eq a, k_eq a) to rounding; the same as pyHarm's own element."""
    cls = pyharm_element_class()
    ref = pyharm_jenkins()
    for a in (0.5 * FS, 1.5 * FS, 10 * FS):
        kc, cq = closed(a)
        e = element(cls, nh, NS)
        p = element(ref, nh, NS)
        i = {1: np.flatnonzero(pyharm_harmonic_index(nh) == 1)[0]}
        x = np.zeros(len(e.indices))
        x[i[1]] = a
        R = e.evalResidual(x, 1.0)
        assert np.abs(R - p.evalResidual(x, 1.0)).max() <= 1e-14 * FS
        assert abs(R[i[1]] - kc) <= SAMPLING * FS / NS**2
        assert abs(R[i[1] + 1] - cq) <= SAMPLING * FS / NS**2
        x = np.zeros(len(e.indices))
        x[i[1] + 1] = a
        S = e.evalResidual(x, 1.0)
        assert S[i[1]] == pytest.approx(-R[i[1] + 1], abs=1e-14 * FS)
        assert S[i[1] + 1] == pytest.approx(R[i[1]], abs=1e-14 * FS)


@pytest.mark.parametrize("nh", [5, [1, 3], [0, 1, 2, 7]])
def test_residual_and_jacobian_against_pyharm(pyharm, nh):
    """Random multi-harmonic motions (stick, slip, shakedown): lcpfric's element gives pyHarm's
    own forces and Jacobian (d = 1, constant N: the same steady cycle)."""
    rng = np.random.default_rng(1)
    e = element(pyharm_element_class(), nh, 64)
    p = element(pyharm_jenkins(), nh, 64)
    for _ in range(30):
        x = rng.normal(size=len(e.indices)) * FS * rng.choice([0.3, 3.0, 30.0])
        assert np.abs(e.evalResidual(x, 1.0) - p.evalResidual(x, 1.0)).max() <= 1e-12 * FS
        Je, dJe = e.evalJacobian(x, 1.0)
        assert np.abs(Je - p.evalJacobian(x, 1.0)[0]).max() <= 1e-12 * KT
        assert not dJe.any()


def test_adim_scaling(pyharm):
    """pyHarm's non-dimensional displacements (units lc): the same forces and Jacobian as its
    own element with the same scaling."""
    rng = np.random.default_rng(2)
    e = element(pyharm_element_class(), 3, 64)
    p = element(pyharm_jenkins(), 3, 64)
    for el in (e, p):
        el.adim(0.25, 3.0)
    x = rng.normal(size=len(e.indices)) * 4 * FS
    assert np.allclose(e.evalResidual(x, 1.0), p.evalResidual(x, 1.0), rtol=0, atol=1e-13)
    assert np.allclose(e.evalJacobian(x, 1.0)[0], p.evalJacobian(x, 1.0)[0], rtol=0, atol=1e-13)


def test_two_directions_steady(pyharm):
    """d = 2 (dirs [0, 1]): lcpfric's element is the steady cycle of the radial return, equal to
    a plain march of 400 periods (pyHarm's own marches 3 periods, not always steady)."""
    from lcpfric.harmonic import fourier_basis

    rng = np.random.default_rng(3)
    e = element(pyharm_element_class(), 2, 32, dirs=(0, 1))
    basis = fourier_basis(2, 32)
    for _ in range(5):
        x = rng.normal(size=len(e.indices)) * FS * 3
        xs = x.reshape(-1, 2).T @ basis.E.T  # pyHarm: harmonic-major, the two directions inside
        s = np.zeros(2)
        for _period in range(400):
            T = np.empty_like(xs)
            for k in range(xs.shape[1]):
                gap = xs[:, k] - s
                if KT * np.linalg.norm(gap) > FS:
                    s = xs[:, k] - FS / KT * gap / np.linalg.norm(gap)
                T[:, k] = KT * (xs[:, k] - s)
        ref = (T @ basis.D.T).T.reshape(-1)
        assert np.abs(e.evalResidual(x, 1.0) - ref).max() <= 1e-10 * FS


# ---- registration ---------------------------------------------------------------------------


def test_registration_routes(pyharm, monkeypatch):
    """pyHarm's factory builds the element by name through a ``pyharm.extensions`` entry point
    (``pyHarm.extension.load``), after ``register_pyharm_element`` (once), and from a Maestro
    input's ``"plugin"`` list."""
    import importlib.metadata

    import pyHarm.extension
    import pyHarm.extension_manager as manager
    from pyHarm.Elements.FactoryElements import ElementDictionary
    from pyHarm.Maestro import Maestro

    from lcpfric.harmonic.pyharm import FACTORY_KEYWORD, oscillator_input, register_pyharm_element

    monkeypatch.delitem(ElementDictionary, FACTORY_KEYWORD, raising=False)
    ep = importlib.metadata.EntryPoint(
        "lcpfric", "lcpfric.harmonic.pyharm:pyharm_extension", "pyharm.extensions"
    )
    monkeypatch.setattr(manager, "_entry_points", lambda: [ep])
    monkeypatch.setattr(pyHarm.extension, "_LOADED_RUNTIME_EXTENSIONS", set())
    pyHarm.extension.load("lcpfric")
    assert ElementDictionary[FACTORY_KEYWORD] is pyharm_element_class()
    monkeypatch.delitem(ElementDictionary, FACTORY_KEYWORD)
    assert register_pyharm_element() is ElementDictionary[FACTORY_KEYWORD]
    assert register_pyharm_element() is pyharm_element_class()
    # a Maestro input's "plugin" list
    monkeypatch.delitem(ElementDictionary, FACTORY_KEYWORD)
    data = oscillator_input(M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, element="Jenkins")
    data["connectors"]["jenkins"]["type"] = FACTORY_KEYWORD
    data["plugin"] = [pyharm_element_class()]
    previous = logging.root.manager.disable
    logging.disable(logging.INFO)  # Maestro logs its banner
    try:
        system = Maestro(data).system
    finally:
        logging.disable(previous)
    assert [type(e).__name__ for e in system.LE_nonlinear_nodlft] == [FACTORY_KEYWORD]


def test_missing_pyharm_names_the_install(monkeypatch):
    """Without pyHarm the module imports, the mapping works, and the element raises an
    ImportError that says ``pip install pyharm-os``."""
    code = (
        "import sys; sys.modules['pyHarm'] = None\n"
        "import lcpfric.harmonic.pyharm as p\n"
        "print(p.pyharm_harmonic_index([1]).tolist())\n"
        "try:\n    p.register_pyharm_element()\n"
        "except ImportError as e:\n    print(type(e).__name__, e.name, e)\n"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("[1, 2]\nMissingDependency pyHarm ")
    assert "pip install pyharm-os" in out.stdout


# ---- the forced response through pyHarm ------------------------------------------------------


@pytest.fixture(scope="module")
def curves(pyharm):
    from lcpfric.harmonic.pyharm import oscillator_input, pyharm_frequency_response

    out = {}
    for name in ("Jenkins", "LcpfricJenkins"):
        data = oscillator_input(
            M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, element=name, harmonics=H, samples=NS
        )
        out[name] = pyharm_frequency_response(data)
    return out


def test_pyharm_curves_agree(curves):
    """pyHarm's continuation with lcpfric's element reproduces the one with its own element
    point for point (same samples, same harmonics): the same steady cycles and Jacobians."""
    a, b = curves["Jenkins"], curves["LcpfricJenkins"]
    assert a["rejected"] == b["rejected"] == 0
    assert a["omega"].size == b["omega"].size > 30
    assert a["omega"][0] == BAND[0] and a["omega"][-1] >= BAND[1]  # its last point crosses it
    assert np.abs(a["omega"] - b["omega"]).max() <= 1e-12
    assert np.abs(a["x"] - b["x"]).max() <= 1e-12 * np.abs(a["x"]).max()
    amplitude = np.hypot(a["x"][:, 1], a["x"][:, 2])
    assert amplitude.max() > 3 * FS / KT  # through the resonance, in gross slip
    assert amplitude.min() < FS / KT  # and stuck away from it


def test_pyharm_points_solve_the_harmonic_balance(curves):
    """Every pyHarm point satisfies lcpfric's harmonic-balance equations to pyHarm's solver
    tolerance, and Newton on them at the same ω moves its amplitude by at most 1e-8."""
    b = curves["LcpfricJenkins"]
    worst_r = worst_a = 0.0
    for x, w in zip(b["x"], b["omega"]):
        q = x.reshape(1, -1)
        r = harmonic_residual(q, w, M, C, K, F, kt=KT, mu=MU, normal_load=N, samples=NS)[0]
        worst_r = max(worst_r, np.linalg.norm(r) / F)
        q = solve_at(q, w, NS)
        worst_a = max(worst_a, abs(np.hypot(*q[0, 1:3]) - np.hypot(*x[1:3])))
    assert worst_r <= 1e-6
    assert worst_a <= 1e-8


def test_lcpfric_loop_matches_pyharm_curve(curves):
    """lcpfric's own harmonic-balance loop finds the same curve: its points satisfy pyHarm's
    system equations (with pyHarm's own element) and its peak is pyHarm's."""
    res = forced_response(
        M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, harmonics=H, samples=NS, tol=1e-12
    )
    assert res.status == "bounds"
    system = curves["Jenkins"]["system"]
    worst = max(
        np.linalg.norm(system.Residual(np.append(q.ravel(), w))) / F
        for q, w in zip(res.coefficients, res.omega)
    )
    assert worst <= 1e-11
    a = curves["Jenkins"]
    peak = np.hypot(a["x"][:, 1], a["x"][:, 2]).max()
    assert res.amplitude().max() == pytest.approx(peak, rel=2e-3)  # the points' spacing


def test_force_harmonics_against_the_closed_form(curves):
    """At points of the curve the pure first harmonic of the motion (its amplitude and phase)
    gives both elements the closed form's first harmonic to the sampling order."""
    b = curves["LcpfricJenkins"]
    amplitude = np.hypot(b["x"][:, 1], b["x"][:, 2])
    picks = [0, int(amplitude.argmax()), int(np.abs(amplitude - 2 * FS).argmin())]
    errors = {}
    for ns in (64, 128, 256, 512):
        els = [element(cls, H, ns) for cls in (pyharm_element_class(), pyharm_jenkins())]
        for i in picks:
            a, phase = amplitude[i], np.arctan2(b["x"][i, 2], b["x"][i, 1])
            x = np.zeros(2 * H + 1)
            x[1:3] = b["x"][i, 1:3]
            kc, cq = closed(a)
            for j, el in enumerate(els):
                R = el.evalResidual(x, b["omega"][i])
                ip, qu = in_phase(R[1], R[2], phase)
                err = max(abs(ip - kc), abs(qu - cq))
                assert err <= SAMPLING * FS / ns**2
                errors.setdefault((i, j), []).append(err)
    stuck = errors.pop((0, 0)), errors.pop((0, 1))
    assert max(max(s) for s in stuck) <= 1e-14  # the stuck point: k_eq = kt, c_eq = 0
    for errs in errors.values():
        assert fitted_order([64, 128, 256, 512], errs) > 1.3


# ---- the harmonic-balance loop alone (no pyHarm) ----------------------------------------------


@pytest.mark.parametrize("mu, k_total", [(0.0, K), (1e6, K + KT)])
def test_loop_linear_limits(mu, k_total):
    """μ = 0 (the element slides freely: no force) and μ huge (it sticks: a spring kt): the
    linear response F / |k - mω² + icω| at every point."""
    res = forced_response(M, C, K, F, BAND, kt=KT, mu=mu, normal_load=N, harmonics=3, samples=32)
    assert res.status == "bounds" and res.omega[0] == BAND[0]
    w = res.omega
    exact = F / np.hypot(k_total - M * w**2, C * w)
    assert np.abs(res.amplitude() - exact).max() <= 1e-9 * exact.max()
    assert np.abs(res.coefficients[:, 0, 3:]).max() <= 1e-12 * exact.max()


def test_loop_one_harmonic_is_the_describing_function():
    """With H = 1 each point solves the describing-function equation
    |k + k_eq(a) - mω² + i(cω + ω c_eq(a))| a = F, to the AFT's sampling error."""
    res = forced_response(M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, harmonics=1, samples=NS)
    a = res.amplitude()
    cf = jenkins_closed_form(KT, MU, N, a)
    lhs = np.hypot(K + cf["k_eq"] - M * res.omega**2, C * res.omega + cf["c_eq_omega"]) * a
    assert np.abs(lhs - F).max() <= 2 * SAMPLING * FS / NS**2
    assert a.max() > 3 * FS


def test_loop_downward_sweep_and_two_dofs():
    """Sweeping downwards gives the same curve; an element between two dofs acts on their
    difference (two equal masses moving together: the element carries no force)."""
    up = forced_response(M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, harmonics=3, samples=64)
    down = forced_response(
        M, C, K, F, BAND[::-1], kt=KT, mu=MU, normal_load=N, harmonics=3, samples=64
    )
    assert down.omega[0] == BAND[1] and down.status == "bounds"
    for q, w in zip(down.coefficients[::7], down.omega[::7]):
        start = up.coefficients[np.abs(up.omega - w).argmin()]
        assert np.abs(solve_at(start, w, 64) - q).max() <= 1e-9 * np.abs(q).max()
    two = forced_response(
        np.eye(2) * M, np.eye(2) * C, np.eye(2) * K, [F, F], BAND,
        contacts=[(0, 1)], kt=KT, mu=MU, normal_load=N, harmonics=2, samples=32,
    )  # fmt: skip
    assert np.abs(two.contact_force).max() <= 1e-12
    exact = F / np.hypot(K - M * two.omega**2, C * two.omega)
    assert np.abs(two.amplitude(1) - exact).max() <= 1e-9 * exact.max()


def test_residual_jacobian_finite_differences():
    rng = np.random.default_rng(4)
    q = rng.normal(size=(1, 7)) * 3 * FS
    args = (M, C, K, F)
    kw = dict(kt=KT, mu=MU, normal_load=N, samples=64)
    r, J, Jw = harmonic_residual(q, 1.2, *args, **kw)
    h = 1e-7
    for j in range(7):
        dq = np.zeros(7)
        dq[j] = h
        rp = harmonic_residual(q + dq, 1.2, *args, **kw)[0]
        rm = harmonic_residual(q - dq, 1.2, *args, **kw)[0]
        assert np.allclose((rp - rm).ravel() / (2 * h), J[:, j], atol=1e-6)
    rp, rm = (harmonic_residual(q, 1.2 + s, *args, **kw)[0] for s in (h, -h))
    assert np.allclose((rp - rm) / (2 * h), Jw, atol=1e-6)


@pytest.mark.parametrize(
    "change, name",
    [
        (dict(omega=(1.0, 1.0)), "omega"),
        (dict(contacts=[3]), "contacts"),
        (dict(contacts=[]), "contacts"),
        (dict(force=[1.0, 2.0]), "force"),
        (dict(harmonics=0), "harmonics"),
        (dict(samples=6), "samples"),
        (dict(kt=-1.0), "kt"),
        (dict(stiffness=[[1.0, 0.0]]), "stiffness"),
    ],
)
def test_loop_bad_input(change, name):
    kw = dict(
        mass=M, damping=C, stiffness=K, force=F, omega=BAND, kt=KT, mu=MU, normal_load=N,
        harmonics=3, samples=32,
    )  # fmt: skip
    kw.update(change)
    with pytest.raises(InputError, match=f"^{name}"):
        forced_response(**kw)
