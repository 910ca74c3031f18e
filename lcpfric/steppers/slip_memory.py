r"""What a cycle remembers of its starting slips, node by node: the preconditioner of the d = 2
cycle map (:mod:`lcpfric.periodic.acceleration`), tracked during a cycle by the steppers that
can (``newton-cg``) and taken from a recorded cycle for the discrete systems.

With circular friction cones (d = 2) the periodic steady state is reached slowly: the slips
transverse to a node's slip direction are forgotten only in part when the node slips, and the
nodes that slip very little each cycle (at the edge of a stick zone) remember nearly all of
theirs. The cycle map (starting slips x to ending slips G(x)) of a half-space contact then
contracts by as little as 0.75 per cycle on a 40-element contact, 0.996 on a 56-element one
(``benchmarks/results/cycle_acceleration.md``).

One node's memory has a closed form when its neighbours are held (its self-compliance c, its
limit b): a start perturbation e of its slip changes its force by ``-e/c`` while it sticks;
when it slips by ``|Δs|`` in the direction u, the component of the perturbation along u is
forgotten (the force sits on its limit whatever the start) and the component along the
perpendicular p keeps the fraction

.. math:: r = \frac{c\,b}{c\,b + |\Delta s|}

(the slip direction turns by ``δθ = -e/(c b + |Δs|)``: the force ``b δθ`` balances the elastic
``-(e + |Δs| δθ)/c``). Over a cycle the increments' ``r p pᵀ`` multiply into a 2 x 2 matrix
``R_i`` per node, the estimate of the cycle map's Jacobian block on that node: the identity
for a node that sticks the whole cycle (its slip stays where it started), zero for one that
slips across (d = 1's case) or separates. The driver then steps each node by the Newton step of
that block, ``x_i + (I - R_i)⁺ (G(x)_i - x_i)``, its singular values floored at 1/MAX_GAIN.
For one node, or nodes that are not coupled, R_i is the cycle map's Jacobian and that step is
Newton's; for coupled nodes the driver accelerates the map
(:class:`~lcpfric.periodic.acceleration.Anderson`)
for the coupling that the blocks leave out. Convergence is still judged on a whole cycle that
repeats.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SlipMemory", "MAX_GAIN", "row_norms"]

#: the largest factor by which a node's cycle change is multiplied (a node that slips very
#: little each cycle remembers nearly all of its start)
MAX_GAIN = 100.0


class SlipMemory:
    """The per-node memory of the starting slips over one cycle (module docstring), for
    ``n`` nodes with d = 2 and self-compliance ``c`` (a scalar or one per node)."""

    def __init__(self, c, n: int):
        self.c = c
        self.n = int(n)
        # the compiled update's form of c: one per node, or a scalar (and an empty array)
        ca = np.asarray(c, dtype=float)
        self._per_node = ca.reshape(-1) if ca.ndim else np.empty(0)
        self._scalar = float(ca) if not ca.ndim else 0.0

    def start(self) -> np.ndarray:
        """``R`` at a cycle's start: the identity on every node, ``(n, 2, 2)``."""
        return np.broadcast_to(np.eye(2), (self.n, 2, 2)).copy()

    def update(self, R: np.ndarray, dv: np.ndarray, b: np.ndarray) -> None:
        """After an increment with the slips ``dv`` (flat, node-major) under the limits b:
        ``R_i <- r p pᵀ R_i`` on every node that moved, in place (compiled:
        :func:`~lcpfric.model.continuum.halfspace_kernels.slip_memory_update`)."""
        from ..model.continuum import halfspace_kernels  # numba: compiled on first use

        halfspace_kernels.slip_memory_update(
            R,
            np.ascontiguousarray(dv, dtype=float).reshape(self.n, 2),
            np.ascontiguousarray(b, dtype=float),
            self._per_node,
            self._scalar,
        )

    def of_cycle(self, u: np.ndarray, b) -> np.ndarray:
        """``R`` of a recorded cycle: the slips ``u`` at its ``steps + 1`` instants (rows,
        node-major n·2 columns) and the limits ``b[k]`` (rows of n) at each instant. A node
        whose slip in an increment is below 1e-9 of its elastic scale ``c b`` counts as
        sticking (a convex solver's round-off, not a slip)."""
        R = self.start()
        c = np.broadcast_to(np.asarray(self.c, dtype=float), (self.n,))
        for k in range(u.shape[0] - 1):
            bk = np.asarray(b[k + 1], dtype=float)
            d = (u[k + 1] - u[k]).reshape(self.n, 2)
            d[np.hypot(d[:, 0], d[:, 1]) <= 1e-9 * c * bk] = 0.0
            self.update(R, d.reshape(-1), bk)
        return R

    def step(self, R: np.ndarray, f: np.ndarray) -> np.ndarray:
        """``(I - R_i)⁺ f_i`` on every node (singular values of ``I - R_i`` floored at
        ``1/MAX_GAIN``), flat like f; f itself on a node that never moved (R_i = I: any start
        of it repeats, and its change is round-off)."""
        f = f.reshape(self.n, 2)
        A = np.eye(2) - R
        U, s, Vt = np.linalg.svd(A)
        s = np.maximum(s, 1.0 / MAX_GAIN)
        g = np.einsum("nji,nj->ni", U, f) / s
        out = np.einsum("nji,nj->ni", Vt, g)
        still = np.all(A == 0.0, axis=(1, 2))
        out[still] = f[still]
        return out.reshape(-1)


def row_norms(X) -> np.ndarray:
    """The lengths of the rows of an ``(k, 2)`` array (as complex numbers: one contiguous
    pass, several times faster than ``hypot`` of the strided columns)."""
    return np.abs(np.ascontiguousarray(X, dtype=float).view(complex)[:, 0])
