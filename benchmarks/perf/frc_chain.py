"""Harmonic balance with continuation on a 10-DOF chain with one Jenkins contact (issue 40,
item 5, measured on ``lcpfric.harmonic.forced_response``): the frequency-response curve through
the first resonance, its points and time, and the convergence with the number of harmonics.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/perf/frc_chain.py [--out PATH]

The chain: ten unit masses, unit springs between neighbours and from the first to the ground,
the last free but for a Jenkins element to the ground (kt = 1, μ = 0.3, N = 1), modal damping
ζ = 1e-3 on the first mode of the free chain (C = 2ζω1 M), forcing 0.05 cos ωt on the last
mass, ω from 0.05 to 0.5 (the first resonance of the stuck chain near 0.28). No exact answer
here: the peak amplitude's convergence with H is measured against the largest H.

Then one mass with a Jenkins element (m = k0 = kt = 1, c = 0.02, μN = 0.3, f = 0.5) against a
time-domain reference (DOP853 at rtol 1e-12 event by event, periods from rest until the state
repeats to 1e-11: ``tests/support/jenkins_oscillator_reference.py``): the first harmonic of x at
the curve's points nearest ω = 0.8, 1.2, 1.6, its relative error against H, at 1024 and 4096
AFT samples (the AFT's own error is that of the samples' piecewise-linear input).
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "tests")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.harmonic import forced_response  # noqa: E402
from support.jenkins_oscillator_reference import steady_cycle  # noqa: E402


def chain(n: int = 10):
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    M = np.eye(n)
    w1 = float(np.sqrt(np.linalg.eigvalsh(K)[0]))
    return M, 2e-3 * w1 * M, K


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/frc-chain.md"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Harmonic balance with continuation on a 10-DOF chain with one Jenkins contact",
        "perf/frc_chain.py",
        markdown=True,
    ):
        M, C, K = chain()
        f = np.zeros(10)
        f[-1] = 0.05
        print("| H | samples | points | s | s per point | peak amplitude (last mass) | at ω |")
        print("|---|---|---|---|---|---|---|")
        peaks = {}
        for H in (1, 3, 5, 7, 11, 15, 21):
            ns = max(64, 8 * H)
            start = time.perf_counter()
            r = forced_response(M, C, K, f, (0.05, 0.5), contacts=(9,), kt=1.0, mu=0.3,
                                normal_load=1.0, harmonics=H, samples=ns)  # fmt: skip
            sec = time.perf_counter() - start
            a = r.amplitude(dof=9)
            peaks[H] = a.max()
            print(f"| {H} | {ns} | {len(r.omega)} | {sec:.2f} | {sec / len(r.omega):.3f} | "
                  f"{a.max():.8f} | {r.omega[np.argmax(a)]:.6f} |")  # fmt: skip
        ref = peaks[max(peaks)]
        print("\npeak amplitude against the largest H:\n")
        for H, p in peaks.items():
            print(f"- H = {H}: {abs(p / ref - 1):.2e}")
        print("\ngoal (issue 40): a 200-point curve in <= 10 s; agreement with shooting within "
              "1e-3 at 15 harmonics (no shooting yet: a time-domain reference below)")  # fmt: skip
        single_dof()


def single_dof() -> None:
    m, c, k0, kt, mu, N, f = 1.0, 0.02, 1.0, 1.0, 0.3, 1.0, 0.5
    print("\n## One mass with a Jenkins element against a time-domain reference\n")
    print("relative error of the first harmonic (a1, b1) of x at the points nearest ω:\n")
    print("| samples | H | points | s | ω ≈ 0.8 | ω ≈ 1.2 | ω ≈ 1.6 |")
    print("|---|---|---|---|---|---|---|")
    for ns in (1024, 4096):
        errs = {}
        for H in (1, 3, 5, 7, 11, 15, 21):
            start = time.perf_counter()
            r = forced_response(m, c, k0, f, (0.5, 2.0), contacts=(0,), kt=kt, mu=mu,
                                normal_load=N, harmonics=H, samples=ns)  # fmt: skip
            sec = time.perf_counter() - start
            row = []
            for target in (0.8, 1.2, 1.6):
                i = int(np.argmin(np.abs(r.omega - target)))
                a1, b1, _, _ = steady_cycle(m, c, k0, kt, mu * N, f, r.omega[i])
                co = r.coefficients[i, 0]
                row.append(float(np.hypot(co[1] - a1, co[2] - b1) / np.hypot(a1, b1)))
            errs[H] = row
            print(f"| {ns} | {H} | {len(r.omega)} | {sec:.2f} | "
                  + " | ".join(f"{e:.2e}" for e in row) + " |")  # fmt: skip
        rate = [np.log(errs[3][j] / errs[11][j]) / np.log(11 / 3) for j in range(3)]
        print("| | order from H = 3 to 11 | | | " + " | ".join(f"{x:.2f}" for x in rate) + " |")


if __name__ == "__main__":
    main()
