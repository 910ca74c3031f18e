"""Quasi-static modal analysis of jointed structures (issue 39, item 4): the closed form, an
independent return map, and the time of the 100-DOF rod.

``OPENBLAS_NUM_THREADS=1 python benchmarks/validation/modal.py [--out DIR] [--figures DIR]``

writes ``DIR/modal.md`` (default ``benchmarks/results``) and ``modal_damping.png``/``.pdf`` into
the figures directory (default ``docs``); about 20 seconds.

1. One mass m on a spring k0 with one Jenkins element (kt, Fs): ω(a) and ζ(a) of
   :func:`lcpfric.analysis.modal.modal_damping` against the closed form
   (:func:`~lcpfric.analysis.modal.jenkins_oscillator`: ``ω² = (k0 + F_J(X)/X)/m``,
   ``F_J(X) = min(kt X, Fs)``, ``X = a/√m``, ``W = 4 Fs (X - Fs/kt)``), 200 amplitudes from 0.1
   to 1000 times the amplitude of the first slip, asked as amplitudes (α found by Brent's method)
   and as modal forces.
2. The rod (:func:`lcpfric.model.jointed.jointed_rod`: 100 masses 1/100 in a line, springs
   k = 100 between neighbours, the first mass tied to the ground by k; a lap joint of 5 Jenkins
   elements kt = 5 across the middle springs and a friction support of 5 elements kt = 1 from
   masses 20, 40, 60, 80, 100 to the ground; slip forces 0.002 to 0.2 geometrically; M and K
   sparse): a and W against an independent return map of the full structure
   (``tests/support/modal_reference.py``: no condensation, backward Euler of Jenkins' flow rule
   by alternating minimization, 200 steps per cycle, three cycles).
3. The rod's 50 amplitudes from 0.1 to 1000 times the first slip's, the first mode: the time,
   per amplitude, and where it goes (cProfile).
4. The figure: ω/ω0 and ζ of the oscillator (closed form marked) and of the rod.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "tests")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import cProfile  # noqa: E402
import pstats  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.analysis.modal import jenkins_oscillator, modal_damping  # noqa: E402
from lcpfric.model.jointed import jointed_rod  # noqa: E402
from lcpfric.model.structure import JointedStructure  # noqa: E402
from support.modal_reference import return_map_cycle  # noqa: E402

#: (m, k0, kt, mu, N) of the one-mass oscillators; the first is the figure's
OSCILLATORS = [
    (1.0, 1.0, 3.0, 0.5, 1.0),
    (2.5, 0.3, 4.0, 0.2, 3.0),
    (0.01, 200.0, 1e4, 0.7, 50.0),
    (1.0, 1e-3, 1.0, 1.0, 1.0),
]


def closed_form():
    print("## 1. One mass with a Jenkins element against the closed form\n")
    print("200 amplitudes from 0.1 to 1000 a_slip (a_slip = √m Fs/kt). Errors: max |Δω|/ω0, "
          "max |Δζ|, max |ΔW|/max W over the amplitudes.\n")  # fmt: skip
    print("| m | k0 | kt | Fs | asked as | max abs(Δω)/ω0 | max abs(Δζ) | max abs(ΔW)/W | "
          "exact solves | seconds |\n|---|---|---|---|---|---|---|---|---|---|")  # fmt: skip
    worst = 0.0
    for m, k0, kt, mu, N in OSCILLATORS:
        s = JointedStructure([[m]], [[k0]], [[0, -1]], kt, mu, N)
        a = np.sqrt(m) * mu * N / kt * np.geomspace(0.1, 1000.0, 200)
        omega, zeta, W, alpha = jenkins_oscillator(a, k0, kt, mu * N, m)
        for how, kwargs in (("a", dict(amplitude=a)), ("α_max", dict(force=alpha))):
            t0 = time.perf_counter()
            r = modal_damping(s, **kwargs)
            sec = time.perf_counter() - t0
            om, ze, WW, _ = jenkins_oscillator(r.a, k0, kt, mu * N, m)  # at the a reached
            e = (np.max(np.abs(r.omega - om)) / r.omega0, np.max(np.abs(r.zeta - ze)),
                 np.max(np.abs(r.W - WW)) / np.max(WW))  # fmt: skip
            worst = max(worst, e[0], e[1])
            print(f"| {m:g} | {k0:g} | {kt:g} | {mu * N:g} | {how} | {e[0]:.1e} | {e[1]:.1e} | "
                  f"{e[2]:.1e} | {r.stats['solves']} | {sec:.2f} |")  # fmt: skip
    print(f"\nLargest error in ω/ω0 or ζ: **{worst:.1e}** (goal 1e-9).\n")


def against_return_map(rod):
    print("## 2. The rod against an independent return map\n")
    print("| α_max | a/a_slip | a | rel. error of a | W | rel. error of W | reference s |")
    print("|---|---|---|---|---|---|---|")
    alphas = np.array([0.3, 0.45, 0.6, 1.0, 2.0, 10.0])
    r = modal_damping(rod, force=alphas, samples=8)
    dense = (rod.mass.toarray(), rod.stiffness.toarray())
    worst = 0.0
    for i, alpha in enumerate(alphas):
        t0 = time.perf_counter()
        ref = return_map_cycle(*dense, rod.contact_dofs, rod.contact_stiffness,
                               rod.friction * rod.normal_load, r.phi, alpha, steps=200,
                               cycles=3, tol=1e-14)  # fmt: skip
        ea = abs(ref["a"] / r.a[i] - 1)
        eW = abs(ref["W"] - r.W[i]) / max(r.W[i], 1e-300) if r.W[i] else abs(ref["W"])
        worst = max(worst, ea, eW)
        print(f"| {alpha:g} | {r.a[i] / r.a_slip:.3g} | {r.a[i]:.10g} | {ea:.1e} | "
              f"{r.W[i]:.10g} | {eW:.1e} | {time.perf_counter() - t0:.2f} |")  # fmt: skip
    print(f"\nLargest relative difference: **{worst:.1e}**.\n")


def rod_timing(rod):
    print("## 3. The rod: 50 amplitudes, first mode\n")
    probe = modal_damping(rod, [1.0])  # a_slip, and the compiled event loop loaded
    a = probe.a_slip * np.geomspace(0.1, 1000.0, 50)
    runs = []
    for _ in range(3):
        t0 = time.perf_counter()
        r = modal_damping(rod, a)
        runs.append(time.perf_counter() - t0)
    sec = min(runs)
    print(f"ω0 = {r.omega0:.10g}, a_slip = {r.a_slip:.6g}; {rod.n} degrees of freedom, "
          f"{rod.n_contacts} contacts (sparse M, K).\n")  # fmt: skip
    print(f"- total **{sec:.3f} s** for 50 amplitudes (best of 3; goal 30 s), "
          f"**{1e3 * sec / 50:.1f} ms per amplitude**")  # fmt: skip
    print(f"- condensation (mode, factorization of K, 11 solves): "
          f"{1e3 * r.stats['condense_seconds']:.1f} ms")  # fmt: skip
    stuck = int(np.count_nonzero(r.sticks))
    print(
        f"- {stuck} amplitudes below the first slip: no exact cycle (a = α c0); the other "
        f"{50 - stuck} took {r.stats['solves']} exact steady cycles (Brent's method: "
        f"{np.mean(r.evaluations[~r.sticks]):.1f} per amplitude), "
        f"{1e3 * r.stats['cycle_seconds'] / max(r.stats['solves'], 1):.2f} ms each"
    )
    print(f"- cycles run by the exact solver per steady cycle: {sorted(set(r.cycles.tolist()))}")
    t0 = time.perf_counter()
    f = modal_damping(rod, force=r.alpha_max)
    print(
        f"- the same 50 asked as modal forces (one cycle each): "
        f"{time.perf_counter() - t0:.3f} s; max abs(Δζ) = {np.max(np.abs(f.zeta - r.zeta)):.1e}\n"
    )
    prof = cProfile.Profile()
    prof.enable()
    modal_damping(rod, a)
    prof.disable()
    stats = pstats.Stats(prof)
    total = stats.total_tt
    rows = {}
    for (file, _, name), (_, _, _, cum, _) in stats.stats.items():
        key = f"{_Path(file).parent.name}/{_Path(file).name}:{name}"
        rows[key] = cum
    print(f"Where the time goes (cProfile, cumulative share of {total:.3f} s under the "
          f"profiler):\n")  # fmt: skip
    print("| function | seconds | share |\n|---|---|---|")
    wanted = ("analysis/modal.py:modal_damping", "analysis/modal.py:_search",
              "periodic/driver.py:steady_state", "exact/discrete.py:exact_system_cycle",
              "exact/events.py:cycle", "sliders.py:contact_system", "model/system.py:__post_init__",
              "model/structure.py:condense", "model/structure.py:mode")  # fmt: skip
    for key in wanted:
        match = [v for k, v in rows.items() if k.endswith(key)]
        if match:
            print(f"| `{key}` | {max(match):.3f} | {max(match) / total:.0%} |")
    print()
    print("| a/a_slip | ω/ω0 | ζ | W | sticks |\n|---|---|---|---|---|")
    for i in range(0, 50, 5):
        print(f"| {r.a[i] / r.a_slip:.3g} | {r.omega_ratio[i]:.8f} | {r.zeta[i]:.6g} | "
              f"{r.W[i]:.6g} | {bool(r.sticks[i])} |")  # fmt: skip
    print()
    return r


def figure(rod_result, out_dir: _Path):
    from lcpfric.figures.modal import figure_modal_damping
    from lcpfric.figures.style import save

    m, k0, kt, mu, N = OSCILLATORS[0]
    s = JointedStructure([[m]], [[k0]], [[0, -1]], kt, mu, N)
    slip = np.sqrt(m) * mu * N / kt
    osc = modal_damping(s, slip * np.geomspace(0.1, 1000.0, 25))
    x = np.geomspace(0.1, 1000.0, 400)
    omega, zeta, _, _ = jenkins_oscillator(slip * x, k0, kt, mu * N, m)
    fig = figure_modal_damping(
        [("one mass", osc), ("100-DOF rod", rod_result)],
        closed_form=(x, omega / osc.omega0, zeta),
    )
    paths = save(fig, out_dir, "modal_damping", ("png", "pdf"))
    print("## 4. The figure\n")
    print(f"The oscillator m = {m:g}, k0 = {k0:g}, kt = {kt:g}, Fs = {mu * N:g} (closed form "
          f"and 25 computed amplitudes) and the rod of section 3; wrote "
          f"{', '.join(p.name for p in paths)}.\n")  # fmt: skip


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(_ROOT / "benchmarks" / "results"))
    p.add_argument("--figures", default=str(_ROOT / "docs"))
    args = p.parse_args(argv)
    out = _Path(args.out) / "modal.md"
    t0 = time.perf_counter()
    with results_file(out, "Quasi-static modal analysis", "validation/modal.py", markdown=True):
        rod = jointed_rod()
        closed_form()
        against_return_map(rod)
        r = rod_timing(rod)
        figure(r, _Path(args.figures))
        print(f"Whole script: {time.perf_counter() - t0:.1f} s.")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
