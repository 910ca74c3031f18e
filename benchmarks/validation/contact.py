"""Continuum contacts: every validation and goal of the Hertz (MDR) and plane (half-plane)
models, measured in one run.

``OPENBLAS_NUM_THREADS=1 python benchmarks/validation/contact.py [--quick] [--no-map] [--out DIR]``

writes ``DIR/contact.md`` (default ``benchmarks/results``). Each validation gives the value, the
closed form it is judged against, their relative difference, and the nodes and steps used;
timings are wall seconds of ``lcpfric.steady_state`` on this machine (shared: other work may
run on the second core). The Hertz map goal runs the command users run, ``lcpfric map --contact
sphere ...`` with 11 phases on a 41 x 41 grid, in a child process on both cores (``--no-map``
skips it; ``--quick`` uses coarser grids and a 11 x 11 map, about a minute in all).

Materials and loads: two identical bodies, E = 200e3, R = 10, μ = 0.5, P0 = 100 (sphere) or
100 per unit length (cylinder); ν = 0 where the classical forms are exact (the sphere's
Mindlin-Deresiewicz and Cattaneo forms rest on Mindlin's approximation otherwise; the plane ones
are exact at any ν for identical bodies), and ν = 0.3 as a check of the same.
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

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import lcpfric
from lcpfric.model import Harmonic
from lcpfric.model.continuum import (
    HalfPlaneCylinder,
    MDRSphere,
    PowerLaw,
    cattaneo_stick_ratio,
    ciavarella_jager_W,
    cylinder_contact,
    cylinder_W,
    mindlin_deresiewicz_W,
    moduli,
)

E, R, MU, P0 = 200e3, 10.0, 0.5, 100.0
PI = math.pi


def sphere(P1=0.0, Q1=0.5, phi=0.0, nu=0.0, **kw):
    return MDRSphere(R, E, nu, MU, Harmonic(P0, P1 * P0), Harmonic(0.0, Q1 * MU * P0, phi), **kw)


def cylinder(P1=0.0, Q1=0.5, phi=0.0, nu=0.0, **kw):
    return HalfPlaneCylinder(
        R, E, nu, MU, Harmonic(P0, P1 * P0), Harmonic(0.0, Q1 * MU * P0, phi), **kw
    )


def timed(model, steps, **kw):
    t = time.perf_counter()
    r = lcpfric.steady_state(model, steps_per_cycle=steps, **kw)
    return r, time.perf_counter() - t


def rel(a, b):
    return (a - b) / b


def order(hs, errs):
    """Least-squares slope of log|err| against log h."""
    e = np.abs(np.asarray(errs))
    return float(np.polyfit(np.log(hs), np.log(e), 1)[0])


def mindlin(lines, quick):
    lines += [
        "## Mindlin-Deresiewicz at constant P (the goals: 0.2 % in 1 s; 0.5 % in 10 s)",
        "",
        "| model | ν | x = Q*/(μP) | nodes | steps | W | closed form | rel. difference | seconds |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    springs, across = (500, 200) if quick else (2000, 400)
    for nu in (0.0, 0.3):
        for x in (0.2, 0.5, 0.9):
            r, s = timed(sphere(Q1=x, nu=nu, nodes=springs), 400)
            ref = mindlin_deresiewicz_W(P0, x * MU * P0, MU, r.contact.k_t0)
            lines.append(
                f"| sphere (MDR) | {nu:g} | {x:g} | {springs} | 400 | {r.W:.8g} "
                f"| {ref:.8g} | {rel(r.W, ref):.2e} | {s:.2f} |"
            )
    for nu in (0.0, 0.3):
        for x in (0.2, 0.5, 0.9):
            r, s = timed(cylinder(Q1=x, nu=nu, nodes=across), 400)
            ref = cylinder_W(P0, x * MU * P0, MU, E, nu)
            lines.append(
                f"| cylinder (half-plane) | {nu:g} | {x:g} | {across} across | 400 "
                f"| {r.W:.8g} | {ref:.8g} | {rel(r.W, ref):.2e} | {s:.2f} |"
            )
    lines.append("")


def normal(lines):
    m = cylinder(nodes=400)
    p = m.pressure(P0)
    ref = cylinder_contact(P0, R, E, 0.0)
    a = m.normal_solution([0.0])[1][0]
    exact = ref["p0"] * np.sqrt(np.maximum(0.0, 1 - (m.x / ref["a"]) ** 2))
    s = sphere(nodes=2000)
    lines += [
        "## Normal problem",
        "",
        f"- Cylinder, 400 elements across: half-width {a:.8g} against Hertz "
        f"{ref['a']:.8g} ({rel(a, ref['a']):.1e}, the element width is "
        f"{m.dx / ref['a']:.1e} a); peak pressure {p.max():.8g} against "
        f"{ref['p0']:.8g} ({rel(p.max(), ref['p0']):.1e}); largest pressure error "
        f"{np.max(np.abs(p - exact)) / ref['p0']:.2e} p0 (at the edge); Δ Σ p = "
        f"{p.sum() * m.dx:.15g} (P = {P0:g}).",
        f"- Sphere (MDR): the spring forces are the cells' exact shares of Hertz's 1-D "
        f"pressure: Σ N = {s.normal_forces([0.0]).sum():.15g} (P = {P0:g}); contact "
        f"radius {s.a0:.8g} = Hertz's.",
        "",
    ]


def cattaneo(lines):
    lines += [
        "## Cattaneo's stick zone (first loading at constant P, Q up to 0.95 μP)",
        "",
        "| model | Q/(μP) | c/a | closed form | difference (cells) |",
        "|---|---|---|---|---|",
    ]
    for name, model, geometry in (
        ("sphere (MDR, 2000)", sphere(Q1=0.95, nodes=2000), "sphere"),
        ("cylinder (400 across)", cylinder(Q1=0.95, nodes=400), "cylinder"),
    ):
        steps = 400
        r = lcpfric.steady_state(
            model, steps_per_cycle=steps, max_cycles=1, on_nonconvergence="ignore"
        )
        c, size = r.stick_size(), r.contact.size
        for j in (20, 40, 60, 80):
            x = 0.95 * math.sin(2 * PI * j / steps)
            ca, ref = c[j] / size[j], cattaneo_stick_ratio(x, geometry)
            lines.append(
                f"| {name} | {x:.4f} | {ca:.5f} | {ref:.5f} "
                f"| {(ca - ref) * size[j] / model.dx:+.2f} |"
            )
    lines.append("")


def phases(lines):
    lines += [
        "## In phase, and half a period apart",
        "",
        "P1/P0 = 0.5, Q1/(μP0) = 0.4 (so Q1 <= μ P1 and P1 < P0: Mindlin and Deresiewicz's "
        "condition for no dissipation in phase).",
        "",
        "| model | nodes, steps | W_norm at φ = 0 | at 0.5 | at 0.5 + π | rel. difference "
        "(φ + π) |",
        "|---|---|---|---|---|---|",
    ]
    for name, make, n in (("sphere (MDR)", sphere, 2000), ("cylinder (half-plane)", cylinder, 400)):
        w0, wa, wb = (
            lcpfric.steady_state(
                make(P1=0.5, Q1=0.4, phi=phi, nodes=n), steps_per_cycle=400
            ).W_normalized
            for phi in (0.0, 0.5, 0.5 + PI)
        )
        lines.append(f"| {name} | {n}, 400 | {w0:.3e} | {wa:.6g} | {wb:.6g} | {rel(wb, wa):.1e} |")
    lines += [
        "",
        "W at φ = 0 is not exactly 0: it is the discretization's (it falls with the "
        "steps and nodes: `tests/test_contact_mdr.py`).",
        "",
    ]


def chord(lines):
    eta = moduli(E, 0.3)["eta"]
    lines += [
        "## Any profile: the Ciavarella-Jäger chord area (f = r⁴, ν = 0.3, 2000 springs, "
        "400 steps)",
        "",
        "| x | W | chord-area form | rel. difference |",
        "|---|---|---|---|",
    ]
    for x in (0.3, 0.8):
        m = MDRSphere(
            None,
            E,
            0.3,
            MU,
            Harmonic(P0, 0.0),
            Harmonic(0.0, x * MU * P0),
            nodes=2000,
            profile=PowerLaw(1.0, 4),
        )
        W = lcpfric.steady_state(m, steps_per_cycle=400).W
        ref = ciavarella_jager_W(m.approach, P0, x * MU * P0, MU, eta)
        lines.append(f"| {x:g} | {W:.8g} | {ref:.8g} | {rel(W, ref):.2e} |")
    lines.append("")


def convergence(lines, quick):
    lines += [
        "## Convergence with steps and nodes (x = 0.5, constant P, against the closed forms)",
        "",
    ]
    fine_nodes, fine_steps = (2000, 1600) if quick else (8000, 6400)
    steps = (100, 200, 400, 800)
    for name, make, ref_of, nodes, node_set in (
        (
            "sphere (MDR)",
            sphere,
            lambda r: mindlin_deresiewicz_W(P0, 0.5 * MU * P0, MU, r.contact.k_t0),
            fine_nodes,
            (50, 100, 200, 400, 800),
        ),
        (
            "cylinder (half-plane)",
            cylinder,
            lambda r: cylinder_W(P0, 0.5 * MU * P0, MU, E, 0.0),
            800 if not quick else 400,
            (50, 100, 200, 400),
        ),
    ):
        es, Ws = [], []
        for n in steps:
            r = lcpfric.steady_state(make(nodes=nodes), steps_per_cycle=n)
            es.append(rel(r.W, ref_of(r)))
            Ws.append(r.W)
        d = np.abs(np.diff(Ws))
        self_orders = np.log2(d[:-1] / d[1:])
        en = []
        ns = node_set if not (quick and name.startswith("cyl")) else (50, 100, 200)
        for n in ns:
            r = lcpfric.steady_state(
                make(nodes=n), steps_per_cycle=fine_steps if name.startswith("sphere") else 1600
            )
            en.append(rel(r.W, ref_of(r)))
        lines += [
            f"**{name}**: steps {list(steps)} at {nodes} nodes: errors "
            + ", ".join(f"{e:.2e}" for e in es)
            + f"; least-squares order {order(1 / np.array(steps), es):.2f} in 1/steps "
            f"(successive differences of W: orders "
            + ", ".join(f"{o:.2f}" for o in self_orders)
            + "). "
            f"Nodes {list(ns)} at {fine_steps if name.startswith('sphere') else 1600} "
            f"steps: errors "
            + ", ".join(f"{e:.2e}" for e in en)
            + f"; least-squares order {order(1 / np.array(ns), en):.2f} in 1/nodes "
            "(not monotone: the slip front crosses discrete nodes).",
            "",
        ]


def small_amplitude(lines):
    from lcpfric.analysis.contact_maps import mdr_W_normalized

    lines += [
        "## Small amplitudes: W grows as Q1³ (sphere, 4000 springs, 200 steps, Q1/(μP1) = 0.8)",
        "",
        "| φ | W_norm at Q1/(μP0) = 0.01, 0.02, 0.04 | ratios (8 for Q1³) |",
        "|---|---|---|",
    ]
    q = np.array([0.01, 0.02, 0.04])
    for phi in (0.5, 1.5):
        w = mdr_W_normalized(
            q / 0.8, q, np.full(3, phi), nodes=4000, steps_per_cycle=200, tol=1e-10
        )
        lines.append(
            f"| {phi:g} | "
            + ", ".join(f"{v:.4e}" for v in w)
            + " | "
            + ", ".join(f"{v:.3f}" for v in w[1:] / w[:-1])
            + " |"
        )
    lines.append("")


def question(lines, quick):
    """Where the maximum over φ lies: the MDR sphere against the paper's single node."""
    from lcpfric.analysis.sweep import sweep
    from lcpfric.figures.contact import K_SUPPORT, PHASE_CASES
    from lcpfric.analysis.contact_maps import mdr_W_normalized

    phi = np.linspace(0.0, PI, 181)
    lines += [
        "## The paper's question: at which phase is the dissipation largest?",
        "",
        f"W against φ on {phi.size} phases in [0, π]: the Hertz contact (MDR, 400 springs, "
        f"400 steps, support stiffness {K_SUPPORT:g} k_t0, and 0 where the loads allow) "
        "and the paper's single node (`exact`, W k11/(f P0)² = Q̂1 Ŵ).",
        "",
        "| P1/P0 | Q1/(μP0) | φ_max/π, sphere (k_s = k_t0) | sphere (k_s = 0) "
        "| single node | W_norm max, sphere (k_s = k_t0) |",
        "|---|---|---|---|---|---|",
    ]
    for p1, q1 in PHASE_CASES:
        out = []
        for ks in (K_SUPPORT, 0.0):
            w = mdr_W_normalized(
                np.full(phi.size, p1),
                np.full(phi.size, q1),
                phi,
                nodes=400,
                steps_per_cycle=400,
                k_support=ks,
            )
            out.append(
                (
                    phi[int(np.nanargmax(w))] / PI if np.any(np.isfinite(w)) else None,
                    np.nanmax(w) if np.any(np.isfinite(w)) else None,
                )
            )
        node = sweep([p1], [q1], phi, progress=False)["W_hat"].values.ravel() * q1
        at = (
            f"{phi[int(np.argmax(node))] / PI:.3f}"
            if node.max() > 0
            else "W = 0 at every φ (shakedown)"
        )
        lines.append(
            f"| {p1:g} | {q1:g} | {out[0][0]:.3f} | "
            + (f"{out[1][0]:.3f}" if out[1][0] is not None else "no equilibrium")
            + f" | {at} | {out[0][1]:.4g} |"
        )
    lines.append("")


