"""What the d = 2 half-space's cycles cost, cycle by cycle, and why its late cycles cost what
they do: the issue's goal case (Mindlin-Deresiewicz, Q1/(μP0) = 0.5, ν = 0.3, d = 2, grid 40,
400 steps per cycle, cycle tolerance 1e-10).

``OPENBLAS_NUM_THREADS=1 python benchmarks/studies/late_cycles.py [--out DIR]``

writes ``DIR/late_cycles.md`` (default ``benchmarks/results``; about 2 minutes). For each cycle:
the tolerance its increments are solved to (the steady-state driver's loose early cycles), the
FFT products, the Newton steps, the increments whose start (the same increment of the previous
cycle) already met the tolerance, the start's natural-map residual over the tolerance
(percentiles over the cycle's increments), the conjugate-gradient iterations per Newton step, and
the cycle's relative change. Then, over the Newton steps of the cycles from the fifth on, how far
each step's conjugate gradients had to reduce their residual (max norm) and in how many
iterations. Last, the same case with other schedules of the increments' tolerance and other
stopping points of the conjugate gradients: the cycles and products each takes, and W against
the default's. Product counts repeat from run to run; the seconds are this machine's.

The instrumentation is a ``newton-cg`` stepper (:class:`lcpfric.steppers.newton_cg.
NewtonCGStepper`) whose increments count their products, Newton steps and CG iterations, and
whose increments' context wraps the private ``_natural`` (the natural map's residual; its first
call in an increment is at the start); it wraps ``cg`` of :mod:`lcpfric.steppers.newton_step`,
and sets the constants ``CG_TOL`` of :mod:`lcpfric.steppers.newton_increment` and ``_LOOSE``,
``_LOOSE_MAX`` / ``loose_tolerance`` of :mod:`lcpfric.periodic.driver` for the variants.
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
from pathlib import Path

import numpy as np


from _report import Report, stamp  # noqa: E402
from halfspace import sphere  # noqa: E402

import lcpfric  # noqa: E402
import lcpfric.periodic.driver as driver  # noqa: E402
import lcpfric.steppers.newton_cg as hs  # noqa: E402
import lcpfric.steppers.newton_increment as increments  # noqa: E402
import lcpfric.steppers.newton_step as newton_step  # noqa: E402

STEPS = 400
#: the cycles whose Newton steps the conjugate-gradient table covers (from the fifth on)
LATE = 4


class _Probed(hs.HalfSpaceIncrements):
    """The increments' context with its first natural-map residual of each increment kept in
    ``probe["first"]`` (``probe``: a dict shared by the copies the cycles make)."""

    probe: dict | None = None

    def _natural(self, *args):
        ev = super()._natural(*args)
        if self.probe is not None and math.isnan(self.probe["first"]):
            self.probe["first"] = ev[4]
        return ev


class _Counted(hs.NewtonCGStepper):
    """The ``newton-cg`` stepper, each increment's products, Newton steps, CG iterations,
    tolerance and start residual / tolerance appended to ``incs`` (the probe of the start's
    residual with ``record``)."""

    def __init__(self, incs, probe, record):
        super().__init__()
        self.incs, self.probe, self.record = incs, probe, record

    def context(self, scene):
        ctx = _Probed(scene.model, self.increment_tol, scene.scales[0])
        ctx.probe = self.probe if self.record else None
        return ctx

    def increment(self, context, state, b, Q, guess=None, tol=None):
        st = context.stats
        before = (st["tangential_products"], st["newton"], st["cg"])
        self.probe["first"] = math.nan
        out = super().increment(context, state, b, Q, guess, tol=tol)
        tolF = tol * context._tolerance_scale()
        self.incs.append(
            (
                st["tangential_products"] - before[0],
                st["newton"] - before[1],
                st["cg"] - before[2],
                tol,
                self.probe["first"] / tolF,
            )
        )
        return out


def run(record=False):
    """Solve the goal's case: ``(stats, result, seconds, increments, steps)`` (``stats``: the
    result's ``solver_stats``). Per increment: (products, Newton steps, CG iterations,
    tolerance, start residual / tolerance, the last NaN unless ``record``); with ``record``,
    per Newton step: (the CG's starting residual / its tolerance, iterations, the increment's
    index)."""
    model = sphere(Q1=0.5, nu=0.3, grid=40, dims=2)
    incs, steps = [], []
    cg = newton_step.cg
    probe = {"first": math.nan}

    def counted_cg(M, g, x, project, pre, tol, stats, step=None, max_iter=None, res=None):
        r = res if project is None else project(res)
        start = float(np.max(np.abs(r))) / tol
        n = stats["cg"]
        out = cg(M, g, x, project, pre, tol, stats, step, max_iter, res)
        steps.append((start, stats["cg"] - n, len(incs)))  # its increment's index
        return out

    if record:
        newton_step.cg = counted_cg
    try:
        t = time.perf_counter()
        res = lcpfric.steady_state(model, _Counted(incs, probe, record), STEPS)
        seconds = time.perf_counter() - t
    finally:
        newton_step.cg = cg
    return res.solver_stats, res, seconds, np.array(incs), np.array(steps)


def variant(label, **settings):
    """The goal's case with module settings changed: ``(label, result, stats, seconds,
    products of each cycle)``."""
    saved = {name: getattr(mod, attr) for name, (mod, attr, _) in settings.items()}
    try:
        for mod, attr, value in settings.values():
            setattr(mod, attr, value)
        stats, res, seconds, incs, _ = run()
    finally:
        for name, (mod, attr, _) in settings.items():
            setattr(mod, attr, saved[name])
    per = [int(incs[c * STEPS : (c + 1) * STEPS, 0].sum()) for c in range(res.cycles)]
    return label, res, stats, seconds, per


def rounded(base):
    """The default schedule rounded down to a power of ``base`` (cycles at the same level
    share their tolerance)."""

    def schedule(change):
        x = min(driver._LOOSE_MAX, driver._LOOSE * change)
        return base ** math.floor(math.log(x) / math.log(base) + 1e-9)

    return schedule


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "results"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(exist_ok=True)
    lines = Report(
        [
            "# The d = 2 half-space's cycles, one by one",
            "",
            f"{stamp('studies/late_cycles.py')}. Mindlin-Deresiewicz, Q1/(μP0) = 0.5, ν = 0.3, "
            f"d = 2, grid 40, {STEPS} steps per cycle, cycle tolerance 1e-10 (the "
            f"issue's d = 2 goal case).",
            "",
        ]
    )
    emit = lines.emit

    stats, res, seconds, incs, steps = run(record=True)
    emit(
        f"W = {res.W:.12e}, {res.cycles} cycles, {stats['tangential_products']} "
        f"tangential FFT products, {stats['newton']} Newton steps, "
        f"{stats['cg']} CG iterations ({seconds:.1f} s with the probes)."
    )
    emit("")
    emit(
        "| cycle | increments' tolerance | products | Newton steps | increments solved by "
        "their start | start's residual / tolerance (10th, 50th, 90th percentile) | CG "
        "iterations per Newton step | change after the cycle |"
    )
    emit("|---|---|---|---|---|---|---|---|")
    changes = [math.nan] + list(res.changes)
    for c in range(res.cycles):
        blk = incs[c * STEPS : (c + 1) * STEPS]
        p10, p50, p90 = np.percentile(blk[:, 4], [10, 50, 90])
        newton = int(blk[:, 1].sum())
        emit(
            f"| {c + 1} | {blk[0, 3]:.1e} | {int(blk[:, 0].sum())} | {newton} | "
            f"{int(np.count_nonzero(blk[:, 1] == 0))} | {p10:.2g}, {p50:.2g}, {p90:.2g} | "
            f"{blk[:, 2].sum() / max(newton, 1):.2f} | "
            f"{'—' if c == 0 else f'{changes[c]:.1e}'} |"
        )
    emit("")
    late = steps[steps[:, 2] >= LATE * STEPS]
    emit(
        f"Newton steps of cycles {LATE + 1} to {res.cycles} ({late.shape[0]}): each step's "
        f"conjugate gradients start at the residual r0 (max norm) and stop below their "
        f"tolerance (c times 0.9 of the increment's, or 1e-2 of the step's starting "
        f"residual where that is larger):"
    )
    emit("")
    emit("| CG iterations | steps | r0 / tolerance (median) |")
    emit("|---|---|---|")
    for k in sorted(set(late[:, 1].astype(int))):
        sel = late[:, 1] == k
        emit(f"| {k} | {int(sel.sum())} | {np.median(late[sel, 0]):.2f} |")
    emit("")
    emit(
        "Each iteration costs two FFT products (the operator's and the preconditioner's), and "
        "each Newton step one more (its known forces and start)."
    )
    emit("")

    emit("## Other schedules (same case, W against the default's)")
    emit("")
    emit(
        "| variant | cycles | products | Newton steps | seconds | W − W(default), relative | "
        "products of each cycle |"
    )
    emit("|---|---|---|---|---|---|---|")
    W0 = res.W
    runs = [
        ("default: a hundredth of the last change, at most 1e-6", {}),
        ("a tenth of the last change", {"loose": (driver, "_LOOSE", 0.1)}),
        ("3/100 of the last change", {"loose": (driver, "_LOOSE", 0.03)}),
        ("3/1000 of the last change", {"loose": (driver, "_LOOSE", 0.003)}),
        (
            "the default rounded down to a power of 10",
            {"sched": (driver, "loose_tolerance", rounded(10.0))},
        ),
        (
            "the default rounded down to a power of 100",
            {"sched": (driver, "loose_tolerance", rounded(100.0))},
        ),
        ("the early cycles' cap 1e-5 (default 1e-6)", {"cap": (driver, "_LOOSE_MAX", 1e-5)}),
        ("the early cycles' cap 1e-4", {"cap": (driver, "_LOOSE_MAX", 1e-4)}),
        ("CG to 0.3 of the tolerance (default 0.9)", {"cg": (increments, "CG_TOL", 0.3)}),
        ("CG to 0.1 of the tolerance", {"cg": (increments, "CG_TOL", 0.1)}),
    ]
    for label, settings in runs:
        label, r, st, s, per = variant(label, **settings)
        emit(
            f"| {label} | {r.cycles} | {st['tangential_products']} | "
            f"{st['newton']} | {s:.1f} | {(r.W - W0) / W0:+.1e} | "
            f"{' '.join(str(p) for p in per)} |"
        )
    emit("")
    lines.write(out / "late_cycles.md")
    print(f"wrote {out / 'late_cycles.md'}")


if __name__ == "__main__":
    main()
