"""The paper's quantitative claims next to what lcpfric computes (a markdown table).

    python benchmarks/validation/paper_claims.py [--quick] [--json] [--out FILE]

The same table as ``lcpfric paper-claims`` (its other options pass through), kept in
``benchmarks/results/paper-claims.md`` (``--out -``: print only).
"""

import sys as _sys
from pathlib import Path as _Path

# the repository, the shared report writer, the perf scripts (halfspace's cases) and the tests'
# shared cases and references (tests/support)
_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [
    str(_ROOT),
    str(_ROOT / "benchmarks"),
    str(_ROOT / "benchmarks" / "perf"),
    str(_ROOT / "tests"),
]

import argparse
import sys

from _report import results_file

from lcpfric.cli import main as cli

OUT = _ROOT / "benchmarks" / "results" / "paper-claims.md"


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], add_help=False)
    parser.add_argument("--out", default=str(OUT))
    args, rest = parser.parse_known_args(argv)
    out = None if args.out == "-" or "--help" in rest or "-h" in rest else args.out
    command = "validation/paper_claims.py" + "".join(f" {a}" for a in argv)
    with results_file(out, "The paper's claims, recomputed", command, markdown=True):
        return cli(["paper-claims", *rest])


if __name__ == "__main__":
    sys.exit(main())
