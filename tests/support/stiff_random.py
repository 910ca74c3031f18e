"""Random stiff systems and their merged limits (issue 36).

A system of n = 2..8 nodes (d = 1) whose nodes are split into clusters; each cluster is tied by
stiff springs (a random spanning tree, sometimes with a loop), ``k s_e`` with k the stiffness
scale (a power of two from 2^20 to 2^40, about 1e6 to 1e12) and s_e in [0.5, 2]; clusters are
joined by soft springs (0..1) and every node is grounded (0.5..2). Stiffnesses are multiples of
1/8, so every entry of K is exact in float64 at every k: K holds its groundings exactly, and the
merged limit is the same for every k. Loads are harmonic, each node its own amplitudes and
phases, the normal loads never reach zero. As k grows each cluster moves as one node: the
*merged* system, one node per cluster with the groundings and soft springs summed over its
nodes (``Eᵀ K_soft E``), the friction limit ``Σ f_i P_i(t)`` (one harmonic, as no node
separates) and the load ``Σ Q_i(t)``.
``W(k) = W_merged + c / k + O(1/k²)``: :func:`extrapolated` takes the c / k term out with two
stiffness scales, k and 8 k.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "Stiff",
    "random_stiff",
    "merged",
    "extrapolated",
    "energy_scale",
    "chain_loads",
    "merged_chain_W",
]


@dataclass(frozen=True)
class Stiff:
    """One random stiff system's parameters (``system(k)`` builds it at the scale k)."""

    label: np.ndarray  # cluster of each node
    ground: np.ndarray
    soft: tuple  # (i, j, s)
    stiff: tuple  # (i, j, s): the spring is k s
    f: np.ndarray
    P0: np.ndarray
    P1: np.ndarray
    psi: np.ndarray
    Q1: np.ndarray
    phi: np.ndarray
    k: float

    @property
    def n(self) -> int:
        return self.label.size

    def stiffness(self, k: float) -> np.ndarray:
        K = np.diag(self.ground.astype(float))
        for springs, scale in ((self.soft, 1.0), (self.stiff, k)):
            for i, j, s in springs:
                e = np.zeros(self.n)
                e[i], e[j] = 1.0, -1.0
                K += scale * s * np.outer(e, e)
        return K

    def system(self, k: float | None = None):
        import lcpfric
        from lcpfric import Harmonic

        k = self.k if k is None else k
        return lcpfric.ContactSystem(
            self.stiffness(k),
            self.f,
            [Harmonic(0.0, q, p + a) for q, p, a in zip(self.Q1, self.psi, self.phi)],
            lcpfric.IndependentSprings(
                [Harmonic(p0, p1, p) for p0, p1, p in zip(self.P0, self.P1, self.psi)]
            ),
            dims=1,
        )


def _eighths(rng, lo: float, hi: float, size=None):
    """Uniform multiples of 1/8 in [lo, hi]."""
    return rng.integers(round(8 * lo), round(8 * hi) + 1, size) / 8.0


