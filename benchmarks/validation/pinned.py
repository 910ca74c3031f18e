#!/usr/bin/env python
"""Pinned results of lcpfric, to check that a restructuring changes no public number: 471 values
(W, Ŵ, W_normalized, cycles, counts) of every model and every method, compared as float.hex.

    python benchmarks/validation/pinned.py --check benchmarks/results/pinned.json
    python benchmarks/validation/pinned.py --out FILE.json   # write {name: hex}
    ... --only SUBSTRING                                     # some cases only

(with ``OPENBLAS_NUM_THREADS=1``, as every benchmark)

``benchmarks/results/pinned.json`` holds the values lcpfric 0.1 gave (written by this script's
0.1 twin, the same cases through 0.1's API), but for the 44 that issue 37's compiled kernels
moved at round-off and that were re-pinned then (``benchmarks/results/pinned-changes.md``: each
with 0.1's value, the new one and why). The three cases that compare a contact's own
stepper with the discrete methods on its ContactSystem solve the contact on a fresh model:
0.1's models kept the normal problem's warm starts from solve to solve, so there a model's W
depended on what had been solved on it before (by up to 1e-11 relative). Expect "471
identical"; a different numpy, scipy or BLAS may change the last bits of some.

Every call into the library goes through the adapters in the section "API adapters" below:
after the restructuring, edit only those. The cases are declarative: ``CASES`` is a list of
``(name, zero-argument function)``; each function returns a dict ``{key: float}`` recorded as
``"<name>.<key>"`` (a scalar return is recorded as ``"<name>"`` itself).
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the repository, the shared report writer, the perf scripts (halfspace's cases) and the tests'
# shared cases and references (tests/support)
_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [
    str(_ROOT),
    str(_ROOT / "benchmarks"),
    str(_ROOT / "benchmarks" / "perf"),
    str(_ROOT / "tests"),
]

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import traceback  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

PI = math.pi
TWO_PI = 2.0 * math.pi


# =================================================================================================
# --- API adapters (edit these after the restructuring) ---
# =================================================================================================
import lcpfric  # noqa: E402


def library_file() -> str:
    return lcpfric.__file__


def installed_methods() -> list[str]:
    return list(lcpfric.available_methods())


# -- models --------------------------------------------------------------------------------------
def harmonic(mean, amplitude, phase=0.0, omega=1.0):
    return lcpfric.Harmonic(mean, amplitude, phase, omega)


def fourier(mean, amplitudes, phases):
    return lcpfric.Fourier(mean=mean, amplitudes=amplitudes, phases=phases)


def node_normalized(P1, Q1, phi):
    return lcpfric.SingleNode.normalized(P1=P1, Q1=Q1, phi=phi)


def node_dimensional(**kw):
    return lcpfric.SingleNode(**kw)


def node_loads(normal, tangential):
    return lcpfric.SingleNode(normal_load=normal, tangential_load=tangential)


def chain(n, **kw):
    return lcpfric.chain(n, **kw)


def block_diagonal(nodes):
    return lcpfric.block_diagonal(nodes)


def contact_system(K, friction, tangential_loads, normal_loads, *, dims=1, compliance=None):
    """A ContactSystem with independent normal springs (``normal_loads``: Load objects)."""
    from lcpfric.model import IndependentSprings

    return lcpfric.ContactSystem(
        K,
        friction,
        tuple(tangential_loads),
        IndependentSprings(tuple(normal_loads)),
        dims=dims,
        compliance=compliance,
    )


def make_scene(system, steps):
    return lcpfric.make_scene(system, steps)


# -- steady states -------------------------------------------------------------------------------
def single(model, method, **kw):
    """The steady state of a SingleNode (result with W, W_hat, cycles, W_cycles)."""
    return lcpfric.steady_state(model, method=method, **kw)


def steady(system, method, **kw):
    """The steady state of a ContactSystem or Scene (result with W, cycles, W_cycles)."""
    return lcpfric.steady_state(system, method=method, **kw)


def events_per_cycle(result):
    return result.solver_stats["events_per_cycle"]


def loop_area(result, node=0):
    from lcpfric.analysis.loop import hysteresis_loop

    return hysteresis_loop(result, node).area


# -- batched single-node grids -------------------------------------------------------------------
def batch_projection(P1, Q1, phi, steps, **kw):
    from lcpfric.batch import projection_W_hat

    return projection_W_hat(P1, Q1, phi, steps, **kw)


def batch_projection_cycles(P1, Q1, phi, steps, **kw):
    from lcpfric.batch import projection_steady_states

    return projection_steady_states(P1, Q1, phi, steps, **kw).cycles


def batch_solver(P1, Q1, phi, method, steps, **kw):
    from lcpfric.batch import batched_W_hat

    return batched_W_hat(P1, Q1, phi, method, steps, **kw)


def exact_grid(P1, Q1, phi):
    from lcpfric.exact import exact_W_hat

    return exact_W_hat(P1, Q1, phi)


# -- continuum contacts --------------------------------------------------------------------------
def mdr_sphere(R, E, nu, mu, P, Q, **kw):
    from lcpfric.model.continuum import MDRSphere

    cls = MDRSphere
    if kw.get("nodes", 2000) < getattr(MDRSphere, "min_nodes", 1):  # one spring, on purpose
        cls = type("FewSprings", (MDRSphere,), {"min_nodes": 1})
    return cls(R, E, nu, mu, P, Q, **kw)


def mdr_power_law(c, n):
    from lcpfric.model.continuum import PowerLaw

    return PowerLaw(c, n)


def mdr_axisymmetric(slope):
    from lcpfric.model.continuum import Axisymmetric

    return Axisymmetric(slope)


def halfplane_cylinder(R, E, nu, mu, P, Q, **kw):
    from lcpfric.model.continuum import HalfPlaneCylinder

    return HalfPlaneCylinder(R, E, nu, mu, P, Q, **kw)


def halfspace_sphere(R, E, nu, mu, P, Q, **kw):
    from lcpfric.model.continuum import HalfSpace

    return HalfSpace.sphere(R, E, nu, mu, P, Q, **kw)


def halfspace_punch(R, radius, E, nu, mu, P, Q, **kw):
    from lcpfric.model.continuum import HalfSpace

    return HalfSpace.punch(R, radius, E, nu, mu, P, Q, **kw)


def halfspace_heights(E, nu, mu, P, Q, heights, spacing, **kw):
    from lcpfric.model.continuum import HalfSpace

    return HalfSpace(E, nu, mu, P, Q, heights=heights, spacing=spacing, **kw)


def halfspace_surface(model):
    """(heights, spacing) of a half-space model: its gap at zero approach and element size."""
    return model.g0 * 1.0, model.h


def contact_k_t0(model):
    return model.k_t0


def contact(model, steps=None, **kw):
    """The periodic steady state of a continuum contact: (W, W_normalized, cycles).
    ``steps`` uniform increments per cycle, or ``t=`` a time grid."""
    t = kw.pop("t", None)
    kw.pop("record", None)
    target = lcpfric.make_scene(model, grid=t) if t is not None else model
    r = lcpfric.steady_state(target, steps_per_cycle=steps, **kw)
    return r.W, r.W_normalized, r.cycles


def contact_as_system(model):
    """The contact (held by a support) as an lcpfric ContactSystem."""
    return model.system()


def scene_times(scene):
    return scene.t


# -- maps ----------------------------------------------------------------------------------------
def _ratio(kw: dict) -> dict:
    """0.2 names a map's support (a multiple of k_t0) k_support_ratio; 0.1 k_support."""
    from lcpfric.analysis import contact_maps

    if "k_support" in kw and "k_support_ratio" in contact_maps.CONTACT_DEFAULTS:
        kw = dict(kw)
        kw["k_support_ratio"] = kw.pop("k_support")
    return kw


