"""The spectrum of the d = 2 half-space's cycle map at its steady state: why d = 2 takes about
a dozen cycles.

``OPENBLAS_NUM_THREADS=1 python benchmarks/studies/cycle_spectrum.py [--quick] [--out DIR]``

writes ``DIR/cycle_spectrum.md`` (default ``benchmarks/results``; about 4 minutes, ``--quick``
about 1). The plain cycle map takes a cycle's starting slips x to its ending ones G(x). At the
steady state x*, Arnoldi's iteration on its Jacobian J (each product a finite difference of two
whole cycles, ``(G(x* + ε v) − G(x*)) / ε``) gives J's largest eigenvalues (Ritz values). The
eigenvalue 1 belongs to the nodes that stick the whole cycle (any start of theirs repeats:
neutral); the others say how fast the cycles settle. Plain cycles contract by the largest one
per cycle; Anderson's acceleration (a secant method, about GMRES on a linear map) does about as
well as a Krylov method can on the whole set, so a spectrum spread over many eigenvalues costs
many cycles however the starts are moved. The cases: Mindlin-Deresiewicz (constant P,
Q1/(μP0) = 0.5, ν = 0.3, d = 2) on grid 20 with 100 steps and on grid 40 with 200 steps.
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
import time
from pathlib import Path

import numpy as np


from _report import Report, stamp  # noqa: E402
from halfspace import sphere  # noqa: E402

import lcpfric  # noqa: E402
from lcpfric.periodic.acceleration import Anderson  # noqa: E402
from lcpfric.results import StepState  # noqa: E402
from lcpfric.steppers.continuum import ContinuumData  # noqa: E402
from lcpfric.steppers.newton_cg import NewtonCGStepper  # noqa: E402

#: Arnoldi steps (products with J)
KRYLOV = 40


def fixed_point(model, steps, tol=1e-13):
    """The steady state's starting state: cycles (Anderson-accelerated, increments to the
    stepper's ``increment_tol`` ``tol``, no warm starts from the previous cycle) until the start
    repeats to 1e-14 of the slips' scale, or, once it repeats to 1e-10, until its change stops
    falling (three cycles without halving the smallest so far: the increments' round-off, about
    1e-12 of the slips with the tolerance 1e-13, a millionth of the finite differences' step).
    The increments are the ``newton-cg`` stepper's, driven by hand on the model's scene.
    Returns ``(cycle, restart, state, x*, G(x*), cycles)``: ``cycle(state)`` runs one cycle
    from a tangential state, ``restart(state, v)`` is the state with the slips v."""
    stepper = NewtonCGStepper(increment_tol=tol)
    scene = lcpfric.make_scene(model, steps)
    ctx = stepper.context(scene)
    b, Q = scene.limits, scene.Q

    def cycle(state):
        for j in range(steps):
            state, _, _ = stepper.increment(ctx, state, b[j + 1], Q[j + 1])
        return state

    def restart(state, v):
        step = StepState(u=state.v, F=state.F, state=None, data=ContinuumData(state, ctx))
        return stepper.restart(scene, step, v).data.tangential

    state = cycle(stepper.start(scene, ctx))
    x, accelerate = state.v.copy(), Anderson()
    smallest, stalled = np.inf, 0
    for k in range(100):
        end = cycle(restart(state, x))
        g = end.v.copy()
        change = np.max(np.abs(g - x)) / np.max(np.abs(g))
        stalled = stalled + 1 if change > 0.5 * smallest else 0
        smallest = min(smallest, change)
        if change <= 1e-14 or (smallest <= 1e-10 and stalled >= 3):
            return cycle, restart, end, x, g, k + 2
        jump = accelerate(x, g)
        state, x = end, (g if jump is None else jump)
    raise RuntimeError("no steady state in 100 cycles")


def ritz(model, steps, krylov=KRYLOV):
    """The Ritz values of the cycle map's Jacobian at the steady state, largest first, and the
    seconds and cycles it took."""
    start = time.perf_counter()
    cycle, restart, state, x, g, cycles = fixed_point(model, steps)
    eps = 1e-6 * float(np.max(np.abs(x)))
    n = x.size
    V = np.zeros((n, krylov + 1))
    H = np.zeros((krylov + 1, krylov))
    v = np.random.default_rng(0).standard_normal(n)
    V[:, 0] = v / np.linalg.norm(v)
    k = krylov
    for j in range(krylov):
        w = (cycle(restart(state, x + eps * V[:, j])).v - g) / eps
        for i in range(j + 1):  # modified Gram-Schmidt
            H[i, j] = V[:, i] @ w
            w -= H[i, j] * V[:, i]
        H[j + 1, j] = np.linalg.norm(w)
        if H[j + 1, j] < 1e-12:
            k = j + 1
            break
        V[:, j + 1] = w / H[j + 1, j]
    values = np.linalg.eigvals(H[:k, :k])
    return values[np.argsort(-np.abs(values))], time.perf_counter() - start, cycles


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="grid 20 only")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "results"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(exist_ok=True)
    lines = Report(
        [
            "# The spectrum of the d = 2 half-space's cycle map",
            "",
            f"{stamp('studies/cycle_spectrum.py' + (' --quick' if args.quick else ''))}. "
            f"Mindlin-Deresiewicz, "
            f"Q1/(μP0) = 0.5, ν = 0.3, d = 2, model tol 1e-13; {KRYLOV} Arnoldi steps, each a "
            f"finite difference of two whole cycles at the steady state.",
            "",
        ]
    )
    emit = lines.emit

    emit(
        "| grid | steps | moduli of the Ritz values, largest first (1: the stuck nodes, "
        "neutral) | non-neutral ≥ 0.2 | seconds |"
    )
    emit("|---|---|---|---|---|")
    for grid, steps in ((20, 100),) if args.quick else ((20, 100), (40, 200)):
        model = sphere(Q1=0.5, grid=grid, nu=0.3, dims=2)  # increments to 1e-13
        values, seconds, _ = ritz(model, steps)
        mags = np.abs(values)
        slow = int(np.count_nonzero((mags >= 0.2) & (mags < 1.0 - 1e-6)))
        shown = " ".join(f"{m:.3f}" for m in mags[:24])
        emit(f"| {grid} | {steps} | {shown} … | {slow} | {seconds:.0f} |")
    emit("")
    emit(
        "Plain cycles contract by the largest non-neutral value per cycle; a Krylov method "
        "(Anderson's acceleration is one) on values up to λ contracts by about "
        "(√κ − 1)/(√κ + 1) per product with κ = 1/(1 − λ), better on a few isolated values. "
        "The values come in groups of 2 to 4 (the contact's reflection symmetries)."
    )
    lines.write(out / "cycle_spectrum.md")
    print(f"wrote {out / 'cycle_spectrum.md'}")


if __name__ == "__main__":
    main()
