"""``lcpfric methods``: the methods usable on this installation, with what each accepts."""

from __future__ import annotations

import json

HELP = "list the methods usable on this installation and what each solves"
DESCRIPTION = (
    "List the method names --method accepts here (the built-in ones and those of the "
    "installed solver packages), each with its kind, the tangential directions and "
    "the models it solves; with --names, the names alone."
)
OPTIONS: dict = {}


def configure(p) -> None:
    p.add_argument("--names", action="store_true", help="the names alone, one per line")
    p.add_argument(
        "--json",
        action="store_true",
        help="print a JSON list of {name, kind, dims, models, accepts, summary}",
    )


def run(args) -> int:
    from ..methods import available_methods, get_method

    names = available_methods()
    rows = []
    for name in names:
        entry, _ = get_method(name)
        rows.append(
            {
                "name": name,
                "kind": entry.kind,
                "dims": list(entry.dims),
                "models": list(entry.models),
                "accepts": entry.accepts,
                "summary": entry.summary,
            }
        )
    if args.json:
        print(json.dumps(rows))
    elif args.names:
        print("\n".join(names))
    else:
        width = max(len(n) for n in names)
        print(f"{'method':<{width}}  {'kind':<12}  d     solves")
        for r in rows:
            dims = ",".join(str(d) for d in r["dims"])
            print(f"{r['name']:<{width}}  {r['kind']:<12}  {dims:<4}  {r['accepts']}")
    return 0