def mdr_map(P1, Q1, phi, **kw):
    from lcpfric.analysis.contact_maps import mdr_W_normalized

    kw = _ratio(kw)
    return mdr_W_normalized(
        np.asarray(P1, float), np.asarray(Q1, float), np.asarray(phi, float), **kw
    )


def halfspace_map(P1, Q1, phi, **kw):
    from lcpfric.analysis.contact_maps import halfspace_W_normalized

    kw = _ratio(kw)
    return halfspace_W_normalized(
        np.asarray(P1, float), np.asarray(Q1, float), np.asarray(phi, float), **kw
    )


def sweep_map(P1, Q1, phi, **kw):
    """A sweep as a dict {(phi, P1, Q1): value} (W_hat, or W_normalized for a contact)."""
    from lcpfric.analysis.sweep import sweep

    if kw.get("contact"):
        kw["contact"] = _ratio(kw["contact"])
    ds = sweep(P1, Q1, phi, progress=False, processes=1, **kw)
    var = "W_normalized" if kw.get("contact") is not None else "W_hat"
    arr = ds[var].values
    return {
        (i, j, k): float(arr[i, j, k])
        for i in range(arr.shape[0])
        for j in range(arr.shape[1])
        for k in range(arr.shape[2])
    }


def analytic_values():
    """Closed forms: Jang and Barber's Eq. (11) (corrected) and (12), and shakedown."""
    from lcpfric import analytic

    sd = lcpfric.shakedown(0.5, 0.7, 0.3 * PI)
    sd2 = lcpfric.shakedown(1.5, 2.0, 0.6 * PI)
    return {
        "jang_barber_05_2": float(analytic.jang_barber(0.5, 2.0)),
        "jang_barber_1_2": float(analytic.jang_barber(1.0, 2.0)),
        "jang_barber_2_3": float(analytic.jang_barber(2.0, 3.0)),
        "shakedown_in.shakedown": float(sd.shakedown),
        "shakedown_in.margin": sd.margin,
        "shakedown_in.shift": sd.shift,
        "shakedown_out.shakedown": float(sd2.shakedown),
        "shakedown_out.margin": sd2.margin,
    }


def motor_values(M, delta, P0, k11, Omega, f):
    from lcpfric.paper.motor import Motor

    motor = Motor(M=M, delta=delta, P0=P0, k11=k11)
    W = motor.dissipation(np.asarray(Omega, float), f)
    return (
        list(np.atleast_1d(W)),
        motor.separation_speed(),
        motor.shakedown_speed(f),
        motor.natural_frequency(),
    )


# =================================================================================================
# --- the cases (declarative) ---
# =================================================================================================
SINGLE_METHODS_FAST = ("explicit", "projection", "active-set", "clarabel", "osqp")
QPSOLVERS = (
    "qpsolvers:clarabel",
    "qpsolvers:highs",
    "qpsolvers:osqp",
    "qpsolvers:proxqp",
    "qpsolvers:scs",
)
CVXPY = ("cvxpy:CLARABEL", "cvxpy:OSQP", "cvxpy:SCS")
STEPS = {
    **{m: 800 for m in SINGLE_METHODS_FAST},
    **{m: 120 for m in QPSOLVERS},
    **{m: 60 for m in CVXPY},
}


def _sn_models():
    return {
        "contact": lambda: node_normalized(0.5, 2.0, 0.6 * PI),
        "separation": lambda: node_normalized(1.5, 2.0, 0.6 * PI),
        "bolt": lambda: node_dimensional(
            k11=1e6, f=0.3, P0=100.0, P1=300.0, Q1=200.0, phi=PI / 2, omega=TWO_PI * 50
        ),
        "fourier": lambda: node_loads(
            fourier(1.0, (1.3, 0.4), (0.0, 0.5)), fourier(0.0, (1.8, 0.6), (1.9, -0.3))
        ),
    }


def _single_case(make, method, full):
    def run():
        kw = {} if method == "exact" else {"steps_per_cycle": STEPS[method]}
        r = single(make(), method, **kw)
        out = {"W": r.W, "W_hat": r.W_hat}
        if full:
            out["cycles"] = r.cycles
            out["W_cycles_last"] = r.W_cycles[-1]
        return out

    return run


