"""The active-set backend (``method="active-set"``): the same increments as the convex backends,
solved on K; its blocks, its d = 2 iteration, the driver without history, large scenes."""

import numpy as np
import pytest

from support import need

import lcpfric
from lcpfric.errors import InputError, SolverError
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings
from lcpfric.model.loads import LoadSet


def staggered_chain(n=12, sep=True, sparse=False, seed=0, dims=1, kc=2.0):
    rng = np.random.default_rng(seed)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    shape = (n, 2) if dims == 2 else n
    return lcpfric.chain(
        n,
        k_coupling=kc,
        P1=P1,
        Q1=rng.uniform(0.5, 2.0, shape),
        phi=rng.uniform(0, 2 * np.pi, shape),
        dims=dims,
        sparse=sparse,
    )


def dense_spd(n=8, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    K = A @ A.T + np.eye(n)
    P1, Q1, phi = rng.uniform(0.3, 1.8, n), rng.uniform(0.5, 2.0, n), rng.uniform(0, 6, n)
    return ContactSystem(
        K,
        np.ones(n),
        tuple(Harmonic(0.0, Q1[i], phi[i]) for i in range(n)),
        IndependentSprings(tuple(Harmonic(1.0, P1[i]) for i in range(n))),
    )


@pytest.mark.parametrize(
    "make",
    [lambda: staggered_chain(sep=True), lambda: staggered_chain(sep=False), dense_spd],
    ids=["chain-separation", "chain-contact", "dense"],
)
@pytest.mark.parametrize("events", [False, True])
def test_same_increments_as_osqp(make, events):
    """The same discretized problem as every convex backend: W to round-off."""
    need("osqp")
    system = make()
    a = lcpfric.steady_state(system, "active-set", 300, tol=1e-12, locate_events=events)
    b = lcpfric.steady_state(system, "osqp", 300, tol=1e-12, locate_events=events)
    assert a.W == pytest.approx(b.W, rel=1e-11)
    assert a.solver_stats["max_residual"] < 1e-10
    np.testing.assert_allclose(a.v, b.v, atol=1e-9 * np.ptp(b.v))


def test_blocks_agree_and_reordered_band():
    """Dense inverse, banded Cholesky (natural and reverse Cuthill-McKee order) and SuperLU give
    the same steps."""
    import scipy.sparse as sp

    system = staggered_chain(n=15, sparse=True)
    ref = lcpfric.steady_state(system, "active-set", 200, tol=1e-12, block="dense").W
    for block in ("banded", "sparse", "auto"):
        W = lcpfric.steady_state(system, "active-set", 200, tol=1e-12, block=block).W
        assert W == pytest.approx(ref, rel=1e-12)
    # the same chain with its nodes shuffled: banded again after reordering
    perm = np.random.default_rng(3).permutation(system.n)
    K = sp.csc_matrix(system.stiffness)[perm][:, perm]
    shuffled = ContactSystem(
        K,
        system.friction[perm],
        tuple(system.tangential_loads[i] for i in perm),
        IndependentSprings(tuple(system.normal.loads[i] for i in perm)),
    )
    from lcpfric.linalg.blocks import BandedBlock, make_block

    block = make_block(shuffled.stiffness)
    assert isinstance(block, BandedBlock) and block.width == 1 and not block.natural
    W = lcpfric.steady_state(shuffled, "active-set", 200, tol=1e-12).W
    assert W == pytest.approx(ref, rel=1e-12)


def test_dense_block_updates_fold_and_products():
    """The dense block through a walk of free sets that change by a few unknowns (corrections,
    folds) or by many (rebuilds): every solve and every product over the solved unknowns equals
    numpy's on K itself."""
    from lcpfric.linalg.blocks import DenseBlock, FOLD_RANK

    rng = np.random.default_rng(5)
    m = 120
    A = rng.standard_normal((m, m)) / np.sqrt(m)
    K = A @ A.T + np.eye(m)
    block = DenseBlock(K)
    free = np.zeros(m, dtype=bool)
    free[rng.choice(m, 50, replace=False)] = True
    for it in range(60):
        flip = rng.choice(m, 60 if it == 30 else int(rng.integers(1, 8)), replace=False)
        free[flip] = ~free[flip]
        sel = np.flatnonzero(free)
        block.set(sel)
        r = rng.standard_normal(m)
        unknowns, x = block.solve(r)
        assert np.array_equal(np.sort(unknowns), sel)
        np.testing.assert_allclose(
            x, np.linalg.solve(K[np.ix_(unknowns, unknowns)], r[unknowns]), rtol=0, atol=1e-10
        )
        y = rng.standard_normal(x.size)
        np.testing.assert_allclose(
            block.product(unknowns, y), K[:, unknowns] @ y, rtol=0, atol=1e-12
        )
    assert block.stats["factorizations"] >= 2  # the first set and the large change
    assert block.stats["updates"] > 40 and FOLD_RANK < 60


def test_uncoupled_and_single_node_equal_the_projection():
    system = lcpfric.chain(
        4, k_coupling=0.0, P1=[0.5, 1.5, 0.2, 2.0], Q1=[1, 2, 0.5, 3], phi=[0.1, 1.0, 2.0, 3.0]
    )
    a = lcpfric.steady_state(system, "active-set", 400, tol=1e-12)
    b = lcpfric.steady_state(system, "projection", 400, tol=1e-12)
    assert a.W == pytest.approx(b.W, rel=1e-12)
    node = lcpfric.SingleNode.normalized(1.5, 2.0, 0.6 * np.pi)
    a = lcpfric.steady_state(node, "active-set", 400, tol=1e-12)
    b = lcpfric.steady_state(node, "projection", 400, tol=1e-12)
    assert a.W_hat == pytest.approx(b.W_hat, rel=1e-12)


def test_second_order_against_exact():
    """With events located, W converges to the exact discrete solution at second order."""
    system = staggered_chain(n=5, kc=1.0)
    exact = lcpfric.steady_state(system, "exact").W
    errors = [
        abs(lcpfric.steady_state(system, "active-set", s, tol=1e-12).W - exact)
        for s in (200, 400, 800)
    ]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.8), orders


