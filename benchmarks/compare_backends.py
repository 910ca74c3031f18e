"""Error against run time for every method on the benchmark cases (see lcpfric/bench.py).

    python benchmarks/compare_backends.py [--quick] [--out DIR] [--methods a,b] [--json]

Same as ``lcpfric bench``.
"""

import sys

from lcpfric.analysis.convergence import main

if __name__ == "__main__":
    sys.exit(main())
