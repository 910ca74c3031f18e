"""The registry's entries: what a method is (:class:`Method`, its kind) and the methods lcpfric
ships (:data:`BUILTIN`, in the order :mod:`lcpfric.methods` registers and lists them).

An entry names its implementation by a ``"module:Class"`` path, so that reading this table
imports no method's code and no solver.
"""

from __future__ import annotations

import importlib
import importlib.util
from dataclasses import dataclass, field

from ..errors import InputError

__all__ = ["Method", "CLOSED_FORM", "TIME_STEPPER", "KINDS", "DISCRETE", "BUILTIN"]

CLOSED_FORM = "closed-form"
TIME_STEPPER = "time-stepper"
KINDS = (CLOSED_FORM, TIME_STEPPER)
#: the models of the discrete methods (``Method.models``)
DISCRETE = ("SingleNode", "ContactSystem")


@dataclass(frozen=True)
class Method:
    """A registry entry.

    Attributes
    ----------
    name : str
        What users type (before any ``:<solver>`` suffix).
    kind : str
        ``"closed-form"`` (returns the steady state directly) or ``"time-stepper"`` (advanced
        by the periodic driver).
    summary : str
        One line for listings.
    target : str or class
        The implementation: a class, or its ``"module:Class"`` path (imported only when the
        method is used).
    dims : tuple of int
        Tangential directions per node it accepts.
    accepts : str
        The systems it accepts, in words (the implementation's ``check`` is the authority).
    models : tuple of str
        The model classes it solves (their names: :func:`methods_for` lists a model's
        methods).
    extra : str or None
        The pip extra that installs what it needs (``pip install "lcpfric[<extra>]"``).
    requires : str or None
        The package it imports (checked with ``importlib.util.find_spec``, not imported).
    solvers : dict
        For a method taking ``:<solver>``: each solver name -> the package that provides it
        (to list what is installed without importing anything).
    default_solver : str or None
        The solver used when no suffix is given (None: a suffix is required).
    grid : str, callable or None
        A function (or its ``"module:function"`` path, imported on use) evaluating
        Ŵ(P̂1, Q̂1, φ) of many single-node points at once (flat arrays; sweeps use it); None:
        point by point through the driver.
    seconds_per_point : float or None
        Cost estimate of ``grid`` per point (closed form), for sizing sweep chunks.
    seconds_per_point_step : float or None
        Cost estimate per point and time step (batched or per-point time steppers).
    floats_per_step : int
        Memory estimate: float64 values held per time step and tangential unknown by one steady
        state (measured peaks, rounded up), for refusing runs that would exhaust memory.
    """

    name: str
    kind: str
    summary: str
    target: object
    dims: tuple = (1,)
    accepts: str = "any ContactSystem or SingleNode"
    models: tuple = DISCRETE
    extra: str | None = None
    requires: str | None = None
    solvers: dict = field(default_factory=dict)
    default_solver: str | None = None
    grid: object = None
    seconds_per_point: float | None = None
    seconds_per_point_step: float | None = None
    floats_per_step: int = 128

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InputError("kind", f"must be one of {KINDS}, got {self.kind!r}")

    @property
    def installed(self) -> bool:
        return self.requires is None or importlib.util.find_spec(self.requires) is not None

    def installed_solvers(self) -> list[str]:
        """The solvers of a ``:<solver>`` method whose packages are installed (not imported)."""
        return [s for s, pkg in self.solvers.items() if importlib.util.find_spec(pkg) is not None]

    def load(self):
        """The implementation class (imports its module)."""
        if not isinstance(self.target, str):
            return self.target
        module, _, attr = self.target.partition(":")
        return getattr(importlib.import_module(module), attr)


# qpsolvers solver name -> the package it imports
_QPSOLVERS = {
    "clarabel": "clarabel",
    "cvxopt": "cvxopt",
    "daqp": "daqp",
    "ecos": "ecos",
    "gurobi": "gurobipy",
    "highs": "highspy",
    "hpipm": "hpipm_python",
    "mosek": "mosek",
    "osqp": "osqp",
    "piqp": "piqp",
    "proxqp": "proxsuite",
    "qpalm": "qpalm",
    "qpoases": "qpoases",
    "qpswift": "qpSWIFT",
    "quadprog": "quadprog",
    "scs": "scs",
}
# cvxpy solvers lcpfric offers (those that fit problem (P)) -> their package
_CVXPY = {"CLARABEL": "clarabel", "ECOS": "ecos", "SCS": "scs", "OSQP": "osqp"}

