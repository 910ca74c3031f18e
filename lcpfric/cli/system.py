"""``lcpfric system``: the steady dissipation of a user's system file (coupled or not), from one
start or over many."""

from __future__ import annotations

import json

HELP = "steady W of a system file (K, B, friction, loads), from a start or over many"
DESCRIPTION = (
    "Read a system from FILE (JSON for small systems, .npz for large: the keys K, friction, "
    "P0, P1, psi, Q0, Q1, phi, optional B, omega and start; P_i = P0_i + P1_i sin(wt + psi_i), "
    "Q_i = Q0_i + Q1_i sin(wt + phi_i), F = Q + K v, N = P + B v) and print its steady "
    "dissipation per cycle W from the file's start (or --start), or the range of W and the "
    "share of starts that shake down over --starts N random admissible starts."
)
OPTIONS = {"u0": "--start", "coupling": "--method", "starts": "--starts"}


def configure(p) -> None:
    p.add_argument("--file", required=True, metavar="FILE", help="the system (.json or .npz)")
    group = p.add_mutually_exclusive_group()
    group.add_argument(
        "--start",
        metavar="FILE",
        default=None,
        help="initial tangential displacements (n numbers: a JSON list or a text file)",
    )
    group.add_argument(
        "--starts",
        metavar="N",
        type=int,
        default=None,
        help="explore N random admissible starts (mobilization ratios in [-1, 1]^n)",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of the random starts (default 0)")
    p.add_argument(
        "--method", default="exact", help="method (default exact: the one for coupled systems)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _read_start(path: str):
    from pathlib import Path

    import numpy as np

    from ..errors import InputError

    p = Path(path)
    if not p.is_file():
        raise InputError("--start", f"{path!r} is not a readable file")
    text = p.read_text(encoding="utf-8", errors="replace").strip()
    try:
        values = json.loads(text) if text.startswith("[") else text.replace(",", " ").split()
        return np.asarray(values, dtype=float).ravel()
    except (ValueError, TypeError):
        raise InputError("--start", f"{path!r} must hold n numbers (a JSON list or text)") from None


def run(args) -> int:
    from ..errors import InputError
    from ..model.files import load_system

    try:
        system, start = load_system(args.file)
    except InputError as exc:
        where = "" if exc.parameter == "file" else f"field {exc.parameter}: "
        raise InputError("--file", f"{where}{exc.detail}") from None
    if args.starts is not None:
        if args.starts < 1:
            raise InputError("--starts", f"must be >= 1, got {args.starts}")
        from ..analysis.starts import explore_starts

        study = explore_starts(system, args.starts, method=args.method, seed=args.seed)
        out = {
            "W": study.W.tolist(),
            "W_min": study.W_min,
            "W_max": study.W_max,
            "shakedown": study.shakedown_share,
            "converged": True,
            "cycles": study.cycles.tolist(),
            "unique": study.unique,
            "branches": len(study.branches),
            "start_min": study.starts[study.start_min].tolist(),
            "start_max": study.starts[study.start_max].tolist(),
            "seconds": study.seconds,
        }
        if args.json:
            print(json.dumps(out))
            return 0
        one = "one steady W" if study.unique else f"{len(study.branches)} steady states"
        print(
            f"W over {args.starts} starts ({args.method}): from {study.W_min:.10g} to "
            f"{study.W_max:.10g} ({one}); {study.shakedown_share:.0%} of the starts shake down"
        )
        return 0
    if args.start is not None:
        start = _read_start(args.start)
    from ..periodic.driver import steady_state
    from ..results import State

    res = steady_state(system, args.method, u0=start)
    import numpy as np

    slipping = bool(np.any(np.asarray(res.state) != State.STICK))
    out = {
        "W": res.W,
        "W_min": res.W,
        "W_max": res.W,
        "shakedown": not slipping,
        "converged": bool(res.converged),
        "cycles": int(res.cycles),
        "method": res.method,
        "seconds": res.seconds,
    }
    if args.json:
        print(json.dumps(out))
        return 0
    verdict = "shakes down (no node slips)" if not slipping else "slips cyclically"
    print(f"W = {res.W:.10g} per cycle ({res.method}, {res.cycles} cycles; the system {verdict})")
    return 0
