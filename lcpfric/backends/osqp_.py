"""OSQP, set up once and updated each step (``method="osqp"``; d = 1 only).

Problem (P) of each contact set (see :mod:`lcpfric.backends.problem`) is handed to OSQP as
``min ½ Fᵀ C_AA F + qᵀ F`` subject to ``-fN <= I F <= fN``; each step calls
``OSQP.update(q=..., l=..., u=...)`` and ``solve()``, warm-started from the previous answer of the
same contact set (OSQP's ``warm_starting``, on by default; cold after the plan's budget dropped
the set's solver). OSQP expresses only boxes and polyhedra, so d = 2 (a disc per node) is
refused, never approximated.

OSQP's own polishing is off: lcpfric's active-set refinement does the same job and is checked,
whereas OSQP's polish can report success on a poor answer (and prints to stdout).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .base import ConvexStepper
from .problem import IncrementProblem, triu_csc
from .status import INACCURATE, INFEASIBLE, MAX_ITER, NUMERICAL, SOLVED, TIME_LIMIT, UNKNOWN

__all__ = ["OSQPStepper", "STATUS_MAP"]

# OSQP's status strings (``info.status``) -> lcpfric's statuses (unknown strings are errors).
STATUS_MAP = {
    "solved": SOLVED,
    "solved inaccurate": INACCURATE,
    "primal infeasible": INFEASIBLE,
    "primal infeasible inaccurate": INFEASIBLE,
    "dual infeasible": INFEASIBLE,
    "dual infeasible inaccurate": INFEASIBLE,
    "maximum iterations reached": MAX_ITER,
    "run time limit reached": TIME_LIMIT,
    "problem non convex": NUMERICAL,
    "interrupted": UNKNOWN,
    "unsolved": UNKNOWN,
}


class OSQPStepper(ConvexStepper):
    """Problem (P) by OSQP (d = 1), set up once per contact set, updated and warm-started.

    ``**settings`` are OSQP's own (``eps_abs``, ``max_iter``, ``rho``, ...) and override
    lcpfric's tight defaults; ``refine``, ``check_tol``, ``active_tol``, ``locate_events`` and
    ``plan_budget`` are those of :class:`~lcpfric.backends.ConvexStepper`.
    """

    name = "osqp"
    can_soc = False
    STATUS_MAP = STATUS_MAP
    # measured (resident memory per solver object, dense P of 50 to 400 unknowns)
    handle_size = (64, 128 * 1024)

    def __init__(self, **options):
        import osqp

        super().__init__(**options)
        self._osqp = osqp
        self._solved = osqp.SolverStatus.OSQP_SOLVED

    def build(self, prob: IncrementProblem, settings: dict):
        import scipy.sparse as sp

        a = prob.size
        solver = self._osqp.OSQP()
        try:
            solver.setup(
                triu_csc(prob.P),
                prob.q.copy(),
                sp.identity(a, format="csc"),
                -np.ones(a),
                np.ones(a),
                **settings,
            )
        except ValueError as exc:
            if "Unrecognized settings" in str(exc):
                raise InputError("settings", f"OSQP does not know {exc}") from None
            raise
        return solver

    def solve(self, prob: IncrementProblem, q: np.ndarray, bdata):
        solver = prob.handle
        solver.update(q=q, l=bdata[0], u=bdata[1])
        info = solver.solve(raise_error=False)
        return info.x, info.info.status, info.info.status_val == self._solved
