"""The d = 2 displacement-driven Jenkins element's exact steady cycle
(:func:`lcpfric.exact.driven2d.driven_cycle_2d`): its checks and its cost.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/jenkins_2d.py [--out PATH]

* along one axis (y = 0, and along the diagonal) against the d = 1 event solver
  (:func:`lcpfric.exact.driven.driven_cycle`), with and without separation;
* a circular motion ``X = a (cos ωt, sin ωt)`` under a constant N against the closed form
  ``W = 2π μN sqrt(a² - (μN/kt)²)`` (a uniform rotation: the slider on the circle of that
  radius, T leading X by arccos(μN/(kt a)));
* the sampled radial-return march (:func:`lcpfric.harmonic.jenkins_march`, d = 2) against it on
  a 2-harmonic motion with a varying N: its error and order in the samples;
* the time per cycle.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.exact.driven import driven_cycle  # noqa: E402
from lcpfric.exact.driven2d import driven_cycle_2d  # noqa: E402
from lcpfric.harmonic import jenkins_march  # noqa: E402
from lcpfric.model import Fourier, Harmonic  # noqa: E402
from lcpfric.model.jenkins import JenkinsElement  # noqa: E402

KT, MU = 2.0, 0.5
X = Fourier(0.3, (2.0, 0.7), (0.4, 1.1))
Y = Fourier(-0.2, (1.3, 0.9), (1.4, 0.3))
NORMALS = {
    "varying N": Fourier(1.0, (0.6, 0.3), (0.2, 2.0)),
    "separating N": Fourier(1.0, (1.4, 0.3), (0.2, 2.0)),
}


def scaled(load, c):
    return Fourier(c * load.mean, tuple(c * a for a in load.amplitudes), load.phases, load.omega)


def timed(fn, repeat=5):
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return out, best


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/jenkins-2d.md"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "The d = 2 displacement-driven Jenkins element, event by event",
        "validation/jenkins_2d.py",
        markdown=True,
    ):
        print(f"kt = {KT}, μ = {MU}; x = {X}; y = {Y}\n")
        print("## Along one axis against the d = 1 event solver\n")
        print("| normal | motion | abs. error in W | max abs. error in T's harmonics 0..3 |")
        print("|---|---|---|---|")
        el = JenkinsElement(kt=KT, mu=MU, N0=1.0)
        c = 1.0 / math.sqrt(2.0)
        for label, N in NORMALS.items():
            ref = driven_cycle(el, X, normal=N, harmonics=3)
            for motion, (x, y, f) in {
                "x only": (X, 0.0, np.array([1.0, 0.0])),
                "y only": (0.0, X, np.array([0.0, 1.0])),
                "diagonal": (scaled(X, c), scaled(X, c), np.array([c, c])),
            }.items():
                cyc = driven_cycle_2d(x, y, N, KT, MU, harmonics=3)
                eF = max(
                    np.abs(cyc.force_cos - f[:, None] * ref.force_cos).max(),
                    np.abs(cyc.force_sin - f[:, None] * ref.force_sin).max(),
                )
                print(f"| {label} | {motion} | {abs(cyc.W - ref.W):.2e} | {eF:.2e} |")
        print("\n## Circular motion against the closed form\n")
        print("| a | kt | μN | W | closed form | rel. error | cycles | max abs(abs(T)/μN - 1) |")
        print("|---|---|---|---|---|---|---|---|")
        for a, kt, F in ((2.0, 1.0, 1.0), (0.37, 20.0, 0.9), (1.01, 1.0, 1.0), (10.0, 3.0, 2.0)):
            cyc = driven_cycle_2d(Harmonic(0, a, math.pi / 2), Harmonic(0, a, 0), F, kt, 1.0)
            W = 2 * math.pi * F * math.sqrt(a * a - (F / kt) ** 2)
            dev = np.abs(np.hypot(*cyc.T) / F - 1).max()
            print(
                f"| {a} | {kt} | {F} | {cyc.W:.15g} | {W:.15g} | {abs(cyc.W / W - 1):.1e} "
                f"| {cyc.cycles} | {dev:.1e} |"
            )
        print("\n## The sampled march (radial return) against the exact cycle\n")
        for label, N in NORMALS.items():
            cyc = driven_cycle_2d(X, Y, N, KT, MU)
            print(f"{label}: exact W = {cyc.W:.15g}, first harmonic {cyc.first_harmonic.ravel()}\n")
            print("| samples | error in W | order | error in 1st harmonics | order |")
            print("|---|---|---|---|---|")
            prev = None
            for ns in (64, 128, 256, 512, 1024, 2048, 4096, 8192):
                th = 2 * np.pi * np.arange(ns) / ns
                res = jenkins_march(np.array([X(th), Y(th)])[None], N(th)[None], KT, MU)
                T = res.force[0]
                a1 = 2 / ns * (T * np.cos(th)).sum(-1)
                b1 = 2 / ns * (T * np.sin(th)).sum(-1)
                eW = abs(res.dissipation[0] - cyc.W)
                eF = max(
                    np.abs(a1 - cyc.force_cos[:, 1]).max(), np.abs(b1 - cyc.force_sin[:, 1]).max()
                )
                o = (
                    ("", "")
                    if prev is None
                    else tuple(f"{math.log2(p / e):.2f}" for p, e in zip(prev, (eW, eF)))
                )
                print(f"| {ns} | {eW:.3e} | {o[0]} | {eF:.3e} | {o[1]} |")
                prev = (eW, eF)
            print()
        print("## Time\n")
        print("| case | cycles run | events | seconds per solve | per cycle run |")
        print("|---|---|---|---|---|")
        cases = {
            "circle a = 2 μN/kt": (Harmonic(0, 2, math.pi / 2), Harmonic(0, 2, 0), 1.0, 1.0, 1.0),
            **{f"2 harmonics, {k}": (X, Y, N, KT, MU) for k, N in NORMALS.items()},
        }
        for label, argsc in cases.items():
            cyc, sec = timed(lambda: driven_cycle_2d(*argsc))
            per = sec / cyc.cycles
            print(f"| {label} | {cyc.cycles} | {cyc.events.size} | {sec:.3f} | {per:.3f} |")
        rtol = {
            r: driven_cycle_2d(X, Y, NORMALS["varying N"], KT, MU, rtol=r)
            for r in (1e-8, 1e-10, 1e-12)
        }
        print(
            "\nIntegration tolerance (2 harmonics, varying N): |W(rtol) - W(1e-12)| =",
            ", ".join(f"{r:g}: {abs(c.W - rtol[1e-12].W):.1e}" for r, c in rtol.items()),
        )


if __name__ == "__main__":
    main()
