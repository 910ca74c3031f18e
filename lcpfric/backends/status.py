"""lcpfric's small set of solver outcomes, and what to do about each.

Each backend maps its solver's own status codes onto these (its ``STATUS_MAP``, cvxpy-style);
an unknown code maps to :data:`UNKNOWN`. Only :data:`SOLVED` is accepted; the others raise
:class:`~lcpfric.errors.SolverError` carrying the backend's own status and the advice below.
"""

from __future__ import annotations

__all__ = [
    "SOLVED",
    "INACCURATE",
    "INFEASIBLE",
    "MAX_ITER",
    "TIME_LIMIT",
    "NUMERICAL",
    "UNKNOWN",
    "ADVICE",
    "advice",
]

#: Outcome ``"solved"``: the solver reports the problem solved to its tolerances; the only
#: outcome accepted (the answer is then checked by :mod:`lcpfric.backends.checks`).
SOLVED = "solved"
#: Outcome ``"inaccurate"``: the solver reached only its reduced accuracy (Clarabel's
#: ``AlmostSolved``, OSQP's ``solved inaccurate``); raises :class:`~lcpfric.errors.SolverError`.
INACCURATE = "inaccurate"
#: Outcome ``"infeasible"``: the solver reports the step primal or dual infeasible, which a
#: consistent scene never is; raises :class:`~lcpfric.errors.SolverError`.
INFEASIBLE = "infeasible"
#: Outcome ``"max_iter"``: the solver stopped at its iteration limit; raises
#: :class:`~lcpfric.errors.SolverError`.
MAX_ITER = "max_iter"
#: Outcome ``"time_limit"``: the solver stopped at its time limit; raises
#: :class:`~lcpfric.errors.SolverError`.
TIME_LIMIT = "time_limit"
#: Outcome ``"numerical"``: the solver ran into numerical trouble; raises
#: :class:`~lcpfric.errors.SolverError`.
NUMERICAL = "numerical"
#: Outcome ``"unknown"``: a status the backend's ``STATUS_MAP`` does not list; raises
#: :class:`~lcpfric.errors.SolverError`.
UNKNOWN = "unknown"

#: What to do about each outcome other than :data:`SOLVED` (outcome -> advice), appended to the
#: message of the :class:`~lcpfric.errors.SolverError` it raises.
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
    """What to do about an outcome (the advice of :data:`UNKNOWN` for an unknown category).

    Parameters
    ----------
    category : str
        One of lcpfric's outcomes (:data:`INACCURATE`, :data:`MAX_ITER`, ...), as a backend's
        ``STATUS_MAP`` gives it; any other string is treated as :data:`UNKNOWN`.

    Returns
    -------
    str
        The advice, in words, that ends the message of the
        :class:`~lcpfric.errors.SolverError` of a step with that outcome.
    """
    return ADVICE.get(category, ADVICE[UNKNOWN])