def single_node_cases():
    cases = []
    models = _sn_models()
    methods = ("exact",) + SINGLE_METHODS_FAST + QPSOLVERS + CVXPY
    for label, make in models.items():
        for method in methods:
            if label == "fourier" and method == "exact":
                continue  # exact needs harmonic loads of one frequency
            full = label in ("separation", "fourier") or method in ("exact", "explicit")
            cases.append((f"sn.{label}.{method}", _single_case(make, method, full)))

    def extremes():
        out = {}
        r = single(node_normalized(0.5, 0.7, 0.3 * PI), "projection", steps_per_cycle=200)
        out["shakedown.projection.W"] = r.W
        out["shakedown.projection.cycles"] = r.cycles
        r = single(node_normalized(1e6, 1e-6, PI / 2), "explicit", steps_per_cycle=2000)
        out["tiny.explicit.W_hat"] = r.W_hat
        r = single(node_normalized(5.0, 5.0, 0.6 * PI), "exact")
        out["large.exact.W_hat"] = r.W_hat
        r = single(node_normalized(0.5, 2.0, 0.0), "exact")
        out["jang_barber.exact.W_hat"] = r.W_hat
        r = single(
            node_normalized(1.5, 2.0, 0.6 * PI),
            "explicit",
            steps_per_cycle=800,
            placement="uniform",
        )
        out["uniform.explicit.W_hat"] = r.W_hat
        out["uniform.explicit.steps_used"] = r.steps_used
        r = single(
            node_normalized(1.5, 2.0, 0.6 * PI), "clarabel", steps_per_cycle=400, refine=False
        )
        out["unrefined.clarabel.W_hat"] = r.W_hat
        return out

    cases.append(("sn.extra", extremes))

    def loops():
        bolt = models["bolt"]()
        r = single(bolt, "exact", steps_per_cycle=1000)
        out = {"bolt.exact1000.area": loop_area(r)}
        r = single(models["separation"](), "projection", steps_per_cycle=800)
        out["separation.projection800.area"] = loop_area(r)
        r = single(models["separation"](), "explicit", steps_per_cycle=800)
        out["separation.explicit800.area"] = loop_area(r)
        return out

    cases.append(("loop", loops))
    return cases


# -- discrete systems ----------------------------------------------------------------------------
def staggered_chain(n=12, sep=True, sparse=False, seed=0, dims=1, kc=2.0):
    rng = np.random.default_rng(seed)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    shape = (n, 2) if dims == 2 else n
    return chain(
        n,
        k_coupling=kc,
        P1=P1,
        Q1=rng.uniform(0.5, 2.0, shape),
        phi=rng.uniform(0, 2 * np.pi, shape),
        dims=dims,
        sparse=sparse,
    )


