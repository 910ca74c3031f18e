"""Clarabel through its direct API (``method="clarabel"``; d = 1 and d = 2).

Each contact set's problem (P) (see :mod:`lcpfric.backends.problem`) is built when a step first
needs it (again if the plan's budget dropped it): ``P = C_AA`` (upper triangle), and the cone
as Clarabel's ``A x + s = b, s ∈ K`` with

* d = 1: ``A = [I; -I]``, ``b = [fN; fN]``, one ``NonnegativeConeT`` (the interval
  ``|F_i| <= f_i N_i``);
* d = 2: per node the rows ``[0 0; -I]`` with ``b_i = (f_i N_i, 0, 0)``, so that
  ``s_i = (f_i N_i, F_i) ∈ SecondOrderConeT(3)``.

Every step only the vectors change: ``DefaultSolver.update(q=..., b=...)``, then ``solve()``.
That needs ``presolve_enable = False`` (Clarabel refuses data updates on a presolved problem).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, SolverError
from .base import ConvexStepper
from .problem import IncrementProblem, triu_csc
from .status import INACCURATE, INFEASIBLE, MAX_ITER, NUMERICAL, SOLVED, TIME_LIMIT, UNKNOWN

__all__ = ["ClarabelStepper", "STATUS_MAP"]

# Clarabel's SolverStatus names -> lcpfric's statuses (unknown names are errors).
STATUS_MAP = {
    "Solved": SOLVED,
    "AlmostSolved": INACCURATE,
    "MaxIterations": MAX_ITER,
    "MaxTime": TIME_LIMIT,
    "PrimalInfeasible": INFEASIBLE,
    "AlmostPrimalInfeasible": INFEASIBLE,
    "DualInfeasible": INFEASIBLE,
    "AlmostDualInfeasible": INFEASIBLE,
    "NumericalError": NUMERICAL,
    "InsufficientProgress": NUMERICAL,
    "CallbackTerminated": UNKNOWN,
    "Unsolved": UNKNOWN,
}


class ClarabelStepper(ConvexStepper):
    """Problem (P) by Clarabel, built once per contact set (while the plan holds it) and
    updated every step.

    ``**settings`` are attributes of ``clarabel.DefaultSettings`` (``max_iter``,
    ``tol_gap_abs``, ...) and override lcpfric's tight defaults; ``refine``, ``check_tol``,
    ``active_tol``, ``locate_events`` and ``plan_budget`` are those of
    :class:`~lcpfric.backends.ConvexStepper`.
    """

    name = "clarabel"
    can_soc = True
    STATUS_MAP = STATUS_MAP
    # measured (resident memory per solver object, dense P of 50 to 400 unknowns, d = 1)
    handle_size = (112, 128 * 1024)

    def __init__(self, **options):
        import clarabel

        super().__init__(**options)
        self._clarabel = clarabel
        self._solved = clarabel.SolverStatus.Solved
        self._settings = {1: self._make_settings(1)}

    def _make_settings(self, dims: int):
        settings = self._clarabel.DefaultSettings()
        for key, value in self.settings_for(dims).items():
            if key.startswith("_") or not hasattr(settings, key):
                raise InputError(key, "is not a Clarabel setting (see clarabel.DefaultSettings)")
            try:
                setattr(settings, key, value)
            except (TypeError, ValueError) as exc:
                raise InputError(key, f"Clarabel refused the value {value!r}: {exc}") from None
        # Clarabel refuses data updates (DefaultSolver.update) on a presolved problem
        settings.presolve_enable = False
        return settings

    def build(self, prob: IncrementProblem, settings: dict):
        import scipy.sparse as sp

        cl = self._clarabel
        a = prob.size
        if prob.dims == 1:
            eye = sp.identity(a, format="csc")
            A = sp.vstack([eye, -eye], format="csc")
            cones = [cl.NonnegativeConeT(2 * a)]
        else:
            nodes = a // 2
            rows = (3 * np.arange(nodes)[:, None] + np.array([1, 2])[None, :]).ravel()
            A = sp.csc_matrix((-np.ones(a), (rows, np.arange(a))), shape=(3 * nodes, a))
            cones = [cl.SecondOrderConeT(3)] * nodes
        b0 = self.bounds(prob, np.ones(a // prob.dims))
        if prob.dims not in self._settings:
            self._settings[prob.dims] = self._make_settings(prob.dims)
        solver = cl.DefaultSolver(triu_csc(prob.P), prob.q, A, b0, cones, self._settings[prob.dims])
        if not solver.is_data_update_allowed():
            raise SolverError(
                "clarabel: the solver does not allow data updates with these "
                "settings (presolve, chordal decomposition or dropped zeros)",
                backend=self.label,
                status="update_not_allowed",
            )
        return solver

    def bounds(self, prob: IncrementProblem, b: np.ndarray):
        if prob.dims == 1:
            return np.concatenate([b, b])
        out = np.zeros(3 * b.size)
        out[0::3] = b
        return out

    def solve(self, prob: IncrementProblem, q: np.ndarray, bdata):
        solver = prob.handle
        solver.update(q=q, b=bdata)
        sol = solver.solve()
        status = sol.status
        return sol.x, status, status == self._solved
