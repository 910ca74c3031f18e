"""The method registry: every name a user can type, what kind of method it is, what it accepts.

=======================  ============  ====  ==========================================  =========
name                     kind          d     what it is                                  extra
=======================  ============  ====  ==========================================  =========
``exact``                closed-form   1     event-by-event steady state in closed form  -
                                             (single node, harmonic loads; vectorized
                                             over grids of points)
``explicit``             time-stepper  1     the paper's state-based stepper, events     -
                                             located inside increments
``projection``           time-stepper  1, 2  closed-form projection per step (diagonal   -
                                             K; batched over grids of points)
``clarabel``             time-stepper  1, 2  Clarabel's direct API, updated in place     clarabel
``osqp``                 time-stepper  1     OSQP, set up once, warm-started             osqp
``active-set``           time-stepper  1, 2  problem (P) on K by a primal-dual           -
                                             active-set method, blocks of K updated
                                             (many nodes, sparse K, stiff K)
``qpsolvers:<solver>``   time-stepper  1     any solver qpsolvers has installed          qpsolvers
``cvxpy:<SOLVER>``       time-stepper  1, 2  one DPP-parametrized cvxpy problem          cvxpy
``mdr-bar``              time-stepper  1     the MDR sphere's bar equation, exact per    -
                                             increment (MDRSphere)
``halfplane-pdas``       time-stepper  1     the half-plane's primal-dual active set     -
                                             (HalfPlaneCylinder)
``newton-cg``            time-stepper  1, 2  the half-space's semismooth Newton, CG on   -
                                             FFT products (HalfSpace)
=======================  ============  ====  ==========================================  =========

Every caller (the periodic driver, sweeps, benchmarks, the CLI) asks this registry: nothing else
compares method names. :func:`get_method` returns a method's :class:`Method` entry (no import
of its code or its solver), :func:`get_stepper` an instance ready to use, and
:func:`available_methods` the names usable here, found without importing any solver package.
A package may add its own method with :func:`register` (see ``docs/architecture.md``). The
:class:`Method` record and the entries lcpfric ships are in :mod:`lcpfric.methods.entries`.
"""

from __future__ import annotations

import difflib
import importlib
import inspect
from typing import Any

from ..errors import InputError, SolverNotFound
from .entries import BUILTIN, CLOSED_FORM, DISCRETE, KINDS, TIME_STEPPER, Method

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


for _m in BUILTIN:
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
    if getattr(model, "is_dynamic", False) and "SingleNode" in names:  # a node with a mass
        names = {"DynamicSingleNode"}
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
