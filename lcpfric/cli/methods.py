"""``lcpfric methods``: the methods usable on this installation."""

from __future__ import annotations

import json

HELP = "list the methods usable on this installation"
DESCRIPTION = ("List the method names --method accepts here: the built-in ones and those of the "
               "installed solver packages.")
OPTIONS: dict = {}


def configure(p) -> None:
    p.add_argument("--json", action="store_true", help="print a JSON list")


def run(args) -> int:
    from ..methods import available_methods

    names = available_methods()
    print(json.dumps(names) if args.json else "\n".join(names))
    return 0
