"""One increment of a convex backend, any size: :class:`Increments`.

Problem (P) from the state at t_k to t_{k+1} (or to an event inside the increment), its answer
refined and checked, the equilibrium check, the node states and the error a failed increment
raises. A mixin of :class:`~lcpfric.backends.base.ConvexStepper`: it uses the backend's
``solve``, ``bounds``, ``bounds_at``, ``guarded``, ``status_category`` and settings.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from ..errors import SolverError
from ..results import State
from ..steppers.dissipation import increment_dissipation
from ..steppers.rates import first_event, path_is_exact
from .checks import separating_slips_agree, worst
from .refine import accept
from .status import advice

if TYPE_CHECKING:
    from ..scene import Scene

__all__ = ["Increments"]


class Increments:
    """The increment of :class:`~lcpfric.backends.base.ConvexStepper` (a mixin)."""

    # -- one increment, any size --------------------------------------------------------------
    def _increment(self, data, scene, k, u, F, stats):
        """Increment k from ``(u, F)`` at t_k: ``(u, F)`` at t_{k+1} and the dissipation to add
        to the increment's trapezoid (nonzero when it was split at events).

        One problem (P) to t_{k+1}; on a coupled d = 1 system whose answer is not the exact
        end state (:func:`~lcpfric.steppers.rates.path_is_exact`: a node slips at the end that
        did not at the start), the increment is split at its events
        (:mod:`~lcpfric.steppers.rates`), one problem (P) per sub-increment."""
        if data.coupled is not None:  # N = P + B u: a fixed point per piece (.coupled)
            return self._coupled_increment(data, scene, k, u, F, stats)
        plan = data.plan
        u1, F1, limit = self._project(data, scene, k, u, stats)
        if (
            not self.locate_events
            or limit is None
            or plan.dims != 1
            or plan.diagonal
            or self._exact_path(plan, k, F, plan.bound[k], u1 - u, F1, limit)
        ):
            return u1, F1, 0.0
        # split at the events: the first one from the rates at the start, solve to it, and
        # again from there while the rest of the increment is not exact
        f = plan.friction
        Qk, Nk = plan.Q[k], plan.N[k]
        dQ, dN = plan.Q[k + 1] - Qk, plan.N[k + 1] - Nk
        sep = (Nk + plan.N[k + 1]) <= 0.0
        a, ua, Fa = 0.0, u, F
        W = 0.0
        for _ in range(4 * plan.n + 16):
            tau = first_event(plan.K, f, Fa, Qk + a * dQ, Nk + a * dN, dQ, dN, sep, a)
            if tau is None:
                break
            ub, Fb, _ = self._project(data, scene, k, ua, stats, tau)
            stats["events"] += 1
            W += increment_dissipation(Fa, Fb, ub - ua)
            a, ua, Fa = tau, ub, Fb
            u1, F1, limit = self._project(data, scene, k, ua, stats)
            if limit is None or self._exact_path(
                plan, k, Fa, f * (Nk + a * dN), u1 - ua, F1, limit
            ):
                break
        W += increment_dissipation(Fa, F1, u1 - ua)
        return u1, F1, W - increment_dissipation(F, F1, u1 - u)

    @staticmethod
    def _exact_path(plan, k, Fa, ba, du, F1, limit):
        """Whether the projection's answer from ``Fa`` (limits ``ba``) to t_{k+1}, slips ``du``,
        is the exact end state: the end pattern is admissible from the start
        (:func:`~lcpfric.steppers.rates.path_is_exact`) and every node separating at t_{k+1}
        slips against its start force (:func:`~lcpfric.backends.checks.separating_slips_agree`).
        """
        sep = plan.separating[k + 1]
        return path_is_exact(Fa, ba, F1, limit, sep, plan.force_scale) and separating_slips_agree(
            Fa, du, sep, plan.force_scale, plan.compliance_scale
        )

    def _project(self, data, scene, k, u, stats, frac=None):
        """Solve, refine and check (P) from ``u`` to t_{k+1} (or, with ``frac``, to the instant
        ``t_k + frac (t_{k+1} - t_k)``, loads interpolated); return ``(u, F, limit)`` there,
        ``limit`` marking the nodes on their friction limit (None for an unrefined answer)."""
        plan = data.plan
        j = k + 1
        if frac is None:
            prob = plan.problem(j)
            if prob is None:  # everything separated: F = 0, u = -C Q
                return -plan.CQ[j], np.zeros(plan.m), None
            neg_CQ, b = plan.neg_CQ[j], plan.node_bounds[j]
            bdata = self.bounds_at(data, prob, j)
            CQ = plan.CQ[j]
        else:
            prob = plan.interior_problem(k)
            CQ = plan.CQ[k] + frac * (plan.CQ[j] - plan.CQ[k])
            neg_CQ = -(CQ if prob.full else CQ[prob.dofs])
            b = plan.bound[k, prob.nodes] + frac * (
                plan.bound[j, prob.nodes] - plan.bound[k, prob.nodes]
            )
            bdata = self.bounds(prob, b)
        q = prob.q
        np.subtract(neg_CQ, u if prob.full else u[prob.dofs], out=q)
        stats["solves"] += 1
        FA, stick = self.solved(plan, scene, k, prob, q, b, bdata, stats)
        u1 = prob.Cf @ FA
        u1 -= CQ
        limit = None
        if stick is not None:  # a refined stick node keeps its displacement exactly
            st = prob.dofs[stick]
            u1[st] = u[st]
            if prob.dims == 1:
                limit = np.zeros(plan.n, dtype=bool)
                limit[prob.nodes[~stick]] = True
        if prob.full:
            return u1, FA, limit
        F1 = np.zeros(plan.m)
        F1[prob.dofs] = FA
        return u1, F1, limit

    def _check_equilibrium(self, plan, scene, rows, U, Fs):
        """``max |Q + K u - F| / s_F`` of the increments ending at ``rows``; raise on the first
        over ``check_tol``."""
        R = U @ plan.K  # K symmetric
        R += plan.Q[rows]
        R -= Fs
        eq = np.abs(R).max(axis=1) / plan.force_scale
        bad = np.flatnonzero(~(eq <= self.check_tol))
        if bad.size:
            i = bad[0]
            self.fail(scene, int(rows[i]) - 1, "solved", {"equilibrium": float(eq[i])})

    def _states(self, plan, rows, dU):
        """Node states over the increments ending at ``rows``, from their slips ``dU``."""
        eps = self.check_tol * plan.compliance_scale * plan.force_scale
        if plan.dims == 1:
            S = (dU > eps).view(np.int8)  # State.FORWARD is 1
            S[dU < -eps] = State.BACKWARD
        else:
            S = (np.hypot(dU[:, 0::2], dU[:, 1::2]) > eps).view(np.int8)
        S[~plan.contact[rows]] = State.SEPARATION
        return S

    def solved(self, plan, scene, k, prob, q, b, bdata, stats):
        """Problem (P) with the right-hand side ``q`` and the limits ``b`` (``bdata`` as the
        backend takes them) solved, refined and checked: ``(FA, stick)``; a solver that fails
        or an answer that fails the checks raises (:meth:`fail`)."""
        x, status, ok = self.guarded(self.solve, prob, q, bdata)
        if not ok:
            self.fail(scene, k, status, None)
        FA, stick, res, kind = accept(
            prob,
            np.array(x, dtype=float),
            q,
            b,
            refine=self.refine,
            active_tol=self.active_tol,
            check_tol=self.check_tol,
            fscale=plan.force_scale,
            cscale=plan.compliance_scale,
        )
        if FA is None:
            self.fail(scene, k, status, res)
        stats[kind] += 1
        stats["max_residual"] = max(stats["max_residual"], worst(res))
        return FA, stick

    def fail(self, scene: Scene, k: int, status: Any, res: dict[str, float] | None) -> NoReturn:
        """Raise the SolverError of step k (status not solved, or residuals over tolerance).

        Parameters
        ----------
        scene : Scene
            The scene (for the increment's instants in the message).
        k : int
            The increment.
        status : Any
            The backend's own status.
        res : dict or None
            The residuals over tolerance; None when the status is not solved.

        Raises
        ------
        lcpfric.errors.SolverError
            Always: its message names the increment, the status or the worst residual, and
            what to do; it carries the backend's label, status and the residuals.
        """
        t0, t1 = scene.t[k], scene.t[k + 1]
        where = f"{self.label}: increment {k} (t = {t0:.6g} -> {t1:.6g})"
        if res is None:
            mapped = self.status_category(status)
            msg = f"{where} ended with solver status {status!s} ({mapped}): {advice(mapped)}"
        else:
            bad = max(res, key=lambda r: math.inf if res[r] != res[r] else res[r])
            msg = (
                f"{where}: the solver reported {status!s} but its answer fails lcpfric's "
                f"residual check ({bad} {res[bad]:.3g} > check_tol {self.check_tol:g}); "
                f"tighten the solver's tolerances" + ("" if self.refine else " or pass refine=True")
            )
            if any(v != v for v in res.values()):
                msg += " (the answer contains NaN: check the loads for NaN or inf)"
        raise SolverError(msg, backend=self.label, status=str(status), residuals=res)
