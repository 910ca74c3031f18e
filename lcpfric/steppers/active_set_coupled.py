r"""The ``active-set`` stepper on coupled systems (``N = P(t) + B u``, d = 1): the pattern
iteration of :mod:`.active_set` with the limits moving with the slips.

The per-step problem
--------------------
Over a (piece of an) increment from ``u_a`` the end state is a stick/slip pattern (each node
sticks, ``u_i = u_{a,i}``, ``|F_i| <= f_i N_i``; or is on its upper limit ``F_i = +f_i N_i``
with ``u_i <= u_{a,i}``; or on its lower one ``F_i = -f_i N_i`` with ``u_i >= u_{a,i}``), with
``F = Q + K u`` and ``N = P + B u`` at the end. With the pattern fixed the end state solves one
linear system: the rows of ``K - diag(σ f) B`` on the limit nodes (σ = ±1 their side;
:func:`~lcpfric.steppers.coupled_path.pattern_point`), a principal submatrix of a P-matrix under
Klarbring's condition (:func:`~lcpfric.model.coupling.check_coupling`), so nonsingular: the
problem is a box LCP with a P-matrix, which has exactly one solution. No fixed point on the
normal reactions is needed: **one linear solve per pattern tried**, where the convex backends
solve a sequence of problems (P) (:mod:`lcpfric.backends.coupled`).

The pattern is updated as in the uncoupled iteration (semismooth Newton on the natural map, the
primal-dual active-set method), from the violations of the answer: a sticking node whose force
is beyond its limit ``f N`` (at the answer's N) goes to that limit; a limit node slipping the
wrong way sticks, or goes to the other limit if its natural map ``F_i - k_ii Δu_i`` lies beyond
it. It starts from the nodes on their limits at the start of the piece and those whose trial
force ``Q + K u_a`` is beyond ``f (P + B u_a)``. Should a pattern recur (the matrix is not an
M-matrix), the iteration continues with single changes, the lowest-numbered violated node first,
one bound at a time (through stick), Murty's least-index rule; for a P-matrix LCP that rule
terminates, and ``max_iter`` bounds it regardless (then
:class:`~lcpfric.errors.SolverError`, status ``"max_iter"``).

The path of an increment (events located with the coupled rate problem) is the convex
backends' one (:func:`~lcpfric.steppers.coupled_path.coupled_path`), so both give the same W to
round-off. A normal reaction that reaches zero raises :class:`~lcpfric.errors.InputError` naming
the node and the instant (separation of a coupled node is not modelled). Every end state passes
the stepper's residual checks (cone, complementarity, stationarity, equilibrium).
"""

from __future__ import annotations

import numpy as np

from ..errors import SolverError
from .coupled_path import compressed, coupled_path, pattern_point

__all__ = ["CoupledPatterns"]

_REL = 1e-12  # a violation below this (relative) is round-off


class CoupledPatterns:
    """The coupled increments of :class:`~lcpfric.steppers.active_set.ActiveSetStepper` (a
    mixin; see the module docstring). Uses the stepper's ``_finish``, ``max_iter`` and
    ``locate_events``."""

    def _coupled_increment(self, plan, k, u, F, stats):
        """Increment k of a coupled system from ``(u, F)``: ``(Δu, F, Fc, states, dW)`` at
        t_{k+1}, as :meth:`~lcpfric.steppers.active_set.ActiveSetStepper._increment`."""
        cp = plan.coupled
        K, B, f = cp.K, cp.B, plan.friction
        Q0, Q1 = plan.row(k)[0], plan.row(k + 1)[0]
        P0, P1 = cp.P[k], cp.P[k + 1]
        contact = np.ones(plan.n, dtype=bool)
        last = {}

        def end_state(ua, frac):
            Qt, Pt = Q0 + frac * (Q1 - Q0), P0 + frac * (P1 - P0)
            u1, sigma = self._coupled_pattern(plan, K, B, f, ua, Qt, Pt, stats, k)
            N = compressed(Pt + B @ u1, cp.t[k] + frac * (cp.t[k + 1] - cp.t[k]))
            Fc = Qt + K @ u1
            F1, s = self._finish(plan, u1 - ua, Fc, f * N, contact, stats, k)
            last.update(Fc=Fc, s=s)
            return u1, F1, sigma != 0

        u1, F1, W = coupled_path(
            K, B, f, (Q0, P0, Q1 - Q0, P1 - P0), u, F, end_state, self.locate_events,
            plan.force_scale, stats,
        )  # fmt: skip
        return u1 - u, F1, last["Fc"], last["s"], W

    def _coupled_pattern(self, plan, K, B, f, ua, Q, P, stats, k):
        """The end state from ``ua`` at the loads ``(Q, P)``: ``(u, σ)``, σ the pattern (+1 on
        the upper limit, -1 on the lower, 0 stuck), by the iteration of the module docstring."""
        stats["solves"] += 1
        kd = plan.kdiag
        tol_f = _REL * plan.force_scale
        tol_u = _REL * plan.force_scale * plan.compliance_scale
        F_tr = Q + K @ ua
        b_tr = f * (P + B @ ua)
        sigma = np.where(F_tr >= b_tr - tol_f, 1, np.where(F_tr <= -b_tr + tol_f, -1, 0))
        seen = set()
        single = False
        for _ in range(self.max_iter):
            stats["iterations"] += 1
            u = pattern_point(K, B, f, Q, P, ua, sigma.astype(float), sigma != 0)
            if u is None:
                raise SolverError(
                    f"active-set: increment {k}: the coupled pattern's matrix K - diag(σ f) B "
                    "is singular (Klarbring's condition fails to round-off)",
                    backend=self.name,
                    status="singular",
                )
            du = u - ua
            F = Q + K @ u
            b = f * (P + B @ u)
            z = F - kd * du
            nat = np.where(z > b, 1, np.where(z < -b, -1, 0))
            bad = np.zeros(plan.n, dtype=bool)
            stuck = sigma == 0
            bad[stuck] = np.abs(F[stuck]) > b[stuck] + tol_f
            bad[sigma == 1] = du[sigma == 1] > tol_u
            bad[sigma == -1] = du[sigma == -1] < -tol_u
            if not bad.any():
                return u, sigma
            key = sigma.tobytes()
            if key in seen and not single:
                single = True
            seen.add(key)
            new = sigma.copy()
            if single:  # Murty: the lowest-numbered violated node, one bound at a time
                stats["single_changes"] += 1
                i = int(np.flatnonzero(bad)[0])
                new[i] = 0 if sigma[i] != 0 else nat[i] if nat[i] != 0 else np.sign(F[i])
            else:
                new[bad] = nat[bad]
            sigma = new
        raise self.unsettled(k, "the coupled stick/slip pattern")
