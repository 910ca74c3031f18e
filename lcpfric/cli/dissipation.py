"""``lcpfric dissipation``: the dissipation per cycle of one load case."""

from __future__ import annotations

import json
import math
import time

from . import _common
from ..errors import InputError

HELP = "dissipation per cycle of one load case"
DESCRIPTION = (
    "Compute the dimensionless dissipation per cycle Ŵ (and W for dimensional input) "
    "of the single node under P = P0 + P1 sin ωt, Q = Q0 + Q1 sin(ωt + φ)."
)
#: API parameter names that differ from the option's name
OPTIONS = {"steps_per_cycle": "--steps"}


def configure(p) -> None:
    _common.add_case_options(p)
    p.add_argument(
        "--method",
        default="exact",
        help="exact (default), explicit, projection, clarabel, osqp, "
        "qpsolvers:<solver>, cvxpy:<SOLVER>; 'lcpfric methods' lists them",
    )
    p.add_argument(
        "--steps",
        default="2000",
        metavar="N",
        help="steps per cycle of a time-stepping method (default 2000); for exact, "
        "the points of the sampled time series",
    )
    p.add_argument(
        "--tol",
        default=None,
        metavar="X",
        help="steady-state tolerance on v of a time-stepping method (default 1e-10)",
    )
    p.add_argument(
        "--max-cycles",
        default=None,
        metavar="N",
        help="cap on the cycles of a time-stepping method (default 100)",
    )
    p.add_argument(
        "--placement",
        default=None,
        choices=("contact", "uniform"),
        help="where the steps of a time-stepping method go (default: contact)",
    )
    _common.add_memory_option(p)
    g = p.add_argument_group(
        "dynamics",
        "A mass (and a viscous damper) on the node: m v'' + c v' + k11 v = F - Q, solved by "
        "exact (normalized input: k11 = omega = 1, so m = beta^2 and c = 2 zeta beta)",
    )
    g.add_argument("--mass", default=None, metavar="M", help="the node's mass (default 0)")
    g.add_argument("--damping", default=None, metavar="C", help="viscous damping (default 0)")


def _with_dynamics(model, args):
    """The node with the --mass and --damping given (unchanged without them)."""
    from .. import _checks
    from ..model import SingleNode

    given = {
        k: _checks.parse_number(getattr(args, k, None), f"--{k}")
        for k in ("mass", "damping")
        if getattr(args, k, None) is not None
    }
    if not given:
        return model
    keep = ("k11", "f", "P0", "P1", "Q1", "omega", "phi", "Q0", "k22")
    return SingleNode(
        **{k: getattr(model, k) for k in keep}, dimensional=model.dimensional, **given
    )


def solve(args):
    """The steady state asked for by the case options: ``(model, result, seconds, assumed,
    closed_form)`` (shared with ``lcpfric loop``)."""
    from .. import _checks

    steps = _checks.positive_int("--steps", args.steps, minimum=4)
    tol = _checks.positive("--tol", _checks.parse_number(args.tol or "1e-10", "--tol"))
    max_cycles = _checks.positive_int("--max-cycles", args.max_cycles or "100", minimum=1)
    method = str(args.method).strip()
    from ..methods import CLOSED_FORM, get_method

    exact = get_method(method)[0].kind == CLOSED_FORM
    for name in ("tol", "max_cycles", "placement"):
        if exact and getattr(args, name) is not None:
            raise InputError(
                "--" + name.replace("_", "-"),
                f"applies to time-stepping methods; {method} is a closed form (no steps, "
                "no cycles to converge)",
            )
    what = (
        f"a time series of {steps + 1} points"
        if exact
        else f"{method} with {steps} steps per cycle"
    )
    _common.check_memory(_common.steady_state_bytes(steps, method), args, "--steps", what)

    model, assumed = _common.case_from_args(args)
    model = _with_dynamics(model, args)
    from ..periodic import steady_state

    t0 = time.perf_counter()
    kwargs = {} if exact else {"placement": args.placement or "contact"}
    res = steady_state(
        model, method=method, steps_per_cycle=steps, tol=tol, max_cycles=max_cycles, **kwargs
    )
    seconds = time.perf_counter() - t0
    return model, res, seconds, assumed, exact


def run(args) -> int:
    model, res, seconds, assumed, exact = solve(args)
    requested = int(res.steps_requested)
    samples = int(len(res.t))
    if args.json:
        out = res.summary()
        out.update(
            seconds=seconds,
            P1_hat=model.P1_hat,
            Q1_hat=model.Q1_hat,
            phi=model.phi,
            steps_requested=requested,
            samples=samples,
        )
        if exact:
            out["time_steps"] = 0
        if res.dynamics is not None:
            d = res.dynamics
            out.update(
                amplitude=d.amplitude,
                floquet=[[float(x.real), float(x.imag)] for x in d.floquet],
                stable=d.stable,
                beta=d.beta,
                zeta=d.zeta,
                orbits=len(d.orbits),
            )
        if assumed:
            out["assumed"] = assumed
        print(json.dumps(out))
        return 0
    print(
        f"P1_hat = {model.P1_hat:.6g}, Q1_hat = {model.Q1_hat:.6g}, "
        f"phi = {model.phi:.6g} rad ({model.phi / math.pi:.4g} pi)"
    )
    print(f"W_hat  = {res.W_hat:.12g}   (dimensionless dissipation per cycle, Eq. 7)")
    if model.dimensional:
        print(f"W      = {res.W:.12g}   (dissipation per cycle, Eq. 5)")
    if res.dynamics is not None:
        d = res.dynamics
        mult = ", ".join(f"{abs(x):.6g}" for x in d.floquet)
        print(
            f"dynamic: beta = {d.beta:.6g}, zeta = {d.zeta:.6g}; amplitude = {d.amplitude:.10g} "
            f"((max v - min v)/2); |Floquet multipliers| = {mult} "
            f"({'stable' if d.stable else 'unstable'}); {len(d.orbits)} orbit(s) found"
        )
    if exact:
        print(
            f"method = exact: closed form (no time steps); time series sampled at {samples} "
            f"points; {seconds * 1e3:.3g} ms"
        )
    else:
        used = res.steps_per_cycle
        counts = (
            f"{used}"
            if used == requested
            else f"{requested} requested, {used} used (separation instants added)"
            if used > requested
            else f"{requested} requested, {used} used"
        )
        print(
            f"method = {res.method}: steps per cycle: {counts}; cycles = {res.cycles}, "
            f"converged = {res.converged}, {seconds * 1e3:.3g} ms"
        )
    if assumed:
        print(_common.assumed_line(assumed))
    return 0
