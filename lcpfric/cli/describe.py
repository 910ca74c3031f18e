"""``lcpfric describe``: the describing functions of a Jenkins element over motion amplitudes
(issue 39, item 3; :func:`lcpfric.analysis.describing.describing_functions`)."""

from __future__ import annotations

import json
import math

HELP = (
    "equivalent stiffness and damping of a Jenkins element (or the Hertz sphere) against the "
    "motion amplitude"
)
DESCRIPTION = (
    "Print, per amplitude a of the motion x = a cos(wt), the describing functions of a Jenkins "
    "element (a spring kt in series with a Coulomb slider, T = kt (x - w), |T| <= mu N) from its "
    "exact steady cycle: the dissipation per cycle W, k_eq (T's in-phase first harmonic over a), "
    "c_eq_omega (w c_eq: the quadrature harmonic over a, > 0 for dissipation), loss_factor "
    "W/(pi k_eq a^2) and force_amplitude (max |T| over the cycle). The normal load is N0, or "
    "N0 + N1 cos(wt + phi), or with a normal spring N0 + kn un1 cos(wt + phi), clipped at zero "
    "(separation). No result depends on w. With --contact sphere --R --E --nu (and --mu, --N0, "
    "optionally --N1 --phi) the contact is the Hertz sphere by the MDR (--nodes springs), under "
    "the prescribed rigid-body displacement x = a cos(wt): constant N0 gives the exact sums of "
    "the springs' closed forms, a varying load the springs' marched cycles (--samples)."
)
OPTIONS = {
    "amplitude": "--amplitude",
    "amplitudes": "--amplitude",
    "start": "--start",
    "harmonics": "--harmonics",
    "samples": "--samples",
    "nodes": "--nodes",
    "P": "--N0",
}
FIELDS = ("W", "k_eq", "c_eq_omega", "loss_factor", "force_amplitude")


