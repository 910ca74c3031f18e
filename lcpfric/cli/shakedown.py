"""``lcpfric shakedown``: does the load case shake down? (exact)"""

from __future__ import annotations

import json

from . import _common

HELP = "does the load case shake down? (exact)"
DESCRIPTION = (
    "Decide exactly whether a constant slip shift keeps the node in stick for ever "
    "(then W = 0): the load ellipse, shifted along Q, fits between Q = ±P."
)
OPTIONS: dict = {}


def configure(p) -> None:
    _common.add_case_options(p)


def run(args) -> int:
    model, assumed = _common.case_from_args(args)
    from ..analysis.shakedown import shakedown

    res = shakedown(model=model)
    if args.json:
        out = {"shakedown": res.shakedown, "shift": res.shift, "margin": res.margin}
        if assumed:
            out["assumed"] = assumed
        print(json.dumps(out))
        return 0
    if res.shakedown:
        print(
            f"shakedown: yes (a constant shift c = {res.shift:.6g} f P0 keeps the node in "
            f"stick; margin {res.margin:.3g})"
        )
    else:
        print(
            f"shakedown: no (the load ellipse does not fit between Q = ±P; margin {res.margin:.3g})"
        )
    if assumed:
        print(_common.assumed_line(assumed))
    return 0
