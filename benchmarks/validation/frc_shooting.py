"""The figure of harmonic balance against shooting on the 10-DOF chain with one Jenkins contact
(issue 40, item 5): the HB curve (H = 15) through the first resonance and shooting's points,
each started from an HB point (so both follow one branch where the curve folds), and their
relative difference in the last mass's first harmonic; ``docs/frc_shooting.png`` and ``.pdf``.
A point where shooting does not converge in 30 Newton iterations is listed, not drawn.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/frc_shooting.py [--out PATH] [--steps N]

The numbers of the comparison over every degree of freedom, and shooting's own convergence in
its increments, are in ``benchmarks/validation/newmark_system.py`` (section 4).
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "benchmarks/validation")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.figures.dynamic import figure_hb_shooting  # noqa: E402
from lcpfric.figures.style import save  # noqa: E402
from lcpfric.harmonic import forced_response  # noqa: E402
from lcpfric.periodic.first_guess import harmonic_start  # noqa: E402
from lcpfric.periodic.newmark_steady import shooting_tolerance  # noqa: E402
from lcpfric.periodic.shooting import shoot  # noqa: E402
from lcpfric.steppers.newmark_system import NewmarkSystem  # noqa: E402
from newmark_system import chain10, first_harmonic  # noqa: E402


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/frc-shooting.md"))
    parser.add_argument("--steps", type=int, default=1600)
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Harmonic balance against shooting on the 10-DOF chain: the figure",
        "validation/frc_shooting.py",
        markdown=True,
    ):
        H = 15
        ch = chain10(0.3)
        f = np.zeros(10)
        f[-1] = 0.05
        hb = forced_response(ch.mass, ch.damping, ch.stiffness, f, (0.2, 0.36),
                             contacts=(9,), kt=1.0, mu=0.3, normal_load=1.0, harmonics=H,
                             samples=8 * H)  # fmt: skip
        a_hb = hb.amplitude(dof=9)
        picks = np.unique(np.linspace(0, len(hb.omega) - 1, 24).round().astype(int))
        print(f"HB: {len(hb.omega)} points; shooting at {len(picks)} of them, {args.steps} "
              "increments a period\n")  # fmt: skip
        print("| ω | amplitude, HB | amplitude, shooting | difference | Newton iterations |")
        print("|---|---|---|---|---|")
        om, amp, diff = [], [], []
        for i in picks:
            w = float(hb.omega[i])
            s = chain10(w)
            path = NewmarkSystem(s)
            r = shoot(lambda z, p=path: p.period(z, args.steps, jacobian=True)[::2],
                      harmonic_start(s, hb.coefficients[i], hb.contact_force[i]),
                      shooting_tolerance(args.steps))  # fmt: skip
            _, _, _, (t, rec) = path.period(r.z, args.steps, record=True)
            x = np.array([q[0][0][-1, 0] for q in rec])
            a1, b1 = first_harmonic(t, x, w)
            a = float(np.hypot(a1, b1))
            d = abs(a / a_hb[i] - 1)
            if not r.converged:  # not drawn: no orbit to compare with
                print(f"| {w:.5f} | {a_hb[i]:.6f} | not converged in {r.iterations} Newton "
                      f"iterations (residual {r.residual:.1e}) | | |")  # fmt: skip
                continue
            om.append(w)
            amp.append(a)
            diff.append(d)
            print(f"| {w:.5f} | {a_hb[i]:.6f} | {a:.6f} | {d:.2e} | {r.iterations} |")
        print(f"\n{len(om)} of {len(picks)} converged; the difference is below 1e-3 at "
              f"{int(np.sum(np.array(diff) < 1e-3))} of them")  # fmt: skip
        fig = figure_hb_shooting(hb.omega, a_hb, om, amp, diff, H)
        paths = save(fig, _ROOT / "docs", "frc_shooting", ("png", "pdf"))
        print("\nwrote " + ", ".join(str(p.relative_to(_ROOT)) for p in paths))


if __name__ == "__main__":
    main()
