"""The ``active-set`` stepper's increment for d = 2 (:mod:`.active_set`, "The method (d = 2)"):
with the stick/slip pattern fixed, Newton's method with a backtracking line search on the
objective ``½ δᵀKδ + F^trᵀδ + Σ_slip b_i ||δ_i||``, whose Hessian ``K_FF + Σ_slip (b_i /
||Δu_i||)(I - ν_i ν_iᵀ)`` is symmetric positive definite; the pattern updated from the natural
map of the disc."""

from __future__ import annotations

import numpy as np


__all__ = ["DiscPatterns"]

_EPS = np.finfo(float).eps


class DiscPatterns:
    """The d = 2 iteration of :class:`~lcpfric.steppers.active_set.ActiveSetStepper`."""

    def disc_pattern(self, plan, F_tr, b, contact, stats, k):
        """The increment for d = 2 (see the module docstring): Newton's method on the
        objective restricted to the free unknowns of a pattern, with a backtracking line
        search, then the pattern updated; returns ``(δ, F, slipping nodes)``.

        A slipping node that Newton's step would carry through ``Δu_i = 0`` (its slip reversed)
        sticks; a sticking node whose force leaves its disc slips, starting from the slip it
        would make alone."""
        K, n = plan.K, plan.n
        kn = plan.kdiag.reshape(n, 2).max(axis=1)
        sep = ~contact
        delta = np.zeros(plan.m)
        F = F_tr.copy()
        slip = np.zeros(n, dtype=bool)
        seen = set()
        for _ in range(self.max_iter):
            F2 = F.reshape(n, 2)
            norm = np.hypot(F2[:, 0], F2[:, 1])
            start = contact & ~slip & (norm > b * (1.0 + 4 * _EPS))
            if start.any():  # the slip each would make alone, against its force
                d2 = delta.reshape(n, 2)
                d2[start] = (
                    -((norm[start] - b[start]) / (kn[start] * norm[start]))[:, None] * F2[start]
                )
                F = F_tr + K @ delta
            elif self._settled(plan, delta, F, b, slip, sep):
                return delta, F, slip
            slip = slip | start
            key = np.packbits(slip).tobytes()
            if key in seen and not start.any():
                break
            seen.add(key)
            delta, F, slip = self._newton(plan, F_tr, delta, b, slip, sep, stats)
            stats["iterations"] += 1
        raise self.unsettled(k, "the d = 2 pattern")

    @staticmethod
    def _settled(plan, delta, F, b, slip, sep):
        """Whether the forces of the pattern's free nodes are at their targets."""
        n = plan.n
        F2, d2 = F.reshape(n, 2), delta.reshape(n, 2)
        g = F2.copy()
        nd = np.hypot(d2[:, 0], d2[:, 1])
        g[slip] += (b[slip] / np.where(nd[slip] > 0, nd[slip], 1.0))[:, None] * d2[slip]
        free = slip | sep
        floor = 64 * _EPS * (plan.force_scale + np.abs(F2[free]).max(initial=0.0))
        return float(np.abs(g[free]).max(initial=0.0)) <= floor

    @staticmethod
    def _newton(plan, F_tr, delta, b, slip, sep, stats):
        """Newton's method on ``Φ(δ) = ½ δᵀKδ + F^trᵀδ + Σ_slip b_i ||δ_i||`` over the
        unknowns of the slipping and separated nodes (the sticking ones fixed at 0)."""
        import scipy.sparse as sp
        from scipy.linalg import cho_factor, cho_solve
        from scipy.sparse.linalg import splu

        K, n = plan.K, plan.n
        sparse = hasattr(K, "tocsc")
        for _ in range(100):
            free = slip | sep
            dofs = np.flatnonzero(np.repeat(free, 2))
            if dofs.size == 0:
                return delta, F_tr + K @ delta, slip
            d2 = delta.reshape(n, 2)
            nd = np.hypot(d2[:, 0], d2[:, 1])
            F = F_tr + K @ delta
            g = F.reshape(n, 2).copy()
            w = np.zeros(n)
            w[slip] = b[slip] / nd[slip]
            nu = d2 / np.where(nd > 0, nd, 1.0)[:, None]
            g += w[:, None] * d2
            gf = g.reshape(-1)[dofs]
            floor = 64 * _EPS * (plan.force_scale + float(np.abs(F[dofs]).max(initial=0.0)))
            if float(np.abs(gf).max(initial=0.0)) <= floor:
                return delta, F, slip
            # the curvature of b ||δ_i|| across the slip direction
            blocks = w[:, None, None] * (np.eye(2)[None] - nu[:, :, None] * nu[:, None, :])
            fn = np.flatnonzero(free)
            # a sparse-matrix first block keeps a sparse matrix on every SciPy
            Dff = (
                sp.block_diag([sp.coo_matrix(blocks[fn[0]]), *blocks[fn[1:]]], format="csc")
                if sparse and fn.size
                else (sp.csc_matrix((0, 0)) if sparse else None)
            )
            if sparse:
                H = K[dofs][:, dofs] + Dff
                step = -splu(H.tocsc()).solve(gf)
            else:
                H = K[np.ix_(dofs, dofs)]
                for i, node in enumerate(fn):
                    H[2 * i : 2 * i + 2, 2 * i : 2 * i + 2] += blocks[node]
                step = -cho_solve(cho_factor(H), gf)
            full = np.zeros(plan.m)
            full[dofs] = step
            s2 = full.reshape(n, 2)
            # the step stops where a slipping node's slip would vanish (its radial part
            # reaches zero): that node sticks from there
            radial = np.einsum("ij,ij->i", s2, nu)
            with np.errstate(divide="ignore", invalid="ignore"):
                reach = np.where(slip & (radial < 0.0), nd / -radial, np.inf)
            tmax = min(1.0, float(reach.min(initial=np.inf)))
            phi0 = _objective(plan, F_tr, delta, b, slip)
            slope = float(gf @ step)
            t = tmax
            # below round-off of Φ the decrease cannot be seen: Newton's full step is taken
            # (it converges quadratically there)
            noise = 64 * _EPS * (abs(phi0) + float(np.abs(full) @ np.abs(F)))
            for _ in range(60):
                trial = delta + t * full
                if (
                    -slope * t <= noise
                    or _objective(plan, F_tr, trial, b, slip) <= phi0 + 1e-4 * t * slope
                ):
                    break
                t *= 0.5
            delta = trial
            if t == tmax and tmax < 1.0:
                stop = slip & (reach <= tmax * (1.0 + 1e-12))
                delta.reshape(n, 2)[stop] = 0.0
                slip = slip & ~stop
            stats["refinements"] += 1
        return delta, F_tr + K @ delta, slip


def _objective(plan, F_tr, delta, b, slip) -> float:
    """``½ δᵀKδ + F^trᵀδ + Σ_slip b_i ||δ_i||`` (d = 2), the function Newton descends."""
    d2 = delta.reshape(-1, 2)
    Kd = plan.K @ delta
    return float(0.5 * delta @ Kd + F_tr @ delta + b[slip] @ np.hypot(d2[slip, 0], d2[slip, 1]))