def hertz_map(lines, quick):
    grid = 11 if quick else 41
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "hertz.nc"
        cmd = [
            sys.executable,
            "-m",
            "lcpfric",
            "map",
            "--contact",
            "sphere",
            "--k-support-ratio",
            "1",
            "--P1",
            f"0:2:{grid}",
            "--Q1",
            f"0:2:{grid}",
            "--phi",
            "0:pi:11",
            "--out",
            str(out),
            "--no-progress",
            "--json",
        ]
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
        t = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True)
        wall = time.perf_counter() - t
        res = json.loads(p.stdout)
    lines += [
        "## The Hertz map (the goal: 11 phases on 41 x 41 in at most 5 minutes)",
        "",
        f"`{' '.join(['lcpfric'] + cmd[3:-4])} --out hertz.nc`: {res['points']} points "
        f"in {wall:.1f} s wall ({res['executor']}, {res['chunks_computed']} chunks; "
        f"200 springs, 200 steps per cycle), largest W_norm {res['W_normalized_max']:.4g} "
        f"at {res['at']}.",
        "",
    ]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-map", action="store_true")
    ap.add_argument("--out", default="benchmarks/results")
    args = ap.parse_args(argv)
    lines = [
        "# Continuum contacts: validations and goals",
        "",
        f"`OPENBLAS_NUM_THREADS=1 python benchmarks/validation/contact.py"
        f"{' --quick' if args.quick else ''}{' --no-map' if args.no_map else ''}`",
        "",
    ]
    t0 = time.perf_counter()
    for step in (
        lambda: mindlin(lines, args.quick),
        lambda: normal(lines),
        lambda: cattaneo(lines),
        lambda: phases(lines),
        lambda: chord(lines),
        lambda: convergence(lines, args.quick),
        lambda: small_amplitude(lines),
        lambda: question(lines, args.quick),
    ):
        n = len(lines)
        step()
        print("\n".join(lines[n:]), flush=True)
    if not args.no_map:
        n = len(lines)
        hertz_map(lines, args.quick)
        print("\n".join(lines[n:]), flush=True)
    lines.append(f"Whole run: {time.perf_counter() - t0:.0f} s.")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = "contact-quick.md" if args.quick else "contact.md"
    (out / name).write_text("\n".join(lines) + "\n")
    print(f"wrote {out / name}")


if __name__ == "__main__":
    main()
