"""The single node's fast path of the convex backends: one node, one unknown, its problem (P)
solved by the backend in Python floats per step (the same answers as the array path, tested
equal), the residual checks in their scalar form."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..results import CycleResult, State, StepState
from ..steppers.dissipation import scalar_share
from .checks import scalar_residuals, scalar_worst

__all__ = ["ScalarCycle"]


class ScalarCycle:
    """The single-node cycle of :class:`~lcpfric.backends.base.ConvexStepper`."""

    def cycle_scalar(self, scene, state):
        """The cycle of a one-unknown scene (the paper's node) in Python floats: the per-step
        overhead around the solver call is a few float operations, not numpy calls. The same
        algorithm as ``step`` (tested equal): refinement on the box, the residual check in its
        scalar form, the stick node keeping its displacement exactly."""
        data = state.data
        plan = data.plan
        steps = scene.steps
        k11 = float(plan.K[0, 0])
        c = float(plan.C[0, 0])
        Q = plan.Q[:, 0].tolist()
        CQ = plan.CQ[:, 0].tolist()
        B = plan.bound[:, 0].tolist()
        # one unknown: a single contact set besides the empty one, its problem held throughout
        contact = plan.contact[:, 0].tolist()
        prob = plan.problem(contact.index(True)) if True in contact else None
        bdata = data.bdata
        solve, guarded = self.solve, self.guarded
        fs = plan.force_scale
        tol = self.check_tol
        delta = self.active_tol * fs
        refine = self.refine
        stats = dict(data.stats)
        res_scale = (fs, c * fs * fs)
        eps = tol * c * fs
        U = [0.0] * (steps + 1)
        Fs = [0.0] * (steps + 1)
        S = [0] * (steps + 1)
        u, F = float(state.u[0]), float(state.F[0])
        U[0], Fs[0], S[0] = u, F, int(state.state[0])
        W = 0.0
        nsolve = nref = 0
        worst_seen = stats["max_residual"]
        for j in range(1, steps + 1):
            if not contact[j]:
                F1, u1, st = 0.0, -CQ[j], State.SEPARATION
            else:
                b = B[j]
                qb = prob.q
                qv = -(CQ[j] + u)
                qb[0] = qv
                bd = bdata[j]
                if bd is None:
                    bd = self.bounds_at(data, prob, j)
                x, status, ok = guarded(solve, prob, qb, bd)
                nsolve += 1
                if not ok:
                    self.fail(scene, j - 1, status, None)
                Fx = float(x[0])
                bad = math.inf
                stuck = False
                if refine:
                    # identify (on the limit with the solver's sign, or stick), then correct:
                    # a limit node whose slip has the wrong sign sticks, a stick node over
                    # its limit goes to the limit
                    ftr = -qv / c
                    on_limit = abs(Fx) >= b - delta
                    if on_limit:
                        F1 = b if Fx >= 0.0 else -b
                        on_limit = F1 * ftr >= b * b
                    if not on_limit:
                        if -b <= ftr <= b:
                            F1, stuck = ftr, True
                        else:
                            F1 = b if ftr > 0 else -b
                    bad = scalar_worst(F1, c * F1 + qv, b, c, res_scale)
                    if bad <= tol:
                        nref += 1
                if not bad <= tol:
                    stuck = False
                    F1 = Fx
                    bad = scalar_worst(F1, c * F1 + qv, b, c, res_scale)
                    if not bad <= tol:
                        g = c * F1 + qv
                        self.fail(scene, j - 1, status, scalar_residuals(F1, g, b, c, res_scale))
                if bad > worst_seen:
                    worst_seen = bad
                # a refined stick node keeps its displacement exactly
                u1 = u if stuck else c * F1 - CQ[j]
                eq = abs(Q[j] + k11 * u1 - F1) / fs
                if not eq <= tol:
                    res = scalar_residuals(F1, c * F1 + qv, b, c, res_scale)
                    res["equilibrium"] = eq
                    self.fail(scene, j - 1, status, res)
                du = u1 - u
                st = State.FORWARD if du > eps else (State.BACKWARD if du < -eps else State.STICK)
                if b <= 0.0:
                    st = State.SEPARATION
            W += scalar_share(F, F1, u1 - u)
            u, F = u1, F1
            U[j], Fs[j], S[j] = u, F, st
        stats["solves"] += nsolve
        stats["refined"] += nref
        stats["unrefined"] += nsolve - nref
        stats["max_residual"] = worst_seen
        stats.update(plan.problems.counts())
        Ua = np.array(U)[:, None]
        Fa = np.array(Fs)[:, None]
        Sa = np.array(S, dtype=np.int8)[:, None]
        end = StepState(
            Ua[-1].copy(), Fa[-1].copy(), Sa[-1].copy(), 0.0, replace(data, stats=stats)
        )
        return end, CycleResult(scene.t, Ua, Fa, Sa, W, self.stats(end))
