"""The fast part of the stability study (benchmarks/stability.py) as regression tests.

Every scenario has an exact reference (see lcpfric/stability.py for the tolerances); a method may
fail with a clear LcpfricError, never with a wrong number.
"""

import pytest

from lcpfric.methods import available_methods
from stability_cases import run_scenario, scenarios  # benchmarks/, put on the path by conftest

QUICK = scenarios(quick=True)
CORE = ["exact", "explicit", "projection"]
# one representative per installed solver family keeps the suite fast; the benchmark runs all
BACKENDS = [m for m in available_methods() if m in ("clarabel", "osqp")]


@pytest.mark.parametrize("method", CORE)
@pytest.mark.parametrize("scenario", QUICK, ids=[f"{s.group}:{s.name}" for s in QUICK])
def test_core_methods_never_wrong(scenario, method):
    if method == "exact" and scenario.group == "multi-node":
        pytest.skip("exact solves the single node")
    row = run_scenario(scenario, method, steps=2000)
    assert row["verdict"] in ("correct", "error"), row


@pytest.mark.slow
@pytest.mark.parametrize("method", BACKENDS)
@pytest.mark.parametrize("scenario", [s for s in QUICK if s.group != "extreme"][:12],
                         ids=lambda s: f"{s.group}:{s.name}")
def test_backends_never_wrong(scenario, method):
    row = run_scenario(scenario, method, steps=1000, refine=4)
    assert row["verdict"] in ("correct", "error"), row


@pytest.mark.parametrize("method", BACKENDS)
def test_backends_at_large_forces(method):
    # Without the driver's unit scaling Clarabel stopped "DualInfeasible" here (forces of 1e6
    # against absolute solver tolerances).
    big = [s for s in scenarios() if s.name in ("P1=1e+06 Q1=1e+06 phi=pi/2",
                                                "P1=1e+06 Q1=1e+06 phi=0")]
    assert len(big) == 2
    for scenario in big:
        row = run_scenario(scenario, method, steps=1000, refine=4)
        assert row["verdict"] == "correct", row