def configure(p) -> None:
    for name, text in (
        ("kt", "tangential stiffness, > 0 (required)"),
        ("mu", "friction coefficient, >= 0 (required)"),
        ("N0", "mean normal load, or the preload with --kn; > 0 (required)"),
        ("N1", "normal load amplitude, >= 0: N = N0 + N1 cos(wt + phi)"),
        ("kn", "normal stiffness, > 0, with --un1: N = N0 + kn un1 cos(wt + phi)"),
        ("un1", "normal displacement amplitude, >= 0 (with --kn)"),
    ):
        p.add_argument(f"--{name}", default=None, metavar="X", help=text)
    p.add_argument(
        "--phi",
        default=None,
        metavar="ANGLE",
        help="phase of the normal load relative to the motion (with --N1 or --un1): radians, "
        "or a multiple of pi such as 0.5pi (default 0)",
    )
    p.add_argument(
        "--amplitude",
        default=None,
        metavar="A[:B:N]",
        help="motion amplitudes a > 0 (required): one value, a comma list, or A:B:N for N "
        "values log-spaced from A to B",
    )
    p.add_argument(
        "--harmonics",
        default="1",
        metavar="H",
        help="also print T's harmonics up to H (|T_k| columns; force_cos and force_sin in "
        "JSON), >= 1 (default 1)",
    )
    p.add_argument(
        "--start",
        default=None,
        metavar="W",
        help="the slider at t = 0 (default 0): it matters only below the slip limit",
    )
    p.add_argument(
        "--method",
        default="single-node",
        choices=("single-node", "driven"),
        help="the exact single node (default) or the event solver (an independent check)",
    )
    g = p.add_argument_group(
        "continuum contact", "the Hertz sphere (MDR springs) under a prescribed displacement"
    )
    g.add_argument(
        "--contact", default=None, choices=("sphere",), help="the Hertz sphere instead of --kt"
    )
    for name, text in (
        ("R", "effective radius, > 0"),
        ("E", "Young's modulus of each body, > 0"),
        ("nu", "Poisson's ratio of each body, in [0, 0.5)"),
    ):
        g.add_argument(f"--{name}", default=None, metavar="X", help=f"{text} (--contact sphere)")
    g.add_argument("--nodes", default="2000", metavar="N", help="MDR springs (default 2000)")
    g.add_argument(
        "--samples",
        default="1024",
        metavar="NS",
        help="samples per period of the springs' march, varying normal load (default 1024)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _refuse_contact(args) -> None:
    from ..errors import InputError

    for name in ("R", "E", "nu"):
        if getattr(args, name) is not None:
            raise InputError(f"--{name}", "applies to --contact sphere")


def _sphere(args):
    """The MDR sphere of ``--contact sphere`` (its options checked, the element's refused)."""
    import math

    from .. import _checks
    from ..errors import InputError
    from ..model import Harmonic
    from ..model.continuum import MDRSphere

    for name in ("kt", "kn", "un1", "start"):
        if getattr(args, name) is not None:
            raise InputError(
                f"--{name}", "does not apply to --contact sphere (its stiffness is the contact's)"
            )
    if args.method != "single-node":
        raise InputError("--method", "does not apply to --contact sphere")
    for name in ("R", "E", "nu", "mu", "N0"):
        if getattr(args, name) is None:
            raise InputError(f"--{name}", "required with --contact sphere (--R --E --nu --mu --N0)")
    R, E, nu, mu, N0 = (
        _checks.parse_number(getattr(args, n), f"--{n}") for n in ("R", "E", "nu", "mu", "N0")
    )
    N1 = 0.0 if args.N1 is None else _checks.parse_number(args.N1, "--N1")
    if args.phi is not None and args.N1 is None:
        raise InputError("--phi", "applies to a varying normal load (--N1)")
    phi = 0.0 if args.phi is None else _checks.parse_angle(args.phi, "--phi")
    if N1 < 0 or N1 >= N0:
        raise InputError("--N1", f"must be in [0, N0) for the sphere (no separation), got {N1:g}")
    nodes = _checks.positive_int("--nodes", args.nodes)
    # N = N0 + N1 cos(wt + phi) = N0 + N1 sin(wt + phi + pi/2)
    P = Harmonic(N0, N1, phi + 0.5 * math.pi) if N1 > 0 else N0
    return MDRSphere(R, E, nu, mu, P, 0.0, nodes=nodes)


def _run_sphere(args, a, harmonics) -> int:
    from .. import _checks
    from ..analysis.describing_contact import contact_describing_functions

    model = _sphere(args)
    samples = _checks.positive_int("--samples", args.samples)
    df = contact_describing_functions(model, a, samples=samples, harmonics=harmonics)
    slip = 1.5 * model.mu * model.P0 / model.k_t0  # Mindlin's gross slip, 3 mu N0/(2 k_t0)
    _print(args, a, df, harmonics, {"slip_limit": slip, "method": df.method}, (
        f"Hertz sphere (MDR, {model.nodes} springs) R = {model.R:.6g}, E = {model.E:.6g}, "
        f"nu = {model.nu:.6g}, mu = {model.mu:.6g}, N0 = {model.P0:.6g}; k_t0 = "
        f"{model.k_t0:.6g}, gross slip from a = 3 mu N0/(2 k_t0) = {slip:.6g}; x = a cos(wt) "
        f"({df.method})"
    ))  # fmt: skip
    return 0


def _print(args, a, df, harmonics, fields, header) -> None:
    """The table (or the JSON object) of describing functions ``df`` over amplitudes ``a``."""
    out = df.as_dict(harmonics=harmonics > 1)
    if args.json:
        one = a.size == 1
        doc = {k: (v[0] if one else v) for k, v in out.items()}
        doc.update(fields)
        print(json.dumps(doc))
        return
    print(header)
    extra = [f"|T_{k}|" for k in range(2, harmonics + 1)]
    names = ["amplitude", *FIELDS, *extra]
    print("  ".join(f"{n:>16}" for n in names))
    for i in range(a.size):
        row = [a[i], *(getattr(df, f)[i] for f in FIELDS)]
        row += [math.hypot(df.force_cos[i, k], df.force_sin[i, k]) for k in range(2, harmonics + 1)]
        print("  ".join(f"{v:>16.10g}" for v in row))


def _element(args):
    from .. import _checks
    from ..errors import InputError
    from ..model.jenkins import JenkinsElement

    for name in ("kt", "mu", "N0"):
        if getattr(args, name) is None:
            raise InputError(f"--{name}", "required (the element: --kt, --mu and --N0)")
    given = {
        name: _checks.parse_number(getattr(args, name), f"--{name}")
        for name in ("kt", "mu", "N0", "N1", "kn", "un1")
        if getattr(args, name) is not None
    }
    if "kn" in given and "N1" in given:
        raise InputError("--kn", "with --kn give the normal displacement amplitude --un1 (N1 = kn "
                         "un1), not --N1")  # fmt: skip
    if "kn" in given and "un1" not in given:
        raise InputError("--kn", "needs --un1, the normal displacement amplitude")
    if "un1" in given and "kn" not in given:
        raise InputError("--un1", "needs --kn, the normal stiffness")
    if args.phi is not None:
        if "N1" not in given and "un1" not in given:
            raise InputError("--phi", "applies to a varying normal load (--N1, or --kn and --un1)")
        given["phi"] = _checks.parse_angle(args.phi, "--phi")
    return JenkinsElement(**given)


def _amplitudes(text):
    from ._grids import parse_amplitudes

    return parse_amplitudes(text, "--amplitude")


def run(args) -> int:
    from .. import _checks
    from ..analysis.describing import describing_functions
    from ..errors import InputError

    if args.amplitude is None:
        raise InputError("--amplitude", "required: one value, a comma list or A:B:N")
    a = _amplitudes(args.amplitude)
    harmonics = _checks.positive_int("--harmonics", args.harmonics)
    if args.contact == "sphere":
        return _run_sphere(args, a, harmonics)
    _refuse_contact(args)
    element = _element(args)
    start = None if args.start is None else _checks.parse_number(args.start, "--start")
    df = describing_functions(element, a, harmonics=harmonics, start=start, method=args.method)
    normal = (
        f"N = N0 + {element.N1:.6g} cos(wt + {element.phi:.6g})" if element.N1 else "constant N"
    )
    _print(args, a, df, harmonics, {"slip_limit": element.slip_limit, "method": df.method}, (
        f"Jenkins element kt = {element.kt:.6g}, mu = {element.mu:.6g}, N0 = {element.N0:.6g} "
        f"({normal}); slip limit mu N0/kt = {element.slip_limit:.6g}; x = a cos(wt)"
    ))  # fmt: skip
    return 0
