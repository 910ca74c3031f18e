"""Convex-solver backends: problem (P) solved by a convex solver at every increment.

Every increment is the maximum-dissipation projection of the trial force onto the friction cone
in the metric of K⁻¹, problem (P). The shared parts, in the order a step uses them:

``problem``
    the derivation of (P); :class:`IncrementProblem` (one per contact set),
    :class:`ScenePlan` (everything a scene's steps need, built once) and its
    :class:`ProblemCache` (the sets' problems, under the byte budget ``plan_budget``)
``settings``
    lcpfric's tight default settings per solver
``status``
    lcpfric's solver outcomes and the advice for each
``checks``
    the independent residual checks of every answer, and its acceptance
``refine``
    the active-set refinement of an answer
``base``
    :class:`ConvexStepper`, the public base every backend subclasses

One module per solver adds only the calls to its solver:

``clarabel_``
    Clarabel's direct API, updated in place each step (d = 1 and 2)
``osqp_``
    OSQP, set up once, updated and warm-started each step (d = 1)
``qpsolvers_``
    any solver qpsolvers has installed (d = 1)
``cvxpy_``
    one DPP-parametrized cvxpy problem per contact set (d = 2 with conic solvers)

The registry (:mod:`lcpfric.methods`) maps the names users type to these modules; a backend's
package is imported only when the method is used.
"""

from .base import ConvexData, ConvexStepper, quiet
from .checks import residuals
from .plan import ProblemCache, ScenePlan
from .problem import DEFAULT_PLAN_BUDGET, IncrementProblem, triu_csc
from .refine import accept, refine_box, refine_disc
from .settings import CONIC_METHODS, TIGHT_SETTINGS
from .status import INACCURATE, INFEASIBLE, MAX_ITER, NUMERICAL, SOLVED, TIME_LIMIT, UNKNOWN, advice

__all__ = [
    "ConvexStepper",
    "ConvexData",
    "quiet",
    "accept",
    "residuals",
    "IncrementProblem",
    "ProblemCache",
    "ScenePlan",
    "DEFAULT_PLAN_BUDGET",
    "triu_csc",
    "refine_box",
    "refine_disc",
    "CONIC_METHODS",
    "TIGHT_SETTINGS",
    "SOLVED",
    "INACCURATE",
    "INFEASIBLE",
    "MAX_ITER",
    "TIME_LIMIT",
    "NUMERICAL",
    "UNKNOWN",
    "advice",
]
