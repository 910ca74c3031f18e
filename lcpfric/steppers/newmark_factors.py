"""The linear algebra of :mod:`lcpfric.steppers.newmark_system`: the effective stiffness of a
step length, its factorization (Cholesky for a dense structure, SuperLU for a sparse one),
solves with rigid contacts held by Lagrange multipliers (a Schur complement on the held
contacts), and the contacts' compliance in its metric. Factorizations are kept per step
length and contact modes, the increments' own lengths for good, the events' sub-lengths in a
small cache."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np
import scipy.linalg as sla

__all__ = ["Factors"]

_SCRATCH = 64  # factorizations of event sub-lengths kept


def _like(A, B):
    import scipy.sparse as sp

    return sp.csc_matrix(B) if sp.issparse(A) else B


class _Factor:
    def __init__(self, A):
        import scipy.sparse as sp

        if sp.issparse(A):
            from scipy.sparse.linalg import splu

            lu = splu(sp.csc_matrix(A))
            self.solve = lambda b: lu.solve(np.asarray(b, dtype=float))
        else:
            c = sla.cho_factor(A)
            self.solve = lambda b: sla.cho_solve(c, b)


class Factors:
    """M, C, K of a dynamic system and the factorizations of its steps (module docstring).

    Parameters
    ----------
    system : DynamicSystem
        The system.
    """

    def __init__(self, system):
        self.M, self.C, self.K = system.mass, system.damping, system.stiffness
        self.G = system.G
        d = system.dims  # per column of G: a d = 2 contact has two
        self.kt = np.repeat(np.where(system.rigid, 0.0, system.contact_stiffness), d)
        self.rigid = np.repeat(system.rigid, d)
        self.scale = system.period
        self.kept: dict = {}
        self.scratch: OrderedDict = OrderedDict()

    @staticmethod
    def key(h) -> float:
        """The cache key of a step length (the length itself: a factorization serves only the
        length it was made for; the grid's equal increments are given one length)."""
        return 0.0 if h == "mass" else float(h)

    def _entry(self, h, sf=None):
        """``(factor of A, cache of (held) -> (W, S))`` for A = M (``h="mass"``) or
        ``K_eff(h) + G_sf diag(kt) G_sfᵀ``."""
        sf = None if sf is None or not sf.any() else sf
        key = (self.key(h), None if sf is None else sf.tobytes())
        hit = self.kept.get(key)
        if hit is None:
            hit = self.scratch.get(key)
            if hit is not None:
                self.scratch.move_to_end(key)
        if hit is not None:
            return hit
        if h == "mass":
            A = self.M
        else:
            A = self.K + (2.0 / h) * self.C + (4.0 / (h * h)) * self.M
            if sf is not None and sf.any():
                Gs = self.G[:, sf]
                A = A + _like(A, (Gs * self.kt[sf]) @ Gs.T)
        hit = (_Factor(A), {})
        if h == "mass" or len(self.kept) < 32 and not self.scratch:
            self.kept[key] = hit
        else:
            self.scratch[key] = hit
            if len(self.scratch) > _SCRATCH:
                self.scratch.popitem(last=False)
        return hit

    def keep(self, h) -> None:
        """Keep the factorizations of the step length h for good (the grid's lengths)."""
        key = (self.key(h), None)
        if key in self.scratch:
            self.kept[key] = self.scratch.pop(key)

    def constrained(self, h, sf, held, rhs, target):
        """Solve ``[A G_h; G_hᵀ 0][x; T] = [rhs; target]`` (A as in :meth:`_entry`, ``held``
        the rigid contacts held): ``(x, T_held)``."""
        fac, schur = self._entry(h, None if h == "mass" else sf)
        x = fac.solve(rhs)
        if not held.any():
            return x, np.zeros((0, rhs.shape[1]))
        key = held.tobytes()
        if key not in schur:
            Wm = fac.solve(self.G[:, held])
            schur[key] = (Wm, sla.lu_factor(self.G[:, held].T @ Wm))
        Wm, S = schur[key]
        T = sla.lu_solve(S, self.G[:, held].T @ x - target)
        return x - Wm @ T, T

    def solve_eff(self, h, r):
        """``K_eff(h)⁻¹ r``."""
        return self._entry(h)[0].solve(r)

    def metric(self, h):
        """``(Z, C_eff)``: ``Z = K_eff⁻¹ G`` and ``C_eff = D⁻¹ + Gᵀ Z`` (D⁻¹ = 0 for a rigid
        contact)."""
        fac, schur = self._entry(h)
        if "metric" not in schur:
            Z = fac.solve(self.G)
            Ce = self.G.T @ Z
            Ce = 0.5 * (Ce + Ce.T)
            fin = ~self.rigid
            Ce[fin, fin] += 1.0 / self.kt[fin]
            schur["metric"] = (Z, Ce)
        return schur["metric"]
