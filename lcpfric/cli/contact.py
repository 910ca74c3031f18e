"""``lcpfric contact``: the dissipation per cycle of a continuum contact (the sphere by
dimensionality reduction, the cylinder by half-plane boundary elements, the sphere, a rounded
flat punch or a height map by half-space boundary elements on a grid)."""

from __future__ import annotations

import json

from . import _common, _materials

HELP = "W per cycle of a continuum contact (sphere, cylinder, punch, height map)"
DESCRIPTION = (
    "The periodic steady state of two identical elastic bodies (effective radius R, "
    "each body's E and nu) under P(t) = P0 + P1 sin wt and Q(t) = Q1 sin(wt + phi) "
    "(d = 1): the sphere by the method of dimensionality reduction (--model mdr), "
    "the cylinder in plane strain by half-plane boundary elements (--model "
    "halfplane; P, Q and W per unit length), and the sphere, a flat punch with "
    "rounded edges or a height map (--heightmap FILE.npy --spacing H) by "
    "half-space boundary elements on a square grid (--model halfspace; --dims 2 "
    "for tractions in the plane, Cerruti's coupling). Prints W per cycle and W "
    "k_t0/(mu^2 P0^2) (3-D) or W pi E*/(mu^2 P0^2) (cylinder). With --k-support 0 "
    "(pure "
    "load control) loads with |Q| > mu P at some instant (gross sliding, or Q during "
    "complete separation) have no equilibrium and are refused. Another material below "
    "(--E2 --nu2, or --rigid): the half-space couples pressure and shear (Dundurs' beta)."
)
#: the models of each geometry (the first is the default)
MODELS = {
    "sphere": ("mdr", "halfspace"),
    "cylinder": ("halfplane",),
    "punch": ("halfspace",),
    "heightmap": ("halfspace",),
}
#: each model's class (the registry's ``models``: the methods that solve it)
CLASSES = {"mdr": "MDRSphere", "halfplane": "HalfPlaneCylinder", "halfspace": "HalfSpace"}
OPTIONS = {
    "steps": "--steps",
    "steps_per_cycle": "--steps",
    "k_support": "--k-support",
    "P": "--P0",
    "Q": "--Q1",
    "heights": "--heightmap",
    "spacing": "--spacing",
    "E2": "--E2",
    "nu2": "--nu2",
}
#: fewest springs across the largest contact radius that resolve it (the models' ``min_nodes``)
MIN_NODES = 10
#: fewest increments per cycle, and fewest half-space elements across the contact
MIN_STEPS, MIN_GRID = 4, 8
#: the defaults of --steps, --nodes (by model) and --grid
STEPS, NODES, GRID = 400, {"mdr": 2000, "halfplane": 400}, 40


