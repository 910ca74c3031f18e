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
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
