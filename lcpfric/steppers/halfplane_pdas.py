r"""The half-plane cylinder's increment (``method="halfplane-pdas"``): problem (P) under load
control by a primal-dual active-set iteration on the stick set.

The nodes in contact carry friction forces ``F_i = -q_i Δ`` (lcpfric's sign: the slip opposes
F), with ``|F_i| <= μ N_i``, ``N_i = p_i Δ``; the relative slips s and the rigid tangential
displacement δ satisfy ``s = δ 1 + C F`` with ``C = A / Δ``; the bodies are held by Q(t) and by
the support: ``Σ F_i - k_support δ + Q = 0``. Each increment is problem (P), the
maximum-dissipation projection, solved by the same primal-dual active-set iteration as the
``active-set`` backend's compliance form with the load-control constraint: with the pattern
fixed, the sticking nodes S keep their slip, ``F_S = y - δ z`` with ``y = C_SS⁻¹ (s_S - C_SA
F_A)``, ``z = C_SS⁻¹ 1``, and δ from the equilibrium; the pattern is updated from ``F_i - Δs_i /
C_ii``. Separated nodes carry no force and no unknown (their slip follows the surface).

The model (:class:`~lcpfric.model.continuum.halfplane.HalfPlaneCylinder`) gives the compliance
``C = A / Δ`` and the friction limits; the stepper keeps the block of C (a
:class:`~lcpfric.linalg.DenseBlock`, updated when the stick set changes by a few nodes) in its
state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SolverError
from ..linalg import DenseBlock, PatternUpdate
from ..model.continuum.halfplane import HalfPlaneCylinder
from .continuum import ContinuumStepper

__all__ = ["HalfPlanePDASStepper"]

_MAX_ITER = 400
#: with a support, single changes by Murty's rule before the bounded least squares take over
_SINGLE_MAX = 64
_EPS = np.finfo(float).eps


@dataclass
class _Surface:
    """The tangential state: relative slips of every node (``v``), rigid displacement δ, and
    the nodes on their upper and lower limits (the next increment's first pattern)."""

    v: np.ndarray
    delta: float
    up: np.ndarray
    dn: np.ndarray


class HalfPlanePDASStepper(ContinuumStepper):
    """The half-plane cylinder's increments (module docstring)."""

    name = "halfplane-pdas"
    model_type = HalfPlaneCylinder

    def context(self, scene):
        """The model and the block of its compliance C (the stick set's solves)."""
        return scene.model, DenseBlock(scene.model.C)

    def start(self, scene, context) -> _Surface:
        total = scene.model.total
        none = np.zeros(total, dtype=bool)
        return _Surface(np.zeros(total), 0.0, none, none)

    def increment(self, context, state: _Surface, b: np.ndarray, Q: float, guess=None, tol=None):
        """Problem (P) with the load-control constraint (module docstring): ``(state, F,
        Δs)``."""
        model, block = context
        C, cd, ks = model.C, model.cdiag, model.k_support
        s0 = state.v
        # a limit within the solve's round-off of zero (an element at its entry load) carries
        # no force: the node is treated as separated
        contact = b > 1e-10 * model.force_scale
        up, dn = state.up & contact, state.dn & contact
        updates = PatternUpdate(contact)
        # Murty's rule (the pattern rule's fallback) changes one node per iteration
        limit = _MAX_ITER + int(contact.sum())
        for _ in range(limit):
            F = np.where(up, b, np.where(dn, -b, 0.0))
            S = np.flatnonzero(contact & ~up & ~dn)
            if S.size:
                block.set(S)
                rhs = s0 - C @ F
                idx, y = block.solve(rhs)
                e = np.zeros(model.total)
                e[S] = 1.0
                _, z = block.solve(e)
                delta = (y.sum() + F.sum() + Q) / (z.sum() + ks)
                F[idx] = y - delta * z
            elif ks > 0.0:
                delta = (F.sum() + Q) / ks
            else:
                raise SolverError(
                    "half-plane: every node in contact slips or is separated "
                    "under pure load control (gross sliding)",
                    backend="halfplane",
                    status="gross_sliding",
                )
            s = delta + C @ F
            s[S] = s0[S]
            ds = s - s0
            # a node on its limit that neither slips nor leaves it (F tracks μN, as at the
            # edge of an in-phase contact) is decided within the solve's round-off (forces to
            # about 1e-14 of their scale), not flipped for ever
            tol = 1e-10 * model.force_scale + 64 * _EPS * (b + np.abs(F))
            nxt = updates.next(F - ds / cd, -b - tol, b + tol, up, dn)
            if nxt is None:
                np.clip(F, -b, b, out=F)  # round-off only (tol above)
                return _Surface(s, delta, up, dn), F, ds
            up, dn = nxt
            if ks > 0.0 and updates.stats["single_changes"] > _SINGLE_MAX:
                break  # Murty's rule is slow here, or cycling: see below
        if ks > 0.0:
            # with a support the increment is a bounded least-squares problem: solved by
            # scipy's bounded-variable least squares, whose active set terminates (the
            # patterns above can cycle under gross sliding, a node flipping between its
            # bounds)
            return self._bounded(model, state, b, Q, contact)
        raise SolverError(
            f"half-plane: the stick/slip pattern did not settle in {limit} iterations",
            backend="halfplane",
            status="max_iter",
        )

    @staticmethod
    def _bounded(model, state, b, Q, contact):
        """The increment with ``k_support > 0`` as ``min ½ Fᵀ (C + 1 1ᵀ/k_s) F + (Q/k_s - s0)ᵀ
        F`` over ``|F| <= b`` (its optimality conditions are problem (P)'s: the gradient is the
        increment's slip), by BVLS on the Cholesky factor; its answer is checked."""
        from scipy.linalg import cho_factor, solve_triangular
        from scipy.optimize import lsq_linear

        C, ks, s0 = model.C, model.k_support, state.v
        on = np.flatnonzero(contact)
        H = C[np.ix_(on, on)] + 1.0 / ks
        g = Q / ks - s0[on]
        U, _ = cho_factor(H, lower=False)  # H = Uᵀ U
        U = np.triu(U)
        y = -solve_triangular(U, g, trans="T")  # ½|U F - y|² = ½FᵀHF + gᵀF + c
        sol = lsq_linear(
            U, y, bounds=(-b[on], b[on]), method="bvls", tol=1e-14, max_iter=50 * on.size
        )
        F = np.zeros(model.total)
        F[on] = sol.x
        delta = (F.sum() + Q) / ks
        s = delta + C @ F
        ds = s - s0
        band = 1e-10 * model.force_scale + 64 * _EPS * (b + np.abs(F))
        up, dn = contact & (F >= b - band) & (ds < 0.0), contact & (F <= -b + band) & (ds > 0.0)
        stick = contact & ~up & ~dn
        # the natural map's residual: sticking nodes keep their slip, the others sit on
        # their limits with the slip opposing the force
        worst = max(
            float(np.max(np.abs(ds[stick]) / model.cdiag[stick], initial=0.0)),
            float(np.max(np.abs(np.abs(F[~stick & contact]) - b[~stick & contact]), initial=0.0)),
        )
        if not sol.success or worst > 1e-8 * model.force_scale:
            raise SolverError(
                f"half-plane: the bounded least-squares increment ended with "
                f"residual {worst:.3g} (status {sol.status}: {sol.message})",
                backend="halfplane",
                status=str(sol.status),
            )
        s[stick] = s0[stick]
        ds[stick] = 0.0
        np.clip(F, -b, b, out=F)
        return _Surface(s, delta, up, dn), F, ds
