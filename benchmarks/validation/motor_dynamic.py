"""The paper's motor (Fig. 9) through resonance (issue 40, item 6): the rotor's inertia on the
joint's stiffness (the dynamic single node, ``Motor.dynamic_dissipation``), against the paper's
quasi-static estimate.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/motor_dynamic.py [--out PATH]
        [--figures DIR]

* the quasi-static limit: at fixed speeds (loads) the joint made stiffer, so that Ω/Ω0 -> 0: the
  dynamic Ŵ against the quasi-static ``exact`` Ŵ, the relative difference and its rate;
* W per revolution against Ω/Ω0 from 0.01 to 2 for the friction coefficients of Fig. 9, with
  the damping ratio ζ = 0.05, beside the quasi-static W; the figure ``docs/motor_dynamic.png``;
* the range of Ω/Ω0 over which the quasi-static estimate stays within 5 % of the dynamic W.
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

from lcpfric import exact_W_hat  # noqa: E402
from lcpfric.exact.dynamic_api import dynamic_cycle  # noqa: E402
from lcpfric.paper.curves import MOTOR, MOTOR_FRICTION  # noqa: E402
from lcpfric.paper.motor import Motor  # noqa: E402

ZETA = 0.05


def limit() -> None:
    print("## 1. The quasi-static limit at fixed speed (the joint made stiffer)\n")
    motor = Motor(**MOTOR)
    print(f"motor {MOTOR}, ζ = {ZETA}; Ω in units of the separation speed "
          f"{motor.separation_speed():.4g} rad/s\n")  # fmt: skip
    print("| f | Ω | β = Ω/Ω0 | Ŵ dynamic | Ŵ quasi-static | rel. difference | rate | s |")
    print("|---|---|---|---|---|---|---|---|")
    for f, speed in ((0.3, 1.5), (0.3, 3.0), (0.8, 3.0)):
        Om = speed * motor.separation_speed()
        P1, Q1 = motor.P1_hat(Om), motor.Q1_hat(Om, f)
        qs = float(exact_W_hat(P1, Q1, motor.phi))
        prev = None
        for beta in (1e-1, 1e-2, 1e-3, 1e-4):
            start = time.perf_counter()
            W = dynamic_cycle(P1, Q1, motor.phi, beta, ZETA).W_hat
            sec = time.perf_counter() - start
            d = abs(W / qs - 1)
            rate = f"{math.log(prev[1] / d) / math.log(prev[0] / beta):.2f}" if prev else ""
            print(f"| {f} | {speed} | {beta:g} | {W:.12g} | {qs:.12g} | {d:.2e} | {rate} | "
                  f"{sec:.2f} |")  # fmt: skip
            prev = (beta, d)
    print("\ngoal: within 1e-4 relative by Ω/Ω0 = 1e-4\n")


def resonance(out_dir: _Path) -> None:
    from lcpfric.figures.dynamic import figure_motor_dynamic
    from lcpfric.figures.style import save

    print(f"## 2. Through resonance (ζ = {ZETA})\n")
    motor = Motor(**MOTOR)
    O0 = motor.natural_frequency()
    ratio = np.geomspace(0.01, 2.0, 161)
    rows = []
    start = time.perf_counter()
    for f in MOTOR_FRICTION:
        W = motor.dynamic_dissipation(ratio * O0, f, ZETA)
        rows.append((f, W, motor.dissipation(ratio * O0, f)))
    seconds = time.perf_counter() - start
    print(f"{len(ratio) * len(MOTOR_FRICTION)} points in {seconds:.1f} s\n")
    bands = ((0.0, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.5), (0.5, 2.0))
    head = " | ".join(f"({a:g}, {b:g}]" for a, b in bands)
    print("Largest |W_qs / W - 1| over the slipping speeds (W > 0) in each band of Ω/Ω0, and the")
    print("largest Ω/Ω0 up to which it stays within 5 % from the shakedown speed on:\n")
    print(f"| f | shakedown below | {head} | within 5 % up to | W_qs / W at 0.5, 1, 2 |")
    print("|---|---|" + "---|" * len(bands) + "---|---|")
    for f, W, Wqs in rows:
        sd = motor.shakedown_speed(f) / O0
        slipping = W > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            err = np.where(slipping, np.abs(Wqs / W - 1.0), np.nan)
        cells = []
        for a, b in bands:
            sel = slipping & (ratio > a) & (ratio <= b)
            cells.append(f"{100 * np.nanmax(err[sel]):.1f} %" if sel.any() else "-")
        bad = np.flatnonzero(slipping & (err > 0.05))
        top = (
            f"{ratio[bad[0] - 1]:.3g}" if bad.size and bad[0] > 0 and slipping[bad[0] - 1] else "-"
        )
        at = ", ".join(f"{np.interp(x, ratio, Wqs / np.where(slipping, W, np.nan)):.3g}"
                       for x in (0.5, 1.0, 2.0))  # fmt: skip
        print(f"| {f} | {sd:.3g} | {' | '.join(cells)} | {top} | {at} |")
    fig = figure_motor_dynamic(ratio, rows, ZETA)
    paths = save(fig, out_dir, "motor_dynamic", ("png", "pdf"))
    print(f"\nwrote {', '.join(p.name for p in paths)}\n")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/motor-dynamic.md"))
    parser.add_argument("--figures", default=str(_ROOT / "docs"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "The paper's motor through resonance",
        "validation/motor_dynamic.py",
        markdown=True,
    ):
        limit()
        resonance(_Path(args.figures))


if __name__ == "__main__":
    main()
