"""Time stepping with inertia for the dynamic single node (issue 40, item 3, for the node):
``method="newmark"`` against ``exact``, its order in the steps per cycle.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/newmark_node.py [--out PATH]

Four cases (normalized: P̂1, Q̂1, φ, β, ζ): stick phases, separation, reversals only (damped),
constant N; W and the amplitude against the exact orbit at 100 to 3200 steps per cycle, the
local orders, and the time of each steady state (shooting included). Then shooting against
plain cycles (periods of motion from rest until the state repeats to the residual shooting
reached) at ζ = 1e-3, 400 steps per cycle: the periods (hence increments) each takes.
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

import lcpfric  # noqa: E402
from lcpfric.steppers.newmark_node import NewmarkPath  # noqa: E402

CASES = {
    "stick phases": (0.5, 2.0, 0.7, 0.3, 0.05),
    "separation": (1.5, 2.0, 0.4, 0.7, 0.02),
    "reversals": (0.5, 2.0, 0.7, 1.3, 0.1),
    "constant N": (0.0, 2.0, 0.3, 0.8, 0.05),
}
STEPS = (100, 200, 400, 800, 1600, 3200)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/newmark-node.md"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Time stepping with inertia: newmark against exact",
        "validation/newmark_node.py",
        markdown=True,
    ):
        print("| case | steps | rel. error in W | order | rel. error in the amplitude | s |")
        print("|---|---|---|---|---|---|")
        lowest = math.inf
        for name, (P1, Q1, phi, beta, zeta) in CASES.items():
            node = lcpfric.SingleNode.normalized(P1, Q1, phi, beta=beta, zeta=zeta)
            ex = lcpfric.steady_state(node, "exact")
            prev = None
            for n in STEPS:
                start = time.perf_counter()
                r = lcpfric.steady_state(node, "newmark", n)
                sec = time.perf_counter() - start
                e = abs(r.W / ex.W - 1)
                ea = abs(r.dynamics.amplitude / ex.dynamics.amplitude - 1)
                order = f"{math.log2(prev / e):.2f}" if prev else ""
                if prev:
                    lowest = min(lowest, math.log2(prev / e))
                print(f"| {name} | {n} | {e:.2e} | {order} | {ea:.2e} | {sec:.2f} |")
                prev = e
        print(f"\nlowest local order in W: {lowest:.2f} (goal: >= 1.8)")
        print("\n## Shooting against cycles (ζ = 1e-3, 400 steps per cycle)\n")
        print("| case (P̂1, Q̂1, φ, β, ζ) | shooting: Newton iterations | periods | cycles: "
              "periods | ratio |")  # fmt: skip
        print("|---|---|---|---|---|")
        for case in ((0.0, 10.0, 0.0, 0.8, 1e-3), (0.5, 5.0, 0.7, 1.3, 1e-3)):
            node = lcpfric.SingleNode.normalized(*case[:3], beta=case[3], zeta=case[4])
            r = lcpfric.steady_state(node, "newmark", 400)
            path, z, k = NewmarkPath(*case), np.zeros(2), 0
            while k < 20_000:
                z1 = path.period(z, 400)[0]
                k += 1
                if np.max(np.abs(z1 - z)) <= r.change:
                    break
                z = z1
            d = r.dynamics
            print(f"| {case} | {d.newton_iterations} | {d.periods} | {k} | "
                  f"{k / d.periods:.1f} |")  # fmt: skip
        print("\nshooting's periods include its central-difference Jacobian (4 periods an "
              "iteration); friction shortens the transients that cycles wait out")  # fmt: skip


if __name__ == "__main__":
    main()
