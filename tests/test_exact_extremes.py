"""The exact solution at extreme inputs, against an independent reference.

References: values of the high-precision mpmath solution (tests/support/exact_reference.py,
written separately from lcpfric.exact) pinned below, so these tests need no mpmath; the tests
marked with ``mpmath`` recompute them and run a randomized audit when mpmath is installed. And
two analytical limits: the small-Q̂1 asymptote ``Ŵ ≈ 2 Q̂1 sin²φ (1 - 1/P̂1²)`` (the slip just
before separation, see lcpfric/exact.py) and Eq. (11) as Q̂1 grows.
"""

import math

import numpy as np
import pytest

from support import need_modules

import lcpfric
from lcpfric.analysis.analytic import jang_barber
from lcpfric.exact import exact_cycle, exact_W_hat

# (P̂1, Q̂1, φ, Ŵ from mpmath, spread): spread is the largest change of the exact Ŵ when one
# input moves by 16 units of round-off. Where it is above 1e-10 Ŵ the problem is ill-conditioned
# and the answer need only be within it; elsewhere within 1e-9 relative.
PINNED = [
    # the issue's examples: the slip before separation is shorter than an angle's round-off
    (1e8, 1e-8, 1.0, 1.4161468365471422e-08, 6.460946812763404e-23),
    (2.0, 1e-15, 1.0, 1.0621101274103568e-15, 4.8457101095725556e-30),
    # ... down to Q̂1/P̂1 = 1e-40, and next to P̂1 = 1, φ = 0 and φ = π
    (2.0, 2e-20, 1.0, 2.1242202548207136e-20, 9.691420219145106e-35),
    (1e6, 1e-14, 1.0, 1.4161468365457263e-14, 6.460946812756944e-29),
    (1e20, 1e-20, 0.7, 8.300328570997589e-21, 7.00204147100053e-35),
    (1.5, 1e-12, 2.5, 3.979654525207844e-13, 9.463287187590903e-27),
    (1.0 + 2**-40, 1e-9, 4.0, 2.084821851194038e-21, 8.141553121934722e-24),
    (1e3, 1e-3, 1e-9, 1.9999960000040004e-21, 1.4210851537019477e-26),
    (2.0, 1e-10, math.pi - 1e-9, 1.500000615690216e-28, 3.3306882464395875e-33),
    (3.0, 1e-5, -1e-9, 1.7777837037234592e-23, 1.2631935403118898e-28),
    # Q̂1 ≫ P̂1: the sticks at the extrema last ~Q̂1^(-1/2) rad (the arcsine form gave 2, not 4)
    (9.644481167533153e-06, 9.023532051937398e16, 3.7694813205813698, 4.0, 1.5720155550870023e-31),
    (
        205493614610.63177,
        1.654511916488313e31,
        2.249505008275555,
        271698559649.17606,
        0.0009683900342531049,
    ),
    (0.5, 1e20, 1.0, 4.0, 1.547016352579145e-34),
    (1e-20, 1e20, 0.7, 4.0, 1.4417920000000051e-34),
    # Q̂1 = P̂1 with φ small: a bound that barely moves while L and Q̂ change by 1
    (1e3, 1e3, 1e-9, 1.1666659416667383e-15, 1.7683653625351198e-18),
    (1e6, 1e6, 1e-9, 1.000000000165917e-12, 7.105439979962276e-18),
    (4.125, 4.75, 0.0, 0.4484101579172002, 1.3771334188058262e-14),
    # P̂1 next to 1, Q̂1 small: L within Q̂1² of zero (ill-conditioned: within the spread)
    (1.0, 4.995817424462735e-10, 5.154704858848491, 1.663671369003528e-28, 5.829716568567585e-24),
    (
        1.0000000000032472,
        0.0005504811217151728,
        6.2239817393421,
        4.1180540820270775e-15,
        2.849115043903456e-20,
    ),
    (
        0.9999999999999999,
        0.04721990970604753,
        3.1116368684444233,
        1.8217383145555677e-10,
        6.665428930594853e-19,
    ),
    # φ far from [0, 2π): sin and cos of the given double, exactly reduced
    (3.0, 1e-5, 1e300, 1.1892092159217854e-05, 0.0),
    # a zero régime exactly (φ = 0, Q̂1 < P̂1 with separation)
    (41.82185082718205, 41.46856146995191, 0.0, 0.0, 1.238493422419563e-25),
    # amplitudes up to 1e300 (1300-digit reference), and a Ŵ of 1e-300
    (1e300, 1e300, 1.0, 7.747722015407339e299, 0.0),
    (1e300, 1e-300, 1.0, 1.4161468365471424e-300, 0.0),
    (1e-300, 1e300, 1.0, 4.0, 0.0),
    (2.0, 1e-300, 1.0, 1.0621101274103569e-300, 0.0),
]
IDS = [f"P1={p:g},Q1={q:g},phi={f:g}" for p, q, f, _, _ in PINNED]


