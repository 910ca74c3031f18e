"""``lcpfric contact``: the dissipation per cycle of a continuum contact (the sphere by
dimensionality reduction, the cylinder by half-plane boundary elements)."""

from __future__ import annotations

import json

HELP = "W per cycle of a continuum contact (Hertz sphere, cylinder)"
DESCRIPTION = ("The periodic steady state of two identical elastic bodies (effective radius R, "
               "each body's E and nu) under P(t) = P0 + P1 sin wt and Q(t) = Q1 sin(wt + phi) "
               "(d = 1): the sphere by the method of dimensionality reduction (--model mdr), "
               "the cylinder in plane strain by half-plane boundary elements (--model "
               "halfplane; P, Q and W per unit length). Prints W per cycle and W k_t0/(mu^2 "
               "P0^2) (sphere) or W pi E*/(mu^2 P0^2) (cylinder). With --k-support 0 (pure "
               "load control) loads with |Q| > mu P at some instant (gross sliding, or Q during "
               "complete separation) have no equilibrium and are refused.")
#: the model of each geometry
MODELS = {"sphere": "mdr", "cylinder": "halfplane"}
#: the methods that solve each model's increments (the first is the default)
METHODS = {"mdr": ("exact-increment",), "halfplane": ("active-set",)}
OPTIONS = {"steps": "--steps", "k_support": "--k-support", "P": "--P0", "Q": "--Q1"}
#: fewest springs across the largest contact radius that resolve it
MIN_NODES = 10


def configure(p) -> None:
    p.add_argument("--geometry", choices=tuple(MODELS), default="sphere",
                   help="sphere (3-D Hertz) or cylinder (plane strain)")
    p.add_argument("--model", choices=tuple(MODELS.values()), default=None,
                   help="mdr (sphere: dimensionality reduction) or halfplane (cylinder: "
                        "boundary elements); default: the geometry's")
    for name, text in (("R", "effective radius"), ("E", "Young's modulus of each body"),
                       ("nu", "Poisson's ratio of each body, in [0, 0.5)"),
                       ("mu", "coefficient of friction"), ("P0", "mean normal load (> 0)"),
                       ("P1", "normal load amplitude"), ("Q1", "tangential load amplitude")):
        p.add_argument(f"--{name}", required=True, metavar="X", help=text)
    p.add_argument("--phi", default="0", metavar="ANGLE",
                   help="phase of Q relative to P: radians, or a multiple of pi (0.6pi, pi/2)")
    p.add_argument("--k-support", default="0", metavar="K",
                   help="tangential stiffness holding the body, in parallel with the contact "
                        "(default 0: pure load control)")
    p.add_argument("--nodes", default=None, metavar="N",
                   help=f"springs across the largest contact radius (mdr, default 2000) or "
                        f"elements across the largest contact width (halfplane, default 400); "
                        f"at least {MIN_NODES}")
    p.add_argument("--steps", default="400", metavar="N", help="increments per cycle")
    p.add_argument("--method", default=None, metavar="M",
                   help="how each increment is solved: exact-increment (mdr: the bar's "
                        "equation in closed form, no solver) or active-set (halfplane: "
                        "primal-dual active set on the stick set); default: the model's")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def run(args) -> int:
    from .. import _checks
    from ..contact import HalfPlaneCylinder, MDRSphere
    from ..errors import InputError
    from ..model.loads import Harmonic

    num = {k: _checks.parse_number(getattr(args, k), f"--{k}")
           for k in ("R", "E", "nu", "mu", "P0", "P1", "Q1")}
    phi = _checks.parse_angle(args.phi, "--phi")
    ks = _checks.parse_number(args.k_support, "--k-support")
    model_name = args.model or MODELS[args.geometry]
    if MODELS[args.geometry] != model_name:
        raise InputError("--model", f"{model_name!r} does not solve the {args.geometry}; use "
                                    f"--model {MODELS[args.geometry]}")
    method = args.method or METHODS[model_name][0]
    if method not in METHODS[model_name]:
        raise InputError("--method", f"{method!r} does not solve the {model_name} model; "
                                     f"use one of {', '.join(METHODS[model_name])}")
    default = "2000" if model_name == "mdr" else "400"
    nodes = _count(args.nodes or default, "--nodes")
    steps = _count(args.steps, "--steps")
    if nodes < MIN_NODES:
        raise InputError("--nodes", f"{nodes} springs are too coarse to resolve the contact; "
                                    f"give at least {MIN_NODES}")
    if not num["P0"] > 0:
        raise InputError("--P0", f"the mean normal load must be > 0, got {num['P0']:g}")
    for k in ("P1", "Q1"):
        if num[k] < 0:
            raise InputError(f"--{k}", f"an amplitude must be >= 0, got {num[k]:g}")
    kind = MDRSphere if model_name == "mdr" else HalfPlaneCylinder
    model = kind(num["R"], num["E"], num["nu"], num["mu"], Harmonic(num["P0"], num["P1"]),
                 Harmonic(0.0, num["Q1"], phi), k_support=ks, nodes=nodes)
    r = model.solve(steps)
    out = {"W": r.W, "W_normalized": r.W_normalized, "normalization": r.normalization,
           "contact_size_max": r.contact_size_max, "nodes": r.nodes,
           "steps_per_cycle": r.steps_per_cycle, "cycles": r.cycles, "converged": r.converged,
           "seconds": r.seconds, "geometry": args.geometry, "model": model_name,
           "method": method}
    if r.k_t0 is not None:
        out["k_t0"] = r.k_t0
    if args.json:
        print(json.dumps(out))
        return 0
    size = "radius" if args.geometry == "sphere" else "half-width"
    unit = "" if args.geometry == "sphere" else " (per unit length)"
    print(f"W = {r.W:.10g} per cycle{unit}; {r.normalization} = {r.W_normalized:.10g} "
          f"(largest contact {size} {r.contact_size_max:.6g}; {r.nodes} nodes, "
          f"{r.steps_per_cycle} steps per cycle, {r.cycles} cycles, {r.seconds:.2f} s)")
    return 0


def _count(text, option: str) -> int:
    from .. import _checks
    from ..errors import InputError

    x = _checks.parse_number(text, option)
    if not (x >= 1 and x == int(x)):
        raise InputError(option, f"must be a whole number >= 1, got {text!r}")
    return int(x)
