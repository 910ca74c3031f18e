"""cvxpy: one DPP-parametrized problem per contact set (``method="cvxpy:<SOLVER>"``).

Problem (P) of each contact set (see :mod:`lcpfric.backends.problem`) is written once with the
step's data as cvxpy ``Parameter`` objects,

    minimize ½ Fᵀ C_AA F + qᵀ F   subject to   |F_i| <= b_i  (d = 1)  or  ||F_i|| <= b_i  (d = 2),

with ``q`` and ``b`` parameters. The problem is DPP (checked with ``is_dcp(dpp=True)``), so cvxpy
compiles it on the first solve and every later step only sets the parameter values and re-solves
(``warm_start=True``). d = 2 needs a conic solver (CLARABEL, ECOS, SCS); the QP solvers (OSQP)
take d = 1 only.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, SolverError, SolverNotFound
from .base import ConvexStepper, quiet
from .problem import IncrementProblem
from .status import INACCURATE, INFEASIBLE, MAX_ITER, NUMERICAL, SOLVED, UNKNOWN

__all__ = ["CvxpyStepper", "installed_solvers", "STATUS_MAP"]

# The solvers lcpfric offers through cvxpy (and whether they take second-order cones); others
# cvxpy may list (MILP codes, SCIPY's LP) do not fit problem (P).
SOLVERS = {"CLARABEL": True, "ECOS": True, "SCS": True, "OSQP": False}

# cvxpy's problem.status -> lcpfric's statuses (cvxpy has already mapped the solver's codes).
STATUS_MAP = {
    "optimal": SOLVED,
    "optimal_inaccurate": INACCURATE,
    "infeasible": INFEASIBLE,
    "infeasible_inaccurate": INFEASIBLE,
    "unbounded": INFEASIBLE,
    "unbounded_inaccurate": INFEASIBLE,
    "infeasible_or_unbounded": INFEASIBLE,
    "user_limit": MAX_ITER,
    "solver_error": NUMERICAL,
}


def installed_solvers() -> list[str]:
    """The cvxpy solvers lcpfric offers that are installed here."""
    import cvxpy as cp

    have = set(cp.installed_solvers())
    return [s for s in SOLVERS if s in have]


class CvxpyStepper(ConvexStepper):
    """Problem (P) through cvxpy, compiled once per contact set (DPP) and re-solved each step.

    Parameters
    ----------
    solver : str, optional
        A cvxpy solver name among :func:`installed_solvers` (default CLARABEL).
    refine, check_tol, active_tol, locate_events, plan_budget
        See :class:`~lcpfric.backends.ConvexStepper`.
    **settings
        Passed to ``Problem.solve`` (the solver's own settings), overriding lcpfric's tight
        defaults for that solver.
    """

    name = "cvxpy"
    STATUS_MAP = STATUS_MAP
    # measured (resident memory per compiled problem after a solve, dense P of 50 to 400
    # unknowns, with CLARABEL, OSQP and SCS: 155 to 226 bytes per entry)
    handle_size = (224, 1024 * 1024)

    def __init__(self, solver: str | None = None, **options):
        import cvxpy as cp

        solver = (solver or "CLARABEL").strip().upper()
        if solver not in SOLVERS:
            raise InputError(
                "method",
                f"cvxpy solver {solver!r} is not offered for this "
                f"problem; choose from {', '.join(SOLVERS)}",
            )
        if solver not in installed_solvers():
            raise SolverNotFound(f"cvxpy:{solver}", "cvxpy", package=solver.lower())
        super().__init__(**options)
        self.solver = solver
        self.settings_key = solver.lower()
        self.can_soc = SOLVERS[solver]
        self._cp = cp

    def build(self, prob: IncrementProblem, settings: dict):
        cp = self._cp
        a = prob.size
        F = cp.Variable(a)
        lin = cp.Parameter(a)
        bnd = cp.Parameter(a // prob.dims)
        objective = cp.Minimize(0.5 * cp.quad_form(F, cp.psd_wrap(prob.P)) + lin @ F)
        if prob.dims == 1:
            constraints = [F <= bnd, -F <= bnd]
        else:
            constraints = [cp.SOC(bnd, cp.reshape(F, (a // 2, 2), order="C"), axis=1)]
        problem = cp.Problem(objective, constraints)
        if not problem.is_dcp(dpp=True):  # pragma: no cover - a guard on the formulation
            raise SolverError("cvxpy: problem (P) is not DPP", backend=self.label, status="not_dpp")
        return problem, F, lin, bnd, settings

    def bounds(self, prob: IncrementProblem, b: np.ndarray):
        return b

    def solve(self, prob: IncrementProblem, q: np.ndarray, bdata):
        problem, F, lin, bnd, settings = prob.handle
        lin.value = q
        bnd.value = bdata
        try:
            quiet(problem.solve, solver=self.solver, warm_start=True, **settings)
        except self._cp.error.SolverError as exc:
            return None, f"solver_error ({exc})", False
        status = problem.status
        return F.value, status, status == "optimal"

    def status_category(self, status) -> str:
        return self.STATUS_MAP.get(str(status).split(" ")[0], UNKNOWN)
