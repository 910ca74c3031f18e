"""Any QP solver qpsolvers has installed (``method="qpsolvers:<solver>"``; d = 1 only).

qpsolvers has no persistent problem object: each step builds a ``qpsolvers.Problem`` with the
contact set's ``P = C_AA`` (prepared once, sparse or dense as the solver prefers), the step's
``q`` and the box ``lb = -fN``, ``ub = fN``, and calls ``solve_problem``, warm-started from the
set's previous answer where the solver takes initial values (cold after the plan's budget dropped
the set). Success is judged by lcpfric's residual check (see :mod:`lcpfric.backends.problem`),
not by ``Solution.found`` alone.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .base import ConvexStepper, quiet
from .problem import IncrementProblem
from .status import INACCURATE, INFEASIBLE, MAX_ITER, NUMERICAL, SOLVED, TIME_LIMIT, UNKNOWN

__all__ = ["QpsolversStepper", "installed_solvers"]

# Solvers that ignore (and warn about) initial values: no warm start for them.
_NO_WARM_START = {
    "highs",
    "hpipm",
    "qpalm",
    "qpoases",
    "quadprog",
    "cvxopt",
    "daqp",
    "ecos",
    "gurobi",
    "mosek",
    "piqp",
    "qpswift",
    "sip",
    "kvxopt",
    "pdhcg",
}

# Words in the solvers' own status strings -> lcpfric's statuses (qpsolvers passes each
# solver's status through unchanged, so there is no single table of codes to map).
_STATUS_WORDS = (
    ("inaccurate", INACCURATE),
    ("almost", INACCURATE),
    ("iter", MAX_ITER),
    ("time", TIME_LIMIT),
    ("infeas", INFEASIBLE),
    ("numeric", NUMERICAL),
    ("solved", SOLVED),
    ("optimal", SOLVED),
)


def installed_solvers() -> list[str]:
    """The qpsolvers solvers usable here (``qpsolvers.available_solvers``)."""
    import qpsolvers

    return sorted(qpsolvers.available_solvers)


class QpsolversStepper(ConvexStepper):
    """Problem (P) by a qpsolvers solver, rebuilt and solved every step (d = 1).

    Parameters
    ----------
    solver : str
        A name in ``qpsolvers.available_solvers`` (``"proxqp"``, ``"osqp"``, ...).
    refine, check_tol, active_tol, locate_events, plan_budget
        See :class:`~lcpfric.backends.ConvexStepper`.
    **settings
        Passed to ``qpsolvers.solve_problem`` (the solver's own settings), overriding
        lcpfric's tight defaults for that solver.
    """

    name = "qpsolvers"
    can_soc = False

    def __init__(self, solver: str | None = None, **options):
        import qpsolvers

        if not solver:
            raise InputError(
                "method",
                f"name the qpsolvers solver, as 'qpsolvers:<solver>'; "
                f"installed: {', '.join(installed_solvers())}",
            )
        solver = solver.strip().lower()
        if solver not in qpsolvers.available_solvers:
            raise InputError(
                "method",
                f"qpsolvers has no usable solver {solver!r} here; "
                f"installed: {', '.join(installed_solvers())}",
            )
        super().__init__(**options)
        self.solver = self.settings_key = solver
        self._qpsolvers = qpsolvers
        # C_AA is dense: a solver that takes dense matrices gets them as they are
        self._sparse = solver not in qpsolvers.dense_solvers
        self._warm = solver not in _NO_WARM_START
        # qpsolvers takes verbose as its own argument, not as a solver setting
        self._verbose = bool(self.user_settings.pop("verbose", False))

    def build(self, prob: IncrementProblem, settings: dict):
        import scipy.sparse as sp

        P = (
            sp.csc_matrix(prob.P)
            if self._sparse
            else (prob.P.toarray() if sp.issparse(prob.P) else np.asarray(prob.P))
        )
        settings = {k: v for k, v in settings.items() if k != "verbose"}
        return {"P": P, "x": None, "settings": settings}

    def handle_bytes(self, prob: IncrementProblem) -> int:
        """The bytes of its copy of P (a CSC matrix for a sparse solver, 12 bytes per entry; a
        dense solver reads ``prob.P`` itself) and of the last answer (the warm start)."""
        s = prob.size
        return (12 * (s if prob.diagonal else s * s) if self._sparse else 0) + 8 * s

    def solve(self, prob: IncrementProblem, q: np.ndarray, bdata):
        handle = prob.handle
        qp = self._qpsolvers
        problem = qp.Problem(handle["P"], q.copy(), lb=bdata[0], ub=bdata[1])
        sol = quiet(
            qp.solve_problem,
            problem,
            solver=self.solver,
            initvals=handle["x"] if self._warm else None,
            verbose=self._verbose,
            **handle["settings"],
        )
        ok = bool(sol.found) and sol.x is not None
        if ok:
            handle["x"] = sol.x
        return sol.x, _status(sol), ok

    def status_category(self, status) -> str:
        text = str(status).lower()
        for word, category in _STATUS_WORDS:
            if word in text:
                return category
        return UNKNOWN


def _status(sol) -> str:
    """The underlying solver's own status, wherever qpsolvers keeps it for that solver."""
    extras = sol.extras or {}
    if "status" in extras:  # clarabel (SolverStatus), scs (info dict)
        return str(extras["status"])
    info = extras.get("info")
    if info is not None and hasattr(info, "status"):  # osqp (str), proxqp (enum)
        return str(info.status)
    return "found" if sol.found else "not found"
