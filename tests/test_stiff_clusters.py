"""Stiff systems in cluster coordinates (issue 36): nearly rigid chains against their merged
node, random stiff systems against their merged limits, and what each method says of them.

``exact`` reads K as a spring network and holds the nodes tied by stiff springs as a cluster
(root displacement and offsets, :mod:`lcpfric.exact.clusters`). As the couplings k_c grow a
cluster tends to one node whose W ``exact`` has in closed form; the difference is the chain's
own c / k_c effect, measured here at k_c = 1e4 and taken out at the larger k_c.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import lcpfric
from lcpfric import Harmonic
from lcpfric.errors import InputError, LcpfricError, SolverError
from lcpfric.exact.clusters import Clusters, ScaledLU, spring_form

sys.path.insert(0, str(Path(__file__).resolve().parent))
from support.stiff_random import (  # noqa: E402
    chain_loads,
    energy_scale,
    extrapolated,
    merged,
    merged_chain_W,
    random_stiff,
)

COUPLINGS = (1e2, 1e4, 1e6, 1e8, 1e10, 1e12)


def chain_at(n, kc, loads):
    P1, Q1, psi, phi = loads
    return lcpfric.chain(n, k_coupling=kc, P0=1.0, P1=P1, Q1=Q1, phi=phi, normal_phase=psi)


@pytest.fixture(scope="module", params=[2, 4, 8], ids=lambda n: f"n{n}")
def chain_case(request):
    n = request.param
    loads = chain_loads(n, seed=n)
    Wm = merged_chain_W(*loads)
    rel = {kc: lcpfric.steady_state(chain_at(n, kc, loads), "exact").W / Wm - 1 for kc in COUPLINGS}
    return n, loads, Wm, rel


def test_exact_tends_to_the_merged_node_to_1e_9(chain_case):
    """W - W_merged = c / k_c to 1e-9 of W at every k_c >= 1e6 (c measured at k_c = 1e4); the
    float64 K Cholesky path drifted by 5e-5 at 1e12."""
    _, _, _, rel = chain_case
    c = rel[1e4] * 1e4
    assert abs(c) > 1e-4  # the coupling effect is there, and measurable
    for kc in COUPLINGS[2:]:
        assert abs(rel[kc] - c / kc) <= 1e-9, (kc, rel[kc], c / kc)


def test_the_coupling_effect_is_first_order(chain_case):
    """The difference from the merged node falls like 1/k_c: the ratio of successive
    differences (k_c x 100) is 100 within the second-order term (2.2 % from 1e2 to 1e4 on
    these chains, 2e-4 from 1e4 to 1e6)."""
    _, _, _, rel = chain_case
    assert rel[1e2] / rel[1e4] == pytest.approx(100.0, rel=3e-2)
    assert rel[1e4] / rel[1e6] == pytest.approx(100.0, rel=1e-3)


def test_stiff_chains_use_cluster_coordinates(chain_case):
    n, loads, _, _ = chain_case
    result = lcpfric.steady_state(chain_at(n, 1e12, loads), "exact")
    stats = result.solver_stats
    assert stats["structured"] and stats["clusters"] == 1
    assert stats["condition_scaled"] < 1e4 < stats["condition"]


@pytest.mark.parametrize("method", ["active-set", "explicit"])
@pytest.mark.parametrize("kc", [1e2, 1e4])
def test_other_methods_agree_where_the_chain_is_soft(method, kc):
    n = 4
    loads = chain_loads(n, seed=n)
    W_exact = lcpfric.steady_state(chain_at(n, kc, loads), "exact").W
    W = lcpfric.steady_state(chain_at(n, kc, loads), method).W
    assert W == pytest.approx(W_exact, rel=2e-6)


@pytest.mark.parametrize("method", ["active-set", "explicit"])
@pytest.mark.parametrize("kc", [1e6, 1e12])
def test_other_methods_answer_or_name_exact(method, kc):
    """A nearly rigid chain: the method answers within 1e-5 of exact, or its error names
    'exact' (never a number off by more)."""
    n = 4
    loads = chain_loads(n, seed=n)
    system = chain_at(n, kc, loads)
    W_exact = lcpfric.steady_state(system, "exact").W
    try:
        W = lcpfric.steady_state(system, method, max_cycles=40).W
    except LcpfricError as exc:
        assert "'exact' solves such systems" in str(exc)
    else:
        assert W == pytest.approx(W_exact, rel=1e-5)


# -- random stiff systems --------------------------------------------------------------------
def random_case_error(seed):
    """Relative distance of exact's extrapolated W from the merged limit, or the error."""
    p = random_stiff(seed)
    try:
        W_k = lcpfric.steady_state(p.system(p.k), "exact").W
        W_8k = lcpfric.steady_state(p.system(8 * p.k), "exact").W
    except LcpfricError as exc:
        return exc
    Wm = lcpfric.steady_state(merged(p), "exact").W
    return abs(extrapolated(W_k, W_8k) - Wm) / max(Wm, energy_scale(p))