def dense_spd(n=8, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    K = A @ A.T + np.eye(n)
    P1, Q1, phi = rng.uniform(0.3, 1.8, n), rng.uniform(0.5, 2.0, n), rng.uniform(0, 6, n)
    return contact_system(
        K,
        np.ones(n),
        [harmonic(0.0, Q1[i], phi[i]) for i in range(n)],
        [harmonic(1.0, P1[i]) for i in range(n)],
    )


def make_chain(n, separation, dims=1):
    return chain(
        n,
        k_coupling=0.5,
        P1=1.5 if separation else 0.5,
        Q1=np.linspace(1.5, 2.5, n),
        phi=0.6 * np.pi,
        normal_phase=np.linspace(0.0, 1.0, n),
        dims=dims,
    )


def readme_chain3():
    return chain(3, k_coupling=10.0, P1=[1.5, 0.5, 2.0], Q1=[1.5, 1.0, 2.0], phi=[0.3, 1.0, 2.0])


def chain5(sparse):
    return chain(
        5,
        k_coupling=10,
        P1=[1.5, 0.5, 2.0, 0.3, 1.2],
        Q1=1.5,
        phi=[0.3, 1.0, 2.0, 3.0, 4.0],
        sparse=sparse,
    )


def chain_d2(kc):
    return chain(
        3,
        k_coupling=kc,
        dims=2,
        P1=[0.5, 1.5, 0.8],
        Q1=[[1.5, 1.0], [2.0, 0.5], [1.2, 1.2]],
        phi=[[0.6 * np.pi, 0.1], [0.3, 1.0], [0.0, 0.5 * np.pi]],
        normal_phase=[0.0, 0.5, 1.0],
    )


def toeplitz_pair(n=30, sep=True, seed=0):
    """The same system matrix-free (Toeplitz compliance by FFT products) and with K = C⁻¹."""
    from scipy.linalg import matmul_toeplitz, toeplitz
    from scipy.sparse.linalg import LinearOperator

    c = np.exp(-np.arange(n) / 3.0)
    c[0] += 1.0
    rng = np.random.default_rng(seed)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    Q1, phi = rng.uniform(0.5, 2.0, n), rng.uniform(0, 2 * np.pi, n)
    Q = [harmonic(0.0, Q1[i], phi[i]) for i in range(n)]
    N = [harmonic(1.0, P1[i]) for i in range(n)]
    op = LinearOperator((n, n), matvec=lambda x: matmul_toeplitz(c, x), dtype=float)
    free = contact_system(None, np.ones(n), Q, N, compliance=op)
    K = np.linalg.inv(toeplitz(c))
    dense = contact_system(0.5 * (K + K.T), np.ones(n), Q, N)
    return free, dense


def _run(make, method, keys=("W", "cycles"), **kw):
    def run():
        r = steady(make(), method, **kw)
        out = {}
        for k in keys:
            if k == "events_per_cycle":
                out[k] = events_per_cycle(r)
            elif k == "W_cycles_last":
                out[k] = r.W_cycles[-1]
            elif k == "W_cycles_first":
                out[k] = r.W_cycles[0]
            else:
                out[k] = getattr(r, k)
        return out

    return run


def discrete_cases():
    W = ("W",)
    Wc = ("W", "cycles")
    cases = [
        # exact, event by event
        ("sys.chain3.exact", _run(readme_chain3, "exact", ("W", "cycles", "events_per_cycle"))),
        ("sys.chain5_dense.exact", _run(lambda: chain5(False), "exact", Wc, steps_per_cycle=64)),
        ("sys.chain5_sparse.exact", _run(lambda: chain5(True), "exact", Wc, steps_per_cycle=64)),
        (
            "sys.stagger12_sep_sparse.exact",
            _run(lambda: staggered_chain(sparse=True), "exact", Wc, steps_per_cycle=64),
        ),
        (
            "sys.stagger12_contact.exact",
            _run(lambda: staggered_chain(sep=False), "exact", Wc, steps_per_cycle=64),
        ),
        ("sys.dense8.exact", _run(dense_spd, "exact", Wc, steps_per_cycle=64)),
        (
            "sys.blockdiag_chains.exact",
            _run(
                lambda: block_diagonal(
                    [
                        readme_chain3(),
                        chain(
                            4,
                            k_coupling=2,
                            k_ground=0.5,
                            P1=0.4,
                            Q1=[1.0, 0.7, 1.3, 0.2],
                            phi=[2.0, 0.1, 1.0, 4.0],
                        ),
                    ]
                ),
                "exact",
                W,
                steps_per_cycle=64,
            ),
        ),
        (
            "sys.blockdiag_nodes.exact",
            _run(
                lambda: block_diagonal(
                    [node_normalized(1.5, 2.0, 0.6 * PI), node_normalized(0.5, 2.0, 0.6 * PI)]
                ),
                "exact",
                W,
                steps_per_cycle=64,
            ),
        ),
        # explicit
        (
            "sys.chain2_sep.explicit",
            _run(
                lambda: make_chain(2, True),
                "explicit",
                ("W", "cycles", "W_cycles_last"),
                steps_per_cycle=200,
                tol=1e-9,
            ),
        ),
        (
            "sys.chain2_contact.explicit",
            _run(lambda: make_chain(2, False), "explicit", Wc, steps_per_cycle=200, tol=1e-9),
        ),
        (
            "sys.chain5_sparse.explicit",
            _run(
                lambda: chain(
                    5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=1.2, phi=0.4, sparse=True
                ),
                "explicit",
                Wc,
                steps_per_cycle=100,
            ),
        ),
        (
            "sys.stagger3.explicit",
            _run(lambda: staggered_chain(n=3), "explicit", Wc, steps_per_cycle=200, tol=1e-12),
        ),
        (
            "sys.stagger3.explicit_nohistory",
            _run(
                lambda: staggered_chain(n=3),
                "explicit",
                Wc,
                steps_per_cycle=200,
                tol=1e-12,
                history=False,
            ),
        ),
        # projection (diagonal K)
        (
            "sys.uncoupled4.projection",
            _run(
                lambda: chain(
                    4,
                    k_coupling=0.0,
                    P1=[0.5, 1.5, 0.2, 2.0],
                    Q1=[1, 2, 0.5, 3],
                    phi=[0.1, 1.0, 2.0, 3.0],
                ),
                "projection",
                Wc,
                steps_per_cycle=400,
                tol=1e-12,
            ),
        ),
        (
            "sys.uncoupled4.projection_nohistory",
            _run(
                lambda: chain(
                    4,
                    k_coupling=0.0,
                    P1=[0.5, 1.5, 0.2, 2.0],
                    Q1=[1, 2, 0.5, 3],
                    phi=[0.1, 1.0, 2.0, 3.0],
                ),
                "projection",
                Wc,
                steps_per_cycle=400,
                tol=1e-12,
                history=False,
            ),
        ),
        (
            "sys.blockdiag_nodes.projection",
            _run(
                lambda: block_diagonal(
                    [
                        node_normalized(1.5, 2.0, 0.6 * PI),
                        node_normalized(0.5, 2.0, 0.6 * PI),
                        node_normalized(5.0, 5.0, 0.6 * PI),
                    ]
                ),
                "projection",
                Wc,
                steps_per_cycle=500,
            ),
        ),
        # convex backends on a coupled chain (with separation and in full contact)
        (
            "sys.chain2_sep.clarabel",
            _run(lambda: make_chain(2, True), "clarabel", Wc, steps_per_cycle=200, tol=1e-9),
        ),
        (
            "sys.chain2_contact.clarabel",
            _run(lambda: make_chain(2, False), "clarabel", Wc, steps_per_cycle=200, tol=1e-9),
        ),
        (
            "sys.chain2_sep.osqp",
            _run(lambda: make_chain(2, True), "osqp", Wc, steps_per_cycle=200, tol=1e-9),
        ),
        (
            "sys.chain2_contact.osqp",
            _run(lambda: make_chain(2, False), "osqp", Wc, steps_per_cycle=200, tol=1e-9),
        ),
        (
            "sys.chain2_sep.active-set",
            _run(lambda: make_chain(2, True), "active-set", Wc, steps_per_cycle=200, tol=1e-9),
        ),
        (
            "sys.chain2_sep.qpsolvers:proxqp",
            _run(
                lambda: make_chain(2, True), "qpsolvers:proxqp", Wc, steps_per_cycle=100, tol=1e-9
            ),
        ),
        (
            "sys.chain2_sep.qpsolvers:highs",
            _run(lambda: make_chain(2, True), "qpsolvers:highs", Wc, steps_per_cycle=100, tol=1e-9),
        ),
        (
            "sys.chain2_sep.cvxpy:CLARABEL",
            _run(lambda: make_chain(2, True), "cvxpy:CLARABEL", Wc, steps_per_cycle=60, tol=1e-9),
        ),
        (
            "sys.chain2_sep.cvxpy:OSQP",
            _run(lambda: make_chain(2, True), "cvxpy:OSQP", Wc, steps_per_cycle=60, tol=1e-9),
        ),
        (
            "sys.stagger12_sep.osqp_noevents",
            _run(staggered_chain, "osqp", Wc, steps_per_cycle=300, tol=1e-12, locate_events=False),
        ),
        ("sys.dense8.osqp", _run(dense_spd, "osqp", Wc, steps_per_cycle=300, tol=1e-12)),
        ("sys.dense8.clarabel", _run(dense_spd, "clarabel", Wc, steps_per_cycle=300, tol=1e-12)),
        # active-set: dense, sparse (blocks), events on/off, no history, matrix-free
        (
            "sys.dense8.active-set",
            _run(dense_spd, "active-set", Wc, steps_per_cycle=300, tol=1e-12),
        ),
        (
            "sys.stagger12_sep.active-set",
            _run(staggered_chain, "active-set", Wc, steps_per_cycle=300, tol=1e-12),
        ),
        (
            "sys.stagger12_sep.active-set_noevents",
            _run(
                staggered_chain,
                "active-set",
                Wc,
                steps_per_cycle=300,
                tol=1e-12,
                locate_events=False,
            ),
        ),
        (
            "sys.stagger12_contact.active-set",
            _run(
                lambda: staggered_chain(sep=False), "active-set", Wc, steps_per_cycle=300, tol=1e-12
            ),
        ),
        (
            "sys.stagger10.active-set_nohistory",
            _run(
                lambda: staggered_chain(n=10),
                "active-set",
                Wc,
                steps_per_cycle=200,
                tol=1e-12,
                history=False,
            ),
        ),
        (
            "sys.stagger15_sparse.active-set_dense",
            _run(
                lambda: staggered_chain(n=15, sparse=True),
                "active-set",
                W,
                steps_per_cycle=200,
                tol=1e-12,
                block="dense",
            ),
        ),
        (
            "sys.stagger15_sparse.active-set_banded",
            _run(
                lambda: staggered_chain(n=15, sparse=True),
                "active-set",
                W,
                steps_per_cycle=200,
                tol=1e-12,
                block="banded",
            ),
        ),
        (
            "sys.stagger15_sparse.active-set_sparse",
            _run(
                lambda: staggered_chain(n=15, sparse=True),
                "active-set",
                W,
                steps_per_cycle=200,
                tol=1e-12,
                block="sparse",
            ),
        ),
        (
            "sys.stagger15_sparse.active-set_auto",
            _run(
                lambda: staggered_chain(n=15, sparse=True),
                "active-set",
                W,
                steps_per_cycle=200,
                tol=1e-12,
            ),
        ),
        (
            "sys.toeplitz30_sep.active-set_matrixfree",
            _run(
                lambda: toeplitz_pair(sep=True)[0],
                "active-set",
                ("W", "cycles", "W_cycles_first", "W_cycles_last"),
                steps_per_cycle=150,
                tol=1e-12,
                max_cycles=3,
                on_nonconvergence="ignore",
            ),
        ),
        (
            "sys.toeplitz30_sep.active-set_dense",
            _run(
                lambda: toeplitz_pair(sep=True)[1],
                "active-set",
                ("W", "cycles", "W_cycles_first", "W_cycles_last"),
                steps_per_cycle=150,
                tol=1e-12,
                max_cycles=3,
                on_nonconvergence="ignore",
            ),
        ),
        (
            "sys.toeplitz30_contact.active-set_matrixfree",
            _run(
                lambda: toeplitz_pair(sep=False)[0],
                "active-set",
                Wc,
                steps_per_cycle=150,
                tol=1e-12,
                locate_events=False,
                max_cycles=3,
                on_nonconvergence="ignore",
            ),
        ),
        (
            "sys.toeplitz12_sep.osqp_matrixfree",
            _run(lambda: toeplitz_pair(n=12)[0], "osqp", Wc, steps_per_cycle=150, tol=1e-12),
        ),
        # d = 2
        (
            "sys.d2_uncoupled3.projection",
            _run(lambda: chain_d2(0.0), "projection", Wc, steps_per_cycle=200, tol=1e-10),
        ),
        (
            "sys.d2_uncoupled3.clarabel",
            _run(lambda: chain_d2(0.0), "clarabel", Wc, steps_per_cycle=200, tol=1e-10),
        ),
        (
            "sys.d2_chain3.clarabel",
            _run(lambda: chain_d2(0.5), "clarabel", Wc, steps_per_cycle=60, tol=1e-10),
        ),
        (
            "sys.d2_chain3.active-set",
            _run(lambda: chain_d2(0.5), "active-set", Wc, steps_per_cycle=60, tol=1e-10),
        ),
        (
            "sys.d2_chain3.cvxpy:CLARABEL",
            _run(lambda: chain_d2(0.5), "cvxpy:CLARABEL", Wc, steps_per_cycle=60, tol=1e-10),
        ),
        (
            "sys.d2_chain3.cvxpy:SCS",
            _run(lambda: chain_d2(0.5), "cvxpy:SCS", Wc, steps_per_cycle=60, tol=1e-10),
        ),
        (
            "sys.d2_stagger4.active-set",
            _run(
                lambda: staggered_chain(n=4, dims=2, seed=1, kc=0.7),
                "active-set",
                Wc,
                steps_per_cycle=120,
                tol=1e-11,
            ),
        ),
        (
            "sys.d2_node.projection",
            _run(
                lambda: chain(1, dims=2, P1=1.5, Q1=[[2.0, 1.0]], phi=[[0.6 * PI, 1.0]]),
                "projection",
                Wc,
                steps_per_cycle=400,
            ),
        ),
    ]
    return cases


# -- batched single-node grids -------------------------------------------------------------------
BATCH_POINTS = [
    (0.5, 2.0, 0.0),
    (0.5, 2.0, 0.6 * PI),
    (1.5, 2.0, 0.6 * PI),
    (5.0, 5.0, 0.6 * PI),
    (0.5, 1.01, 0.3 * PI),
    (0.0, 1.0, 2.0),
    (1.0, 1.5, 1.0),
    (3.0, 0.2, 0.0),
]


def _batch_arrays():
    return tuple(np.array(c) for c in zip(*BATCH_POINTS))


def _per_point(values):
    return {f"p{i}": float(v) for i, v in enumerate(np.ravel(values))}


def batch_cases():
    def proj(placement):
        def run():
            P1, Q1, phi = _batch_arrays()
            out = _per_point(batch_projection(P1, Q1, phi, 600, placement=placement))
            cyc = batch_projection_cycles(P1, Q1, phi, 600, placement=placement)
            out.update({f"cycles{i}": float(c) for i, c in enumerate(np.ravel(cyc))})
            return out

        return run

    def solver(method):
        def run():
            P1, Q1, phi = _batch_arrays()
            return _per_point(batch_solver(P1, Q1, phi, method, 300))

        return run

    def exact():
        P1, Q1, phi = _batch_arrays()
        out = _per_point(exact_grid(P1, Q1, phi))
        out["scalar_1e20"] = float(exact_grid(1e20, 3e19, 0.5 * PI))
        out["scalar_tiny"] = float(exact_grid(1e-8, 2e-8, 0.7))
        return out

    return [
        ("batch.projection_uniform", proj("uniform")),
        ("batch.projection_contact", proj("contact")),
        ("batch.clarabel", solver("clarabel")),
        ("batch.osqp", solver("osqp")),
        ("batch.exact", exact),
    ]


# -- continuum contacts --------------------------------------------------------------------------
R_, E_, MU_, P0_ = 10.0, 200e3, 0.5, 100.0


def _contact_case(make, steps=None, **kw):
    def run():
        W, Wn, cycles = contact(make(), steps, **kw)
        return {"W": W, "W_normalized": Wn, "cycles": cycles}

    return run


def _hs_sphere(P1=0.0, Q1=0.25, phi=0.0, nu=0.0, grid=16, dims=1, k_support=0.0):
    return halfspace_sphere(
        1.0,
        1.0,
        nu,
        0.5,
        harmonic(1.0, P1, 0.0, TWO_PI),
        harmonic(0.0, Q1, phi, TWO_PI),
        grid=grid,
        dims=dims,
        k_support=k_support,
    )


def _mdr(P1=0.0, Q1=0.25, phi=0.0, nu=0.0, **kw):
    return mdr_sphere(
        R_, E_, nu, MU_, harmonic(P0_, P1 * P0_), harmonic(0.0, Q1 * MU_ * P0_, phi), **kw
    )


def _cyl(P1=0.0, Q1=0.25, phi=0.0, **kw):
    return halfplane_cylinder(
        R_, E_, 0.3, MU_, harmonic(P0_, P1 * P0_), harmonic(0.0, Q1 * MU_ * P0_, phi), **kw
    )


def _as_system_case(make, steps, methods, model_tol=1e-12, **opts):
    """The contact held by a support as a ContactSystem: the model's own W on the scene's grid,
    and each method's W on that scene."""

    def run():
        scene = make_scene(contact_as_system(make()), steps)
        # the model's own W on a fresh model (lcpfric 0.1's models kept the normal problem's
        # warm starts from earlier solves, so that W depended on what was solved before)
        W, Wn, cycles = contact(make(), t=scene_times(scene), tol=model_tol)
        out = {"model.W": W, "model.W_normalized": Wn, "model.cycles": cycles}
        for method in methods:
            r = steady(
                scene,
                method,
                tol=1e-12,
                locate_events=False,
                **(opts if method == "clarabel" else {}),
            )
            out[f"{method}.W"] = r.W
            out[f"{method}.cycles"] = r.cycles
        return out

    return run


def contact_cases():
    def hs_heightmap():
        P, Q = harmonic(1.0, 0.3, 0.0, TWO_PI), harmonic(0.0, 0.2, 0.5, TWO_PI)
        s = halfspace_sphere(1.0, 1.0, 0.0, 0.5, P, Q, grid=12)
        heights, h = halfspace_surface(s)
        W, Wn, cycles = contact(halfspace_heights(1.0, 0.0, 0.5, P, Q, heights, h), 40)
        W2, Wn2, c2 = contact(s, 40)
        return {
            "W": W,
            "W_normalized": Wn,
            "cycles": cycles,
            "sphere.W": W2,
            "sphere.W_normalized": Wn2,
        }

    def mdr_profiles():
        out = {}
        eta_free = [
            ("powerlaw", lambda: mdr_power_law(1.0, 4)),
            ("axisymmetric", lambda: mdr_axisymmetric(lambda r: 4.0 * r**3)),
        ]
        for label, prof in eta_free:
            m = mdr_sphere(
                None,
                E_,
                0.3,
                MU_,
                harmonic(P0_, 0.0),
                harmonic(0.0, 0.3 * MU_ * P0_),
                nodes=500,
                profile=prof(),
            )
            W, Wn, cycles = contact(m, 200)
            out[f"{label}.W"] = W
            out[f"{label}.cycles"] = cycles
        return out

    def hs_k_t0():
        return {"sphere16": contact_k_t0(_hs_sphere()), "mdr": contact_k_t0(_mdr(nodes=10))}

    return [
        (
            "contact.mdr.readme",
            _contact_case(
                lambda: mdr_sphere(R_, E_, 0.3, MU_, harmonic(100, 50), harmonic(0, 20, 0.5 * PI)),
                400,
            ),
        ),
        ("contact.mdr.md_const_P", _contact_case(lambda: _mdr(Q1=0.5, nu=0.3, nodes=2000), 400)),
        ("contact.mdr.phase", _contact_case(lambda: _mdr(P1=0.5, Q1=0.4, phi=0.5, nodes=500), 200)),
        (
            "contact.mdr.support_separation",
            _contact_case(lambda: _mdr(P1=1.5, Q1=0.6, phi=0.3, nodes=300, k_support=2e3), 200),
        ),
        (
            "contact.mdr.one_spring",
            _contact_case(
                lambda: mdr_sphere(
                    R_,
                    E_,
                    0.0,
                    MU_,
                    harmonic(P0_, 0.6 * P0_),
                    harmonic(0.0, 0.9 * MU_ * P0_, 0.5 * PI),
                    nodes=1,
                    k_support=3e3,
                ),
                300,
                tol=1e-12,
            ),
        ),
        ("contact.mdr.profiles", mdr_profiles),
        (
            "contact.halfplane.readme",
            _contact_case(
                lambda: halfplane_cylinder(
                    10, 200e3, 0.3, 0.5, harmonic(100, 0), harmonic(0, 25), nodes=400
                ),
                400,
            ),
        ),
        (
            "contact.halfplane.phase",
            _contact_case(lambda: _cyl(P1=0.5, Q1=0.4, phi=0.5, nodes=200), 200),
        ),
        (
            "contact.halfplane.support_separation",
            _contact_case(lambda: _cyl(P1=1.5, Q1=0.6, phi=0.3, nodes=100, k_support=1e3), 200),
        ),
        (
            "contact.halfplane.gross_sliding_support",
            _contact_case(lambda: _cyl(0.9, 0.8, 0.2 * PI, nodes=400, k_support=1e4), 8),
        ),
        (
            "contact.halfplane.as_system",
            _as_system_case(
                lambda: _cyl(P1=1.5, Q1=0.6, phi=1.0, nodes=40, k_support=2e3),
                150,
                ("active-set", "clarabel"),
            ),
        ),
        (
            "contact.halfspace.d1_md_grid20",
            _contact_case(lambda: _hs_sphere(Q1=0.25, grid=20), 100),
        ),
        (
            "contact.halfspace.d1_phase_grid16",
            _contact_case(lambda: _hs_sphere(P1=0.5, Q1=0.2, phi=0.7, grid=16), 60),
        ),
        (
            "contact.halfspace.d2_nu0_grid12",
            _contact_case(lambda: _hs_sphere(P1=0.5, Q1=0.2, phi=0.7, grid=12, dims=2), 60),
        ),
        (
            "contact.halfspace.d2_nu03_grid12",
            _contact_case(lambda: _hs_sphere(P1=0.5, Q1=0.2, phi=0.7, grid=12, nu=0.3, dims=2), 60),
        ),
        (
            "contact.halfspace.d2_nu03_md_grid12",
            _contact_case(lambda: _hs_sphere(Q1=0.25, grid=12, nu=0.3, dims=2), 40),
        ),
        (
            "contact.halfspace.d1_support_separation",
            _contact_case(
                lambda: _hs_sphere(
                    P1=1.3,
                    Q1=0.3,
                    phi=0.5 * PI,
                    grid=16,
                    k_support=contact_k_t0(_hs_sphere(grid=16)),
                ),
                20,
            ),
        ),
        (
            "contact.halfspace.punch",
            _contact_case(
                lambda: halfspace_punch(
                    1.0,
                    0.5,
                    1.0,
                    0.0,
                    0.5,
                    harmonic(1.0, 0.3, 0.0, TWO_PI),
                    harmonic(0.0, 0.2, 0.5, TWO_PI),
                    grid=16,
                ),
                40,
            ),
        ),
        ("contact.halfspace.heightmap", hs_heightmap),
        (
            "contact.halfspace.as_system_d1",
            _as_system_case(
                lambda: _hs_sphere(P1=0.5, Q1=0.3, phi=0.7, grid=10, k_support=2.0),
                80,
                ("active-set", "clarabel"),
            ),
        ),
        (
            "contact.halfspace.as_system_d2",
            _as_system_case(
                lambda: _hs_sphere(P1=0.5, Q1=0.3, phi=0.7, nu=0.3, grid=10, dims=2, k_support=2.0),
                80,
                ("clarabel",),
                model_tol=1e-10,
                check_tol=1e-4,
            ),
        ),
        ("contact.k_t0", hs_k_t0),
    ]


# -- maps, sweeps, the paper's motor -------------------------------------------------------------
MAP_POINTS = [(0.5, 0.4, 0.5), (0.0, 0.5, 0.0), (1.5, 0.6, 0.3), (0.9, 0.8, 2.0), (0.3, 0.2, 0.0)]


def map_cases():
    def mdr(ks):
        def run():
            P1, Q1, phi = (np.array(c) for c in zip(*MAP_POINTS))
            return _per_point(
                mdr_map(P1, Q1, phi, nodes=120, steps_per_cycle=120, k_support=ks, tol=1e-10)
            )

        return run

    def mdr_defaults():
        return _per_point(mdr_map([0.5, 1.2], [0.4, 0.3], [0.5 * PI, 1.0], k_support=1.0))

    def hs(dims, nu, ks=0.0):
        def run():
            return _per_point(
                halfspace_map(
                    [0.5, 0.5, 0.2],
                    [0.4, 0.2, 0.3],
                    [0.5, 1.5, 0.0],
                    grid=12,
                    dims=dims,
                    nu=nu,
                    steps_per_cycle=24,
                    k_support=ks,
                )
            )

        return run

    def sweep_exact():
        vals = sweep_map([0.0, 0.5, 1.5], [1.0, 2.0], [0.0, 0.6 * PI])
        return {"phi{}_P{}_Q{}".format(*k): v for k, v in vals.items()}

    def sweep_projection():
        vals = sweep_map([0.5, 1.5], [2.0], [0.6 * PI], method="projection", steps_per_cycle=400)
        return {"phi{}_P{}_Q{}".format(*k): v for k, v in vals.items()}

    def sweep_explicit():
        vals = sweep_map([1.5], [2.0], [0.6 * PI], method="explicit", steps_per_cycle=400)
        return {"phi{}_P{}_Q{}".format(*k): v for k, v in vals.items()}

    def sweep_contact():
        vals = sweep_map(
            [0.5, 1.5],
            [0.5],
            [0.3 * PI],
            contact={"k_support": 1.0, "nodes": 60},
            steps_per_cycle=60,
        )
        return {"phi{}_P{}_Q{}".format(*k): v for k, v in vals.items()}

    def sweep_contact_halfspace():
        vals = sweep_map(
            [0.5], [0.4], [0.5], contact={"model": "halfspace", "grid": 12}, steps_per_cycle=24
        )
        return {"phi{}_P{}_Q{}".format(*k): v for k, v in vals.items()}

    def motor():
        W, sep, shake, nat = motor_values(
            20.0, 0.5e-3, 2000.0, 5e8, [100.0, 300.0, 450.0, 900.0], 0.3
        )
        out = {f"W{i}": w for i, w in enumerate(W)}
        out.update(separation_speed=sep, shakedown_speed=shake, natural_frequency=nat)
        return out

    return [
        ("map.mdr_ks0", mdr(0.0)),
        ("map.mdr_ks05", mdr(0.5)),
        ("map.mdr_defaults", mdr_defaults),
        ("map.halfspace_d1", hs(1, 0.0)),
        ("map.halfspace_d2", hs(2, 0.3)),
        ("map.halfspace_d1_support", hs(1, 0.0, 1.0)),
        ("sweep.exact", sweep_exact),
        ("sweep.projection", sweep_projection),
        ("sweep.explicit", sweep_explicit),
        ("sweep.contact_mdr", sweep_contact),
        ("sweep.contact_halfspace", sweep_contact_halfspace),
        ("analytic", analytic_values),
        ("motor", motor),
    ]


CASES = single_node_cases() + discrete_cases() + batch_cases() + contact_cases() + map_cases()


# =================================================================================================
# --- the driver ---
# =================================================================================================
def _as_float(value) -> float:
    if isinstance(value, (bool, np.bool_)):
        return float(value)
    return float(value)


def run_cases(only=None):
    values, names_of, problems, timings = {}, {}, [], {}
    selected = [(n, f) for n, f in CASES if only is None or any(s in n for s in only)]
    total = time.perf_counter()
    print(f"{'name':<62} {'value':>24} {'seconds':>8}")
    for name, func in selected:
        start = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                out = func()
            except Exception as exc:  # noqa: BLE001 - a failing case is reported and skipped
                seconds = time.perf_counter() - start
                problems.append((name, f"{type(exc).__name__}: {exc}"))
                print(
                    f"{name:<62} {'FAILED':>24} {seconds:8.2f}  {type(exc).__name__}: "
                    f"{str(exc).splitlines()[0] if str(exc) else ''}"
                )
                traceback.print_exc(limit=3, file=sys.stderr)
                names_of[name] = []
                continue
        seconds = time.perf_counter() - start
        timings[name] = seconds
        items = out.items() if isinstance(out, dict) else [(None, out)]
        names_of[name] = []
        for i, (key, val) in enumerate(items):
            full = name if key is None else f"{name}.{key}"
            values[full] = _as_float(val)
            names_of[name].append(full)
            print(f"{full:<62} {values[full]:>24.16g} {(f'{seconds:8.2f}' if i == 0 else ''):>8}")
        for w in caught:
            msg = f"{w.category.__name__}: {str(w.message).splitlines()[0][:120]}"
            print(f"    warning in {name}: {msg}")
    total = time.perf_counter() - total
    return values, names_of, problems, timings, total


def _reldiff(a: float, b: float) -> str:
    if math.isnan(a) or math.isnan(b):
        return f"nan mismatch ({a!r} vs {b!r})"
    if a == b:
        return "0 (same value, different hex: signed zero?)"
    scale = max(abs(a), abs(b))
    return f"{abs(a - b) / scale:.3e}"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--out", help="write {name: float.hex(value)} to this JSON file")
    g.add_argument("--check", help="recompute and compare with this JSON file")
    p.add_argument(
        "--only",
        action="append",
        help="run only the cases whose name contains this substring (repeatable)",
    )
    p.add_argument(
        "--changes",
        help="with --check: write the values that differ as a markdown table to this file",
    )
    p.add_argument("--list", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)

    print(f"lcpfric from {library_file()}")
    print(f"methods installed: {', '.join(installed_methods())}")
    values, names_of, problems, timings, total = run_cases(args.only)
    if not names_of:
        print(f"no case matches --only {args.only}")
        return 2
    print(f"\n{len(values)} values from {len(names_of)} cases in {total:.1f} s")
    slow = sorted(timings.items(), key=lambda kv: -kv[1])[:5]
    print("slowest cases: " + ", ".join(f"{n} {s:.2f} s" for n, s in slow))
    if problems:
        print(f"\n{len(problems)} case(s) raised:")
        for name, msg in problems:
            print(f"  {name}: {msg.splitlines()[0]}")

    hexed = {k: float.hex(v) for k, v in values.items()}
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(hexed, fh, indent=1, sort_keys=False)
        print(f"wrote {len(hexed)} values to {args.out}")
        return 1 if problems else 0

    with open(args.check) as fh:
        ref = json.load(fh)
    if args.only:
        # the reference names of the selected cases (a name is "<case>" or "<case>.<key>")
        # and, of the names of no current case (a case dropped or renamed since), those that
        # contain a substring
        selected = set(names_of)

        def case_of(key):
            owners = [c for c, _ in CASES if key == c or key.startswith(c + ".")]
            return max(owners, key=len) if owners else None

        expected = set()
        for k in ref:
            c = case_of(k)
            if (c in selected) if c is not None else any(s in k for s in args.only):
                expected.add(k)
    else:
        expected = set(ref)
    same, differ, missing = 0, [], sorted(expected - set(hexed))
    extra = sorted(set(hexed) - set(ref))
    print(f"\n{'name':<62} comparison")
    for name in [k for k in ref if k in hexed]:
        a, b = float.fromhex(ref[name]), float.fromhex(hexed[name])
        if ref[name] == hexed[name]:
            same += 1
            print(f"{name:<62} identical")
        else:
            differ.append(name)
            print(f"{name:<62} DIFFERS rel {_reldiff(a, b)}  ({ref[name]} -> {hexed[name]})")
    for name in missing:
        print(f"{name:<62} MISSING (not computed)")
    for name in extra:
        print(f"{name:<62} NEW (not in the reference)")
    print(
        f"\n{same} identical, {len(differ)} differ, {len(missing)} missing, "
        f"{len(extra)} new (of {len(expected)} expected)"
    )
    if args.changes:
        rows = [
            f"| {n} | {float.fromhex(ref[n])!r} | {float.fromhex(hexed[n])!r} "
            f"| {_reldiff(float.fromhex(ref[n]), float.fromhex(hexed[n]))} |"
            for n in differ
        ]
        with open(args.changes, "w") as fh:
            fh.write(
                "| value | pinned | now | relative difference |\n|---|---|---|---|\n"
                + "\n".join(rows)
                + "\n"
            )
        print(f"wrote {len(rows)} changed values to {args.changes}")
    ok = not differ and not missing and not problems
    print("OK: every value bit-identical" if ok else "MISMATCH")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
