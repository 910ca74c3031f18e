"""lcpfric's small set of solver outcomes, and what to do about each.

Each backend maps its solver's own status codes onto these (its ``STATUS_MAP``, cvxpy-style);
an unknown code maps to :data:`UNKNOWN`. Only :data:`SOLVED` is accepted; the others raise
:class:`~lcpfric.errors.SolverError` carrying the backend's own status and the advice below.
"""

from __future__ import annotations

__all__ = ["SOLVED", "INACCURATE", "INFEASIBLE", "MAX_ITER", "TIME_LIMIT", "NUMERICAL",
           "UNKNOWN", "ADVICE", "advice"]

SOLVED = "solved"
INACCURATE = "inaccurate"
INFEASIBLE = "infeasible"
MAX_ITER = "max_iter"
TIME_LIMIT = "time_limit"
NUMERICAL = "numerical"
UNKNOWN = "unknown"

ADVICE = {
    INACCURATE: "the solver reached only its reduced accuracy; tighten or rescale, or try "
                "another backend",
    INFEASIBLE: "the solver reports the step infeasible, which the data of a consistent scene "
                "never are (F = 0 is always admissible): check the scene for negative normal "
                "reactions on nodes marked in contact, or NaN loads",
    MAX_ITER: "the solver stopped at its iteration limit; raise max_iter (max_iters for SCS)",
    TIME_LIMIT: "the solver stopped at its time limit; raise time_limit",
    NUMERICAL: "the solver ran into numerical trouble; check that K is well conditioned, or "
               "try another backend",
    UNKNOWN: "the solver returned a status lcpfric does not know; see its documentation",
}

# Backends that can express the d = 2 cone, for the error of those that cannot.


def advice(category: str) -> str:
    """What to do about an outcome (the advice of UNKNOWN for an unknown category)."""
    return ADVICE.get(category, ADVICE[UNKNOWN])
