"""The paper's claims as lcpfric computes them."""

import math

import numpy as np
import pytest

from lcpfric.exact import exact_W_hat
from lcpfric.paper.claims import (
    claims_markdown,
    paper_claims,
    peak_phase,
    separation_fraction,
    sqrt_law,
)


@pytest.fixture(scope="module")
def claims():
    return {c.key: c for c in paper_claims(quick=True)}


def test_peak_near_0_6_pi_for_P1_Q1_5():
    best, top = peak_phase(5.0, 5.0)
    assert best / math.pi == pytest.approx(0.60160, abs=2e-5)
    h = 1e-4
    assert top >= exact_W_hat(5.0, 5.0, best + h) and top >= exact_W_hat(5.0, 5.0, best - h)
    assert top == pytest.approx(7.782063, abs=1e-6)


def test_peak_phase_of_shakedown_case_is_undefined():
    best, top = peak_phase(0.2, 0.2)
    assert math.isnan(best) and top == 0.0


def test_separation_fraction():
    assert separation_fraction(1.5) == pytest.approx(0.267720, abs=1e-6)
    assert separation_fraction(0.5) == 0.0
    assert separation_fraction(1e9) == pytest.approx(0.5, abs=1e-8)  # the paper's 50 % limit
    np.testing.assert_allclose(separation_fraction([1.0, 2.0]), [0.0, 1 / 3])


def test_sqrt_law_is_rough():
    law = sqrt_law(n=21)
    assert 1.25 < law["c_min"] < law["c_median"] < law["c_max"] < 1.6
    assert law["diagonal"][1e4] == pytest.approx(1.349, abs=2e-3)


def test_claim_verdicts(claims):
    assert claims["fig7-separation"].verdict == "disagrees"
    assert claims["fig7-separation"].numbers["fraction"] == pytest.approx(0.2677, abs=1e-4)
    assert claims["fig7-separation"].numbers["fraction_from_cycle"] == pytest.approx(
        claims["fig7-separation"].numbers["fraction"], abs=1e-12
    )
    assert claims["eq11-12"].verdict == "misprint"
    assert claims["eq11-12"].numbers["max_abs_diff"] < 1e-12
    for key in ("phi0-zero", "phi0-monotone", "fig5", "fig6-peak", "fig7-peak"):
        assert claims[key].verdict == "agrees", key
    peaks = claims["fig7-peak"].numbers["phi_max_over_pi"]
    assert peaks[0.1] < 0.52 and peaks[300.0] < 0.51 and max(peaks.values()) > 0.65
    assert "period-pi" in claims and "sqrt-law" in claims and "abstract" in claims


def test_markdown_table(claims):
    table = claims_markdown(list(claims.values()))
    lines = table.splitlines()
    assert lines[0].startswith("| claim |") and len(lines) == len(claims) + 2
    assert all(line.count(" | ") == 4 for line in lines[2:])
