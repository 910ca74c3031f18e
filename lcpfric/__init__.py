"""lcpfric: the energy that friction dissipates in elastic contact systems under periodic loads.

The data flow is the layout (``docs/architecture.md``):

    model/  ->  scene  ->  steppers/, backends/, exact/  ->  periodic/  ->  analysis/, figures/,
    (what the   (one cycle   (one increment: the paper's       (the one       paper/, cli/
    system or   on a grid,   stepper, projections, convex      driver:        (maps, loops,
    contact is) any model)   solvers, the contacts' own;       cycles to      figures, the
                             the exact steady states)          steady state)  paper's claims)
                 methods: the registry of every method name, for every model

Quick use::

    >>> import lcpfric
    >>> node = lcpfric.SingleNode.normalized(P1=0.5, Q1=2.0, phi=0.0)
    >>> round(lcpfric.steady_state(node, method="exact").W_hat, 12)
    1.866666666667

The public names below are imported on first use, so that ``import lcpfric`` (and the command
line) stays fast; :data:`__all__` lists them all.
"""

from __future__ import annotations

import importlib

from .errors import (
    ConvergenceError,
    ConvergenceWarning,
    InputError,
    LcpfricError,
    MissingDependency,
    MissingExtra,
    ResolutionWarning,
    SolverError,
    SolverNotFound,
    UndefinedQuantity,
)

__version__ = "0.2.0"

# public name -> the module that defines it
_LAZY = {
    "analytic": "lcpfric.analysis.analytic",
    "exact_W_hat": "lcpfric.exact",
    "Fourier": "lcpfric.model",
    "Harmonic": "lcpfric.model",
    "Periodic": "lcpfric.model",
    "ContactSystem": "lcpfric.model",
    "IndependentSprings": "lcpfric.model",
    "NormalModel": "lcpfric.model",
    "SingleNode": "lcpfric.model",
    "MDRSphere": "lcpfric.model.continuum",
    "HalfPlaneCylinder": "lcpfric.model.continuum",
    "HalfSpace": "lcpfric.model.continuum",
    "W_from_W_hat": "lcpfric.model",
    "W_hat_from_W": "lcpfric.model",
    "chain": "lcpfric.model",
    "block_diagonal": "lcpfric.model",
    "load_system": "lcpfric.model.files",
    "available_methods": "lcpfric.methods",
    "get_stepper": "lcpfric.methods",
    "get_method": "lcpfric.methods",
    "steady_state": "lcpfric.periodic.driver",
    "CycleResult": "lcpfric.results",
    "State": "lcpfric.results",
    "SteadyState": "lcpfric.results",
    "StepState": "lcpfric.results",
    "BatchResult": "lcpfric.results",
    "ContactExtras": "lcpfric.results",
    "Scene": "lcpfric.scene",
    "make_scene": "lcpfric.scene",
    "with_tangential_load": "lcpfric.scene",
    "methods_for": "lcpfric.methods",
    "Shakedown": "lcpfric.analysis.shakedown",
    "shakedown": "lcpfric.analysis.shakedown",
    "explore_starts": "lcpfric.analysis.starts",
    "StartStudy": "lcpfric.analysis.starts",
    # contacts for vibration codes: displacement-driven elements, AFT, describing functions,
    # the amplitude-dependent frequency and damping of a jointed structure
    "JenkinsElement": "lcpfric.model.jenkins",
    "JointedStructure": "lcpfric.model.structure",
    "driven_cycle": "lcpfric.exact.driven",
    "DrivenCycle": "lcpfric.exact.driven_result",
    "driven_cycle_2d": "lcpfric.exact.driven2d",
    "DrivenCycle2D": "lcpfric.exact.driven2d_result",
    "jenkins_aft": "lcpfric.harmonic",
    "jenkins_residual": "lcpfric.harmonic",
    "AFTResult": "lcpfric.harmonic",
    "describing_functions": "lcpfric.analysis.describing",
    "DescribingFunctions": "lcpfric.analysis.describing",
    "contact_describing_functions": "lcpfric.analysis.describing_contact",
    "modal_damping": "lcpfric.analysis.modal",
    "ModalDamping": "lcpfric.analysis.modal",
    # the contact inside a vibrating structure
    "DynamicSystem": "lcpfric.model.dynamic_system",
    "rayleigh": "lcpfric.model.dynamic_system",
}

__all__ = [
    "ConvergenceError",
    "ConvergenceWarning",
    "InputError",
    "LcpfricError",
    "MissingDependency",
    "MissingExtra",
    "ResolutionWarning",
    "SolverError",
    "SolverNotFound",
    "UndefinedQuantity",
    "__version__",
    *_LAZY,
]


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
