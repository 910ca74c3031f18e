"""The ``lcpfric`` command line.

Subcommands: ``dissipation`` (Ŵ of one load case), ``shakedown``, ``methods``, and, where
installed, ``map``, ``figures`` and ``bench``. Bad input prints one line naming the parameter
and its allowed range and exits with code 2 (no traceback); a solver failure exits with code 1.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

from .. import _checks
from ..errors import ConvergenceError, InputError, LcpfricError, SolverError, SolverNotFound

__all__ = ["main", "build_parser"]

_DIMENSIONAL = ("k11", "k22", "f", "P0", "Q0", "omega")
# API parameter names that the CLI exposes as options of the same name
_OPTION_NAMES = {"method", "tol", "max-cycles", "placement", "steps"}


class _Parser(argparse.ArgumentParser):
    """argparse that exits with code 2 and one line (no usage dump) on a bad option value."""

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(2, f"{self.prog}: error: {message}\n")


def _model_from_args(args):
    from ..model import SingleNode

    phi = _checks.parse_angle(args.phi, "--phi")
    P1 = _checks.parse_number(args.P1, "--P1")
    Q1 = _checks.parse_number(args.Q1, "--Q1")
    dims = {k: getattr(args, k) for k in _DIMENSIONAL if getattr(args, k) is not None}
    try:
        if dims:
            values = {k: _checks.parse_number(v, f"--{k}") for k, v in dims.items()}
            return SingleNode(P1=P1, Q1=Q1, phi=phi, **values)
        return SingleNode.normalized(P1=P1, Q1=Q1, phi=phi)
    except InputError as exc:  # name the option as the user typed it
        if not exc.parameter.startswith("--"):
            raise InputError(f"--{exc.parameter}", str(exc).split(": ", 1)[1]) from None
        raise


def _cmd_dissipation(args) -> int:
    from ..periodic import steady_state

    model = _model_from_args(args)
    steps = _checks.positive_int("--steps", args.steps, minimum=4)
    t0 = time.perf_counter()
    res = steady_state(model, method=args.method, steps_per_cycle=steps, tol=args.tol,
                       max_cycles=args.max_cycles)
    seconds = time.perf_counter() - t0
    out = res.summary()
    out["seconds"] = seconds
    out["P1_hat"], out["Q1_hat"] = model.P1_hat, model.Q1_hat
    out["phi"] = model.phi
    if args.json:
        print(json.dumps(out))
    else:
        print(f"P1_hat = {model.P1_hat:.6g}, Q1_hat = {model.Q1_hat:.6g}, "
              f"phi = {model.phi:.6g} rad ({model.phi / 3.141592653589793:.4g} pi)")
        print(f"W_hat  = {res.W_hat:.12g}   (dimensionless dissipation per cycle, Eq. 7)")
        if res.W is not None:
            print(f"W      = {res.W:.12g}   (dissipation per cycle, Eq. 5)")
        print(f"method = {res.method}, steps per cycle = {res.steps_per_cycle}, cycles = "
              f"{res.cycles}, converged = {res.converged}, {seconds * 1e3:.3g} ms")
    return 0


def _cmd_shakedown(args) -> int:
    from ..analysis.shakedown import shakedown

    model = _model_from_args(args)
    res = shakedown(model=model)
    if args.json:
        print(json.dumps({"shakedown": res.shakedown, "shift": res.shift, "margin": res.margin}))
    else:
        if res.shakedown:
            print(f"shakedown: yes (a constant shift c = {res.shift:.6g} f P0 keeps the node in "
                  f"stick; margin {res.margin:.3g})")
        else:
            print(f"shakedown: no (the load ellipse does not fit between Q = ±P; margin "
                  f"{res.margin:.3g})")
    return 0


def _cmd_methods(args) -> int:
    from ..methods import available_methods

    names = available_methods()
    print(json.dumps(names) if args.json else "\n".join(names))
    return 0


def _add_case_options(p):
    p.add_argument("--P1", required=True, help="normal load amplitude (P̂1 if no dimensional "
                                               "option is given)")
    p.add_argument("--Q1", required=True, help="tangential load amplitude (Q̂1 if normalized)")
    p.add_argument("--phi", default="0", help="phase in radians, or like 0.6pi, pi/2")
    g = p.add_argument_group("dimensional inputs (any of these makes P1, Q1 dimensional)")
    for name, text in (("k11", "tangential stiffness"), ("k22", "normal stiffness"),
                       ("f", "coefficient of friction"), ("P0", "mean normal load"),
                       ("Q0", "mean tangential load"), ("omega", "angular frequency")):
        g.add_argument(f"--{name}", default=None, help=text)
    p.add_argument("--json", action="store_true", help="print one JSON object")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="lcpfric", description="Frictional dissipation per load cycle in "
                                                 "elastic contact systems under periodic loads.")
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"lcpfric {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    p = sub.add_parser("dissipation", help="dissipation per cycle of one load case")
    _add_case_options(p)
    p.add_argument("--method", default="exact", help="exact, explicit, projection, clarabel, "
                                                     "osqp, qpsolvers:<solver>, cvxpy:<SOLVER>")
    p.add_argument("--steps", default=2000, help="steps per cycle (time-stepping methods)")
    p.add_argument("--tol", type=float, default=1e-10, help="steady-state tolerance on v")
    p.add_argument("--max-cycles", type=int, default=100, help="cap on cycles")
    p.set_defaults(func=_cmd_dissipation)
    p = sub.add_parser("shakedown", help="does the load case shake down? (exact)")
    _add_case_options(p)
    p.set_defaults(func=_cmd_shakedown)
    p = sub.add_parser("methods", help="list the methods usable on this installation")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_methods)
    for module in ("analysis.sweep", "paper.figures", "paper.claims", "analysis.convergence"):
        try:
            mod = __import__(f"lcpfric.{module}", fromlist=["register_cli"])
        except ImportError:
            continue
        register = getattr(mod, "register_cli", None)
        if register is not None:
            register(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except InputError as exc:
        message = str(exc)
        option = exc.parameter.replace("_", "-")
        if not option.startswith("--") and option in _OPTION_NAMES:
            message = f"--{option}: {message.split(': ', 1)[1]}"
        print(f"lcpfric: error: {message}", file=sys.stderr)
        return 2
    except SolverNotFound as exc:
        print(f"lcpfric: error: {exc}", file=sys.stderr)
        return 2
    except (SolverError, ConvergenceError) as exc:
        status = f" (solver status: {exc.status})" if getattr(exc, "status", "") else ""
        print(f"lcpfric: failed: {exc}{status}", file=sys.stderr)
        return 1
    except LcpfricError as exc:
        print(f"lcpfric: failed: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("lcpfric: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
