"""The method registry: the names users type, mapped to steppers.

=======================  ===========================================================  =========
name                     what it is                                                   extra
=======================  ===========================================================  =========
``exact``                closed-form event-by-event steady state (single node,        -
                         harmonic loads)
``explicit``             the paper's state-based stepper, events located (d = 1)      -
``projection``           closed-form projection per step (diagonal K)                 -
``clarabel``             Clarabel, direct API, problem built once per scene           clarabel
``osqp``                 OSQP, set up once, updated and warm-started (d = 1)          osqp
``qpsolvers:<name>``     any solver qpsolvers has installed (d = 1)                   qpsolvers
``cvxpy:<SOLVER>``       one DPP-parametrized cvxpy problem, compiled once            cvxpy
=======================  ===========================================================  =========

Backends register themselves in :data:`BACKENDS` by module; a backend's package is imported only
when the method is used, and a missing one raises :class:`~lcpfric.errors.SolverNotFound` naming
the extra to install.
"""

from __future__ import annotations

import importlib

from .errors import InputError, SolverNotFound
from .steppers import ExplicitStepper, ProjectionStepper, Stepper

__all__ = ["get_stepper", "available_methods", "BACKENDS", "STEPPERS"]

STEPPERS: dict[str, type[Stepper]] = {
    "explicit": ExplicitStepper,
    "projection": ProjectionStepper,
}

# name -> (module under lcpfric.backends, class name, extra, python package it needs)
BACKENDS: dict[str, tuple[str, str, str, str]] = {
    "clarabel": ("clarabel_", "ClarabelStepper", "clarabel", "clarabel"),
    "osqp": ("osqp_", "OSQPStepper", "osqp", "osqp"),
    "qpsolvers": ("qpsolvers_", "QpsolversStepper", "qpsolvers", "qpsolvers"),
    "cvxpy": ("cvxpy_", "CvxpyStepper", "cvxpy", "cvxpy"),
}


def _split(method: str) -> tuple[str, str | None]:
    if not isinstance(method, str) or not method.strip():
        raise InputError("method", f"must be a method name such as 'exact', got {method!r}")
    name, _, sub = method.strip().partition(":")
    return name.lower(), (sub or None)


def get_stepper(method, **options) -> Stepper:
    """Return a stepper instance for a method name (or pass a Stepper instance/class through).

    ``options`` go to the stepper's constructor (tolerances, solver settings).
    """
    if isinstance(method, Stepper):
        return method
    if isinstance(method, type) and issubclass(method, Stepper):
        return method(**options)
    name, sub = _split(method)
    if name in STEPPERS:
        if sub:
            raise InputError("method", f"{name!r} takes no ':<solver>' suffix")
        return STEPPERS[name](**options)
    if name in BACKENDS:
        module, cls, extra, package = BACKENDS[name]
        if importlib.util.find_spec(package) is None:
            raise SolverNotFound(method, extra, available_methods())
        try:
            mod = importlib.import_module(f"lcpfric.backends.{module}")
        except ModuleNotFoundError as exc:
            if exc.name and exc.name.split(".")[0] == package:
                raise SolverNotFound(method, extra, available_methods()) from exc
            raise
        stepper_cls = getattr(mod, cls)
        return stepper_cls(sub, **options) if sub is not None else stepper_cls(**options)
    raise InputError("method", f"unknown method {method!r}; choose from "
                               f"{', '.join(available_methods())}")


def available_methods() -> list[str]:
    """Method names usable on this installation (qpsolvers and cvxpy with their solvers)."""
    out = ["exact", *STEPPERS]
    for name, (module, cls, extra, package) in BACKENDS.items():
        if importlib.util.find_spec(package) is None:
            continue
        try:
            mod = importlib.import_module(f"lcpfric.backends.{module}")
        except ImportError:
            continue
        listing = getattr(mod, "installed_solvers", None)
        if listing is None:
            out.append(name)
        else:
            out.extend(f"{name}:{s}" for s in listing())
    return out
