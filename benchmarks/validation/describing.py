"""Describing functions of the Jenkins element (issue 39, items 1 and 3): the measured errors
against the notes' closed forms, the agreement of the two exact paths with a varying normal
load, the fine-sample return map's convergence to them, the time per amplitude, and the figure.

``OPENBLAS_NUM_THREADS=1 python benchmarks/validation/describing.py [--out DIR] [--figures DIR]``

writes ``DIR/describing.md`` (default ``benchmarks/results``) and ``describing_functions.png`` /
``.pdf`` into the figures directory (default ``docs``); about 30 seconds.

1. Constant N: k_eq, ω c_eq and W of ``describing_functions`` (the exact single node, and the
   event solver) against the closed forms evaluated in 50 digits by mpmath (the double inputs
   taken as exact), 200 amplitudes log-spaced over 0.5 to 1000 slip limits μN/kt, three
   elements; and the shakedown below the slip limit.
2. Varying normal load ``N0 + N1 cos(ωt + φ)``: the exact single node against the event solver
   (independent event logic: companion-matrix roots of trigonometric polynomials), W and the
   first harmonics, 200 amplitudes from 0.3 to 1000 slip limits, with and without separation.
3. The fine-sample return map (tests/support/jenkins_reference.py; shares nothing with either
   exact path) against them: errors and the fitted order, for a varying normal load and for a
   three-harmonic motion with a two-harmonic normal load.
4. Time per amplitude.
5. The figure (the Jenkins element).
6. The Hertz sphere (MDR springs) under a prescribed displacement: W against Mindlin-Deresiewicz
   at the force amplitude reached, 100 amplitudes from 0.01 to 0.99 of the gross-slip
   displacement, against the number of springs; with a varying normal load, the march's
   convergence in the samples; its figure ``describing_sphere.png`` / ``.pdf``.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "tests")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import mpmath as mp  # noqa: E402
import numpy as np  # noqa: E402

from lcpfric.analysis.describing import describing_functions, jenkins_closed_form  # noqa: E402
from lcpfric.exact.driven import driven_cycle  # noqa: E402
from lcpfric.exact.jenkins_node import jenkins_cycle  # noqa: E402
from lcpfric.model import Fourier  # noqa: E402
from lcpfric.model.jenkins import JenkinsElement  # noqa: E402
from support.jenkins_reference import return_map_cycle  # noqa: E402

ELEMENTS = [(1.0, 1.0, 1.0), (2.3, 0.37, 5.1), (1e3, 0.2, 7.0)]
VARYING = [
    (1.0, 0.6, 1.0, 0.5, 0.0),
    (1.0, 0.6, 1.0, 0.8, 0.5 * math.pi),
    (1.0, 0.6, 1.0, 0.99, 2.5),
    (1.5, 0.3, 2.0, 3.0, 2.0),
    (1.0, 1.0, 1.0, 1.0, 1.0),
]


def _mp(kt, mu, N, a):
    mp.mp.dps = 50
    kt, Fs, a = mp.mpf(kt), mp.mpf(mu) * mp.mpf(N), mp.mpf(a)
    if a <= Fs / kt:
        return float(kt), 0.0, 0.0
    tau = mp.acos(1 - 2 * Fs / (kt * a))
    k = kt / mp.pi * (tau - mp.sin(2 * tau) / 2)
    c = 4 * Fs / (mp.pi * a) * (1 - Fs / (kt * a))
    return float(k), float(c), float(4 * Fs * (a - Fs / kt))


def closed_forms() -> None:
    print("## 1. Constant N against the closed forms (50-digit reference)\n")
    print("Largest relative error over 200 amplitudes log-spaced over 0.5 to 1000 slip limits "
          "(and below the slip limit, the largest |k_eq/kt - 1|, |c_eq| and W).\n")  # fmt: skip
    print(
        "| kt, mu, N | method | k_eq | w c_eq | W | -B1/a (quadrature harmonic) | "
        "below the slip limit | ms per amplitude |\n|---|---|---|---|---|---|---|---|"
    )
    describing_functions(JenkinsElement(1.0, 1.0, 1.0), [0.5, 2.0])  # imports: not timed
    for params in ELEMENTS:
        el = JenkinsElement(*params)
        a = el.slip_limit * np.geomspace(0.5, 1000.0, 200)
        ref = np.array([_mp(*params, ai) for ai in a])
        s = ref[:, 2] > 0
        for method in ("single-node", "driven", "closed form (float)"):
            t0 = time.perf_counter()
            if method.startswith("closed"):
                cf = jenkins_closed_form(*params, a)
                k, c, W, B = cf["k_eq"], cf["c_eq_omega"], cf["W"], None
            else:
                df = describing_functions(el, a, method=method)
                k, c, W, B = df.k_eq, df.c_eq_omega, df.W, -df.force_sin[:, 1] / a
            ms = 1e3 * (time.perf_counter() - t0) / a.size
            eb = "-" if B is None else f"{np.max(np.abs(B[s] / ref[s, 1] - 1)):.1e}"
            stuck = (f"{np.max(np.abs(k[~s] / params[0] - 1)):.1e}, {np.max(np.abs(c[~s])):.1e}, "
                     f"{np.max(np.abs(W[~s])):.1e}")  # fmt: skip
            print(f"| {params} | {method} | {np.max(np.abs(k / ref[:, 0] - 1)):.1e} | "
                  f"{np.max(np.abs(c[s] / ref[s, 1] - 1)):.1e} | "
                  f"{np.max(np.abs(W[s] / ref[s, 2] - 1)):.1e} | {eb} | "
                  f"{stuck} ({(~s).sum()} amplitudes) | {ms:.2f} |")  # fmt: skip
    print()


def two_paths() -> None:
    print("## 2. Varying normal load: the exact single node against the event solver\n")
    print("200 amplitudes log-spaced over 0.3 to 1000 slip limits μN0/kt; W relative to μ max N "
          "a, the first harmonics and the force amplitude relative to μ max N.\n")  # fmt: skip
    print(
        "| kt, mu, N0, N1, phi | separates | W | first harmonics | force amplitude | "
        "ms per amplitude (node / driven) |\n|---|---|---|---|---|---|"
    )
    for kt, mu, N0, N1, phi in VARYING:
        el = JenkinsElement(kt, mu, N0, N1, phi)
        a = el.slip_limit * np.geomspace(0.3, 1000.0, 200)
        t0 = time.perf_counter()
        one = describing_functions(el, a, harmonics=1)
        t1 = time.perf_counter()
        two = describing_functions(el, a, harmonics=1, method="driven")
        t2 = time.perf_counter()
        sc = mu * (N0 + N1)
        eW = np.max(np.abs(one.W - two.W) / (sc * a))
        eH = max(np.max(np.abs(one.force_cos - two.force_cos)),
                 np.max(np.abs(one.force_sin - two.force_sin))) / sc  # fmt: skip
        eF = np.max(np.abs(one.force_amplitude - two.force_amplitude)) / sc
        print(f"| {kt:g}, {mu:g}, {N0:g}, {N1:g}, {phi:.3g} | {'yes' if N1 > N0 else 'no'} | "
              f"{eW:.1e} | {eH:.1e} | {eF:.1e} | {1e3 * (t1 - t0) / a.size:.2f} / "
              f"{1e3 * (t2 - t1) / a.size:.2f} |")  # fmt: skip
    print()


def return_map() -> None:
    print("## 3. The fine-sample return map against the exact cycle\n")
    print("Largest error of W and of T's Fourier coefficients (k <= 3) at n samples per period; "
          "order by least squares.\n")  # fmt: skip
    el = JenkinsElement(1.5, 0.3, 2.0, 3.0, 2.0)
    el3 = JenkinsElement(1.3, 0.6, 1.0)
    x3 = Fourier(0.1, (2.0, 0.7, 0.3), (0.4, 1.1, -0.5), 1.0)
    N3 = Fourier(1.0, (1.4, 0.5), (0.2, 2.0), 1.0)
    cases = [
        ("harmonic x = 5 slip limits, N1 = 1.5 N0, phi = 2 (separates)",
         el, el.motion(5 * el.slip_limit), el.normal_load(), jenkins_cycle(
             el, 5 * el.slip_limit, harmonics=3)),
        ("3 harmonics of x, 2 of N (separates), start 0.3", el3, x3, N3,
         driven_cycle(el3, x3, normal=N3, harmonics=3, start=0.3)),
    ]  # fmt: skip
    steps = np.array([1000, 2000, 4000, 8000, 16000, 32000, 64000])
    print(
        "| case | W exact | errors at 1000, 2000, ..., 64000 samples | order |\n|---|---|---|---|"
    )
    for name, e, x, N, cyc in cases:
        errs = []
        for n in steps:
            r = return_map_cycle(e.kt, e.mu, x, N, 2 * math.pi, int(n), start=0.3, harmonics=3)
            errs.append(max(abs(r["W"] - cyc.W), np.max(np.abs(r["force_cos"] - cyc.force_cos)),
                            np.max(np.abs(r["force_sin"] - cyc.force_sin))))  # fmt: skip
        order = -np.polyfit(np.log(steps), np.log(errs), 1)[0]
        print(f"| {name} | {cyc.W:.15g} | {', '.join(f'{v:.1e}' for v in errs)} | {order:.2f} |")
    print()


def timing() -> None:
    print("## 4. Time per amplitude\n")
    el = JenkinsElement(1.0, 1.0, 1.0, 0.5, 1.0)
    a = np.geomspace(0.5, 1000.0, 200)
    x3 = Fourier(0.0, (2.0, 0.7, 0.3), (0.4, 1.1, -0.5), 1.0)
    rows = []
    for name, fn in (
        ("describing_functions, 200 amplitudes (single node)",
         lambda: describing_functions(el, a)),
        ("describing_functions, 200 amplitudes (event solver)",
         lambda: describing_functions(el, a, method="driven")),
        ("jenkins_cycle, one amplitude (256 samples)", lambda: jenkins_cycle(el, 3.0)),
        ("driven_cycle, harmonic motion (256 samples)", lambda: driven_cycle(el, el.motion(3.0))),
        ("driven_cycle, 3-harmonic motion, 3 force harmonics",
         lambda: driven_cycle(el, x3, harmonics=3)),
    ):  # fmt: skip
        fn()
        best = min(_timed(fn) for _ in range(5))
        per = best / (a.size if "200" in name else 1)
        rows.append(f"| {name} | {1e3 * best:.2f} | {1e3 * per:.3f} |")
    print("| call | ms (best of 5) | ms per amplitude |\n|---|---|---|")
    print("\n".join(rows))
    print()


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def figure(out_dir: _Path) -> None:
    from lcpfric.figures.describing import figure_describing_functions
    from lcpfric.figures.style import save

    const = JenkinsElement(1.0, 1.0, 1.0)
    vary = JenkinsElement(1.0, 1.0, 1.0, N1=0.8, phi=0.5 * math.pi)
    a = np.geomspace(0.3, 1000.0, 300)
    marks = np.geomspace(0.3, 1000.0, 17)
    fig = figure_describing_functions(
        [("constant N", describing_functions(const, a)),
         (r"$N = N_0(1 - 0.8\,\sin\omega t)$", describing_functions(vary, a))],
        kt=1.0,
        slip_limit=1.0,
        closed=(marks, jenkins_closed_form(1.0, 1.0, 1.0, marks)),
    )  # fmt: skip
    paths = save(fig, out_dir, "describing_functions", ("png", "pdf"))
    print(f"## 5. The figure\n\nwrote {', '.join(p.name for p in paths)} (x = a cos ωt; "
          f"constant N, and N0 + 0.8 N0 cos(ωt + π/2); closed form marked)\n")  # fmt: skip


def sphere(out_dir: _Path) -> None:
    from lcpfric.analysis.describing_contact import contact_describing_functions
    from lcpfric.figures.describing import figure_describing_functions
    from lcpfric.figures.style import save
    from lcpfric.model import Harmonic
    from lcpfric.model.continuum import MDRSphere
    from lcpfric.model.continuum.closed_forms import mindlin_deresiewicz_W, mindlin_force

    print("## 6. The Hertz sphere under a prescribed displacement (MDR springs)\n")
    print("`MDRSphere(R=1, E=1, nu=0.3, mu=0.3, P)`, x = a cos ωt. Constant P = 1e-3: the springs' "
          "closed forms summed (`method='closed-form'`), W against Mindlin-Deresiewicz at the "
          "force amplitude reached, 100 amplitudes log-spaced over 0.01 to 0.99 of the gross-"
          "slip displacement δ* = 3μP/(2 k_t0):\n")  # fmt: skip
    print("| springs | max \\|W/W_MD - 1\\| | at a/δ* | max over a/δ* >= 0.1 | seconds |")
    print("|---|---|---|---|---|")
    for nodes in (500, 1000, 2000, 4000):
        m = MDRSphere(1.0, 1.0, 0.3, 0.3, 1e-3, 0.0, nodes=nodes)
        star = 1.5 * m.mu * m.P0 / m.k_t0
        a = star * np.geomspace(0.01, 0.99, 100)
        r = contact_describing_functions(m, a)
        md = np.array([mindlin_deresiewicz_W(m.P0, q, m.mu, m.k_t0) for q in r.force_amplitude])
        err = np.abs(r.W / md - 1)
        i = int(np.argmax(err))
        big = a >= 0.1 * star
        print(f"| {nodes} | {err[i]:.2e} | {a[i] / star:.3f} | {err[big].max():.2e} | "
              f"{r.seconds:.3f} |")  # fmt: skip
    print()
    vary = MDRSphere(1.0, 1.0, 0.3, 0.3, Harmonic(1e-3, 5e-4, 0.0), 0.0, nodes=2000)
    star = 1.5 * vary.mu * vary.P0 / vary.k_t0
    a = star * np.array([0.1, 0.5, 2.0])
    print("Varying P = P0 (1 + 0.5 sin ωt) (the springs' march, exact for the piecewise-linear "
          "input through the samples): W and k_eq at a/δ* = 0.1, 0.5, 2, relative change from "
          "the previous sample count:\n")  # fmt: skip
    print("| samples | W | ΔW/W | k_eq | Δk_eq/k_eq | seconds |\n|---|---|---|---|---|---|")
    prev = None
    for ns in (256, 512, 1024, 2048):
        r = contact_describing_functions(vary, a, samples=ns)
        dW = "-" if prev is None else ", ".join(f"{v:.1e}" for v in np.abs(r.W / prev.W - 1))
        dk = "-" if prev is None else ", ".join(f"{v:.1e}" for v in np.abs(r.k_eq / prev.k_eq - 1))
        print(f"| {ns} | {', '.join(f'{v:.6e}' for v in r.W)} | {dW} | "
              f"{', '.join(f'{v:.6g}' for v in r.k_eq)} | {dk} | {r.seconds:.2f} |")  # fmt: skip
        prev = r
    print()
    m = MDRSphere(1.0, 1.0, 0.3, 0.3, 1e-3, 0.0, nodes=2000)
    unit = m.mu * m.P0 / m.k_t0
    a = unit * np.geomspace(0.05, 1000.0, 120)
    marks = unit * np.geomspace(0.05, 1.45, 9)
    star = 1.5 * unit
    md = np.array([mindlin_deresiewicz_W(m.P0, q, m.mu, m.k_t0)
                   for q in mindlin_force(marks, m.P0, m.mu, m.k_t0)])  # fmt: skip
    fig = figure_describing_functions(
        [("constant P", contact_describing_functions(m, a)),
         (r"$P = P_0(1 + 0.5\,\sin\omega t)$", contact_describing_functions(vary, a, samples=512))],
        kt=m.k_t0,
        slip_limit=star,
        closed=(marks, {"c_eq_omega": md / (np.pi * marks**2)}),
        stiffness=r"k_{t0}",
        amplitude_unit=r"\delta^*",
        limit_text=r"gross slip (constant P)",
        closed_label="Mindlin-Deresiewicz",
    )  # fmt: skip
    paths = save(fig, out_dir, "describing_sphere", ("png", "pdf"))
    print(
        f"wrote {', '.join(p.name for p in paths)} (2000 springs; δ* = 3μP0/(2 k_t0); "
        "Mindlin-Deresiewicz's W at Mindlin's force amplitude, as ω c_eq = W/(π a²))\n"
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(_ROOT / "benchmarks" / "results"))
    p.add_argument("--figures", default=str(_ROOT / "docs"))
    args = p.parse_args(argv)
    out = _Path(args.out) / "describing.md"
    with results_file(out, "Describing functions of the Jenkins element",
                      "validation/describing.py", markdown=True):  # fmt: skip
        closed_forms()
        two_paths()
        return_map()
        timing()
        figure(_Path(args.figures))
        sphere(_Path(args.figures))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
