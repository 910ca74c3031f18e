r"""The convex backends on coupled systems (``N = P(t) + B u``, d = 1): one increment as a fixed
point of problem (P) on the normal reactions (:class:`CoupledIncrements`).

The per-step problem
--------------------
Over an increment (or a piece of one, to the fraction τ) the end state of a coupled system
solves problem (P) (:mod:`~lcpfric.backends.problem`) with its limits ``f_i N_i`` taken at the
*end* displacements, ``N = P(t) + B u``: the projection of the trial force onto a box that
depends on the answer. It is solved as a sequence of ordinary problems (P), the normal
reactions updated between them (a fixed point on u)::

    u⁽⁰⁾ = u_a,    u⁽ʲ⁺¹⁾ = T(u⁽ʲ⁾) = the answer of (P) with the limits  f ∘ (P(t) + B u⁽ʲ⁾),

stopped when ``|u⁽ʲ⁺¹⁾ - u⁽ʲ⁾|∞ <= fixed_point_tol · c · s_F`` (c, s_F the compliance and force
scales of the residual checks).

When it converges (a sufficient condition)
------------------------------------------
In the displacements, (P) with limits ``w = f ∘ N >= 0`` is
``u = argmin ½ uᵀKu + Qᵀu + Σ w_i |u_i - u_{a,i}|``: ``K u + Q + ξ = 0`` with
``ξ_i = w_i σ_i``, ``σ_i ∈ sign(u_i - u_{a,i})``. For two limits w, w' and their answers u, u',
``K (u - u') = -(ξ - ξ')``, and with ``d = u - u_a``, ``d' = u' - u_a``, ``|σ| <= 1``::

    (ξ_i - ξ'_i)(d_i - d'_i) = w_i|d_i| - w_i σ_i d'_i - w'_i σ'_i d_i + w'_i|d'_i|
                             >= (w_i - w'_i)(|d_i| - |d'_i|) >= -|w_i - w'_i| |u_i - u'_i|,

so ``λmin(K) |u - u'|₂² <= (u - u')ᵀK(u - u') <= |w - w'|₂ |u - u'|₂``, i.e.
``|u - u'|₂ <= |w - w'|₂ / λmin(K)``. With ``w - w' = diag(f) B (u⁽ʲ⁾ - u⁽ʲ⁻¹⁾)``::

    |u⁽ʲ⁺¹⁾ - u⁽ʲ⁾|₂ <= κ |u⁽ʲ⁾ - u⁽ʲ⁻¹⁾|₂,     κ = ||diag(f) B||₂ / λmin(K),

and T is a contraction when κ < 1: the iteration converges to the unique end state from any
start, geometrically with ratio κ (Banach). κ < 1 is the sufficient condition
:func:`~lcpfric.model.coupling.check_coupling` tries first (there it makes every
``K + diag(s f) B`` positive definite); a system that is well posed only by its minors (κ >= 1)
may still converge (the bound is not sharp: on the nodes that slip the map is linear with the
matrix ``-K⁻¹ diag(s f) B`` restricted to them, and its spectral radius decides), or not: then
the increment raises :class:`~lcpfric.errors.SolverError` with status ``"coupled_fixed_point"``,
naming the measured contraction and κ, never a silent answer.

Pattern steps (``pattern_steps=True``, the default): each refined answer names its stick nodes
and the signs of its limit nodes; on that pattern the fixed point is the solution of one linear
system (the rows of ``K + diag(s f) B`` on the limit nodes, a principal submatrix of a P-matrix,
so nonsingular), which is taken as the next iterate. When the pattern is right the next problem
(P) returns it unchanged and the iteration stops: two convex solves per piece. When a pattern
step does not at least halve the change the iteration falls back to plain fixed-point steps
(which converge when κ < 1). The backends' stats count every solve (``solves``) and the
fixed-point iterations (``fixed_point_iterations``, ``fixed_point_max_ratio``, the largest
measured ratio of successive changes).

The path inside an increment
----------------------------
As for uncoupled systems (:mod:`~lcpfric.steppers.rates`), the answer is the exact end state of
the increment for piecewise-linear loads when its pattern is admissible from the start
(:func:`~lcpfric.steppers.rates.path_is_exact`, with the limits ``f (P + B u)`` at both ends):
with the pattern fixed, u, F and N are linear in τ. Otherwise the first event is located from
the coupled rate problem at the start (the rate LCP with ``K + diag(s f) B`` on the rows on a
limit, as the explicit stepper; the normal reactions' rate ``dP + B du`` in the margins), the
fixed point is solved to it and again from there (one copy of this path for the convex backends
and ``active-set``: :mod:`lcpfric.steppers.coupled_path`). The dissipation is the sum of the pieces'
trapezoids ``-½ (F_a + F_b)·(u_b - u_a)``, exact on the linear pieces. A normal reaction that
reaches zero raises :class:`~lcpfric.errors.InputError` naming the node and the instant
(separation of a coupled node is not modelled).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SolverError
from ..steppers.dissipation import increment_dissipation
from ..steppers.coupled_path import compressed, coupled_path, pattern_point

__all__ = ["CoupledPlan", "CoupledIncrements"]


@dataclass(frozen=True)
class CoupledPlan:
    """What the coupled increments need besides the scene's plan.

    Parameters
    ----------
    B : (n, n) ndarray
        The coupling block, ``N = P + B u``.
    P : (N+1, n) ndarray
        The normal loads P on the grid (not clipped: a coupled node is always in contact).
    contraction_bound : float
        κ = ``||diag(f) B||₂ / λmin(K)``: the fixed point contracts when κ < 1.

    Attributes
    ----------
    B, P, contraction_bound
        The parameters, as given.
    """

    B: np.ndarray
    P: np.ndarray
    contraction_bound: float

    @classmethod
    def of(cls, scene) -> CoupledPlan | None:
        """The coupled plan of a scene, or None for an uncoupled system.

        Parameters
        ----------
        scene : Scene
            A discrete system's scene.

        Returns
        -------
        CoupledPlan or None
            The plan (None when the system has no coupling block).
        """
        system = scene.system
        B = getattr(system, "coupling", None)
        if B is None:
            return None
        K = system.dense_stiffness()
        P = np.asarray(system.normal.loads_at(scene.t), dtype=float)
        kappa = float(np.linalg.norm(system.friction[:, None] * B, 2) / np.linalg.eigvalsh(K)[0])
        return cls(np.asarray(B, dtype=float), P, kappa)


class CoupledIncrements:
    """The increments of :class:`~lcpfric.backends.base.ConvexStepper` on a coupled system (a
    mixin; see the module docstring). Uses the backend's ``solve``, ``bounds``, ``guarded``,
    ``fail`` and the options ``refine``, ``active_tol``, ``check_tol``, ``locate_events``,
    ``fixed_point_tol``, ``fixed_point_max`` and ``pattern_steps``."""

    def _coupled_increment(self, data, scene, k, u, F, stats):
        """Increment k of a coupled system from ``(u, F)`` at t_k: ``(u, F)`` at t_{k+1} and the
        dissipation to add to the increment's trapezoid (nonzero when split at events), along
        the path of :func:`~lcpfric.steppers.coupled_path.coupled_path`."""
        plan, cp = data.plan, data.coupled
        loads = (plan.Q[k], cp.P[k], plan.Q[k + 1] - plan.Q[k], cp.P[k + 1] - cp.P[k])

        def end_state(ua, frac):
            return self._fixed_point(data, scene, k, ua, frac, stats)

        u1, F1, W = coupled_path(
            plan.K, cp.B, plan.friction, loads, u, F, end_state, self.locate_events,
            plan.force_scale, stats,
        )  # fmt: skip
        return u1, F1, W - increment_dissipation(F, F1, u1 - u)

    def _fixed_point(self, data, scene, k, ua, frac, stats):
        """The end state ``(u, F, limit)`` of (P) from ``ua`` to the fraction ``frac`` of
        increment k, its limits ``f (P + B u)`` at the answer: the fixed point of the module
        docstring, with pattern steps unless ``pattern_steps`` is off."""
        plan, cp = data.plan, data.coupled
        K, B, f = plan.K, cp.B, plan.friction
        j = k + 1
        Pt = cp.P[k] + frac * (cp.P[j] - cp.P[k])
        Qt = plan.Q[k] + frac * (plan.Q[j] - plan.Q[k])
        CQ = plan.CQ[k] + frac * (plan.CQ[j] - plan.CQ[k])
        prob = plan.problems.get(np.ones(plan.n, dtype=bool))
        tol = self.fixed_point_tol * plan.compliance_scale * plan.force_scale
        w = ua
        pattern = self.pattern_steps
        prev = ratio = np.inf
        ratios = []
        for it in range(1, self.fixed_point_max + 1):
            N = Pt + B @ w
            u1, F1, limit = self._solve_box(
                data, scene, k, prob, CQ, ua, f * np.maximum(N, 0.0), stats
            )
            stats["solves"] += 1
            change = float(np.abs(u1 - w).max())
            if np.isfinite(prev) and prev > 0.0:
                ratio = change / prev
                ratios.append(ratio)
            if change <= tol:
                break
            if pattern and ratios and ratio > 0.5:
                pattern = False  # the pattern steps do not pay: plain fixed-point steps
            prev = change
            w = u1
            if pattern and limit is not None:
                point = pattern_point(K, B, f, Qt, Pt, ua, np.sign(F1), limit)
                w = ua if point is None else point
        else:
            measured = max(ratios[-5:]) if ratios else np.inf
            t = scene.t[k] + frac * (scene.t[j] - scene.t[k])
            kappa = cp.contraction_bound
            why = (
                f"its sufficient condition κ = ||diag(f) B||₂ / λmin(K) < 1 does not hold "
                f"(κ = {kappa:.3g})"
                if kappa >= 1
                else f"κ = ||diag(f) B||₂ / λmin(K) = {kappa:.3g}: raise fixed_point_max"
            )
            raise SolverError(
                f"{self.label}: the coupled fixed point on the normal reactions did not converge "
                f"in {self.fixed_point_max} convex solves in increment {k} (to t = {t:.6g}): "
                f"measured contraction {measured:.3g} per iteration (last change {change:.3g}, "
                f"tolerance {tol:.3g}); {why}; or use method 'active-set' (the coupled LCP "
                f"directly), 'exact' or 'explicit' (the rate LCP with K + diag(s f) B)",
                backend=self.label,
                status="coupled_fixed_point",
                residuals={"contraction": float(measured), "bound": kappa},
            )
        compressed(Pt + B @ u1, scene.t[k] + frac * (scene.t[j] - scene.t[k]))
        stats["fixed_point_iterations"] = stats.get("fixed_point_iterations", 0) + it
        if ratios:
            stats["fixed_point_max_ratio"] = max(
                stats.get("fixed_point_max_ratio", 0.0), max(ratios)
            )
        return u1, F1, limit

    def _solve_box(self, data, scene, k, prob, CQ, ua, b, stats):
        """(P) on every node from ``ua``, ``C Q`` of its end ``CQ``, limits ``b``: solved,
        refined and checked; ``(u, F, limit)`` (``limit`` None for an unrefined answer)."""
        plan = data.plan
        q = prob.q
        np.subtract(-CQ, ua, out=q)
        FA, stick = self.solved(plan, scene, k, prob, q, b, self.bounds(prob, b), stats)
        u1 = prob.Cf @ FA
        u1 -= CQ
        if stick is None:
            return u1, FA, None
        u1[stick] = ua[stick]  # a refined stick node keeps its displacement exactly
        return u1, FA, ~stick
