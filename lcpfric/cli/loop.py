"""``lcpfric loop``: the hysteresis loop of one load case (F against v over the steady cycle)."""

from __future__ import annotations

import json
import math

from . import _common, dissipation

HELP = "hysteresis loop of one load case: F against v over the steady cycle"
DESCRIPTION = (
    "Compute the steady state of one load case (the options of 'lcpfric "
    "dissipation') and report its hysteresis loop, the friction force against the "
    "tangential displacement over the steady cycle, whose enclosed area is the "
    "dissipation per cycle W; with --out, draw it (stick, slip and separation "
    "coloured) as a PNG, PDF or SVG figure. " + _common.OUTPUT_RULE
)
OPTIONS = dict(dissipation.OPTIONS)
FORMATS = (".png", ".pdf", ".svg")


def configure(p) -> None:
    dissipation.configure(p)
    p.add_argument(
        "--out",
        default=None,
        metavar="FILE",
        help="draw the loop into FILE (.png, .pdf or .svg; its parent must exist)",
    )


def run(args) -> int:
    out = None
    if args.out is not None:
        out = _common.output_file(args.out, "--out", FORMATS)
        _common.require_extras("loop figures", ["matplotlib"])
    model, res, seconds, assumed, _exact = dissipation.solve(args)
    from ..analysis.loop import hysteresis_loop, state_shares

    loop = hysteresis_loop(res)
    # time shares (steps of unequal length weighed by their duration; exact for the closed form)
    shares = {state.label: share for state, share in state_shares(res, model=model).items()}
    if out is not None:
        from ..figures.loop import figure_loop, loop_labels

        names, units = loop_labels(model)
        fig = figure_loop(
            loop,
            title=f"{res.method}, P̂1 = {model.P1_hat:.4g}, "
            f"Q̂1 = {model.Q1_hat:.4g}, φ = {model.phi / math.pi:.4g}π",
            units=units,
            names=names,
        )
        fig.savefig(out)
    summary = {
        "area": loop.area,
        "W": res.W,
        "W_hat": res.W_hat,
        "method": res.method,
        "points": int(loop.v.size),
        "shares": shares,
        "seconds": seconds,
        "out": None if out is None else str(out),
    }
    if assumed:
        summary["assumed"] = assumed
    if args.json:
        print(json.dumps(summary))
        return 0
    print(
        f"hysteresis loop of {res.method}: {loop.v.size} points; enclosed area -∮F dv = "
        f"{loop.area:.10g}, W = {res.W:.10g} (W_hat = {res.W_hat:.10g})"
    )
    print("share of the cycle's time: " + ", ".join(f"{k} {v:.1%}" for k, v in shares.items()))
    if out is not None:
        print(f"wrote {out}")
    if assumed:
        print(_common.assumed_line(assumed))
    return 0