def random_stiff(seed: int, k: float | None = None) -> Stiff:
    """A seeded random stiff system (module docstring); k = 2^p, p uniform in 20..40, unless
    given."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 9))
    m = int(rng.integers(1, n + 1)) if n > 2 else 1
    label = np.sort(rng.integers(0, m, n))
    label = np.unique(label, return_inverse=True)[1]  # clusters 0..m-1, none empty
    if label.max() == n - 1:  # every cluster a single node: tie the first two
        label[1] = label[0]
        label = np.unique(label, return_inverse=True)[1]
    stiff = []
    for c in range(int(label.max()) + 1):
        nodes = rng.permutation(np.nonzero(label == c)[0])
        for a in range(1, nodes.size):
            stiff.append((int(nodes[a]), int(nodes[rng.integers(0, a)]), _eighths(rng, 0.5, 2.0)))
        if nodes.size >= 3 and rng.random() < 0.3:  # a loop
            i, j = rng.choice(nodes, 2, replace=False)
            stiff.append((int(i), int(j), _eighths(rng, 0.5, 2.0)))
    soft = []
    for i in range(n):
        for j in range(i + 1, n):
            if label[i] != label[j] and rng.random() < 0.5:
                soft.append((i, j, _eighths(rng, 0.0, 1.0)))
    P0 = rng.uniform(0.5, 2.0, n)
    return Stiff(
        label=label,
        ground=_eighths(rng, 0.5, 2.0, n),
        soft=tuple(soft),
        stiff=tuple(stiff),
        f=rng.uniform(0.2, 1.0, n),
        P0=P0,
        P1=P0 * rng.uniform(0.0, 0.9, n),
        psi=rng.uniform(0.0, 2.0 * np.pi, n),
        Q1=rng.uniform(0.2, 2.0, n),
        phi=rng.uniform(-np.pi, np.pi, n),
        k=float(2.0 ** rng.integers(20, 41)) if k is None else float(k),
    )


def merged(p: Stiff, k: float | None = None):
    """The merged system (one node per cluster; a SingleNode when there is one cluster) of the
    system at the scale k (default ``p.k``)."""
    import lcpfric
    from lcpfric import Harmonic

    from lcpfric.exact.clusters import spring_form

    m = int(p.label.max()) + 1
    E = np.zeros((p.n, m))
    E[np.arange(p.n), p.label] = 1.0
    # the groundings and soft springs of K as stored (its exactly rounded row sums): float64
    # holds a grounding beside a stiff spring k only to eps k, and W is that K's
    g, S = spring_form(p.stiffness(p.k if k is None else k))
    soft = np.where(p.label[:, None] == p.label[None, :], 0.0, -S)
    np.fill_diagonal(soft, g - soft.sum(axis=1))
    Km = E.T @ soft @ E
    zb = np.zeros(m, dtype=complex)  # friction limits Σ f P1 e^{iψ}
    b0 = np.zeros(m)
    zq = np.zeros(m, dtype=complex)
    np.add.at(zb, p.label, p.f * p.P1 * np.exp(1j * p.psi))
    np.add.at(b0, p.label, p.f * p.P0)
    np.add.at(zq, p.label, p.Q1 * np.exp(1j * (p.psi + p.phi)))
    normal = [Harmonic(b0[c], abs(zb[c]), float(np.angle(zb[c]))) for c in range(m)]
    tangential = [Harmonic(0.0, abs(zq[c]), float(np.angle(zq[c]))) for c in range(m)]
    if m == 1:
        return lcpfric.SingleNode(
            k11=float(Km[0, 0]),
            f=1.0,
            P0=float(b0[0]),
            normal_load=normal[0],
            tangential_load=tangential[0],
        )
    return lcpfric.ContactSystem(
        Km, np.ones(m), tangential, lcpfric.IndependentSprings(normal), dims=1
    )


def energy_scale(p: Stiff) -> float:
    """A dissipation scale of the system, ``(Σ Q1)² / Σ g``: what W is compared against when
    the merged system shakes down (W_merged = 0)."""
    return float(np.sum(p.Q1) ** 2 / np.sum(p.ground))


def extrapolated(W_k: float, W_8k: float) -> float:
    """``W_merged`` from W at the scales k and 8 k, the c / k term taken out (Richardson)."""
    return W_8k + (W_8k - W_k) / 7.0


def chain_loads(n: int, seed: int):
    """Seeded loads of an n-node chain whose merged node slips (W > 0): per node the normal
    amplitude P1 (P0 = 1), the tangential Q1, the normal phase ψ and Q's phase φ relative to P."""
    rng = np.random.default_rng(seed)
    while True:
        P1, Q1 = rng.uniform(0.0, 0.9, n), rng.uniform(1.5, 3.0, n)
        psi, phi = rng.uniform(-0.5, 0.5, n), rng.uniform(-0.3, 0.3, n)
        if merged_chain_W(P1, Q1, psi, phi) > 0:
            return P1, Q1, psi, phi


def merged_chain_W(P1, Q1, psi, phi) -> float:
    """W of a chain's merged node: stiffness n, P = Σ P_i, Q = Σ Q_i (P0_i = 1, f = 1)."""
    import lcpfric
    from lcpfric import Harmonic

    n = len(P1)
    zp, zq = np.sum(P1 * np.exp(1j * psi)), np.sum(Q1 * np.exp(1j * (psi + phi)))
    node = lcpfric.SingleNode(
        k11=float(n),
        f=1.0,
        P0=float(n),
        normal_load=Harmonic(float(n), abs(zp), float(np.angle(zp))),
        tangential_load=Harmonic(0.0, abs(zq), float(np.angle(zq))),
    )
    return lcpfric.steady_state(node, "exact").W
