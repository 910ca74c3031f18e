"""The 3-D half-space contact: every validation and goal of issue 13, measured in one run.

``OPENBLAS_NUM_THREADS=1 python benchmarks/perf/halfspace.py [--quick] [--no-heightmap]
[--out DIR]``

writes ``DIR/halfspace.md`` (default ``benchmarks/results``). Each validation gives the value,
the closed form (or the MDR model) it is judged against, their relative difference, and the
grid and steps used. Timings are wall seconds of ``lcpfric.steady_state`` on this machine, and
CPU seconds of this process beside them (the machine is shared: other work may run on the
second core). The floor of a product is one pure FFT pair on the padded grid (scipy.fft,
preallocated input), timed here in the same run beside one of the solvers' products; the wall
time is split into the time in the products and outside them.

``--goals`` runs only the timing goals (the full run's grid and steps, 3 runs each) and prints
them without writing a file; ``--heightmap-512`` only the 512 x 512 height map's goal (issue
37: a steady state in at most 5 minutes under 6 GB; wall and CPU seconds and the peak resident
memory), printed.

Materials and loads: two identical bodies, E = 200e3, R = 10, μ = 0.5, P0 = 100; ν = 0 where
the classical forms are exact, ν = 0.3 with d = 2 for Cerruti's coupling. The height map
(``--no-heightmap`` skips it, about 5 minutes) is a sphere with a self-affine roughness on a
256 x 256 grid (``rough_sphere``), seeded, so the run repeats.
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
import math
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import lcpfric
from lcpfric.model import Harmonic
from lcpfric.model.continuum import (
    MDRSphere,
    cattaneo_stick_ratio,
    hertz_contact,
    mindlin_deresiewicz_W,
)
from lcpfric.model.continuum.halfspace import HalfSpace
from lcpfric.steppers.newton_cg import NewtonCGStepper

from _report import Report, stamp

E, R, MU, P0 = 200e3, 10.0, 0.5, 100.0
PI = math.pi
#: timings of the d = 1 / d = 2 goal: the best of this many runs each
REPEATS = 5


def sphere(P1=0.0, Q1=0.5, phi=0.0, nu=0.0, **kw):
    return HalfSpace.sphere(
        R,
        E,
        nu,
        MU,
        Harmonic(P0, P1 * P0, 0.0, 2 * PI),
        Harmonic(0.0, Q1 * MU * P0, phi, 2 * PI),
        **kw,
    )


def mdr(P1=0.0, Q1=0.5, phi=0.0, nu=0.0, nodes=2000):
    return MDRSphere(
        R,
        E,
        nu,
        MU,
        Harmonic(P0, P1 * P0, 0.0, 2 * PI),
        Harmonic(0.0, Q1 * MU * P0, phi, 2 * PI),
        nodes=nodes,
    )


def timed(model, steps, **kw):
    """``lcpfric.steady_state(model, steps_per_cycle=steps, **kw)`` (``kw``: the driver's
    options and the ``newton-cg`` stepper's): ``(result, wall, CPU seconds)``."""
    w, c = time.perf_counter(), time.process_time()
    r = lcpfric.steady_state(model, steps_per_cycle=steps, **kw)
    return r, time.perf_counter() - w, time.process_time() - c


def rel(a, b):
    return (a - b) / b


def fft_floors(*models, repeats=100, batches=7):
    """Per model, ``(floor, product)`` in seconds: the floor is one pure FFT pair on its padded
    M x M grid by scipy.fft, on a preallocated input (``rfftn`` + ``irfftn`` for d = 1, the
    complex ``fftn`` + ``ifftn`` for d = 2, whose one complex pair carries both components);
    the product is one of the solvers' products (``Convolution.padded``: the pruned pair with
    its spectral multiplication and its arrays). Each the best of ``batches`` batches of
    ``repeats``, the models' batches interleaved (the machine is shared: one long batch caught
    other work in one run, 170 µs against 123)."""
    import scipy.fft as sfft

    cases = []
    for m in models:
        M = m.op.M
        x = m.op.empty()
        rng = np.random.default_rng(0)
        x.real[: m.N, : m.N] = rng.standard_normal((m.N, m.N))
        if m.dims == 1:

            def pair(x=x, M=M):
                sfft.irfftn(sfft.rfftn(x), s=(M, M))

        else:
            x.imag[: m.N, : m.N] = rng.standard_normal((m.N, m.N))

            def pair(x=x):
                sfft.ifftn(sfft.fftn(x))

        cases.append((pair, lambda m=m, x=x: m.op.padded("tangential", x, 1.0 / m.h**2)))
    best = [[math.inf, math.inf] for _ in models]
    for _ in range(batches):
        for i, fs in enumerate(cases):
            for k, f in enumerate(fs):
                f()
                t = time.perf_counter()
                for _ in range(repeats):
                    f()
                best[i][k] = min(best[i][k], (time.perf_counter() - t) / repeats)
    return [tuple(b) for b in best]


def split(st, seconds):
    """The solver statistics ``st`` of a result (``solver_stats``) in words."""
    per = st["tangential_products"] / max(st["increments"], 1)
    return (
        f"normal {st['normal_seconds']:.2f} s ({st['normal_solves']} solves, "
        f"{st['normal_products']} products), tangential {st['tangential_seconds']:.2f} s "
        f"({st['increments']} increments, {per:.1f} products and "
        f"{st['newton'] / max(st['increments'], 1):.2f} Newton steps per increment); "
        f"wall {seconds:.2f} s"
    )


def rough_sphere(N=256, seed=13, hurst=0.8, rms=None):
    """A sphere (R) on an N x N grid of side 2.4 a(P_max), plus a self-affine roughness (Hurst
    exponent ``hurst``, wavelengths from the grid's side / 4 to 4 elements, rms 0.1 of the
    Hertz approach at P0 by default) faded out between 0.9 and 1.1 a(P_max) so the contact
    stays inside the grid: ``(heights, spacing)``."""
    a_max = hertz_contact(1.5 * P0, R, E, 0.0)["a"]
    h = 2.4 * a_max / N
    g = (np.arange(N) - (N - 1) / 2) * h
    base = (g[:, None] ** 2 + g[None, :] ** 2) / (2 * R)
    rng = np.random.default_rng(seed)
    kx = np.fft.fftfreq(N, h)
    k = np.hypot(kx[:, None], kx[None, :])
    lo, hi = 4.0 / (N * h), 1.0 / (4 * h)
    amp = np.where((k >= lo) & (k <= hi), np.maximum(k, lo) ** (-1 - hurst), 0.0)
    noise = np.fft.ifft2(amp * np.exp(2j * PI * rng.random((N, N)))).real
    d0 = hertz_contact(P0, R, E, 0.0)["d"]
    noise *= (0.1 * d0 if rms is None else rms) / noise.std()
    r = np.hypot(g[:, None], g[None, :]) / a_max
    fade = np.clip((1.1 - r) / 0.2, 0.0, 1.0)
    return base + noise * np.sin(0.5 * PI * fade) ** 2, h


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser grids, fewer steps")
    ap.add_argument("--no-heightmap", action="store_true", help="skip the 256 x 256 height map")
    ap.add_argument("--heightmap-only", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--size", type=int, default=None, help=argparse.SUPPRESS)
    ap.add_argument(
        "--heightmap-512",
        action="store_true",
        help="only the 512 x 512 height map's goal (in a child process), printed",
    )
    ap.add_argument(
        "--goals", action="store_true", help="only the d = 1 / d = 2 timing goals, printed"
    )
    ap.add_argument(
        "--readme-figure",
        action="store_true",
        help="only draw docs/halfspace_zones.png (a 128 x 128 rough sphere, by "
        "the command users run)",
    )
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "results"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(exist_ok=True)
    if args.heightmap_only:
        return heightmap(args.quick, args.size)
    if args.heightmap_512:
        proc = subprocess.run(
            [sys.executable, __file__, "--heightmap-only", "--size", "512"],
            capture_output=True,
            text=True,
        )
        if proc.returncode != 0:
            raise SystemExit(proc.stderr)
        print(proc.stdout.strip())
        return None
    if args.readme_figure:
        return readme_figure()
    lines = Report(
        [
            "# The 3-D half-space contact (issue 13)",
            "",
            f"{stamp('perf/halfspace.py' + (' --quick' if args.quick else ''))}. "
            f"E = {E:g}, R = {R:g}, μ = {MU}, P0 = {P0:g}.",
            "",
        ]
    )
    emit = lines.emit

    grid = 24 if args.quick and not args.goals else 40
    steps = 100 if args.quick and not args.goals else 400

    if args.goals:
        return goals(lines, grid, steps)
    # -- Hertz ---------------------------------------------------------------------------------
    emit("## Hertz: the normal problem")
    emit("")
    emit("| grid | elements in contact | radius (of the area) / a | p_max / p0 | h² Σp / P |")
    emit("|---|---|---|---|---|")
    hz = hertz_contact(P0, R, E, 0.0)
    for g in (20, 40, 80):
        m = sphere(grid=g, Q1=0.0)
        p = m.pressure(P0)
        a = math.sqrt(np.count_nonzero(p) * m.h**2 / math.pi)
        emit(
            f"| {g} | {np.count_nonzero(p)} | {a / hz['a']:.5f} | {p.max() / hz['p0']:.5f} | "
            f"{m.h**2 * p.sum() / P0:.15f} |"
        )
    emit("")

    # -- Cattaneo -------------------------------------------------------------------------------
    emit("## Cattaneo: the stick radius, Q rising from 0 at constant P")
    emit("")
    m = HalfSpace.sphere(R, E, 0.0, MU, P0, Harmonic(0.0, 0.95 * MU * P0, 0.0, 2 * PI), grid=grid)
    b = m.normal_solution(np.zeros(1))[0][0]
    a = math.sqrt(np.count_nonzero(b) * m.h**2 / math.pi)
    n_inc = 200
    t = np.linspace(0.0, 0.25, n_inc + 1)
    # the increments by hand: the newton-cg stepper's context for the model's scene (its
    # tolerance scale is the loads', whatever the scene's steps)
    stepper = NewtonCGStepper()
    scene = lcpfric.make_scene(m, 4)
    ctx = stepper.context(scene)
    state = stepper.start(scene, ctx)
    emit(
        f"grid {grid} ({np.count_nonzero(b)} elements in contact), {n_inc} increments to "
        f"Q = 0.95 μP; radii of the stick zone's and the contact's areas; h/a = {m.h / a:.3f}"
    )
    emit("")
    emit("| Q/(μP) | c/a | (1 − x)^(1/3) | difference / (h/a) |")
    emit("|---|---|---|---|")
    for j in range(1, n_inc + 1):
        Q = float(m.Q(t[j]))
        state, F, dv = stepper.increment(ctx, state, b, Q)
        x = Q / (MU * P0)
        if j % 25 == 0 or j == n_inc:
            c = math.sqrt(np.count_nonzero((b > 0) & (dv == 0.0)) * m.h**2 / math.pi)
            ref = cattaneo_stick_ratio(x)
            emit(f"| {x:.3f} | {c / a:.4f} | {ref:.4f} | {(c / a - ref) / (m.h / a):+.2f} |")
    emit("")

    md_section(lines, args.quick, grid, steps)

    # -- against the MDR model, varying P -------------------------------------------------------
    emit("## Against the axisymmetric (MDR) model, varying P with a phase")
    emit("")
    cases = [(0.5, 0.4, 0.5 * PI), (0.3, 0.6, 0.7 * PI)]
    grids = (16, 24, 32) if args.quick else (16, 24, 32, 48, 64)
    st = 100 if args.quick else 200
    emit(f"ν = 0, d = 1, {st} steps per cycle for both; MDR with 2000 springs.")
    emit("")
    emit(
        "| P1/P0 | Q1/(μP0) | φ/π | MDR W k_t0/(μ²P0²) | "
        + " | ".join(f"grid {g}" for g in grids)
        + " | order |"
    )
    emit("|---" * (5 + len(grids)) + "|")
    for P1, Q1, phi in cases:
        ref = lcpfric.steady_state(mdr(P1, Q1, phi), steps_per_cycle=st).W_normalized
        diffs = []
        for g in grids:
            r = lcpfric.steady_state(sphere(P1, Q1, phi, grid=g), steps_per_cycle=st)
            diffs.append(rel(r.W_normalized, ref))
        hs = np.array([1.0 / g for g in grids])
        order = np.polyfit(np.log(hs), np.log(np.abs(diffs)), 1)[0]
        emit(
            f"| {P1} | {Q1} | {phi / PI:.2f} | {ref:.6f} | "
            + " | ".join(f"{d:+.2e}" for d in diffs)
            + f" | {order:.2f} |"
        )
    emit("")
    emit("Order: the least-squares slope of log|difference| against log(1/grid).")
    emit("")
    P1, Q1, phi = cases[0]
    g = 24 if args.quick else 40
    ref3 = lcpfric.steady_state(mdr(P1, Q1, phi, nu=0.3), steps_per_cycle=st).W_normalized
    r3, w3, _ = timed(
        sphere(P1, Q1, phi, nu=0.3, dims=2, grid=g), st, max_cycles=80, on_nonconvergence="ignore"
    )
    r4 = lcpfric.steady_state(sphere(P1, Q1, phi, nu=0.3, dims=1, grid=g), steps_per_cycle=st)
    emit(
        f"ν = 0.3, P1/P0 = {P1}, Q1/(μP0) = {Q1}, φ = {phi / PI:.2f}π, grid {g}: d = 2 "
        f"(Cerruti's coupling) {r3.W_normalized:.6f}, d = 1 (Mindlin's approximation) "
        f"{r4.W_normalized:.6f}, MDR {ref3:.6f}: d = 2 differs from MDR by "
        f"{rel(r3.W_normalized, ref3):+.2e} and from d = 1 on the same grid by "
        f"{rel(r3.W_normalized, r4.W_normalized):+.2e} (the physical effect of the transverse "
        f"tractions). d = 2 after {r3.cycles} cycles ({w3:.1f} s): relative change of the "
        f"cycle {r3.change:.1e} (converged: {r3.converged}); W of its last cycles: "
        f"{', '.join(f'{w:.9f}' for w in r3.W_cycles[-3:] * r3.W_normalized / r3.W)}."
    )
    emit("")

    # -- the maps' cycle tolerance with d = 2 ---------------------------------------------------
    emit("## The maps' cycle tolerance with d = 2")
    emit("")
    emit(
        "ν = 0.3, d = 2, grid 20, 100 steps (the maps' defaults): cycles and seconds to each "
        "cycle tolerance, and W's difference from its value at 1e-10."
    )
    emit("")
    emit("| P1/P0 | Q1/(μP0) | φ/π | tol 1e-6 | tol 1e-8 | tol 1e-10 |")
    emit("|---|---|---|---|---|---|")
    for P1, Q1, phi in ((0.5, 0.4, 0.5 * PI), (0.3, 0.6, 0.7 * PI), (0.8, 0.2, 0.2 * PI)):
        runs = [
            timed(sphere(P1, Q1, phi, nu=0.3, dims=2, grid=20), 100, tol=tol)
            for tol in (1e-6, 1e-8, 1e-10)
        ]
        ref = runs[-1][0].W
        emit(
            f"| {P1} | {Q1} | {phi / PI:.2f} | "
            + " | ".join(f"{r.cycles} cycles, {w:.1f} s, {rel(r.W, ref):+.1e}" for r, w, _ in runs)
            + " |"
        )
    emit("")

    # -- the same contact as an lcpfric system, solved by the backends --------------------------
    emit("## The same contact as an lcpfric ContactSystem, solved by the backends")
    emit("")
    from lcpfric.scene import make_scene

    # d = 2 at constant P, to the cycle tolerance 1e-10 (the increments' own accuracy)
    for g, dims, nu, P1, methods in (
        (24 if args.quick else 36, 1, 0.0, 0.5, ("active-set",)),
        (10, 2, 0.3, 0.0, ("clarabel",)),
    ):
        m = sphere(P1, 0.6, 0.7 * PI, nu=nu, grid=g, dims=dims, k_support=1.0)
        m = m.with_support(m.k_t0)
        scene = make_scene(m.system(), 200)
        w = time.perf_counter()
        tol = 1e-12 if dims == 1 else 1e-10  # d = 2: the increments' own accuracy
        ref = lcpfric.steady_state(lcpfric.make_scene(m, grid=scene.t), tol=tol)
        w_model = time.perf_counter() - w
        for method in methods:
            opts = {"check_tol": 1e-4} if dims == 2 else {}
            w = time.perf_counter()
            r = lcpfric.steady_state(scene, method, tol=tol, locate_events=False, **opts)
            emit(
                f"grid {g} ({m.nodes} nodes), d = {dims}, ν = {nu}, P1/P0 = {P1}, Q1/(μP0) = "
                f"0.6, φ = 0.7π, support k_t0, the "
                f"scene's {scene.t.size - 1} steps: the model {ref.W:.12g} in {w_model:.2f} "
                f"s, {method} {r.W:.12g} ({rel(r.W, ref.W):+.1e}) in "
                f"{time.perf_counter() - w:.2f} s."
            )
    emit("")

    # -- properties ------------------------------------------------------------------------------
    emit("## In phase, and W(φ + π) = W(φ)")
    emit("")
    g = 24 if args.quick else 32
    for s in (100, 200) if args.quick else (100, 200, 400):
        w0 = lcpfric.steady_state(sphere(0.5, 0.4, 0.0, grid=g), steps_per_cycle=s).W_normalized
        emit(f"In phase, P1/P0 = 0.5, Q1/(μP0) = 0.4, grid {g}, {s} steps: W_norm = {w0:.3e}")
    wa = lcpfric.steady_state(sphere(0.5, 0.4, 0.5 * PI, grid=g), steps_per_cycle=200).W_normalized
    wb = lcpfric.steady_state(sphere(0.5, 0.4, 1.5 * PI, grid=g), steps_per_cycle=200).W_normalized
    emit(f"φ = 0.5π: {wa:.10f}; φ = 1.5π: {wb:.10f} (relative difference {rel(wb, wa):+.1e}).")
    emit("")

    if not args.no_heightmap:
        proc = subprocess.run(
            [sys.executable, __file__, "--heightmap-only"] + (["--quick"] if args.quick else []),
            capture_output=True,
            text=True,
        )
        if proc.returncode != 0:
            raise SystemExit(proc.stderr)
        emit(proc.stdout.strip())
        emit("")
    path = out / ("halfspace-quick.md" if args.quick else "halfspace.md")
    lines.write(path)
    print(f"wrote {path}")


def goals(lines, grid, steps):
    """``--goals``: the timing goals alone (printed as they are emitted)."""
    md_section(lines, False, grid, steps, short=True, reps=3)


def md_section(lines, quick, grid, steps, short=False, reps=None):
    """Mindlin-Deresiewicz at constant P and the d = 1 / d = 2 timing goals (``short``: without
    the runs that turn the stepper's options off)."""
    emit = lines.emit
    # -- Mindlin-Deresiewicz and the d = 1 / d = 2 goal -----------------------------------------
    emit("## Mindlin-Deresiewicz at constant P, and the timing goals")
    emit("")
    hz = hertz_contact(P0, R, E, 0.0)
    k_t0 = hz["k_t0"]
    md = mindlin_deresiewicz_W(P0, 0.5 * MU * P0, MU, k_t0)
    # the machine is shared: each timing is the best of REPEATS runs, d = 1 and d = 2
    # interleaved, so a slow spell hits both alike (every run's time is listed)
    reps = reps or (1 if quick else REPEATS)
    runs = {}
    for _ in range(reps):
        for key, nu, dims, kw in (
            ("d1", 0.0, 1, {}),
            ("d2", 0.3, 2, {}),
            ("d2_1e-6", 0.3, 2, {"tol": 1e-6}),
            ("d1_two", 0.0, 1, {"max_cycles": 2, "on_nonconvergence": "ignore"}),
            ("d2_two", 0.3, 2, {"max_cycles": 2, "on_nonconvergence": "ignore"}),
        ):
            m = sphere(Q1=0.5, grid=grid, nu=nu, dims=dims)
            r, w, c = timed(m, steps, **kw)
            runs.setdefault(key, []).append((w, c, r, m))

    def best(key):
        return min(runs[key], key=lambda x: x[0])

    def walls(key):
        return ", ".join(f"{x[0]:.2f}" for x in runs[key])

    w1, c1, r1, m1 = best("d1")
    w2, c2, r2, m2 = best("d2")
    (floor, prod), (floor2, prod2) = fft_floors(m1, m2)
    emit(
        f"x = Q*/(μP) = 0.5, ν = 0, d = 1, grid {grid} ({m1.contact_max} elements in the "
        f"contact, {m1.N} x {m1.N} grid), {steps} steps: W = {r1.W:.8g} against "
        f"{md:.8g} ({rel(r1.W, md):+.2e}), {r1.cycles} cycles, {w1:.2f} s wall "
        f"({c1:.2f} s CPU; the best of {reps} run{'s' if reps > 1 else ''}: "
        f"{walls('d1')} s). {split(r1.solver_stats, w1)}."
    )
    per_step = w1 / r1.solver_stats["increments"]
    emit(
        f"Per increment {per_step * 1e3:.2f} ms = {per_step / floor:.1f} FFT pairs "
        f"(the floor: one pure pair, rfftn + irfftn, {floor * 1e6:.0f} µs on the "
        f"{m1.op.M} x {m1.op.M} padded grid; d = 2's complex fftn + ifftn "
        f"{floor2 * 1e6:.0f} µs). One of the solvers' products (the pruned pair with its "
        f"spectral multiplication): {prod * 1e6:.0f} µs for d = 1 ({prod / floor:.2f}x the "
        f"floor), {prod2 * 1e6:.0f} µs for d = 2 ({prod2 / floor2:.2f}x)."
    )
    emit("")
    md3 = mindlin_deresiewicz_W(P0, 0.5 * MU * P0, MU, hertz_contact(P0, R, E, 0.3)["k_t0"])
    emit(
        f"ν = 0.3, d = 2, same grid and steps: W = {r2.W:.8g} against Mindlin-Deresiewicz "
        f"(Mindlin's approximation) {md3:.8g} ({rel(r2.W, md3):+.2e}), {r2.cycles} cycles "
        f"({r2.solver_stats.get('extrapolations', 0)} moved starts), {w2:.2f} s wall "
        f"({c2:.2f} s CPU; runs: {walls('d2')} s). {split(r2.solver_stats, w2)}."
    )
    w2b, _, r2b, _ = best("d2_1e-6")
    emit(
        f"With the cycle tolerance 1e-6 instead of 1e-10: {r2b.cycles} cycles, {w2b:.2f} s "
        f"wall (runs: {walls('d2_1e-6')} s; {w2b / w1:.2f}x d = 1's time at 1e-10), W "
        f"{rel(r2b.W, r2.W):+.1e} from the converged one."
    )
    # the same work for both: the virgin cycle and one more
    two = [best("d1_two")[0], best("d2_two")[0]]
    emit(
        f"The first two cycles alone (the same work for both): d = 1 {two[0]:.2f} s, d = 2 "
        f"{two[1]:.2f} s ({two[1] / two[0]:.2f}x; runs: {walls('d1_two')} and "
        f"{walls('d2_two')} s); d = 2's other {r2.cycles - 2} cycles take "
        f"{w2 - two[1]:.2f} s. The third cycle's W is {rel(r2.W_cycles[2], r2.W):+.1e} from "
        f"the converged one."
    )
    p1, p2 = r1.solver_stats["tangential_products"], r2.solver_stats["tangential_products"]
    emit(
        f"Ratio d = 2 / d = 1: {w2 / w1:.2f} in all (CPU {c2 / c1:.2f}); an FFT pair costs "
        f"{floor2 / floor:.2f} times d = 1's; tangential FFT products {p2} against {p1} "
        f"({p2 / p1:.2f}x)."
    )
    # the wall time split into the FFT products (their count times one product's time above)
    # and the rest (the solvers' own work, the normal problem, the driver)
    f1, f2 = p1 * prod, p2 * prod2
    emit(
        f"Split: the FFT products take about {f1:.2f} s of d = 1's {w1:.2f} s and {f2:.2f} s "
        f"of d = 2's {w2:.2f} s ({f2 / f1:.2f}x), the rest {w1 - f1:.2f} and {w2 - f2:.2f} s "
        f"({(w2 - f2) / (w1 - f1):.2f}x): outside / inside the products "
        f"{(w1 - f1) / f1:.2f} for d = 1 and {(w2 - f2) / f2:.2f} for d = 2. At the floor "
        f"(the products' count times one pure pair) the pairs would take {p1 * floor:.2f} "
        f"and {p2 * floor2:.2f} s: the wall time is {w1 / (p1 * floor):.2f}x and "
        f"{w2 / (p2 * floor2):.2f}x that."
    )
    if not quick and not short:
        # the newton-cg stepper's options that turn each off
        for what, option in (
            ("per-node memory of the cycles' starts (Anderson alone)", "slip_memory"),
            ("moved starts of the cycles (neither the memory nor Anderson)", "accelerate"),
            ("previous cycle's increments as starts", "warm_start"),
        ):
            m = sphere(Q1=0.5, grid=grid, nu=0.3, dims=2)
            r, w, _ = timed(m, steps, max_cycles=80, on_nonconvergence="ignore", **{option: False})
            st = r.solver_stats
            emit(
                f"d = 2 without the {what}: {r.cycles} cycles, {w:.2f} s wall "
                f"({w / w2:.2f}x), {st['tangential_products'] / st['increments']:.1f} "
                f"products per increment, W {rel(r.W, r2.W):+.1e} from the default one "
                f"(converged: {r.converged})."
            )
        # a finer grid settles more slowly still
        m = sphere(Q1=0.5, grid=56, nu=0.3, dims=2)
        r, w, _ = timed(m, 200, max_cycles=200, on_nonconvergence="ignore")
        emit(
            f"d = 2 on grid 56 ({m.contact_max} elements in the contact), 200 steps: "
            f"{r.cycles} cycles, {w:.1f} s wall, relative change {r.change:.1e} (converged: "
            f"{r.converged})."
        )
    emit("")
    emit(
        f"Goals: d = 1 within 1 % of Mindlin-Deresiewicz in at most 30 s (aim 5 s): "
        f"{abs(rel(r1.W, md)) * 100:.2f} % in {w1:.2f} s with {m1.contact_max} nodes in the "
        f"contact. d = 2 (ν = 0.3) at most 3x d = 1: {w2 / w1:.2f}x in all, "
        f"{two[1] / two[0]:.2f}x over the first two cycles, {w2b / w1:.2f}x to the cycle "
        f"tolerance 1e-6."
    )
    emit("")


def peak_memory_mb() -> float:
    """This process's peak resident memory in MB: VmHWM, which starts afresh at exec (ru_maxrss
    keeps the parent's peak across fork and exec, and this runs in a child of the main run)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def heightmap(quick: bool, size: int | None = None):
    """The 256 x 256 height map's steady state, or the ``size`` x ``size`` one (in its own
    process, for its peak memory)."""
    N = size or (64 if quick else 256)
    steps = 100
    heights, h = rough_sphere(N)
    start, cpu = time.perf_counter(), time.process_time()
    m = HalfSpace(
        E,
        0.0,
        MU,
        Harmonic(P0, 0.5 * P0),
        Harmonic(0.0, 0.4 * MU * P0, 0.5 * PI),
        heights=heights,
        spacing=h,
    )
    # the cycle's ends only (history=False): the peak memory is the solve's, not the record's
    r = lcpfric.steady_state(m, steps_per_cycle=steps, history=False)
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    peak = peak_memory_mb()
    print(f"## A {N} x {N} height map\n")
    print(
        f"A sphere with a self-affine roughness (Hurst 0.8, rms 0.1 of the Hertz approach at "
        f"P0; `rough_sphere`), ν = 0, d = 1, P1/P0 = 0.5, Q1/(μP0) = 0.4, φ = 0.5π, {steps} "
        f"steps per cycle: W = {r.W:.8g} (W_norm {r.W_normalized:.6f}, k_t0 from the "
        f"contact's area at P0), {r.cycles} cycles, converged {r.converged}; at most "
        f"{r.contact.nodes_in_contact_max} elements in contact. Steady state in {wall:.1f} s "
        f"wall ({cpu:.1f} s CPU; setup included), peak resident memory {peak:.0f} MB. "
        f"{split(r.solver_stats, wall)}."
    )
    if size is not None:  # --heightmap-512 (or --size): the floor and the goal
        st = r.solver_stats
        count = st["normal_products"] + st["tangential_products"]
        floor, product = heightmap_floor(m)
        print(
            f"\nThe floor: {count} FFT products ({st['normal_products']} normal, "
            f"{st['tangential_products']} tangential; {count / st['increments']:.1f} per step), "
            f"one pure pair (rfftn + irfftn) {floor * 1e3:.1f} ms on the {m.op.M} x {m.op.M} "
            f"padded grid, one of the solvers' (pruned) products {product * 1e3:.1f} ms: the "
            f"products take about {count * product:.0f} s, {count * floor:.0f} s at one pure "
            f"pair each; the rest {wall - count * product:.0f} s."
        )
        print(
            f"\nGoal (issue 37, 512 x 512): a steady state in at most 5 minutes under 6 GB: "
            f"{N} x {N}: {wall:.1f} s "
            f"wall ({wall / 60:.2f} min), {cpu:.1f} s CPU, peak {peak / 1024:.2f} GB."
        )
        return
    print(
        f"\nGoal: a steady state in at most 10 minutes under 4 GB: {wall / 60:.1f} min, "
        f"{peak / 1024:.2f} GB."
    )


def heightmap_floor(m, repeats=5):
    """``(floor, product)`` in seconds on a height map's padded grid: one pure real FFT pair
    (``rfftn`` + ``irfftn``, scipy.fft, preallocated input) and one of the solvers' pruned
    products (``Convolution.padded``), each the best of ``repeats``."""
    import scipy.fft as sfft

    M, N = m.op.M, m.N
    x = m.op.empty()
    x[:N, :N] = np.random.default_rng(0).standard_normal((N, N))
    best = []
    for f in (
        lambda: sfft.irfftn(sfft.rfftn(x), s=(M, M)),
        lambda: m.op.padded("tangential", x, 1.0),
    ):
        f()
        times = []
        for _ in range(repeats):
            t = time.perf_counter()
            f()
            times.append(time.perf_counter() - t)
        best.append(min(times))
    return tuple(best)


def readme_figure():
    """docs/halfspace_zones.png: ``lcpfric contact --heightmap`` on a 128 x 128 rough sphere."""
    import shutil
    import tempfile

    heights, h = rough_sphere(128)
    docs = Path(__file__).resolve().parents[2] / "docs"
    with tempfile.TemporaryDirectory() as tmp:
        np.save(Path(tmp) / "rough128.npy", heights)
        cmd = [
            "lcpfric",
            "contact",
            "--heightmap",
            "rough128.npy",
            "--spacing",
            repr(h),
            "--E",
            f"{E:g}",
            "--nu",
            "0",
            "--mu",
            str(MU),
            "--P0",
            f"{P0:g}",
            "--P1",
            f"{0.5 * P0:g}",
            "--Q1",
            f"{0.4 * MU * P0:g}",
            "--phi",
            "0.5pi",
            "--steps",
            "100",
            "--figures",
            "figs",
        ]
        print(" ".join(cmd))
        subprocess.run(cmd, cwd=tmp, check=True)
        shutil.copy(Path(tmp) / "figs" / "halfspace-zones.png", docs / "halfspace_zones.png")
    print(f"wrote {docs / 'halfspace_zones.png'}")


if __name__ == "__main__":
    main()
