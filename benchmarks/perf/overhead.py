"""Per-step overhead of lcpfric's convex backends over the raw solver call.

For each backend and scene size, the same scene is run to its steady state; then one cycle is
timed twice:

* lcpfric: ``stepper.cycle(scene, state)``, everything a step does (the linear term, the solver
  call, refinement, the residual check, the dissipation, storing the cycle);
* raw: the solver calls alone, replayed with the very vectors lcpfric passed in that cycle, on the
  same solver objects and settings, through the solver's own API (Clarabel
  ``update(q=, b=)`` + ``solve()``; OSQP ``update(q=, l=, u=)`` + ``solve()``; qpsolvers
  ``solve_problem(Problem(...))``; cvxpy ``param.value = ...`` + ``problem.solve()``).

The ratio lcpfric / raw is printed per backend (best of ``--repeat`` alternating runs). With
``--json`` the last line is one JSON object mapping backend names to ratios: the key is the
backend for the first size (the paper's single node by default) and ``backend@n=<size>`` for the
others.

Run::

    PYTHONPATH=. python benchmarks/perf/overhead.py [--json] [--sizes 1,10] [--repeat 5]
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

from lcpfric import SingleNode, available_methods, get_stepper, make_scene
from lcpfric.model import chain

DEFAULT_BACKENDS = ("clarabel", "osqp", "qpsolvers:proxqp", "cvxpy:CLARABEL")
# steps per cycle: short timed blocks, repeated, keep the minimum robust on a shared machine
STEPS = {"clarabel": 1000, "osqp": 1000, "qpsolvers": 200, "cvxpy": 100}


def make(size: int, steps: int):
    if size == 1:  # the paper's node, with separation
        return make_scene(SingleNode.normalized(1.5, 2.0, 0.6 * np.pi), steps)
    system = chain(
        size,
        k_coupling=0.5,
        P1=0.5,
        Q1=np.linspace(1.5, 2.5, size),
        phi=0.6 * np.pi,
        normal_phase=np.linspace(0.0, 1.0, size),
    )
    return make_scene(system, steps)


def raw_call(stepper):
    """The backend's own update + solve, for one recorded call."""
    name = stepper.name
    if name == "clarabel":

        def call(prob, q, bdata):
            h = prob.handle
            h.update(q=q, b=bdata)
            sol = h.solve()
            return sol.x
    elif name == "osqp":

        def call(prob, q, bdata):
            h = prob.handle
            h.update(q=q, l=bdata[0], u=bdata[1])
            return h.solve(raise_error=False).x
    elif name == "qpsolvers":
        import qpsolvers

        def call(prob, q, bdata):
            problem = qpsolvers.Problem(prob.handle["P"], q, lb=bdata[0], ub=bdata[1])
            return qpsolvers.solve_problem(
                problem, solver=stepper.solver, initvals=prob.handle["x"], **prob.handle["settings"]
            ).x
    elif name == "cvxpy":

        def call(prob, q, bdata):
            problem, F, lin, bnd, settings = prob.handle
            lin.value = q
            bnd.value = bdata
            problem.solve(solver=stepper.solver, warm_start=True, **settings)
            return F.value
    else:  # pragma: no cover
        raise ValueError(name)
    return call


def measure(method: str, size: int, steps: int, repeat: int) -> dict:
    scene = make(size, steps)
    stepper = get_stepper(method)
    state = stepper.init(scene)
    for _ in range(3):  # to the steady state (periodic warm starts)
        state, _cyc = stepper.cycle(scene, state)
    # record the calls of one cycle
    calls = []
    solve = stepper.solve

    def recording(prob, q, bdata):
        calls.append((prob, q.copy(), bdata))
        return solve(prob, q, bdata)

    stepper.solve = recording
    state, _cyc = stepper.cycle(scene, state)
    del stepper.solve
    raw = raw_call(stepper)
    t_lcp, t_raw = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        state, _cyc = stepper.cycle(scene, state)
        t_lcp.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for prob, q, bdata in calls:
            raw(prob, q, bdata)
        t_raw.append(time.perf_counter() - t0)
    ncalls = max(1, len(calls))
    lcp, rw = min(t_lcp) / ncalls, min(t_raw) / ncalls
    return {
        "method": method,
        "n": size,
        "steps": scene.steps,
        "solves": len(calls),
        "lcpfric_us": 1e6 * lcp,
        "raw_us": 1e6 * rw,
        "ratio": lcp / rw,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true", help="last line: JSON {backend: ratio}")
    parser.add_argument("--backends", default=",".join(DEFAULT_BACKENDS))
    parser.add_argument("--sizes", default="1,10", help="scene sizes n (1 = the paper's node)")
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument(
        "--steps", type=int, default=0, help="steps per cycle (default: per backend, see STEPS)"
    )
    parser.add_argument(
        "--out",
        default=str(_ROOT / "benchmarks" / "results" / "overhead.md"),
        help='the results file (default: %(default)s; "-": print only)',
    )
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "The convex backends' overhead over the raw solver call",
        "perf/overhead.py" + "".join(f" {a}" for a in (sys.argv[1:] if argv is None else argv)),
    ):
        have = set(available_methods())
        sizes = [int(s) for s in args.sizes.split(",")]
        ratios = {}
        print(
            f"{'backend':18s} {'n':>4s} {'steps':>6s} {'lcpfric us/solve':>17s} "
            f"{'raw us/solve':>13s} {'ratio':>6s}"
        )
        for method in args.backends.split(","):
            if method not in have:
                print(f"{method:18s} not installed: skipped")
                continue
            steps = args.steps or STEPS[method.split(":")[0]]
            for i, size in enumerate(sizes):
                r = measure(method, size, steps, args.repeat)
                print(
                    f"{method:18s} {size:4d} {r['steps']:6d} {r['lcpfric_us']:17.1f} "
                    f"{r['raw_us']:13.1f} {r['ratio']:6.2f}",
                    flush=True,
                )
                ratios[method if i == 0 else f"{method}@n={size}"] = round(r["ratio"], 3)
        if args.json:
            print(json.dumps(ratios))
        return 0


if __name__ == "__main__":
    sys.exit(main())
