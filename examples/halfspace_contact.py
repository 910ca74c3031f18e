"""
A sphere on the half-space: stick, slip and separation
======================================================

Two identical spheres (ν = 0.3) on boundary elements of the 3-D half-space, with tractions in
the plane (``dims=2``: Cerruti's coupling of the two tangential directions), under a normal load
oscillating by half its mean and a tangential load a quarter of a cycle later, held by a
support. The steady state (``newton-cg``: semismooth Newton steps, conjugate gradients on FFT
products) is drawn at four instants of the cycle: which elements stick, slip forward or
backward, or are separated.

    python examples/halfspace_contact.py [--grid N]
"""

import argparse
import math
import os

import lcpfric
from lcpfric import Harmonic


def main(argv=None):
    parser = argparse.ArgumentParser(description="A sphere on the half-space")
    parser.add_argument(
        "--grid",
        type=int,
        default=int(os.environ.get("LCPFRIC_EXAMPLE_GRID", 24)),
        help="elements across the largest contact",
    )
    args = parser.parse_args(argv)

    def sphere(k_support):
        return lcpfric.HalfSpace.sphere(
            10.0,
            200e3,
            0.3,
            0.5,
            Harmonic(100.0, 50.0),
            Harmonic(0.0, 30.0, 0.5 * math.pi),
            grid=args.grid,
            dims=2,
            k_support=k_support,
        )

    model = sphere(0.0)
    model = model.with_support(model.k_t0)
    res = lcpfric.steady_state(model, steps_per_cycle=80)
    st = res.solver_stats
    print(
        f"{model.N} x {model.N} elements, at most {res.contact.nodes_in_contact_max} in "
        f"contact; W = {res.W:.6g} N mm per cycle, W k_t0/(μ² P0²) = {res.W_normalized:.5f}"
    )
    print(
        f"{res.cycles} cycles ({st.get('extrapolations', 0)} starts moved), "
        f"{st['tangential_products']} FFT products in the increments, "
        f"{res.seconds:.1f} s"
    )

    from lcpfric.figures.halfspace import figure_zone_maps

    fig = figure_zone_maps(model, res, fractions=(0.0, 0.25, 0.5, 0.75))
    import matplotlib.pyplot as plt

    manager = plt.figure(figsize=fig.get_size_inches()).canvas.manager  # show it via pyplot
    manager.canvas.figure = fig
    fig.set_canvas(manager.canvas)
    plt.show()


if __name__ == "__main__":
    main()
