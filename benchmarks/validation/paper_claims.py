"""Print the paper's quantitative claims next to what lcpfric computes (markdown table).

    PYTHONPATH=. python benchmarks/validation/paper_claims.py [--quick] [--json]

Same as ``lcpfric paper-claims``.
"""

import sys as _sys
from pathlib import Path as _Path

# the repository, the shared report writer, the perf scripts (halfspace's cases) and the tests'
# shared cases and references (tests/support)
_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "benchmarks" / "perf"),
                 str(_ROOT / "tests")]

import sys
from pathlib import Path


from lcpfric.cli import main as cli  # noqa: E402


def main(argv=None) -> int:
    return cli(["paper-claims", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(main())
