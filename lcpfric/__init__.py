"""lcpfric: the energy that friction dissipates in elastic contact systems under periodic loads.

The data flow is the layout (``docs/architecture.md``):

    model/  ->  scene  ->  steppers/, backends/  ->  periodic  ->  analysis/, paper/, cli/
    (what the   (one cycle   (one increment:        (cycles to     (maps, shakedown, figures,
    system is)  on a grid)   explicit, projection,   steady state)  the paper's claims)
                             convex solvers)
                 exact, closed_form: the single node's steady state in closed form
                 methods: the registry of every method name

Quick use::

    >>> import lcpfric
    >>> node = lcpfric.SingleNode.normalized(P1=0.5, Q1=2.0, phi=0.0)
    >>> round(lcpfric.steady_state(node, method="exact").W_hat, 12)
    1.866666666667

The public names below are imported on first use, so that ``import lcpfric`` (and the command
line) stays fast.
"""

from __future__ import annotations

import importlib

from .errors import (ConvergenceError, ConvergenceWarning, InputError, LcpfricError,
                     MissingDependency, MissingExtra, ResolutionWarning, SolverError,
                     SolverNotFound, UndefinedQuantity)

__version__ = "0.1.0"

# public name -> the module that defines it
_LAZY = {
    "analytic": "lcpfric.analysis.analytic",
    "exact_W_hat": "lcpfric.exact",
    "Fourier": "lcpfric.model", "Harmonic": "lcpfric.model", "Periodic": "lcpfric.model",
    "ContactSystem": "lcpfric.model", "IndependentSprings": "lcpfric.model",
    "NormalModel": "lcpfric.model", "SingleNode": "lcpfric.model",
    "W_from_W_hat": "lcpfric.model", "W_hat_from_W": "lcpfric.model",
    "chain": "lcpfric.model", "block_diagonal": "lcpfric.model",
    "available_methods": "lcpfric.methods", "get_stepper": "lcpfric.methods",
    "get_method": "lcpfric.methods",
    "steady_state": "lcpfric.periodic.driver",
    "CycleResult": "lcpfric.results", "State": "lcpfric.results",
    "SteadyState": "lcpfric.results", "StepState": "lcpfric.results",
    "BatchResult": "lcpfric.results",
    "Scene": "lcpfric.scene", "make_scene": "lcpfric.scene",
    "Shakedown": "lcpfric.analysis.shakedown", "shakedown": "lcpfric.analysis.shakedown",
}

__all__ = ["ConvergenceError", "ConvergenceWarning", "InputError", "LcpfricError",
           "MissingDependency", "MissingExtra", "ResolutionWarning", "SolverError",
           "SolverNotFound",
           "UndefinedQuantity", "__version__", *_LAZY]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'lcpfric' has no attribute {name!r}")
    mod = importlib.import_module(module)
    value = mod if name == "analytic" else getattr(mod, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
