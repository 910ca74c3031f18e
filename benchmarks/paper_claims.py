"""Print the paper's quantitative claims next to what lcpfric computes (markdown table).

    PYTHONPATH=. python benchmarks/paper_claims.py [--quick] [--json]

Same as ``lcpfric paper-claims``.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from lcpfric.cli import main as cli  # noqa: E402


def main(argv=None) -> int:
    return cli(["paper-claims", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(main())
