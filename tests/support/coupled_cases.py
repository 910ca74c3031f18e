"""Coupled systems (``N = P + B u``) the tests of several methods share: the two-node system
of the start figure's kind, a well-posed 3-node system whose plain fixed point on N does not
contract, and one coupled node (with a normal load that separates it, or not)."""

from __future__ import annotations

import numpy as np

from lcpfric.model import ContactSystem, Harmonic, IndependentSprings

__all__ = [
    "two_nodes",
    "K3",
    "B3",
    "full_slip_system",
    "coupled_node",
    "separating_node",
    "pair_order",
]


def two_nodes(c: float = 1.0) -> ContactSystem:
    """Two coupled nodes, the coupling block scaled by c (c = 0: the uncoupled system)."""
    return ContactSystem(
        np.array([[2.824, 0.764], [0.764, 2.740]]),
        friction=np.array([0.625, 0.407]),
        tangential_loads=(Harmonic(0.0, 1.442, 3.388), Harmonic(0.0, 1.429, 1.351)),
        normal=IndependentSprings((Harmonic(4.314, 0.951, 4.160), Harmonic(3.202, 0.334, 5.216))),
        coupling=c * np.array([[0.952, -0.096], [-0.015, -1.532]]),
    )


#: a well-posed 3-node system (every K + diag(s) B a P-matrix) whose fixed point on N does not
#: contract on the full forward slip: the spectral radius of K^-1 B there is 1.043
K3 = np.array([[2.734, -0.493, -2.086], [-0.493, 0.638, 0.419], [-2.086, 0.419, 3.676]])
B3 = np.array([[-0.096, 1.124, -0.566], [-0.086, 0.132, -0.505], [0.255, 0.855, 0.079]])


def full_slip_system() -> ContactSystem:
    """Constant loads whose exact state from u = 0 slips every node forward to u = 0.5 (f = 1,
    P = 10): ``F = -f N`` there."""
    P = np.full(3, 10.0)
    Q = -K3 @ np.full(3, 0.5) - (P + B3 @ np.full(3, 0.5))
    return ContactSystem(
        K3,
        np.ones(3),
        tuple(Harmonic(q, 0.0, 0.0) for q in Q),
        IndependentSprings(tuple(Harmonic(p, 0.0, 0.0) for p in P)),
        coupling=B3,
    )


def coupled_node(normal=None, b: float = -1.2) -> ContactSystem:
    """One coupled node (k = 2, f = 0.5, Q = 3 sin ωt), N = P + b u."""
    return ContactSystem(
        np.array([[2.0]]),
        np.array([0.5]),
        (Harmonic(0.0, 3.0, 0.0),),
        IndependentSprings((Harmonic(4.0, 0.5, 1.0) if normal is None else normal,)),
        coupling=np.array([[b]]),
    )


def separating_node() -> ContactSystem:
    """One coupled node whose normal reaction reaches zero (P = 1, b = -1.9)."""
    return coupled_node(Harmonic(1.0, 0.0, 0.0), -1.9)


def pair_order(method: str) -> float:
    """The least-squares order of ``method``'s W against ``exact`` on :func:`two_nodes` from the
    start ratios (-0.8, 0), over 100..6400 steps (measured 2.50 for every method)."""
    import lcpfric
    from lcpfric.analysis.starts import start_from_ratios

    s = two_nodes()
    u0 = start_from_ratios(s, [-0.8, 0.0])
    W = lcpfric.steady_state(s, "exact", u0=u0).W
    ns = np.array([100, 200, 400, 800, 1600, 3200, 6400])
    err = [abs(lcpfric.steady_state(s, method, n, u0=u0, tol=1e-12).W - W) for n in ns]
    return float(-np.polyfit(np.log(ns), np.log(err), 1)[0])
