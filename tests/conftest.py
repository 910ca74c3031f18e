import sys
from pathlib import Path

import pytest

# the benchmark harnesses live with the benchmarks; the stability tests reuse their scenarios
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))

from support import CASES  # noqa: E402


@pytest.fixture(params=sorted(CASES), ids=sorted(CASES))
def case(request):
    return CASES[request.param]
