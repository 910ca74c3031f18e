"""The continuum contact models across hard loads, grids and steps: does every case reach its
steady state, in how many cycles and how long?

`OPENBLAS_NUM_THREADS=1 python benchmarks/studies/robustness_contact.py` (about 1.5 minutes) writes
`benchmarks/results/robustness_contact.md`. The cases: large increments (8 steps per cycle)
and finer ones (40), near separation, gross sliding held by a support (Q1 = 1.5 μP0), complete
separation (P1 = 1.3), opposite phases; small tangential loads (Q1 down to 1e-4 μP0); large
increments on fine grids; d = 1 and d = 2 (ν = 0.3); the sphere on the half-space, the
half-plane cylinder and the MDR sphere. A case that fails is reported with its error, not
hidden: this is the sweep that found the defects fixed at 7b43c88 … 442b263.
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

import argparse
import math
import time
import warnings
from pathlib import Path

import lcpfric
from _report import Report, stamp
from lcpfric.errors import LcpfricError, ResolutionWarning
from lcpfric.model import Harmonic
from lcpfric.model.continuum import HalfPlaneCylinder, HalfSpace, MDRSphere
from lcpfric.steppers.newton_cg import NewtonCGStepper

E, R, MU, P0 = 200e3, 10.0, 0.5, 100.0
TWO_PI = 2.0 * math.pi
#: (P1/P0, Q1/(μP0), φ/π): near separation, gross sliding, complete separation, opposite phases
HARD = ((0.9, 0.8, 0.2), (0.3, 1.5, 0.7), (1.3, 0.6, 0.5), (0.5, 0.9, 1.0))


def loads(P1, Q1, phi):
    return (Harmonic(P0, P1 * P0, 0.0, TWO_PI), Harmonic(0.0, Q1 * MU * P0, phi * math.pi, TWO_PI))


def sphere(P1, Q1, phi, *, grid, dims, supported):
    nu = 0.3 if dims == 2 else 0.0

    def make(ks):
        return HalfSpace.sphere(
            R, E, nu, MU, *loads(P1, Q1, phi), grid=grid, dims=dims, k_support=ks
        )

    return make(make(1.0).k_t0) if supported else make(0.0)


class _Tracked(NewtonCGStepper):
    """The half-space's ``newton-cg`` stepper keeping its latest increments' context, whose
    statistics (Newton steps) add up over the cycles run, also those of a case that fails."""

    context_now = None

    def context(self, scene):
        self.context_now = super().context(scene)
        return self.context_now

    def copy_context(self, context):
        self.context_now = super().copy_context(context)
        return self.context_now


def run(make, steps):
    """``(outcome, seconds, newton steps or '')`` of one case."""
    start = time.perf_counter()
    method = None
    try:
        model = make()
        method = _Tracked() if isinstance(model, HalfSpace) else None
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ResolutionWarning)
            r = lcpfric.steady_state(model, method, steps, max_cycles=100)
        note = (
            " (W = 0: ResolutionWarning)"
            if any(issubclass(w.category, ResolutionWarning) for w in caught)
            else ""
        )
        outcome = (
            f"{r.cycles} cycles, W_norm {r.W_normalized:.6g}{note}"
            if r.converged
            else f"not converged ({r.change:.2g})"
        )
    except LcpfricError as exc:
        outcome = f"**{type(exc).__name__}**: {str(exc)[:120]}"
    ctx = getattr(method, "context_now", None)
    stats = ctx.stats if ctx is not None else {}
    return outcome, time.perf_counter() - start, stats.get("newton", "")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "results"))
    args = ap.parse_args(argv)
    lines = Report(
        [
            "# The continuum contact models across hard cases",
            "",
            f"{stamp('studies/robustness_contact.py')}. E = {E:g}, R = {R:g}, "
            f"μ = {MU}, P0 = {P0:g}; the half-space's support, where there is one, is k_t0; "
            f"the half-plane's 1e4 per unit length. At most 100 cycles.",
            "",
            "| model | case | steps | outcome | seconds | Newton steps |",
            "|---|---|---|---|---|---|",
        ]
    )
    failures = 0

    def row(model, case, steps, make):
        nonlocal failures
        outcome, seconds, newton = run(make, steps)
        failures += outcome.startswith("**") or outcome.startswith("not")
        lines.emit(f"| {model} | {case} | {steps} | {outcome} | {seconds:.1f} | {newton} |")

    for grid in (32, 64):
        for steps in (8, 40):
            for P1, Q1, phi in HARD:
                for dims in (1, 2):
                    row(
                        f"half-space d = {dims}, grid {grid}",
                        f"P1 {P1}, Q1 {Q1}, φ {phi}π, support",
                        steps,
                        lambda: sphere(P1, Q1, phi, grid=grid, dims=dims, supported=True),
                    )
    for grid in (16, 40):
        for q in (1e-4, 1e-2):
            for dims in (1, 2):
                row(
                    f"half-space d = {dims}, grid {grid}",
                    f"Q1 {q:g} μP0, constant P",
                    100,
                    lambda: sphere(0.0, q, 0.0, grid=grid, dims=dims, supported=False),
                )
    row(
        "half-space d = 1, grid 120",
        "Q1 0.5, constant P (large increments)",
        8,
        lambda: sphere(0.0, 0.5, 0.0, grid=120, dims=1, supported=False),
    )
    row(
        "half-space d = 1, grid 96",
        "P1 0.5, Q1 0.4, φ 0.5π (large increments)",
        8,
        lambda: sphere(0.5, 0.4, 0.5, grid=96, dims=1, supported=False),
    )
    for steps in (8, 100):
        for P1, Q1, phi in HARD:
            row(
                "half-plane, 400 elements",
                f"P1 {P1}, Q1 {Q1}, φ {phi}π, support",
                steps,
                lambda: HalfPlaneCylinder(
                    R, E, 0.3, MU, *loads(P1, Q1, phi), nodes=400, k_support=1e4
                ),
            )
            row(
                "MDR, 2000 springs",
                f"P1 {P1}, Q1 {Q1}, φ {phi}π, support",
                steps,
                lambda: MDRSphere(R, E, 0.3, MU, *loads(P1, Q1, phi), nodes=2000, k_support=1e4),
            )
    lines += ["", f"{failures} case(s) without a steady state."]
    out = Path(args.out)
    out.mkdir(exist_ok=True)
    lines.write(out / "robustness_contact.md")
    print(f"{failures} case(s) without a steady state; wrote {out / 'robustness_contact.md'}")
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
