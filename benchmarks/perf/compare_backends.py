"""Error against run time for every method on the benchmark cases (:mod:`comparison`): each
method at increasing steps per cycle, judged against the exact solution; writes compare.csv,
compare.md and (with matplotlib) compare.png, or with --coupled the coupled d = 1 cases against
method 'exact' (compare-coupled.csv, .md, .png).

    python benchmarks/perf/compare_backends.py [--quick] [--coupled] [--out DIR] [--methods a,b]
        [--cases a,b] [--steps n,m] [--budget S] [--json]

Bad input exits with code 2 and one line naming the option.
"""

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

import argparse
import importlib.util
import json
import sys
import time


OUTPUTS = ("compare.csv", "compare.md", "compare.png")
COUPLED_OUTPUTS = ("compare-coupled.csv", "compare-coupled.md", "compare-coupled.png")


def configure(p) -> None:
    p.add_argument("--quick", action="store_true", help="reduced set, under 3 minutes")
    p.add_argument(
        "--coupled",
        action="store_true",
        help="the coupled d = 1 cases (chains with k_coupling = 10, a dense SPD K, a "
        "separating node reversing, a 100-node chain) against method 'exact', with a "
        "Richardson check; "
        "default methods exact, explicit, clarabel, osqp, active-set, qpsolvers:proxqp, "
        "cvxpy:CLARABEL (those installed), steps 100 to 12800, budget 40 s",
    )
    p.add_argument(
        "--out",
        default="bench-out",
        metavar="DIR",
        help="output directory (default bench-out; its parent must exist)",
    )
    p.add_argument(
        "--methods",
        default=None,
        metavar="LIST",
        help="comma-separated methods (default: all installed)",
    )
    p.add_argument("--cases", default=None, metavar="LIST", help="comma-separated case names")
    p.add_argument(
        "--budget",
        default=None,
        metavar="SECONDS",
        help="seconds per run before a method stops refining (> 0; default 20, or 1 with --quick)",
    )
    p.add_argument(
        "--steps",
        default=None,
        metavar="LIST",
        help="comma-separated steps per cycle (default: 50 to 1e5, or the --quick set)",
    )
    p.add_argument("--placement", default="contact", choices=("contact", "uniform"))
    p.add_argument("--json", action="store_true", help="print the headline numbers as JSON last")
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace the results of an earlier run in --out (refused otherwise)",
    )


def _list(text, option: str) -> list[str]:
    from lcpfric.errors import InputError

    items = [s.strip() for s in str(text).split(",") if s.strip()]
    if not items:
        raise InputError(option, f"expected a comma-separated list, got {text!r}")
    return items


def run(args) -> int:
    import comparison as bench
    from lcpfric import _checks
    from lcpfric import memory
    from lcpfric.errors import InputError

    from lcpfric.cli._paths import output_dir

    out = output_dir(args.out, "--out")  # checked (and probed) before any work
    coupled = bool(getattr(args, "coupled", False))
    earlier = [n for n in (COUPLED_OUTPUTS if coupled else OUTPUTS) if (out / n).exists()]
    if earlier and not args.overwrite:
        raise InputError(
            "--out",
            f"{args.out!r} holds the results of an earlier run ({', '.join(earlier)}); give "
            "another directory, or --overwrite to replace them",
        )
    all_cases = bench.COUPLED_CASES if coupled else bench.CASES
    cases = all_cases
    if coupled and args.quick:  # the 100-node chain is left to the full run
        cases = tuple(c for c in all_cases if c.max_steps is None)
    if args.cases is not None:
        names = _list(args.cases, "--cases")
        unknown = [n for n in names if n not in {c.name for c in all_cases}]
        if unknown:
            raise InputError(
                "--cases",
                f"unknown {unknown}; choose from "
                f"{[c.name for c in all_cases]}"
                + (
                    ""
                    if coupled
                    else f" (or --coupled for {[c.name for c in bench.COUPLED_CASES]})"
                ),
            )
        cases = tuple(c for c in all_cases if c.name in names)
    methods = None
    if args.methods is not None:
        methods = _list(args.methods, "--methods")
        from lcpfric.methods import get_stepper

        for m in methods:
            get_stepper(m)  # an unknown name or a missing extra fails here, named --methods
    if coupled:
        steps = bench.COUPLED_QUICK_STEPS if args.quick else bench.COUPLED_STEPS
    else:
        steps = bench.QUICK_STEPS if args.quick else bench.FULL_STEPS
    if args.steps is not None:
        steps = tuple(
            _checks.positive_int("--steps", s, minimum=4) for s in _list(args.steps, "--steps")
        )
    if args.budget is not None:
        budget = _checks.positive("--budget", _checks.parse_number(args.budget, "--budget"))
    else:
        budget = 1.0 if args.quick else (40.0 if coupled else 20.0)
    from lcpfric.methods import CLOSED_FORM, available_methods, get_method

    if methods is None and coupled:
        installed = set(available_methods())
        methods = [m for m in bench.COUPLED_METHODS if m in installed]
    if methods is None and args.quick:  # the quick set: the methods the registry rates fast
        methods = [
            m
            for m in bench.default_methods()
            if (get_method(m)[0].seconds_per_point_step or 0.0) < 1e-4
        ]
    worst = max(
        (
            memory.steady_state_bytes(max(steps), m)
            for m in (methods or ["solver"])
            if m == "solver" or get_method(m)[0].kind != CLOSED_FORM
        ),
        default=0.0,
    )
    memory.check(worst, "--steps", f"a run with {max(steps)} steps per cycle")

    t0 = time.perf_counter()
    rows = bench.run_comparison(
        cases,
        methods,
        steps,
        budget=budget,
        repeats=1 if args.quick else 3,
        placement=args.placement,
    )
    cmd = (
        "python benchmarks/perf/compare_backends.py"
        + (" --coupled" if coupled else "")
        + (" --quick" if args.quick else "")
        + (f" --cases {args.cases}" if args.cases else "")
        + (f" --methods {args.methods}" if args.methods else "")
        + (f" --steps {args.steps}" if args.steps else "")
        + (f" --budget {budget:g}" if args.budget is not None else "")
        + f" --out {args.out}"
        + (f" --placement {args.placement}" if args.placement != "contact" else "")
    )
    write = bench.write_coupled_outputs if coupled else bench.write_outputs
    out.mkdir(exist_ok=True)
    headline = write(rows, str(out), cases, cmd)
    headline["seconds"] = time.perf_counter() - t0
    outputs = COUPLED_OUTPUTS if coupled else OUTPUTS
    written = [name for name in outputs if (out / name).exists()]
    headline["files"] = written
    note = ""
    if outputs[2] not in written:
        note = (
            f' ({outputs[2]} not drawn: matplotlib is not installed; pip install "lcpfric[plot]")'
            if importlib.util.find_spec("matplotlib") is None
            else f" ({outputs[2]} not drawn)"
        )
    print(f"wrote {out}/{', '.join(written) or 'nothing'} in {headline['seconds']:.0f} s{note}")
    if args.json:
        print(json.dumps(headline))
    return 0


def main(argv=None) -> int:
    from lcpfric.errors import InputError

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    configure(p)
    args = p.parse_args(argv)
    try:
        return run(args)
    except InputError as exc:
        print(f"compare_backends.py: error: {exc.parameter}: {exc.detail}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
