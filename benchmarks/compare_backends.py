"""Error against run time for every method on the benchmark cases (see
lcpfric/analysis/convergence.py).

    python benchmarks/compare_backends.py [--quick] [--out DIR] [--methods a,b] [--json]

Same as ``lcpfric bench`` (same options, checks and exit codes).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from lcpfric.cli import main as cli  # noqa: E402


def main(argv=None) -> int:
    return cli(["bench", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(main())
