"""Print the paper's quantitative claims next to what lcpfric computes (markdown table).

    PYTHONPATH=. python benchmarks/paper_claims.py [--quick] [--json]
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from lcpfric.paper.claims import claims_command  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarser grids")
    parser.add_argument("--json", action="store_true", help="JSON instead of markdown")
    return claims_command(parser.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
