"""Accuracy and time per step of every installed backend on the paper's node.

For the node (P̂1, Q̂1, φ) = (1.5, 2, 0.6π) (separation) at ``--steps`` steps per cycle (4000 by
default), each method's steady-state Ŵ is compared with the exact one, with the active-set
refinement (the default) and without it (the solver's own answers, lcpfric's tight default
settings), next to the closed-form projection on the same grid. The time per step is the wall
time of the steady state divided by the steps taken (cycles x steps).

Run::

    python benchmarks/validation/backend_accuracy.py [--steps 4000] [--json]

The explicit stepper is on its own grid (the paper's discretization), so its error differs from
the projection's; the convex backends, refined, solve the projection's problem.
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

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse
import json
import sys
import time

import numpy as np

from lcpfric import SingleNode, steady_state
from lcpfric.backends import ConvexStepper
from lcpfric.exact import exact_W_hat
from lcpfric.methods import get_stepper, methods_for

CASE = (1.5, 2.0, 0.6 * np.pi)


def run(method: str, steps: int, refine: bool | None) -> dict:
    node = SingleNode.normalized(*CASE)
    options = {} if refine is None else {"refine": refine}
    t0 = time.perf_counter()
    # unrefined answers carry the solver's noise: a looser cycle-to-cycle test
    res = steady_state(node, method, steps, tol=1e-10 if refine is not False else 1e-7, **options)
    seconds = time.perf_counter() - t0
    exact = exact_W_hat(*CASE)
    return {
        "method": method,
        "refine": refine,
        "W_hat": res.W_hat,
        "error": (res.W_hat - exact) / exact,
        "cycles": res.cycles,
        "us_per_step": 1e6 * seconds / (res.cycles * res.steps_per_cycle),
        "max_residual": res.solver_stats.get("max_residual"),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--json", action="store_true", help="last line: JSON of the rows")
    parser.add_argument(
        "--out",
        default=str(_ROOT / "benchmarks" / "results" / "backend-accuracy.md"),
        help='the results file (default: %(default)s; "-": print only)',
    )
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "The backends against exact and against the projection",
        "validation/backend_accuracy.py"
        + "".join(f" {a}" for a in (sys.argv[1:] if argv is None else argv)),
    ):
        rows = [run("projection", args.steps, None), run("explicit", args.steps, None)]
        for method in methods_for(SingleNode.normalized(*CASE)):
            if method in ("exact", "explicit", "projection"):
                continue
            # the convex backends with and without their refinement; the others as they are
            convex = isinstance(get_stepper(method), ConvexStepper)
            for refine in (True, False) if convex else (None,):
                try:
                    rows.append(run(method, args.steps, refine))
                except Exception as exc:  # report, do not stop: a backend may fail unrefined
                    rows.append(
                        {
                            "method": method,
                            "refine": refine,
                            "error": None,
                            "failure": f"{type(exc).__name__}: {str(exc)[:90]}",
                        }
                    )
        projected = rows[0]["W_hat"]
        print(
            f"{'method':20s} {'refine':>6s} {'rel. error vs exact':>20s} "
            f"{'vs projection':>14s} {'us/step':>9s} {'cycles':>6s} {'max residual':>12s}"
        )
        for r in rows:
            if r.get("error") is None:
                print(f"{r['method']:20s} {str(r['refine']):>6s}  failed: {r['failure']}")
                continue
            resid = r.get("max_residual")
            r["vs_projection"] = abs(r["W_hat"] - projected) / abs(projected)
            print(
                f"{r['method']:20s} {str(r['refine']):>6s} {r['error']:20.3e} "
                f"{r['vs_projection']:14.1e} {r['us_per_step']:9.1f} {r['cycles']:6d} "
                f"{'' if resid is None else f'{resid:.1e}':>12s}",
                flush=True,
            )
        if args.json:
            print(json.dumps(rows))
        return 0


if __name__ == "__main__":
    sys.exit(main())
