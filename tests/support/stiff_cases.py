"""Stiff coupled systems (d = 1, n = 4..6) with extended-precision references.

Three families, each at the stiffness ratios of :data:`RATIOS`, the loads seeded and the same at
every ratio of a family:

``chain``
    ``lcpfric.chain(6, k_coupling=1, k_ground=1/ratio)``: a weakly grounded chain, nearly free
    to translate as a whole (eigenvalues of K from about 1/ratio to 4).
``stiff-chain``
    ``lcpfric.chain(4, k_coupling=ratio, k_ground=1)``: a nearly rigid chain; its nodes slip
    relative to each other by about 1/ratio, and W scales as 1/ratio.
``dense``
    ``K = D K0 D`` with K0 = A Aᵀ/n + I (A seeded, standard normal) and
    D = diag(geomspace(1, sqrt(ratio), n)), so the diagonal stiffnesses span ``ratio``. Node i's
    loads are scaled by D_i (P0_i = D_i, P1_i = D_i p_i, Q1_i = D_i q_i, f = 1): in the variables
    D u and D⁻¹ F the problem is K0's, so W does not depend on the ratio (in exact arithmetic;
    the float64 inputs differ in their last bits), which checks the reference across ratios.

Every node sticks and slips over part of the steady cycle, and nodes with P1 > P0 separate (the
pinned references' comments list the increments per node).

The chains' loads are mirrored (node n-1-i has node i's normal load and the opposite
tangential one): the net tangential load vanishes, and at some increment of the steady cycle
every node slips at once, so the cycle map forgets the start (ρ = 0, the references' comments)
and any driver reaches the steady state in a few cycles. Seeded loads without that symmetry
push a chain along or let it drift: on the weakly grounded chain the steady state then sits
about 0.3 ratio from u = 0 (the ground springs balancing the chain's walk), on the nearly rigid
chain the cycle map contracts by ρ = 1 - 1.2/ratio per cycle. Their W is well-defined (the
reference finds the fixed point by Newton's method) but a driver that only cycles needs about
ratio cycles to get there, a test of the driver, not of the increment.

The references come from tests/support/stiff_reference.py (mpmath), pinned in
tests/support/stiff_references.py.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RATIOS", "STEPS", "stiff_cases", "dense_stiffness"]

RATIOS = (1.0, 1e4, 1e8, 1e10, 1e12)
STEPS = 300  # steps per cycle: what keeps the mpmath reference at seconds per case


def _name(family: str, ratio: float) -> str:
    return f"{family}-r1e{round(np.log10(ratio))}"


def _harmonic_loads(P0, P1, Q1, phi, psi):
    from lcpfric.model import Harmonic, IndependentSprings

    normal = IndependentSprings(tuple(Harmonic(a, b, c) for a, b, c in zip(P0, P1, psi)))
    tangential = tuple(Harmonic(0.0, q, s + f) for q, s, f in zip(Q1, psi, phi))
    return normal, tangential


def _chain_loads(n: int, seed: int) -> dict:
    """Seeded mirrored chain loads for nodes i < n/2: P1 in [0.2, 2] (P1 > 1 separates), Q1 in
    [1, 2.5], random phases; node n-1-i gets node i's normal load and the opposite tangential
    load (phase + π)."""
    rng = np.random.default_rng(seed)
    P1, Q1 = rng.uniform(0.2, 2.0, n), rng.uniform(1.0, 2.5, n)
    phi, psi = rng.uniform(0.0, 2 * np.pi, n), rng.uniform(0.0, 2 * np.pi, n)
    h = n // 2
    for x in (P1, Q1, psi, phi):
        x[n - h :] = x[:h][::-1]
    phi[n - h :] += np.pi
    return dict(P1=P1, Q1=Q1, phi=phi, normal_phase=psi)


def dense_stiffness(n: int, ratio: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``(K, D)``: K = D K0 D exactly symmetric (the upper triangle mirrored)."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    K0 = A @ A.T / n + np.eye(n)
    D = np.geomspace(1.0, np.sqrt(ratio), n)
    K = D[:, None] * K0 * D[None, :]
    return np.triu(K) + np.triu(K, 1).T, D


def _dense(n: int, ratio: float, seed: int):
    from lcpfric.model import ContactSystem

    K, D = dense_stiffness(n, ratio, seed)
    rng = np.random.default_rng(seed + 1000)
    p, q = rng.uniform(0.2, 2.0, n), rng.uniform(0.5, 2.0, n)
    phi, psi = rng.uniform(0.0, 2 * np.pi, n), rng.uniform(0.0, 2 * np.pi, n)
    normal, tangential = _harmonic_loads(D, D * p, D * q, phi, psi)
    return ContactSystem(K, np.ones(n), tangential, normal)


def stiff_cases() -> dict:
    """``{name: (system, steps per cycle)}`` for every family and ratio (names like
    ``chain-r1e8``)."""
    from lcpfric import chain

    out = {}
    for ratio in RATIOS:
        out[_name("chain", ratio)] = (
            chain(6, k_coupling=1.0, k_ground=1.0 / ratio, **_chain_loads(6, 0)),
            STEPS,
        )
    for ratio in RATIOS:
        out[_name("stiff-chain", ratio)] = (
            chain(4, k_coupling=ratio, k_ground=1.0, **_chain_loads(4, 0)),
            STEPS,
        )
    for ratio in RATIOS:
        out[_name("dense", ratio)] = (_dense(6, ratio, 3), STEPS)
    return out
