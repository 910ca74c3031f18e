"""
A contact with several nodes
============================

The general uncoupled system ``F = Q(t) + K u``, ``|F_i| <= f_i N_i(t)``.

Three nodes of a joint, each with its own tangential stiffness, friction coefficient and loads
(normal loads in phase but of different amplitude, as across a rocking joint; tangential loads
with different phases). With a diagonal stiffness K the nodes do not interact tangentially, so
the ``projection`` method solves each increment in closed form, and the total dissipation must
equal the sum of the single-node exact results: this script checks that.

    python examples/multi_node.py [--steps N]
"""

import argparse
import math
import os

import numpy as np

import lcpfric
from lcpfric import ContactSystem, Harmonic, IndependentSprings, SingleNode

OMEGA = 2 * math.pi * 50.0  # a 50 Hz load cycle
#           k [N/m]  f     P0 [N]  P1 [N]  Q1 [N]  φ
NODES = [
    (2.0e8, 0.3, 1000.0, 400.0, 450.0, 0.5 * math.pi),
    (3.0e8, 0.4, 1000.0, 1200.0, 700.0, 0.6 * math.pi),
    (2.5e8, 0.5, 1000.0, 2500.0, 900.0, 0.3 * math.pi),
]


def system() -> ContactSystem:
    k, f, P0, P1, Q1, phi = (np.array(c) for c in zip(*NODES))
    return ContactSystem(
        stiffness=np.diag(k),
        friction=f,
        tangential_loads=tuple(Harmonic(0.0, q, p, OMEGA) for q, p in zip(Q1, phi)),
        normal=IndependentSprings(tuple(Harmonic(p0, p1, 0.0, OMEGA) for p0, p1 in zip(P0, P1))),
        dims=1,
    )


DESCRIPTION = "A contact with several nodes"


def main(argv=None):
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument(
        "--steps",
        type=int,
        default=int(os.environ.get("LCPFRIC_EXAMPLE_STEPS", 4000)),
        help="steps per cycle",
    )
    args = parser.parse_args(argv)

    print(
        f"{'node':>4} {'k [N/m]':>9} {'f':>4} {'P1_hat':>7} {'Q1_hat':>7} {'phi/pi':>6} "
        f"{'W exact [mJ]':>13}"
    )
    exact = []
    for i, (k, f, P0, P1, Q1, phi) in enumerate(NODES):
        node = SingleNode(k11=k, f=f, P0=P0, P1=P1, Q1=Q1, omega=OMEGA, phi=phi)
        exact.append(lcpfric.steady_state(node, method="exact").W)
        print(
            f"{i:4d} {k:9.2g} {f:4.2g} {node.P1_hat:7.3f} {node.Q1_hat:7.3f} "
            f"{phi / math.pi:6.2f} {1e3 * exact[-1]:13.6f}"
        )

    res = lcpfric.steady_state(system(), method="projection", steps_per_cycle=args.steps)
    total = sum(exact)
    print(
        f"\nprojection, {res.steps_per_cycle} steps per cycle, {res.cycles} cycles, converged "
        f"{res.converged}: W = {1e3 * res.W:.6f} mJ per cycle"
    )
    print(
        f"sum of the single-node exact results:          {1e3 * total:.6f} mJ "
        f"(relative difference {abs(res.W - total) / total:.1e})"
    )
    print(f"dissipated power at 50 Hz: {50.0 * res.W:.4f} W")


if __name__ == "__main__":
    main()
