"""The method registry: every name a user can type, what kind of method it is, what it accepts.

=======================  =============  ======  ==========================================  ========
name                     kind           d       what it is                                  extra
=======================  =============  ======  ==========================================  ========
``exact``                closed-form    1       event-by-event steady state in closed form  -
                                                (single node, harmonic loads; vectorized
                                                over grids of points)
``explicit``             time-stepper   1       the paper's state-based stepper, events     -
                                                located inside increments
``projection``           time-stepper   1, 2    closed-form projection per step (diagonal   -
                                                K; batched over grids of points)
``clarabel``             time-stepper   1, 2    Clarabel's direct API, updated in place     clarabel
``osqp``                 time-stepper   1       OSQP, set up once, warm-started             osqp
``active-set``           time-stepper   1, 2    problem (P) on K by a primal-dual active-set  -
                                                method, blocks of K updated (many nodes,
                                                sparse K, stiff K)
``qpsolvers:<solver>``   time-stepper   1       any solver qpsolvers has installed          qpsolvers
``cvxpy:<SOLVER>``       time-stepper   1, 2    one DPP-parametrized cvxpy problem          cvxpy
``mdr-bar``              time-stepper   1       the MDR sphere's bar equation, exact per    -
                                                increment (MDRSphere)
``halfplane-pdas``       time-stepper   1       the half-plane's primal-dual active set     -
                                                (HalfPlaneCylinder)
``newton-cg``            time-stepper   1, 2    the half-space's semismooth Newton, CG on   -
                                                FFT products (HalfSpace)
=======================  =============  ======  ==========================================  ========

Every caller (the periodic driver, sweeps, benchmarks, the CLI) asks this registry: nothing else
compares method names. :func:`get_method` returns a method's :class:`Method` entry (no import
of its code or its solver), :func:`get_stepper` an instance ready to use, and
:func:`available_methods` the names usable here, found without importing any solver package.
A package may add its own method with :func:`register` (see ``docs/architecture.md``).
"""

from __future__ import annotations

import difflib
import importlib
import importlib.util
import inspect
from dataclasses import dataclass, field
from typing import Any

from .errors import InputError, SolverNotFound

__all__ = [
    "Method",
    "CLOSED_FORM",
    "TIME_STEPPER",
    "METHODS",
    "register",
    "unregister",
    "get_method",
    "get_stepper",
    "available_methods",
    "grid_function",
    "methods_for",
    "check_options",
    "DISCRETE",
]

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

METHODS: dict[str, Method] = {}


def register(method: Method, *, replace: bool = False) -> Method:
    """Add ``method`` to the registry (``replace=True`` to overwrite an entry of that name)."""
    if not isinstance(method, Method):
        raise InputError("method", f"must be a lcpfric.methods.Method, got {type(method).__name__}")
    key = method.name.lower()
    if key in METHODS and not replace:
        raise InputError("method", f"{method.name!r} is registered already; pass replace=True")
    METHODS[key] = method
    return method


def unregister(name: str) -> None:
    """Remove a registry entry (for plugins and tests)."""
    METHODS.pop(str(name).lower(), None)


for _m in (
    Method(
        "exact",
        CLOSED_FORM,
        "closed-form event-by-event steady state",
        "lcpfric.exact.solver:ExactSolver",
        dims=(1,),
        accepts="harmonic loads of one frequency: SingleNode, or ContactSystem (d = 1, "
        "IndependentSprings)",
        grid="lcpfric.exact:exact_W_hat",
        seconds_per_point=1.2e-6,
        floats_per_step=12,
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
):
    register(_m)
del _m


def _split(method) -> tuple[str, str | None]:
    if not isinstance(method, str) or not method.strip():
        raise InputError("method", f"must be a method name such as 'exact', got {method!r}")
    name, _, sub = method.strip().partition(":")
    return name.strip().lower(), (sub.strip() or None)


def get_method(method: str) -> tuple[Method, str | None]:
    """The registry entry of a method name, and its ``:<solver>`` suffix (or None).

    Imports nothing: neither the method's code nor its solver.

    Parameters
    ----------
    method : str
        A method name as users type it, case-insensitive, with an optional ``:<solver>``
        suffix (``"exact"``, ``"qpsolvers:proxqp"``, ``"cvxpy:ECOS"``).

    Returns
    -------
    entry : Method
        The method's registry entry.
    solver : str or None
        The ``:<solver>`` suffix as given (None without one; not checked against the
        installed solvers here, see :func:`get_stepper`).

    Raises
    ------
    InputError
        ``method`` is not a non-empty string, is an unknown name (the message suggests the
        closest known names), or has a suffix the method does not take.
    """
    name, sub = _split(method)
    entry = METHODS.get(name)
    if entry is None:
        close = difflib.get_close_matches(name, list(METHODS), n=2)
        hint = f" (did you mean {' or '.join(repr(c) for c in close)}?)" if close else ""
        raise InputError(
            "method",
            f"unknown method {method!r}{hint}; choose from {', '.join(available_methods())}",
        )
    if sub is not None and not entry.solvers:
        raise InputError("method", f"{entry.name!r} takes no ':<solver>' suffix")
    return entry, sub


def check_options(cls, options: dict, what: str) -> None:
    """Raise InputError for keyword options that ``cls``'s constructor does not take (unless it
    takes ``**settings``, passed on to a solver that checks them itself)."""
    params = inspect.signature(cls.__init__).parameters
    if any(p.kind is p.VAR_KEYWORD for p in params.values()):
        return
    valid = sorted(
        n
        for n, p in params.items()
        if n != "self" and p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)
    )
    unknown = sorted(set(options) - set(valid))
    if unknown:
        raise InputError(
            unknown[0],
            f"is not an option of {what}; valid options: {', '.join(valid) if valid else 'none'}",
        )