def test_discs_agree_with_clarabel():
    """d = 2: the Newton iteration gives clarabel's steps."""
    need("clarabel")
    system = staggered_chain(n=4, dims=2, seed=1, kc=0.7)
    a = lcpfric.steady_state(system, "active-set", 120, tol=1e-11)
    b = lcpfric.steady_state(system, "clarabel", 120, tol=1e-11)
    assert a.W == pytest.approx(b.W, rel=1e-9)
    assert a.solver_stats["max_residual"] < 1e-9


def test_no_history_and_large_scene(monkeypatch):
    """history=False keeps two rows and gives the same W; a scene over the size limit keeps
    its loads as Rows and gives the same W."""
    import lcpfric.scene as scene

    system = staggered_chain(n=10)
    full = lcpfric.steady_state(system, "active-set", 200, tol=1e-12)
    ends = lcpfric.steady_state(system, "active-set", 200, tol=1e-12, history=False)
    assert ends.W == full.W and ends.cycles == full.cycles
    assert ends.v.shape == (2, 10) and ends.t.shape == (2,) and ends.N.shape == (2, 10)
    np.testing.assert_array_equal(ends.v[-1], full.v[-1])
    monkeypatch.setattr(scene, "LAZY_BYTES", 1000)
    sc = scene.make_scene(system, 200)
    assert isinstance(sc.Q, scene.Rows) and isinstance(sc.N, scene.Rows)
    np.testing.assert_array_equal(np.asarray(sc.Q), system.tangential(sc.t))
    np.testing.assert_array_equal(sc.Q[3], np.asarray(sc.Q)[3])
    np.testing.assert_array_equal(np.asarray(sc.Q / 4.0), np.asarray(sc.Q) / 4.0)
    lazy = lcpfric.steady_state(system, "active-set", 200, tol=1e-12, history=False)
    assert lazy.W == pytest.approx(full.W, rel=1e-13)


def test_explicit_without_history():
    system = staggered_chain(n=3)
    a = lcpfric.steady_state(system, "explicit", 200, tol=1e-12)
    b = lcpfric.steady_state(system, "explicit", 200, tol=1e-12, history=False)
    assert a.W == b.W


def test_load_set_equals_each_load():
    loads = [
        Harmonic(0.3, 1.2, 0.7),
        lcpfric.model.Fourier(1.0, (0.5, 0.2), (0.1, 2.0)),
        Harmonic(-1.0, 0.0, 0.0),
        Harmonic(0.0, 2.0, 1.0, omega=2.0),
        lcpfric.model.Periodic(lambda t: np.cos(t) ** 2, 2 * np.pi),
    ]
    t = np.linspace(0, 7, 53)
    got = LoadSet(loads)(t)
    want = np.stack([np.broadcast_to(p(t), t.shape) for p in loads], axis=-1)
    np.testing.assert_allclose(got, want, rtol=0, atol=8 * np.finfo(float).eps * 3)
    assert LoadSet(loads)(0.4).shape == (5,)


def test_bad_options_and_unsupported_history():
    need("osqp")
    system = staggered_chain(n=3)
    with pytest.raises(InputError, match="block"):
        lcpfric.steady_state(system, "active-set", 100, block="cholmod")
    with pytest.raises(InputError, match="max_iter"):
        lcpfric.steady_state(system, "active-set", 100, max_iter=0)
    with pytest.raises(InputError, match="history"):
        lcpfric.steady_state(system, "osqp", 100, history=False)
    with pytest.raises(InputError, match="history"):
        lcpfric.steady_state(system, "active-set", 100, history="no")


def test_iteration_cap_raises_with_status():
    system = staggered_chain(n=30, kc=5.0)
    with pytest.raises(SolverError) as info:
        lcpfric.steady_state(system, "active-set", 100, max_iter=1)
    assert info.value.status == "max_iter" and info.value.backend == "active-set"
