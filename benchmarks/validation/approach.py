"""Continuum contacts under a prescribed normal approach (issue 39, item 1: the normal side as a
normal displacement): the grids' exact load-approach relations against the closed forms, and the
describing functions of a sphere under an oscillating approach.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/approach.py [--out PATH]

* the half-plane cylinder: the discrete approach (of the points at distance ℓ) under a load
  against ``(2P/(π E*)) (ln(2ℓ/a) + 1/2)``, and its order in the element width;
* the half-space sphere: the table's load at the approach d against Hertz's
  ``4/3 E* √R d^(3/2)`` by grid, and the round trip (the normal solve at the table's load finds
  the approach);
* the sphere under ``d(t) = d0 + d1 sin(ωt + 0.3)``, ``x = a cos ωt``: the half-space's describing
  functions by grid against the MDR sphere's (2000 springs) under the same approach (neither is
  exact: the two discretizations' agreement, by grid);
* the half-plane under an approach that separates over part of the cycle: W and k_eq.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.analysis.describing_contact import contact_describing_functions  # noqa: E402
from lcpfric.model import Harmonic  # noqa: E402
from lcpfric.model.continuum.closed_forms import cylinder_approach, moduli  # noqa: E402
from lcpfric.model.continuum.halfplane import HalfPlaneCylinder  # noqa: E402
from lcpfric.model.continuum.halfspace import HalfSpace  # noqa: E402
from lcpfric.model.continuum.mdr import MDRSphere  # noqa: E402
from lcpfric.model.continuum.normal3d import normal_contact  # noqa: E402

E, NU, MU = 1.0, 0.3, 0.3


def cylinder() -> None:
    print("## 1. Half-plane cylinder: the approach of the points at distance ℓ = 50 R")
    print("R = 1, E = 1, ν = 0.3, P = 1e-3 per unit length")
    exact = float(cylinder_approach(1e-3, 1.0, E, NU, 50.0))
    print(f"closed form δ = (2P/(π E*)) (ln(2ℓ/a) + 1/2) = {exact:.12g}")
    print("| elements | δ (discrete) | relative error | order |")
    print("|---|---|---|---|")
    prev = None
    for n in (100, 200, 400, 800, 1600):
        m = HalfPlaneCylinder(1.0, E, NU, MU, 1e-3, 0.0, nodes=n, datum=50.0)
        p = m.normal_problem().pressure(1e-3)
        d = float(np.mean((m.h + m.A @ p)[p > 0]))
        err = abs(d / exact - 1)
        order = f"{np.log2(prev / err):.2f}" if prev else ""
        print(f"| {n} | {d:.12g} | {err:.2e} | {order} |")
        prev = err
    print()


def sphere_table() -> None:
    print("## 2. Half-space sphere: the grid's exact P(d) against Hertz")
    d = Harmonic(1e-2, 0.5e-2, 0.0)
    print("R = 1, E = 1, ν = 0.3; d(t) = 1e-2 + 0.5e-2 sin t; 16 instants")
    print("| grid | build (s) | max |P/Hertz - 1| | order | max |d(P) - d| / d (round trip) |")
    print("|---|---|---|---|---|")
    Es = moduli(E, NU)["E*"]
    t = np.linspace(0.0, 2 * np.pi, 17)[:-1]
    prev = None
    for grid in (16, 24, 32, 40):
        start = time.perf_counter()
        m = HalfSpace.under_approach(E, NU, MU, d, R=1.0, grid=grid)
        built = time.perf_counter() - start
        P = m.P(t)
        err = float(np.max(np.abs(P / (4 / 3 * Es * d(t) ** 1.5) - 1)))
        trip = max(abs(normal_contact(m.op, m.g0, x).d / d(s) - 1) for s, x in zip(t, P))
        order = f"{np.log(prev[1] / err) / np.log(grid / prev[0]):.2f}" if prev else ""
        print(f"| {grid} | {built:.2f} | {err:.3e} | {order} | {trip:.1e} |")
        prev = (grid, err)
    print()


def describing() -> None:
    print("## 3. A sphere under an oscillating approach: half-space against MDR")
    d = Harmonic(1e-2, 0.5e-2, 0.3)
    a = np.array([1e-4, 1e-3, 1e-2])
    print("d(t) = 1e-2 + 0.5e-2 sin(t + 0.3), x = a cos t; MDR 2000 springs, 2048 samples;")
    print("half-space d = 1, active-set, 200 steps")
    mdr = contact_describing_functions(
        MDRSphere.under_approach(1.0, E, NU, MU, d, nodes=2000), a, samples=2048
    )
    print(f"MDR ({mdr.seconds:.2f} s): W = {np.array2string(mdr.W, precision=6)}")
    print(f"                k_eq = {np.array2string(mdr.k_eq, precision=6)}")
    print("| grid | s | W/W_MDR - 1 at a = 1e-4, 1e-3, 1e-2 | k_eq/k_eq,MDR - 1 |")
    print("|---|---|---|---|")
    for grid in (16, 24, 32):
        hs = contact_describing_functions(
            HalfSpace.under_approach(E, NU, MU, d, R=1.0, grid=grid), a, steps=200
        )
        w = ", ".join(f"{x:+.2e}" for x in hs.W / mdr.W - 1)
        k = ", ".join(f"{x:+.2e}" for x in hs.k_eq / mdr.k_eq - 1)
        print(f"| {grid} | {hs.seconds:.1f} | {w} | {k} |")
    print()


def separating() -> None:
    print("## 4. The half-plane under an approach that separates")
    d = Harmonic(0.01, 0.02, 0.0)
    m = HalfPlaneCylinder.under_approach(1.0, E, NU, MU, d, datum=50.0, nodes=100)
    t = np.linspace(0.0, m.period, 721)
    apart = float(np.mean(m.P(t) == 0.0))
    print(f"d(t) = 0.01 + 0.02 sin t (ℓ = 50): apart over {apart:.3f} of the cycle")
    r = contact_describing_functions(m, [1e-4, 1e-3, 1e-2], steps=400)
    for x, W, k in zip(r.amplitude, r.W, r.k_eq):
        print(f"a = {x:g}: W = {W:.6e}, k_eq = {k:.6e}")
    print(f"({r.seconds:.1f} s)")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/approach.md"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Continuum contacts under a prescribed normal approach",
        "validation/approach.py",
        markdown=True,
    ):
        cylinder()
        sphere_table()
        describing()
        separating()


if __name__ == "__main__":
    main()