def check_random(seeds):
    errors, answered = [], 0
    for seed in seeds:
        out = random_case_error(seed)
        if isinstance(out, LcpfricError):
            errors.append((seed, type(out).__name__))
            continue
        answered += 1
        assert out <= 1e-9, (seed, out)  # no silent drift
    assert answered >= 0.8 * len(seeds), errors
    return errors


def test_random_stiff_systems_match_their_merged_limit_or_raise():
    check_random(range(40))


@pytest.mark.slow
def test_a_thousand_random_stiff_systems():
    check_random(range(40, 1040))


# -- pieces --------------------------------------------------------------------------------------
def test_spring_form_is_exact_for_the_stored_entries():
    K = lcpfric.chain(5, k_coupling=1e12, k_ground=0.75).stiffness
    g, S = spring_form(K)
    assert np.array_equal(g, np.full(5, 0.75))  # 1e12 + 0.75 - 1e12 ... exactly rounded
    assert np.allclose(np.diag(g) + np.diag(S.sum(axis=1)) - S, K, rtol=0, atol=0)


def test_clusters_and_rerooting():
    K = np.array(
        [
            [1e9 + 1, -1e9, 0.0, 0.0],
            [-1e9, 1e9 + 2, -1.0, 0.0],
            [0.0, -1.0, 3.0, -1.0],
            [0.0, 0.0, -1.0, 2.0],
        ]
    )
    cl = Clusters(K)
    assert cl.count == 3 and cl.label[0] == cl.label[1] != cl.label[2]
    x = np.array([0.3, 1e-10, -0.2, 0.1])  # canonical: node 0 the root of {0, 1}
    stuck = np.array([False, True, True, True])
    root = cl.roots(stuck)
    assert list(root) == [1, 1, 2, 3]
    y = cl.reroot(x, cl.canonical, root)
    u = cl.to_u(x, cl.canonical)
    assert np.allclose(cl.to_u(y, root), u, rtol=1e-15, atol=0)
    assert np.array_equal(cl.reroot(y, root, cl.canonical)[1:], x[1:])
    # K T x = K u, with the stiff spring acting on the offset alone
    assert np.allclose(cl.KT(root) @ y, K @ u, rtol=0, atol=1e-6)


def test_scaled_lu_solves_columns_of_many_scales():
    A = np.array([[2.0e12, -1.0], [-1.0e12, 3.0]])
    b = np.array([1.0, 2.0])
    lu = ScaledLU(A)
    assert np.allclose(A @ lu.solve(b), b, rtol=1e-15, atol=1e-15)
    assert lu.cond < 10


def test_dense_scaled_family_no_longer_drifts():
    """K = D K0 D with D spanning 1e6: W does not depend on the scaling; the plain form
    returned -2.03 (converged, no warning) at the ratio 1e10 and 0.78 at 1e12."""
    from support.stiff_cases import stiff_cases

    cases = stiff_cases()
    ref = lcpfric.steady_state(cases["dense-r1e0"][0], "exact").W
    for ratio in ("1e4", "1e8", "1e10", "1e12"):
        W = lcpfric.steady_state(cases[f"dense-r{ratio}"][0], "exact").W
        assert W == pytest.approx(ref, rel=1e-11), ratio


def test_an_unguaranteed_answer_is_an_error_naming_the_condition():
    """Springs of 1e3 and 1e13 in one cluster: the offsets of the soft spring's ends would be
    held to 1e-6 only; exact refuses before any work, naming the condition number."""
    n = 3
    K = np.zeros((n, n))
    for i, j, k in ((0, 1, 1e13), (1, 2, 4e3)):
        e = np.zeros(n)
        e[i], e[j] = 1.0, -1.0
        K += k * np.outer(e, e)
    K += np.eye(n)
    system = lcpfric.ContactSystem(
        K,
        np.ones(n),
        [Harmonic(0.0, 2.0, 0.3 * i) for i in range(n)],
        lcpfric.IndependentSprings([Harmonic(1.0, 0.5, 0.1 * i) for i in range(n)]),
        dims=1,
    )
    try:
        W = lcpfric.steady_state(system, "exact").W
    except (InputError, SolverError) as exc:
        assert "condition number" in str(exc)
    else:  # answered: then to the digits the merged limit allows
        assert math.isfinite(W)