def _within(value, ref, spread):
    return abs(value - ref) <= 1e-9 * abs(ref) + spread


@pytest.mark.parametrize("P1,Q1,phi,ref,spread", PINNED, ids=IDS)
def test_pinned_extremes_scalar_and_vectorized(P1, Q1, phi, ref, spread):
    scalar = exact_W_hat(P1, Q1, phi)
    vector = exact_W_hat(np.array([P1, P1]), np.array([Q1, Q1]), np.array([phi, phi]))
    for value in (scalar, *vector):
        assert _within(value, ref, spread), (value, ref)
    if spread <= 1e-10 * ref:  # well-conditioned: relative, however small Ŵ is
        assert abs(scalar - ref) <= 1e-9 * ref


@pytest.mark.parametrize(
    "P1,Q1,phi,ref",
    [(1e8, 1e-8, 1.0, 1.4161468365471422e-08), (2.0, 1e-15, 1.0, 1.0621101274103568e-15)],
)
def test_issue_examples_through_every_entry(P1, Q1, phi, ref):
    # exact_W_hat, steady_state(..., "exact"), exact_cycle and sweep returned exactly 0 here
    assert exact_W_hat(P1, Q1, phi) == pytest.approx(ref, rel=1e-9)
    assert float(exact_W_hat(np.array(P1), Q1, phi)) == pytest.approx(ref, rel=1e-9)
    node = lcpfric.SingleNode.normalized(P1, Q1, phi)
    assert lcpfric.steady_state(node, "exact").W_hat == pytest.approx(ref, rel=1e-9)
    assert exact_cycle(P1, Q1, phi).W_hat == pytest.approx(ref, rel=1e-9)
    need_modules("xarray")
    from lcpfric.analysis.sweep import sweep

    ds = sweep([P1], [Q1], [phi], progress=False)
    assert float(ds["W_hat"].values.ravel()[0]) == pytest.approx(ref, rel=1e-9)


def test_small_Q1_asymptote():
    # Stuck since re-contact, w is -2 Q̂1 sin φ sin β from where the interval closes; the last
    # slip gives Ŵ = 2 Q̂1 sin²φ sin²β (1 + O(Q̂1/g)), sin²β = 1 - 1/P̂1², g = sqrt(P̂1² - 1)
    # (the mpmath reference: |Ŵ/asymptote - 1| <= 1.0 Q̂1/g on 200 random points).
    rng = np.random.default_rng(5)
    P1 = 1.0 + 10.0 ** rng.uniform(-3, 20, 400)
    g = np.sqrt(P1 - 1) * np.sqrt(P1 + 1)
    Q1 = g * 10.0 ** rng.uniform(-20, -6, 400)
    phi = rng.uniform(0, 2 * np.pi, 400)
    asym = 2 * Q1 * np.sin(phi) ** 2 * (1 - 1 / P1**2)
    bound = 2.0 * Q1 / g + 1e-12
    vec = exact_W_hat(P1, Q1, phi)
    assert np.all(np.abs(vec / asym - 1) <= bound)
    for p, q, f, a, b in zip(P1[:100], Q1[:100], phi[:100], asym, bound):
        assert abs(exact_W_hat(float(p), float(q), float(f)) / a - 1) <= b


def test_large_Q1_against_eq_11_and_the_limit_4():
    for P1 in (0.0, 0.5, 0.99):
        for k in range(3, 21):
            Q1 = 10.0**k
            assert exact_W_hat(P1, Q1, 0.0) == pytest.approx(jang_barber(P1, Q1), rel=1e-12)
            for phi in (0.3, 1.0, np.pi / 2, 2.5):
                # |Ŵ - 4| = O(1/Q̂1) for any φ when P̂1 < 1
                assert abs(exact_W_hat(P1, Q1, phi) - 4.0) <= 10.0 / Q1 + 1e-14


def test_vectorized_and_scalar_agree_over_the_extreme_range():
    rng = np.random.default_rng(11)
    n = 3000
    P1 = 10.0 ** rng.uniform(-20, 20, n)
    Q1 = np.where(
        rng.random(n) < 0.5, 10.0 ** rng.uniform(-20, 20, n), P1 * 10.0 ** rng.uniform(-20, 20, n)
    )
    Q1 = np.clip(Q1, 0, 1e300)
    phi = rng.uniform(-10, 10, n)
    vec = exact_W_hat(P1, Q1, phi)
    sca = np.array([exact_W_hat(float(p), float(q), float(f)) for p, q, f in zip(P1, Q1, phi)])
    assert np.all(np.isfinite(vec)) and np.all(vec >= 0)
    assert np.all(np.abs(vec - sca) <= 1e-13 * sca)


