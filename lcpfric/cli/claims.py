"""``lcpfric paper-claims``: the paper's quantitative claims, recomputed."""

from __future__ import annotations

import json

HELP = "recompute the paper's quantitative claims"
DESCRIPTION = "Recompute every checkable number of the paper and print a markdown table (or JSON)."
OPTIONS: dict = {}


def configure(p) -> None:
    p.add_argument("--quick", action="store_true", help="coarser grids (well under a second)")
    p.add_argument("--json", action="store_true", help="print JSON")


def run(args) -> int:
    from dataclasses import asdict

    from ..paper.claims import jsonable, claims_markdown, paper_claims

    claims = paper_claims(quick=args.quick)
    if args.json:
        print(json.dumps([jsonable(asdict(c)) for c in claims], indent=1, ensure_ascii=False))
    else:
        print(claims_markdown(claims))
    return 0
