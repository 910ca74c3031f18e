"""Stability study: every method on stiff and extreme cases, classified correct / wrong / error.

    python benchmarks/validation/stability.py [--quick] [--out DIR] [--methods a,b] [--groups g,h]
        [--steps N]

Writes stability.csv and stability.md (see tests/support/stability_cases.py for the matrix, the
references and the verdicts).
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
import csv
import os
import sys
import time
from collections import Counter

from lcpfric.methods import available_methods
from support.stability_cases import applies, coupled_agreement, run_scenario, scenarios


def _err(row):
    return "" if row["rel_error"] is None else f"(error {row['rel_error']:.2e})"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--out", default="bench-out")
    p.add_argument("--methods", default=None)
    p.add_argument(
        "--groups",
        default=None,
        help="comma-separated groups (extreme, boundary, ratio, dimensional, "
        "multi-node, stiff); default all",
    )
    p.add_argument("--steps", type=int, default=4000)
    args = p.parse_args(argv)
    groups = args.groups.split(",") if args.groups else None
    methods = args.methods.split(",") if args.methods else available_methods()
    if args.quick and not args.methods:
        methods = [m for m in methods if not m.startswith(("qpsolvers:", "cvxpy:"))]
    os.makedirs(args.out, exist_ok=True)
    t0 = time.perf_counter()
    rows = []
    for sc in scenarios(args.quick):
        if groups and sc.group not in groups:
            continue
        for m in methods:
            if not applies(sc, m):
                continue
            row = run_scenario(sc, m, args.steps)
            row["scaled_error_scale"] = sc.scale if sc.scale is not None else abs(row["reference"])
            rows.append(row)
            if row["verdict"] != "correct":
                print(
                    f"{row['verdict']:7s} {m:20s} {sc.group:11s} {sc.name:32s} "
                    f"{row['scaled_error'] if row['scaled_error'] is not None else ''} "
                    f"{row['message'][:100]}"
                )
    with open(os.path.join(args.out, "stability.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    cmd = (
        "python benchmarks/validation/stability.py"
        + (" --quick" if args.quick else "")
        + (f" --steps {args.steps}" if args.steps != 4000 else "")
        + (f" --methods {args.methods}" if args.methods else "")
        + (f" --groups {args.groups}" if args.groups else "")
        + f" --out {args.out}"
    )
    lines = [
        f"Reproduce: `{cmd}`",
        "",
        "References: the independent mpmath solution, pinned in "
        "tests/support/stability_references.py. Verdicts: `exact` must be within 1e-9 "
        "relative (or the 16-ulp input spread where Ŵ is ill-conditioned); the "
        "time-stepping methods within 1e-4 relative or 1e-9 of the scale "
        "1 + sqrt(P̂1 Q̂1) (see tests/support/stability_cases.py). The stiff group "
        "(coupled, stiffness ratios 1 to 1e12) is judged against the mpmath reference of "
        "the discretization itself (tests/support/stiff_reference.py, pinned in "
        "tests/support/stiff_references.py), within 1e-8 relative at the case's grid, for "
        "the methods that compute it (those taking locate_events, run with "
        "locate_events=False and tol=1e-13).",
        "",
        "Worst errors: relative, over the runs whose reference is at least 1e-6 of the "
        "scale 1 + sqrt(P̂1 Q̂1) (for `exact`: over the runs where Ŵ is well-conditioned, "
        "its 16-ulp input spread below 1e-10 of it); "
        "and on the scale, over all runs (what the time-stepping verdict uses next to a "
        "zero régime, where Ŵ is 1e-12 to 1e-18).",
        "",
        "| method | group | correct | wrong | error | worst relative error | "
        "worst error on the scale | runs that needed 16x steps |",
        "|---|---|---|---|---|---|---|---|",
    ]
    groups = list(dict.fromkeys(r["group"] for r in rows))
    for m in methods:
        for g in groups:
            sub = [r for r in rows if r["method"] == m and r["group"] == g]
            if not sub:
                continue
            c = Counter(r["verdict"] for r in sub)
            rel = [
                r["rel_error"]
                for r in sub
                if r["rel_error"] is not None
                and (
                    abs(r["reference"]) >= 1e-6 * r["scaled_error_scale"]
                    if m != "exact"
                    else r["spread"] <= 1e-10 * abs(r["reference"])
                )
            ]
            scl = [r["scaled_error"] for r in sub if r["scaled_error"] is not None]
            refined = sum(1 for r in sub if r["message"].startswith("error on the scale"))
            fmt = lambda xs: f"{max(xs):.1e}" if xs else "-"  # noqa: E731
            lines.append(
                f"| {m} | {g} | {c['correct']} | {c['wrong']} | {c['error']} | "
                f"{fmt(rel)} | {fmt(scl)} | {refined} |"
            )
    bad = [r for r in rows if r["verdict"] != "correct"]
    if bad:
        lines += ["", "Not correct:", ""]
        lines += [
            f"- {r['method']} on {r['group']} {r['scenario']}: {r['verdict']} "
            f"{_err(r)} "
            f"{r['message']}"
            for r in bad
        ]
    if not groups or "multi-node" in groups:
        lines += ["", "Coupled chain (no exact solution: agreement between methods):", ""]
        for ratio in (1e4,) if args.quick else (1.0, 1e4, 1e8):
            agree = coupled_agreement(methods, ratio, steps=min(args.steps, 2000))
            nums = [v for v in agree.values() if isinstance(v, float)]
            spread = (max(nums) - min(nums)) / max(abs(x) for x in nums) if nums else float("nan")
            lines.append(
                f"- stiffness ratio {ratio:g}: relative spread {spread:.2e} across "
                + ", ".join(
                    f"{k} = {v:.8g}" if isinstance(v, float) else f"{k}: {v}"
                    for k, v in agree.items()
                )
            )
    with open(os.path.join(args.out, "stability.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    c = Counter(r["verdict"] for r in rows)
    print(
        f"{len(rows)} runs: {c['correct']} correct, {c['wrong']} wrong, {c['error']} clear "
        f"errors in {time.perf_counter() - t0:.0f} s; wrote {args.out}/stability.md"
    )
    return 1 if c["wrong"] else 0


if __name__ == "__main__":
    sys.exit(main())
