"""Convergence of the convex backends for two tangential directions (d = 2).

Usage::

    python benchmarks/validation/order_d2.py [--method clarabel]

With d = 2 there is no exact solution to judge against, so the order is measured from successive
differences of W over doubling grids (``|W_2N - W_N|`` falls by 2^p for order p). Cases: one node
with collinear loads (both directions in phase: the slip direction is fixed), one node with
non-collinear loads (the slip direction turns), and a 3-node chain (k_coupling = 10) with
non-collinear loads.
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
import sys
import math

import numpy as np

import lcpfric


def cases():
    yield (
        "1 node, collinear",
        lcpfric.chain(1, dims=2, P1=0.5, Q1=[[1.2, 0.9]], phi=[[0.6 * math.pi, 0.6 * math.pi]]),
    )
    yield (
        "1 node, non-collinear",
        lcpfric.chain(1, dims=2, P1=0.5, Q1=[[1.2, 0.9]], phi=[[0.6 * math.pi, 0.1 * math.pi]]),
    )
    yield (
        "3-node chain, non-collinear",
        lcpfric.chain(
            3,
            k_coupling=10.0,
            dims=2,
            P1=0.5,
            Q1=[[1.2, 0.9], [1.0, 1.1], [0.8, 1.3]],
            phi=[[0.6 * math.pi, 0.1 * math.pi], [0.3, 1.2], [2.0, 0.4]],
        ),
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--method", default="clarabel")
    ap.add_argument("--steps", type=int, nargs="+", default=[200, 400, 800, 1600, 3200])
    ap.add_argument(
        "--out",
        default=str(_ROOT / "benchmarks" / "results" / "order-d2.md"),
        help='the results file (default: %(default)s; "-": print only)',
    )
    args = ap.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Two tangential directions: the order in the steps",
        "validation/order_d2.py"
        + "".join(f" {a}" for a in (sys.argv[1:] if argv is None else argv)),
        markdown=True,
    ):
        cols = " | ".join(f"\\|W({2 * s}) - W({s})\\|" for s in args.steps[:-1])
        print(f"| case | {cols} | order |")
        print("|---" * (len(args.steps) + 1) + "|")
        for name, system in cases():
            W = [
                lcpfric.steady_state(system, method=args.method, steps_per_cycle=s, tol=1e-12).W
                for s in args.steps
            ]
            d = np.abs(np.diff(W))
            order = -np.polyfit(np.log(args.steps[:-1]), np.log(d), 1)[0] if np.all(d > 0) else 0
            print(f"| {name} | {' | '.join(f'{x:.2e}' for x in d)} | {order:.2f} |", flush=True)


if __name__ == "__main__":
    main()
