"""
Loads with two harmonics
========================

A single contact node under loads with two harmonics (beyond the paper's Eq. 1).

The normal load gets a second harmonic, P(t) = P0 + P1 sin ωt + P2 sin(2ωt + ψ), and so does the
tangential load. The closed-form ``exact`` method needs the paper's one-harmonic loads, so the
time-stepping methods take over: ``explicit`` (the paper's state-based stepper, events located)
and ``projection`` (one closed-form projection per step). With P2 = Q2 = 0 all three agree, which
checks the steppers; then the second harmonic is switched on.

    python examples/two_harmonic.py [--steps N]
"""

import argparse
import math
import os

import lcpfric
from lcpfric import Fourier, SingleNode
from lcpfric.analysis.loop import state_shares

P0, P1, Q1, PHI = 1.0, 1.5, 2.0, 0.6 * math.pi  # the paper's units: k11 = f = P0 = 1


def node(P2: float, Q2: float) -> SingleNode:
    normal = Fourier(mean=P0, amplitudes=(P1, P2), phases=(0.0, 0.3), omega=1.0)
    tangential = Fourier(mean=0.0, amplitudes=(Q1, Q2), phases=(PHI, -0.5), omega=1.0)
    return SingleNode(k11=1.0, f=1.0, normal_load=normal, tangential_load=tangential)


DESCRIPTION = "Loads with two harmonics"


def main(argv=None):
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument(
        "--steps",
        type=int,
        default=int(os.environ.get("LCPFRIC_EXAMPLE_STEPS", 4000)),
        help="steps per cycle of the time-stepping methods",
    )
    args = parser.parse_args(argv)

    exact = lcpfric.exact_W_hat(P1 / P0, Q1, PHI)
    print(f"one harmonic (P1 = {P1}, Q1 = {Q1}, φ = 0.6π): exact W_hat = {exact:.8f}")
    for method in ("explicit", "projection"):
        res = lcpfric.steady_state(node(0.0, 0.0), method=method, steps_per_cycle=args.steps)
        print(
            f"  {method:>10}: W_hat = {res.W_hat:.8f} (relative error "
            f"{abs(res.W_hat - exact) / exact:.1e}, {res.cycles} cycles)"
        )

    print(
        f"\nsecond harmonics switched on ({args.steps} steps per cycle; W is the energy "
        "dissipated per cycle, in units of f P0² / k11 = 1 here):"
    )
    print(
        f"{'P2':>5} {'Q2':>5} {'shakedown':>10} {'explicit W':>12} {'projection W':>13} "
        f"{'separation':>11}"
    )
    for P2, Q2 in ((0.0, 0.0), (0.3, 0.0), (0.0, 0.5), (0.3, 0.5), (0.6, 1.0)):
        n = node(P2, Q2)
        res = {
            m: lcpfric.steady_state(n, method=m, steps_per_cycle=args.steps)
            for m in ("explicit", "projection")
        }
        # the share of the cycle's time in separation (steps weighed by their duration: the
        # default placement may cross a whole separation in one step)
        sep = state_shares(res["explicit"])[lcpfric.State.SEPARATION]
        print(
            f"{P2:5.2f} {Q2:5.2f} {str(lcpfric.shakedown(n).shakedown):>10} "
            f"{res['explicit'].W:12.6f} {res['projection'].W:13.6f} {100 * sep:10.1f}%"
        )


if __name__ == "__main__":
    main()