def get_stepper(method: Any, **options: Any) -> Any:
    """An instance of a method, ready to use: a time stepper, or a closed-form solver.

    Parameters
    ----------
    method : str, Stepper instance or Stepper class
        A registry name (``"clarabel"``, ``"qpsolvers:proxqp"``, ``"exact"``, ...); an instance
        is passed through, a class is instantiated with ``options``.
    **options
        The method's own options (its constructor's keyword arguments: tolerances, solver
        settings). An option it does not take raises :class:`InputError` naming the valid ones.

    Returns
    -------
    Stepper or ExactSolver
        The method's implementation (:class:`~lcpfric.steppers.base.Stepper` for a time
        stepper, :class:`~lcpfric.exact.solver.ExactSolver` for ``"exact"``), constructed with
        ``options`` and, for a ``:<solver>`` method, the solver's name as the registry spells
        it (the method's default solver when no suffix is given); ``method`` itself when it is
        an instance.

    Raises
    ------
    InputError
        Unknown name or option; options given with an instance; a ``:<solver>`` method without
        a solver (and no default), or with a solver it does not know.
    SolverNotFound
        The method's optional dependency is missing (the message names what to install).
    """
    if getattr(method, "kind", None) in KINDS and not isinstance(method, type):
        if options:
            raise InputError(
                sorted(options)[0],
                "options cannot be given with a method instance; pass them to its constructor",
            )
        return method
    if isinstance(method, type):
        check_options(method, options, repr(getattr(method, "name", method.__name__)))
        return method(**options)
    entry, sub = get_method(method)
    sub = sub or entry.default_solver
    if entry.solvers:
        if sub is None:
            raise InputError(
                "method",
                f"name the solver, as '{entry.name}:<solver>'; installed: "
                f"{', '.join(entry.installed_solvers()) or 'none'}",
            )
        sub = _solver_name(entry, sub)
    if not entry.installed:
        raise SolverNotFound(method, entry.extra, available_methods())
    try:
        cls = entry.load()
    except ModuleNotFoundError as exc:
        top = (exc.name or "").split(".")[0]
        if entry.requires and top == entry.requires.split(".")[0]:
            raise SolverNotFound(method, entry.extra, available_methods()) from exc
        raise
    check_options(cls, options, repr(entry.name))
    return cls(sub, **options) if entry.solvers else cls(**options)


def _solver_name(entry: Method, sub: str) -> str:
    """The solver name as the registry spells it, checking that it is installed."""
    spelled = {s.lower(): s for s in entry.solvers}
    name = spelled.get(sub.lower())
    installed = entry.installed_solvers()
    if name is None:
        raise InputError(
            "method",
            f"'{entry.name}:{sub}': {entry.name} has no solver {sub!r} "
            f"that fits problem (P); "
            f"installed: {', '.join(installed) or 'none'}; others it "
            f"knows: {', '.join(s for s in entry.solvers if s not in installed)}",
        )
    if name not in installed:
        raise SolverNotFound(
            f"{entry.name}:{name}", entry.extra, available_methods(), package=entry.solvers[name]
        )
    return name


def available_methods() -> list[str]:
    """Method names usable on this installation.

    Found with ``importlib.util.find_spec``: no solver package is imported.

    Returns
    -------
    list of str
        The registry's names whose optional dependency is installed, in registry order; a
        ``:<solver>`` method once per installed solver (``"qpsolvers:osqp"``, ...).
    """
    out = []
    for entry in METHODS.values():
        if not entry.installed:
            continue
        if entry.solvers:
            out.extend(f"{entry.name}:{s}" for s in entry.installed_solvers())
        else:
            out.append(entry.name)
    return out


def methods_for(model: object) -> list[str]:
    """The installed method names that solve ``model``, by the registry's ``models``.

    Parameters
    ----------
    model : SingleNode, ContactSystem or ContactModel
        The model; a method solves it when the name of its class, or of one of its base
        classes, is in the method's ``models`` (``Method.models``).

    Returns
    -------
    list of str
        The names usable on this installation, in registry order; a ``:<solver>`` method once
        per installed solver.
    """
    names = {c.__name__ for c in type(model).__mro__}
    out = []
    for entry in METHODS.values():
        if names & set(entry.models) and entry.installed:
            out.extend(
                [f"{entry.name}:{s}" for s in entry.installed_solvers()]
                if entry.solvers
                else [entry.name]
            )
    return out


def grid_function(method: str):
    """``(function, entry)`` evaluating Ŵ of many single-node points at once for ``method``,
    or ``(None, entry)`` where the method has no such form (then run point by point)."""
    entry, sub = get_method(method)
    if entry.grid is None or sub is not None:
        return None, entry
    if callable(entry.grid):
        return entry.grid, entry
    module, _, attr = entry.grid.partition(":")
    return getattr(importlib.import_module(module), attr), entry
