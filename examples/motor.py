"""
A motor bolted to a foundation (the paper's Figs. 8-9)
=======================================================

A 20 kg rotor whose centre of mass is 0.5 mm off its axis turns at Ω. The bolts preload the joint
with P0 = 2 kN and its tangential stiffness is k11 = 5e8 N/m. The out-of-balance force
M Ω² δ loads the joint normally and tangentially, a quarter of a turn apart (φ = π/2):
P1 = Q1 = M Ω² δ, so P̂1 = M Ω² δ / P0 and Q̂1 = P̂1 / f.

This script prints the energy dissipated in the joint per revolution against speed for several
coefficients of friction, checks one point through the general dimensional API, and draws Fig. 9.

    python examples/motor.py [--out DIR] [--points N]
"""

import argparse
import math
import os
from pathlib import Path

import numpy as np

import lcpfric
from lcpfric.paper.motor import Motor

FRICTION = (0.1, 0.2, 0.3, 0.5, 0.8)


DESCRIPTION = "A motor bolted to a foundation (the paper's Figs. 8-9)"


def main(argv=None):
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument(
        "--out",
        default=None,
        help="directory for fig9_motor.png (default: draw it on screen, or in "
        "the documentation's gallery)",
    )
    parser.add_argument(
        "--points",
        type=int,
        default=int(os.environ.get("LCPFRIC_EXAMPLE_POINTS", 400)),
        help="speeds in the figure",
    )
    args = parser.parse_args(argv)

    motor = Motor(M=20.0, delta=0.5e-3, P0=2000.0, k11=5e8)
    print(
        f"rotor M = {motor.M} kg, offset δ = {motor.delta * 1e3} mm, preload P0 = {motor.P0} N, "
        f"joint stiffness k11 = {motor.k11:.3g} N/m"
    )
    print(
        f"natural frequency Ω0 = sqrt(k11/M) = {motor.natural_frequency():.0f} rad/s "
        "(the analysis is quasi-static: Ω ≪ Ω0)"
    )
    print(
        f"separation begins at Ω = {motor.separation_speed():.1f} rad/s "
        f"({motor.separation_speed() * 30 / math.pi:.0f} rpm)"
    )
    for f in FRICTION:
        print(
            f"  f = {f:<4g}: no dissipation (shakedown) below Ω = {motor.shakedown_speed(f):.1f} "
            "rad/s"
        )

    speeds = np.array([100, 200, 300, 400, 500, 600, 800, 1000.0])
    print("\nenergy dissipated per revolution W [mJ]")
    print(
        f"{'Ω [rad/s]':>10} {'rpm':>6} {'P1_hat':>7} "
        + " ".join(f"{'f=' + str(f):>9}" for f in FRICTION)
    )
    table = {f: motor.dissipation(speeds, f) for f in FRICTION}
    for i, w in enumerate(speeds):
        print(
            f"{w:10.0f} {w * 30 / math.pi:6.0f} {motor.P1_hat(w):7.3f} "
            + " ".join(f"{1e3 * table[f][i]:9.4f}" for f in FRICTION)
        )

    # The same number through the general, dimensional single-node API (Eqs. 1-6).
    Omega, f = 600.0, 0.3
    node = lcpfric.SingleNode(
        k11=motor.k11,
        f=f,
        P0=motor.P0,
        P1=motor.force(Omega),
        Q1=motor.force(Omega),
        omega=Omega,
        phi=math.pi / 2,
    )
    W = lcpfric.steady_state(node, method="exact").W
    W_motor = motor.dissipation(Omega, f)
    print(
        f"\ncheck at Ω = {Omega:g} rad/s, f = {f}: SingleNode + steady_state gives W = "
        f"{1e3 * W:.6f} mJ; Motor.dissipation gives {1e3 * W_motor:.6f} mJ"
    )

    from lcpfric.paper.figures import figure_motor

    fig = figure_motor(motor.M, motor.delta, motor.P0, motor.k11, FRICTION, points=args.points)
    if args.out is None:
        _show(fig)
        return
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "fig9_motor.png"
    fig.savefig(path, dpi=150)
    print(f"wrote {path}")


def _show(fig) -> None:
    """Show a figure built outside pyplot (lcpfric's figures are) through pyplot: it takes the
    place of a new pyplot figure's own."""
    import matplotlib.pyplot as plt

    manager = plt.figure(figsize=fig.get_size_inches()).canvas.manager
    manager.canvas.figure = fig
    fig.set_canvas(manager.canvas)
    plt.show()


if __name__ == "__main__":
    main()