#: the built-in methods, registered by :mod:`lcpfric.methods` in this order
BUILTIN: tuple[Method, ...] = (
    Method(
        "exact",
        CLOSED_FORM,
        "closed-form event-by-event steady state",
        "lcpfric.exact.solver:ExactSolver",
        dims=(1,),
        accepts="harmonic loads of one frequency: SingleNode (with a mass too), or "
        "ContactSystem (d = 1, IndependentSprings)",
        models=DISCRETE + ("DynamicSingleNode",),
        grid="lcpfric.exact:exact_W_hat",
        seconds_per_point=1.2e-6,
        floats_per_step=12,
    ),
    Method(
        "newmark",
        TIME_STEPPER,
        "Newmark's average acceleration with events located, shooting (dynamic models)",
        "lcpfric.steppers.newmark_node:NewmarkNode",
        dims=(1,),
        accepts="SingleNode with a mass, harmonic loads; DynamicSystem (d = 1)",
        models=("DynamicSingleNode", "DynamicSystem"),
        seconds_per_point_step=2e-5,
        floats_per_step=16,
    ),
    Method(
        "explicit",
        TIME_STEPPER,
        "the paper's state-based stepper, events located",
        "lcpfric.steppers.explicit:ExplicitStepper",
        dims=(1,),
        seconds_per_point_step=3e-6,
        floats_per_step=32,
    ),
    Method(
        "projection",
        TIME_STEPPER,
        "closed-form maximum-dissipation projection per step",
        "lcpfric.steppers.projection:ProjectionStepper",
        dims=(1, 2),
        accepts="diagonal K (uncoupled nodes; isotropic per node for d = 2)",
        grid="lcpfric.batch:projection_W_hat",
        seconds_per_point_step=3e-7,
        floats_per_step=32,
    ),
    Method(
        "clarabel",
        TIME_STEPPER,
        "problem (P) by Clarabel's direct API, updated in place",
        "lcpfric.backends.clarabel_:ClarabelStepper",
        dims=(1, 2),
        extra="clarabel",
        requires="clarabel",
        seconds_per_point_step=3e-5,
    ),
    Method(
        "osqp",
        TIME_STEPPER,
        "problem (P) by OSQP, set up once and warm-started",
        "lcpfric.backends.osqp_:OSQPStepper",
        dims=(1,),
        extra="osqp",
        requires="osqp",
        seconds_per_point_step=3e-5,
    ),
    Method(
        "active-set",
        TIME_STEPPER,
        "problem (P) on K by a primal-dual active-set method (many nodes, stiff K)",
        "lcpfric.steppers.active_set:ActiveSetStepper",
        dims=(1, 2),
        seconds_per_point_step=3e-6,
        floats_per_step=32,
    ),
    Method(
        "qpsolvers",
        TIME_STEPPER,
        "problem (P) by any QP solver qpsolvers has installed",
        "lcpfric.backends.qpsolvers_:QpsolversStepper",
        dims=(1,),
        extra="qpsolvers",
        requires="qpsolvers",
        solvers=_QPSOLVERS,
        seconds_per_point_step=5e-4,
    ),
    Method(
        "cvxpy",
        TIME_STEPPER,
        "problem (P) as one DPP-parametrized cvxpy problem",
        "lcpfric.backends.cvxpy_:CvxpyStepper",
        dims=(1, 2),
        extra="cvxpy",
        requires="cvxpy",
        solvers=_CVXPY,
        default_solver="CLARABEL",
        seconds_per_point_step=1.5e-3,
    ),
    Method(
        "mdr-bar",
        TIME_STEPPER,
        "the MDR sphere's bar equation, exact per increment (no solver)",
        "lcpfric.steppers.mdr_bar:MDRBarStepper",
        dims=(1,),
        accepts="MDRSphere",
        models=("MDRSphere",),
    ),
    Method(
        "halfplane-pdas",
        TIME_STEPPER,
        "the half-plane cylinder's primal-dual active set on the stick set",
        "lcpfric.steppers.halfplane_pdas:HalfPlanePDASStepper",
        dims=(1,),
        accepts="HalfPlaneCylinder",
        models=("HalfPlaneCylinder",),
    ),
    Method(
        "newton-cg",
        TIME_STEPPER,
        "the half-space's semismooth Newton, conjugate gradients on FFT products",
        "lcpfric.steppers.newton_cg:NewtonCGStepper",
        dims=(1, 2),
        accepts="HalfSpace",
        models=("HalfSpace",),
    ),
)
