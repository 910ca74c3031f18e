"""The convex backends under test and their tolerances, in one table.

``unrefined`` is the relative agreement of Ŵ with the closed-form projection on the same grid
when the backend's own answer is used (``refine=False``) with lcpfric's default (tight)
settings; with refinement (the default) every backend reproduces the projection to rounding,
``REFINED``. ``steps`` keeps the slow backends' tests short. ``max_iter`` is the setting that
caps the iterations (for the failure-path test) and the start of the status it must report.
"""

import pytest

from lcpfric import available_methods

REFINED = 1e-12  # relative, Ŵ against the projection on the same grid

BACKENDS = {
    # method              extra        unrefined  steps  (iteration-cap setting, status prefix)
    "clarabel":           ("clarabel",  2e-6,  2000, ({"max_iter": 1}, "MaxIterations")),
    "osqp":               ("osqp",      1e-8,  2000, ({"max_iter": 1}, "maximum iterations")),
    "qpsolvers:clarabel": ("qpsolvers", 2e-6,   100, ({"max_iter": 1}, "MaxIterations")),
    "qpsolvers:highs":    ("qpsolvers", 1e-10,  100, ({"qp_iteration_limit": 0}, "not found")),
    "qpsolvers:osqp":     ("qpsolvers", 1e-8,   100, ({"max_iter": 1}, "maximum iterations")),
    "qpsolvers:proxqp":   ("qpsolvers", 1e-9,   100, ({"max_iter": 1}, "QPSolverOutput.PROXQP")),
    "qpsolvers:scs":      ("qpsolvers", 1e-7,   100, ({"max_iters": 1}, "solved (inaccurate")),
    "cvxpy:CLARABEL":     ("cvxpy",     2e-6,    60, ({"max_iter": 1}, "user_limit")),
    "cvxpy:OSQP":         ("cvxpy",     1e-7,    60, ({"max_iter": 1}, "user_limit")),
    "cvxpy:SCS":          ("cvxpy",     1e-7,    60, ({"max_iters": 1}, "optimal_inaccurate")),
    "cvxpy:ECOS":         ("ecos",      1e-7,    60, ({"max_iters": 1}, "user_limit")),
}

FAST = ("clarabel", "osqp")  # the direct APIs: cheap enough for every case


def need(method: str) -> None:
    """Skip the test when ``method`` is not installed, naming the extra to install."""
    if method not in available_methods():
        extra = BACKENDS[method][0]
        hint = "pip install ecos" if extra == "ecos" else f'pip install "lcpfric[{extra}]"'
        pytest.skip(f"{method} is not installed here ({hint})")


def params(methods=None):
    """pytest parameters over the table, every installed backend (the rest skip)."""
    return [pytest.param(m, id=m) for m in (methods or BACKENDS)]