def test_period_pi_at_extreme_ratios():
    for P1, Q1 in [(2.0, 2e-20), (1e6, 1e-14), (0.5, 5e19), (1.0, 1e20), (1e-3, 1e17)]:
        for phi in (0.3, 1.0, 2.0):
            a, b = exact_W_hat(P1, Q1, phi), exact_W_hat(P1, Q1, phi + np.pi)
            assert abs(a - b) <= 1e-9 * a


def test_zero_regimes_are_exactly_zero():
    P1 = np.linspace(1.0, 50.0, 99)
    assert np.all(exact_W_hat(P1, 0.999 * P1, 0.0) == 0.0)  # φ = 0, Q̂1 < P̂1 (Eq. 12)
    assert exact_W_hat(0.5, 0.3, 1.0) == 0.0  # shakedown
    assert exact_W_hat(2.0, 0.0, 1.0) == 0.0  # Q̂1 = 0 (the limit)


# -- against the mpmath reference itself, when mpmath is installed ------------------------------


def _audit(points, reference_W_hat, input_spread):
    worst = 0.0
    for p, q, f in points:
        ref = reference_W_hat(p, q, f)
        for value in (exact_W_hat(p, q, f), float(exact_W_hat(np.array([p]), q, f)[0])):
            err = abs(value - ref)
            if err > 1e-9 * ref:  # ill-conditioned points must be within their spread
                assert err <= 1e-9 * ref + input_spread(p, q, f), (p, q, f, value, ref)
            else:
                worst = max(worst, err / ref if ref else 0.0)
    return worst


def test_pinned_values_match_the_mpmath_reference():
    need_modules("mpmath")
    from support.exact_reference import reference_W_hat

    for P1, Q1, phi, ref, _ in PINNED:
        dps = 1300 if max(P1, Q1) > 1e100 or min(P1, Q1) < 1e-100 else None
        assert reference_W_hat(P1, Q1, phi, dps=dps) == pytest.approx(ref, rel=4e-16, abs=0)


def test_random_audit_against_mpmath_quick():
    need_modules("mpmath")
    from support.exact_reference import draw
    from support.exact_reference import input_spread, reference_W_hat

    worst = _audit(
        [tuple(map(float, p)) for p in draw(180, seed=123)], reference_W_hat, input_spread
    )
    assert worst <= 1e-9


@pytest.mark.slow
def test_random_audit_against_mpmath():
    need_modules("mpmath")
    from support.exact_reference import draw
    from support.exact_reference import input_spread, reference_W_hat

    worst = _audit(
        [tuple(map(float, p)) for p in draw(2700, seed=7)], reference_W_hat, input_spread
    )
    assert worst <= 1e-9


def test_reference_agrees_with_eqs_11_12_and_the_energy_identity():
    need_modules("mpmath")
    import mpmath as mp
    from support.exact_reference import jang_barber_mp, reference_cycle

    rng = np.random.default_rng(3)
    for P1, Q1 in 10.0 ** rng.uniform(-20, 20, (40, 2)):
        r = reference_cycle(float(P1), float(Q1), 0.0)
        with mp.workdps(r["dps"]):
            jb = jang_barber_mp(P1, Q1)
            assert abs(r["W_hat"] - jb) <= mp.mpf(10) ** -40 * (abs(jb) + 1e-300)
    for P1, Q1, phi in [(1.5, 2.0, 0.6 * np.pi), (0.5, 1.01, 0.3 * np.pi), (2.0, 1e-15, 1.0)]:
        r = reference_cycle(P1, Q1, phi)
        with mp.workdps(r["dps"]):
            assert abs(r["J"] - r["J_energy"]) <= mp.mpf(10) ** -40 * r["J"]


@pytest.mark.slow
def test_reference_agrees_with_a_fine_grid():
    need_modules("mpmath")
    from support.exact_reference import grid_W_hat, reference_W_hat

    P1 = np.array([0.5, 1.5, 3.0, 0.0, 2.0])
    Q1 = np.array([2.0, 2.0, 1.5, 1.5, 3.0])
    phi = np.array([1.9, 1.9, 0.4, 2.0, 2.8])
    grid = grid_W_hat(P1, Q1, phi, steps=40_000)
    ref = np.array([reference_W_hat(*x) for x in zip(P1, Q1, phi)])
    assert np.all(np.abs(grid - ref) <= 1e-6 * ref)
