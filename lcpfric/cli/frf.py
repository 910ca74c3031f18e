"""``lcpfric frf``: the frequency response of the dynamic single node (W, amplitude, phase and
stability against the forcing frequency, exact; :mod:`lcpfric.analysis.frequency_response`)."""

from __future__ import annotations

import json

HELP = "frequency response of the node with a mass: W, amplitude, phase against omega"
DESCRIPTION = (
    "Solve the node with a mass m and damping c (m v'' + c v' + k11 v = F - Q, |F| <= f N) under "
    "P = P0 + P1 sin wt, Q = Q0 + Q1 sin(wt + phi) exactly at each forcing frequency w of "
    "--omega, and print W per cycle, the amplitude (max v - min v)/2, the lag of v behind -Q "
    "and the orbit's stability (its Floquet multipliers). Without --k11, --f and --P0 the "
    "input is normalized (k11 = f = P0 = 1: --P1 and --Q1 are P1_hat and Q1_hat)."
)
OPTIONS = {"omegas": "--omega", "samples": "--samples"}


def configure(p) -> None:
    p.add_argument("--P1", required=True, metavar="X", help="normal load amplitude")
    p.add_argument("--Q1", required=True, metavar="X", help="tangential load amplitude")
    p.add_argument(
        "--phi", default="0", metavar="ANGLE", help="phase of Q relative to P (radians, or 0.5pi)"
    )
    for name, text in (
        ("k11", "tangential stiffness (default 1)"),
        ("f", "coefficient of friction (default 1)"),
        ("P0", "mean normal load (default 1)"),
    ):
        p.add_argument(f"--{name}", default=None, metavar="X", help=text)
    p.add_argument("--mass", required=True, metavar="M", help="the node's mass, > 0")
    p.add_argument("--damping", default="0", metavar="C", help="viscous damping (default 0)")
    p.add_argument(
        "--omega",
        required=True,
        metavar="A:B:N",
        help="forcing frequencies: one value, a comma list, or A:B:N (N values, linear)",
    )
    p.add_argument(
        "--samples", default="256", metavar="N", help="samples for the phase (default 256)"
    )
    p.add_argument("--out", default=None, metavar="FILE", help="write the figure (.png or .pdf)")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def run(args) -> int:
    from .. import _checks
    from ..analysis.frequency_response import frequency_response
    from ..errors import InputError
    from ..model import SingleNode
    from ._grids import parse_grid

    num = {k: _checks.parse_number(getattr(args, k), f"--{k}") for k in ("P1", "Q1", "mass",
           "damping")}  # fmt: skip
    phi = _checks.parse_angle(args.phi, "--phi")
    dims = {
        k: _checks.parse_number(getattr(args, k), f"--{k}")
        for k in ("k11", "f", "P0")
        if getattr(args, k) is not None
    }
    omegas = parse_grid(args.omega, "--omega")
    if not num["mass"] > 0:
        raise InputError("--mass", f"must be > 0 (a frequency response needs a mass), got "
                         f"{num['mass']:g}")  # fmt: skip
    samples = _checks.positive_int("--samples", args.samples, 16)
    out = None
    if args.out is not None:
        from ._paths import output_file

        out = output_file(args.out, "--out", (".png", ".pdf"))
        from . import _common

        _common.require_extras("frequency-response figures", ["matplotlib"])
    node = SingleNode(P1=num["P1"], Q1=num["Q1"], phi=phi, omega=float(omegas[0]), **dims,
                      mass=num["mass"], damping=num["damping"], dimensional=bool(dims))  # fmt: skip
    for w in omegas:  # every frequency checked before the work
        if not w > 0:
            raise InputError("--omega", f"every frequency must be > 0, got {w:g}")
        SingleNode(P1=num["P1"], Q1=num["Q1"], phi=phi, omega=float(w), **dims,
                   mass=num["mass"], damping=num["damping"])  # fmt: skip
    res = frequency_response(node, omegas, samples=samples)
    if out is not None:
        from ..figures.dynamic import figure_frequency_response

        figure_frequency_response(res).savefig(out)
    fields = {
        "omega": res.omega.tolist(),
        "beta": res.beta.tolist(),
        "W": res.W.tolist(),
        "amplitude": res.amplitude.tolist(),
        "phase": res.phase.tolist(),
        "stable": res.stable.tolist(),
        "orbits": res.orbits.tolist(),
    }
    if args.json:
        one = len(omegas) == 1
        js = {k: (v[0] if one else v) for k, v in fields.items()}
        js.update(omega0=float(node.natural_frequency), zeta=node.zeta, seconds=res.seconds)
        if out is not None:
            js["figure"] = str(out)
        print(json.dumps(js))
        return 0
    print(f"omega0 = {node.natural_frequency:.10g}, zeta = {node.zeta:.6g}; exact, "
          f"{res.seconds:.3g} s")  # fmt: skip
    print(f"{'omega':>14} {'omega/omega0':>13} {'W':>16} {'amplitude':>16} {'phase':>10}  stable")
    for w, b, W, a, ph, st in zip(*(fields[k] for k in ("omega", "beta", "W", "amplitude",
                                                         "phase", "stable"))):  # fmt: skip
        print(f"{w:14.8g} {b:13.6g} {W:16.10g} {a:16.10g} {ph:10.6f}  {'yes' if st else 'NO'}")
    if out is not None:
        print(f"wrote {out}")
    return 0