def configure(p) -> None:
    p.add_argument(
        "--geometry",
        choices=("sphere", "cylinder", "punch"),
        default=None,
        help="sphere (3-D Hertz), cylinder (plane strain) or punch (a flat punch "
        "of radius --radius with edges rounded to --R)",
    )
    p.add_argument(
        "--model",
        choices=("mdr", "halfplane", "halfspace"),
        default=None,
        help="mdr (sphere: dimensionality reduction), halfplane (cylinder: "
        "boundary elements) or halfspace (sphere, punch, height map: boundary "
        "elements on a grid); default: the geometry's first",
    )
    p.add_argument(
        "--R",
        default=None,
        metavar="X",
        help="effective radius (sphere, cylinder) or the punch's edge radius",
    )
    for name, text in (
        ("E", "Young's modulus of each body"),
        ("nu", "Poisson's ratio of each body, in [0, 0.5)"),
        ("mu", "coefficient of friction"),
        ("P0", "mean normal load (> 0)"),
        ("P1", "normal load amplitude"),
        ("Q1", "tangential load amplitude"),
    ):
        p.add_argument(f"--{name}", required=True, metavar="X", help=text)
    _materials.add_options(p)
    p.add_argument(
        "--phi",
        default="0",
        metavar="ANGLE",
        help="phase of Q relative to P: radians, or a multiple of pi (0.6pi, pi/2)",
    )
    p.add_argument(
        "--k-support",
        default="0",
        metavar="K",
        help="tangential stiffness holding the body, in parallel with the contact, in "
        "force per length (absolute; the output prints the contact's own k_t0 to compare; "
        "default 0: pure load control)",
    )
    p.add_argument(
        "--nodes",
        default=None,
        metavar="N",
        help=f"springs across the largest contact radius (mdr, default {NODES['mdr']}) or "
        f"elements across the largest contact width (halfplane, default "
        f"{NODES['halfplane']}); at least {MIN_NODES}",
    )
    p.add_argument(
        "--steps",
        default=str(STEPS),
        metavar="N",
        help=f"increments per cycle (default {STEPS}; at least {MIN_STEPS})",
    )
    g = p.add_argument_group("half-space (--model halfspace)")
    g.add_argument(
        "--grid",
        default=None,
        metavar="N",
        help=f"elements across the largest contact's diameter (sphere, punch; "
        f"default {GRID}, at least {MIN_GRID}); the grid adds 3 %% on each side",
    )
    g.add_argument(
        "--dims",
        default=None,
        choices=("1", "2"),
        help="tangential directions: 1 (tractions along Q) or 2 (in the plane, "
        "Cerruti's coupling when nu > 0)",
    )
    g.add_argument("--radius", default=None, metavar="X", help="the punch's flat radius")
    g.add_argument(
        "--heightmap",
        default=None,
        metavar="FILE.npy",
        help="a square 2-D array of the gap at zero approach (the two surfaces' "
        "heights summed), in length units; needs --spacing",
    )
    g.add_argument("--spacing", default=None, metavar="H", help="the height map's grid spacing")
    g.add_argument(
        "--figures",
        default=None,
        metavar="DIR",
        help="also draw the stick/slip/separation maps (and the traction vectors "
        "with --dims 2) of the steady cycle into DIR",
    )
    g.add_argument(
        "--instants",
        default=None,
        metavar="F,F,...",
        help="with --figures: fractions of the period at which the zones are drawn "
        "(default 0,0.25,0.5,0.75)",
    )
    g.add_argument(
        "--animation",
        default=None,
        metavar="FILE.gif",
        help="also write an animation of the zones over the steady cycle",
    )
    p.add_argument(
        "--method",
        default=None,
        metavar="M",
        help="how each increment is solved, a method of `lcpfric methods` that "
        "solves the model: mdr-bar (mdr: the bar's equation in closed form, "
        "no solver), halfplane-pdas (halfplane: primal-dual active set on the "
        "stick set) or newton-cg (halfspace: semismooth Newton, conjugate "
        "gradients on FFT products); default: the model's",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--no-progress", action="store_true", help="no progress report on stderr")
    _common.add_memory_option(p)


def run(args) -> int:
    from ._progress import Progress

    # on stderr unless --no-progress or --json; quiet for quick runs (it starts after a delay)
    args.reporter = Progress(not args.no_progress and not args.json, what="lcpfric contact")
    try:
        return _run(args)
    finally:
        args.reporter.close()


def _run(args) -> int:
    from .. import _checks
    from ..errors import InputError
    from ..model.continuum import HalfPlaneCylinder, MDRSphere
    from ..model.loads import Harmonic
    from ..periodic import steady_state

    num = {k: _scaled(getattr(args, k), f"--{k}") for k in ("E", "nu", "mu", "P0", "P1", "Q1")}
    phi = _checks.parse_angle(args.phi, "--phi")
    ks = _scaled(args.k_support, "--k-support")
    if args.heightmap is not None and args.geometry is not None:
        raise InputError("--geometry", "does not apply to --heightmap (the array is the surface)")
    geometry = "heightmap" if args.heightmap is not None else args.geometry or "sphere"
    model_name = args.model or MODELS[geometry][0]
    if model_name not in MODELS[geometry]:
        raise InputError(
            "--model",
            f"{model_name!r} does not solve the {geometry}; use "
            f"--model {' or '.join(MODELS[geometry])}",
        )
    method = _method(args.method, model_name)
    second = _materials.second(args, model_name, num, _scaled)
    steps = _checks.positive_int("--steps", args.steps, MIN_STEPS)
    if not num["P0"] > 0:
        raise InputError("--P0", f"the mean normal load must be > 0, got {num['P0']:g}")
    for k in ("P1", "Q1"):
        if num[k] < 0:
            raise InputError(f"--{k}", f"an amplitude must be >= 0, got {num[k]:g}")
    if model_name != "halfspace":
        only = ("grid", "radius", "heightmap", "spacing", "figures", "animation", "instants")
        for option in only:
            if getattr(args, option) is not None:
                raise InputError(
                    f"--{option}", f"applies to --model halfspace only, not --model {model_name}"
                )
        if args.dims is not None:
            raise InputError("--dims", f"applies to --model halfspace only, not {model_name}")
    P, Q = Harmonic(num["P0"], num["P1"]), Harmonic(0.0, num["Q1"], phi)
    if model_name == "halfspace":
        model = _halfspace(args, geometry, num, P, Q, ks, steps, second)
    else:
        if args.R is None:
            raise InputError("--R", f"the {geometry} needs its effective radius")
        R = _scaled(args.R, "--R")
        kind = MDRSphere if model_name == "mdr" else HalfPlaneCylinder
        given = NODES[model_name] if args.nodes is None else args.nodes
        nodes = _checks.positive_int("--nodes", given, kind.min_nodes)
        if nodes > kind.max_nodes:
            raise InputError("--nodes", f"must be at most {kind.max_nodes}, got {nodes}")
        _scene_memory(args, nodes, 1, steps, False, "--nodes")
        model = kind(R, num["E"], num["nu"], num["mu"], P, Q, k_support=ks, nodes=nodes, **second)
    record = model_name == "halfspace" and (args.figures or args.animation) is not None
    if model_name == "halfspace" and model.N**2 * steps > 4e6:  # seconds of normal solves
        args.reporter.stage(f"{model.N} x {model.N} grid: the normal problem at every instant")
    r = steady_state(model, method, steps, history=record, progress=args.reporter.cycle)
    c = r.contact
    out = {
        "W": r.W,
        "W_normalized": c.W_normalized,
        "normalization": c.normalization,
        "contact_size_max": c.contact_size_max,
        "nodes": c.nodes,
        "steps_per_cycle": r.steps_per_cycle,
        "cycles": r.cycles,
        "converged": r.converged,
        "seconds": r.seconds,
        "geometry": geometry,
        "model": model_name,
        "method": r.method,
    }
    if c.k_t0 is not None:
        out["k_t0"] = c.k_t0
    if second:
        out.update(E2=second["E2"], nu2=second.get("nu2"), beta=getattr(model, "beta", 0.0))
    if model_name == "halfspace":
        st = r.solver_stats
        out.update(
            dims=model.dims,
            grid=getattr(model, "grid_across", model.N),
            grid_side=model.N,
            nodes_in_contact_max=c.nodes_in_contact_max,
            normal_seconds=st["normal_seconds"],
            tangential_seconds=st["tangential_seconds"],
        )
        out["files"] = _pictures(args, model, r)
    args.reporter.close()  # before the results, so that they do not mix with a bar
    if args.json:
        print(json.dumps(out))
        return 0
    size = "half-width" if geometry == "cylinder" else "radius"
    unit = " (per unit length)" if geometry == "cylinder" else ""
    k_t0 = "" if c.k_t0 is None else f"k_t0 = {c.k_t0:.6g}; "
    print(
        f"W = {r.W:.10g} per cycle{unit}; {c.normalization} = {c.W_normalized:.10g} "
        f"({k_t0}largest contact {size} {c.contact_size_max:.6g}; {c.nodes} nodes, "
        f"{r.steps_per_cycle} steps per cycle, {r.cycles} cycles, {r.method}, "
        f"{r.seconds:.2f} s)"
    )
    for path in out.get("files", ()):
        print(f"wrote {path}")
    return 0


def _halfspace(args, geometry, num, P, Q, ks, steps, second=None):
    """The half-space model of the options, every option checked before any work."""
    from .. import _checks
    from ..model.continuum.halfspace import HalfSpace
    from ..errors import InputError
    from ._paths import output_dir, output_file

    dims = int(args.dims or 1)
    if args.nodes is not None:
        raise InputError("--nodes", "the half-space takes --grid (elements across the contact)")
    if args.figures is not None:
        output_dir(args.figures, "--figures")
    elif args.instants is not None:
        raise InputError("--instants", "sets the instants --figures draws; give --figures DIR")
    args.fractions = _fractions(args.instants or "0,0.25,0.5,0.75")
    if args.animation is not None:
        output_file(args.animation, "--animation", ".gif")
    common = dict(dims=dims, k_support=ks, **(second or {}))
    if geometry == "heightmap":
        for option in ("grid", "radius", "R"):
            if getattr(args, option) is not None:
                raise InputError(
                    f"--{option}", "does not apply to --heightmap (the array is the surface)"
                )
        if args.spacing is None:
            raise InputError("--spacing", "the height map needs its grid spacing")
        spacing = _scaled(args.spacing, "--spacing")
        heights = _load_heightmap(args.heightmap)
        record = (args.figures or args.animation) is not None
        _scene_memory(args, heights.size, dims, steps, record, "--heightmap")
        return HalfSpace(
            num["E"], num["nu"], num["mu"], P, Q, heights=heights, spacing=spacing, **common
        )
    if args.spacing is not None:
        raise InputError("--spacing", "applies to --heightmap only")
    if args.R is None:
        raise InputError(
            "--R", f"the {geometry} needs --R (its radius, or the punch's edge radius)"
        )
    R = _scaled(args.R, "--R")
    grid = _checks.positive_int("--grid", GRID if args.grid is None else args.grid, MIN_GRID)
    side = grid + 2 * max(2, -(-3 * grid // 100))
    record = (args.figures or args.animation) is not None
    _scene_memory(args, side * side, dims, steps, record, "--grid")
    if geometry == "punch":
        if args.radius is None:
            raise InputError("--radius", "the punch needs its flat radius")
        radius = _scaled(args.radius, "--radius")
        return HalfSpace.punch(R, radius, num["E"], num["nu"], num["mu"], P, Q, grid=grid, **common)
    if args.radius is not None:
        raise InputError("--radius", "applies to --geometry punch only")
    return HalfSpace.sphere(R, num["E"], num["nu"], num["mu"], P, Q, grid=grid, **common)


def _fractions(text) -> tuple:
    """``--instants``: fractions of the period in [0, 1]."""
    import math

    from .. import _checks
    from ..errors import InputError

    parts = [x for x in str(text).split(",") if x.strip()]
    if not parts:
        raise InputError("--instants", "must name at least one fraction of the period")
    out = tuple(_checks.parse_number(x, "--instants") for x in parts)
    if any(not (math.isfinite(f) and 0.0 <= f <= 1.0) for f in out) or len(out) > 12:
        raise InputError(
            "--instants", f"must be 1 to 12 fractions of the period in [0, 1], got {text!r}"
        )
    return out


def _scaled(text, option: str) -> float:
    """A number of the contact's inputs, within 1e-100 to 1e100 in magnitude (or 0): the
    models' formulas take powers and products of them, which overflow beyond."""
    from .. import _checks
    from ..errors import InputError

    x = _checks.parse_number(text, option)
    if x != 0.0 and not 1e-100 <= abs(x) <= 1e100:
        raise InputError(
            option, f"must be 0 or of magnitude 1e-100 to 1e100 (change the units), got {x:g}"
        )
    return x


def _scene_memory(args, nodes, dims, steps, record, option) -> None:
    """Refuse a model and steps whose cycle would not fit in memory, before any work (the
    driver checks the same, after the model's set-up): blamed on --steps when the default steps
    would fit, else on the option that sets the nodes (``option``)."""
    from .. import memory

    need = memory.continuum_bytes(nodes, dims, steps, record)
    limit = _common.memory_limit(args)
    if (
        need > limit[0]
        and steps > STEPS
        and memory.continuum_bytes(nodes, dims, STEPS, record) <= limit[0]
    ):
        option = f"{option}, --steps"
    _common.check_memory(need, args, option, f"{nodes} nodes x {steps} steps (d = {dims})")


def _pictures(args, model, r) -> list:
    files = []
    if args.figures is not None:
        from pathlib import Path

        from ..figures.halfspace import write_halfspace_figures

        Path(args.figures).mkdir(exist_ok=True)
        args.reporter.stage(f"writing the figures into {args.figures}")
        written = write_halfspace_figures(
            args.figures, model, r, fractions=args.fractions, progress=args.reporter.stage
        )
        files += [str(f) for f in written]
    if args.animation is not None:
        from ..figures.halfspace import animate_zones

        args.reporter.stage(f"writing the animation {args.animation}")
        files.append(str(animate_zones(model, r, args.animation, progress=args.reporter.stage)))
    return files


def _method(text, model_name: str) -> str | None:
    """``--method``: a registry method that solves the model (None: the model's own)."""
    from ..errors import InputError
    from ..methods import METHODS, get_method

    if text is None:
        return None
    entry, _ = get_method(str(text).strip())
    cls = CLASSES[model_name]
    if cls not in entry.models:
        names = [m.name for m in METHODS.values() if cls in m.models]
        raise InputError(
            "--method",
            f"{entry.name!r} does not solve the {model_name} model "
            f"({cls}); use {' or '.join(names)}",
        )
    return entry.name


def _load_heightmap(path):
    """The height map of ``--heightmap``: one array in numpy's ``.npy`` format."""
    import numpy as np

    from ..errors import InputError

    how = "save the height map (one 2-D array) with numpy.save"
    try:
        heights = np.load(path, allow_pickle=False)
    except OSError as exc:
        raise InputError("--heightmap", f"cannot read {str(path)!r}: {exc}") from None
    except ValueError:
        raise InputError(
            "--heightmap",
            f"{str(path)!r} is not a .npy array file (or holds Python objects); {how}",
        ) from None
    if not isinstance(heights, np.ndarray):  # a .npz archive: several arrays
        heights.close()
        raise InputError("--heightmap", f"{str(path)!r} is a .npz archive, not one array; {how}")
    return heights
