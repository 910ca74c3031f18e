"""What every increment of the ``active-set`` stepper needs for a scene (:class:`Plan`: K and its
block, the loads one instant at a time, the limits and scales) and what its state carries
(:class:`ActiveSetData`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..linalg import OperatorBlock, make_block
from ..scene import column_reduce

__all__ = ["Plan", "ActiveSetData", "CoupledRows"]


class Plan:
    """What every step of a scene needs: K and its block, the loads, the limits, the scales.

    The loads are read one instant at a time (:meth:`row`), so that a scene whose Q and N are
    :class:`~lcpfric.scene.Rows` (1e5 nodes) is never built whole."""

    def __init__(self, scene, block: str, cg_max_iter: int):
        system = scene.system
        self.n, self.m, self.dims = system.n, system.m, system.dims
        K = system.stiffness
        self.K = K
        self.matrix_free = system.matrix_free
        if self.matrix_free:  # the compliance form: C by its products
            self.block = OperatorBlock(system.compliance, cg_max_iter)
            cdiag = system.compliance_diagonal()
            self.kdiag = 1.0 / cdiag
        else:
            self.block = make_block(K, block)
            self.kdiag = np.asarray(K.diagonal(), dtype=float).copy()
        self.Q, self.N = scene.Q, scene.N
        self.friction = np.asarray(system.friction, dtype=float)
        f = self.friction
        sizes = column_reduce(self.Q, lambda x: float(np.max(np.abs(x), initial=0.0)))
        sizes += column_reduce(self.N, lambda x: float(np.max(x * f, initial=0.0)))
        if not all(np.isfinite(sizes)):
            raise InputError(
                "scene",
                "the tangential loads and normal reactions on the grid "
                "must be finite; found NaN or inf",
            )
        scale = max(sizes, default=0.0)
        self.force_scale = scale if scale > 0 else 1.0
        # the compliance scale of the residuals: 1/min k_ii (max C_ii for a diagonal K; C is
        # never formed), or max C_ii of a matrix-free system
        self.compliance_scale = float(1.0 / np.min(self.kdiag))
        self.diagonal = system.is_diagonal()
        self.row_norm = 0.0 if K is None else float(abs(K).sum(axis=1).max())  # ||K||_inf
        self._rows: dict[int, tuple] = {}
        B = getattr(system, "coupling", None)  # N = P + B u (:mod:`.active_set_coupled`)
        self.coupled = None if B is None else CoupledRows.of(scene)

    def row(self, k: int) -> tuple:
        """``(Q, N, b = f N, in contact)`` at grid instant k (the last few are kept)."""
        out = self._rows.get(k)
        if out is None:
            if len(self._rows) >= 4:
                self._rows.clear()
            N = self.N[k]
            out = self._rows[k] = (self.Q[k], N, N * self.friction, N > 0.0)
        return out


@dataclass(frozen=True)
class CoupledRows:
    """What the increments of a coupled system need besides the plan.

    Parameters
    ----------
    K, B : (n, n) ndarray
        The stiffness (dense) and the coupling block, ``N = P + B u``.
    P : (N+1, n) ndarray
        The normal loads on the grid, not clipped (a coupled node is always in contact).
    t : (N+1,) ndarray
        The grid instants (for the messages).

    Attributes
    ----------
    K, B, P, t
        The parameters, as given.
    """

    K: np.ndarray
    B: np.ndarray
    P: np.ndarray
    t: np.ndarray

    @classmethod
    def of(cls, scene) -> CoupledRows:
        """The coupled rows of a coupled system's scene.

        Parameters
        ----------
        scene : Scene
            The scene of a system with a coupling block.

        Returns
        -------
        CoupledRows
            K, B, P and t.
        """
        system = scene.system
        t = np.asarray(scene.t, dtype=float)
        P = np.asarray(system.normal.loads_at(t), dtype=float)
        B = np.asarray(system.coupling, dtype=float)
        return cls(np.asarray(system.dense_stiffness(), dtype=float), B, P, t)


@dataclass(frozen=True)
class ActiveSetData:
    """What the active-set backend carries in ``StepState.data``.

    Attributes
    ----------
    plan : Plan
        K, its block (updated in place: a cache whose content never changes an answer beyond
        round-off, which the checks bound), the loads and limits on the grid.
    stats : dict
        ``solves``, ``iterations``, ``refinements``, ``single_changes``, ``max_residual``.
    u_lo : (m,) ndarray
        What the float64 displacements could not hold of the slips added to them (compensated
        summation): on a weakly grounded system u is 1e12 times the slips, and adding them
        step after step would otherwise random-walk u away from the forces.
    Fc, u_of_Fc : (m,) ndarray
        The forces as computed (``Q + K u`` before the slipping ones are put on their limits),
        and the displacement array they belong to.
    """

    plan: Plan
    stats: dict
    u_lo: np.ndarray
    Fc: np.ndarray
    u_of_Fc: np.ndarray

    def computed_forces(self, state) -> np.ndarray:
        """``Fc`` if it belongs to ``state.u``, else ``state.F`` (a state whose displacement
        was replaced, by the driver's extrapolation for instance)."""
        return self.Fc if state.u is self.u_of_Fc else state.F
