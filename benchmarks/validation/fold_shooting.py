"""Harmonic balance against shooting where the 10-DOF chain's response folds (issue 40, item 5):
shooting at 1600, 3200 and 6400 increments a period, each started from the HB point, against
HB (H = 15) at the five fold points of ``newmark_system.py``'s section 4 (there shooting at
1600 increments still moves by 1e-2 to 7e-2 from 800).

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/fold_shooting.py [--out PATH]

The difference is the largest over the degrees of freedom of
``|(a1, b1)_HB - (a1, b1)_shooting| / max |(a1, b1)_HB|``.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "benchmarks/validation")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.harmonic import forced_response  # noqa: E402
from lcpfric.periodic.first_guess import harmonic_start  # noqa: E402
from lcpfric.periodic.newmark_steady import shooting_tolerance  # noqa: E402
from lcpfric.periodic.shooting import shoot  # noqa: E402
from lcpfric.steppers.newmark_system import NewmarkSystem  # noqa: E402
from newmark_system import chain10, first_harmonic  # noqa: E402


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/fold-shooting.md"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Harmonic balance against shooting where the chain's response folds",
        "validation/fold_shooting.py",
        markdown=True,
    ):
        ch = chain10(0.3)
        f = np.zeros(10)
        f[-1] = 0.05
        hb = forced_response(ch.mass, ch.damping, ch.stiffness, f, (0.05, 0.5),
                             contacts=(9,), kt=1.0, mu=0.3, normal_load=1.0, harmonics=15,
                             samples=120)  # fmt: skip
        picks = np.unique(np.linspace(0, len(hb.omega) - 1, 12).round().astype(int))[5:10]
        steps = (1600, 3200, 6400)
        print("| ω | " + " | ".join(f"HB vs shooting ({n})" for n in steps)
              + " | Newton iterations | s |")  # fmt: skip
        print("|---|" + "---|" * (len(steps) + 2))
        for i in picks:
            om = float(hb.omega[i])
            s = chain10(om)
            hbc = hb.coefficients[i][:, 1:3]
            scale = np.max(np.hypot(*hbc.T))
            diffs, its, start = [], [], time.perf_counter()
            for n in steps:
                path = NewmarkSystem(s)
                r = shoot(lambda z, p=path, k=n: p.period(z, k, jacobian=True)[::2],
                          harmonic_start(s, hb.coefficients[i], hb.contact_force[i]),
                          shooting_tolerance(n))  # fmt: skip
                _, _, _, (t, rec) = path.period(r.z, n, record=True)
                x = np.array([q[0][0][:, 0] for q in rec])
                c = np.stack(first_harmonic(t, x, om), axis=1)
                d = float(np.max(np.hypot(*(hbc - c).T)) / scale)
                diffs.append(f"{d:.2e}" if r.converged else f"{d:.2e} (not converged)")
                its.append(str(r.iterations))
            print(f"| {om:.5f} | " + " | ".join(diffs) + f" | {', '.join(its)} | "
                  f"{time.perf_counter() - start:.1f} |")  # fmt: skip


if __name__ == "__main__":
    main()
