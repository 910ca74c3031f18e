import sys
from pathlib import Path

import numpy as np
import pytest

# the benchmark harnesses live with the benchmarks; the stability tests reuse their scenarios
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))

# Cases (P̂1, Q̂1, φ) used across the suite: full contact, separation, near shakedown, large loads.
CASES = {
    "contact": (0.5, 2.0, 0.0),
    "contact-phase": (0.5, 2.0, 0.6 * np.pi),
    "separation": (1.5, 2.0, 0.6 * np.pi),
    "large": (5.0, 5.0, 0.6 * np.pi),
    "near-shakedown": (0.5, 1.01, 0.3 * np.pi),
}


@pytest.fixture(params=sorted(CASES), ids=sorted(CASES))
def case(request):
    return CASES[request.param]


def fitted_order(steps, errors):
    """Least-squares slope of -log(error) against log(steps): the measured order."""
    steps, errors = np.asarray(steps, float), np.asarray(errors, float)
    return -np.polyfit(np.log(steps), np.log(errors), 1)[0]
