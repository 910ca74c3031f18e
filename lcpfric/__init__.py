"""lcpfric: the energy that friction dissipates in elastic contact systems under periodic loads.

The data flow is the layout: model (:mod:`~lcpfric.model`, :mod:`~lcpfric.loads`,
:mod:`~lcpfric.systems`) -> scene (:mod:`~lcpfric.scene`) -> stepper (:mod:`~lcpfric.steppers`,
:mod:`~lcpfric.backends`, :mod:`~lcpfric.batch`) -> periodic driver (:mod:`~lcpfric.periodic`) ->
analysis (:mod:`~lcpfric.exact`, :mod:`~lcpfric.analytic`, :mod:`~lcpfric.shakedown`,
:mod:`~lcpfric.sweep`, :mod:`~lcpfric.figures`, :mod:`~lcpfric.paper`, :mod:`~lcpfric.bench`,
:mod:`~lcpfric.stability`, :mod:`~lcpfric.cli`).

Quick use::

    >>> import lcpfric
    >>> node = lcpfric.SingleNode.normalized(P1=0.5, Q1=2.0, phi=0.0)
    >>> round(lcpfric.steady_state(node, method="exact").W_hat, 12)
    1.866666666667
"""

from . import _legacy
from .analysis import analytic
from .errors import (ConvergenceError, ConvergenceWarning, InputError, LcpfricError, SolverError,
                     SolverNotFound)
from .exact import exact_W_hat
from .model import Fourier, Harmonic, Periodic
from .methods import available_methods, get_stepper
from .model import ContactSystem, IndependentSprings, SingleNode, W_from_W_hat, W_hat_from_W
from .periodic import steady_state
from .results import CycleResult, State, SteadyState
from .scene import Scene, make_scene
from .analysis.shakedown import Shakedown, shakedown
from .model import block_diagonal, chain

__version__ = "0.1.0"

_legacy.install()

__all__ = [
    "analytic", "ConvergenceError", "ConvergenceWarning", "InputError", "LcpfricError",
    "SolverError", "SolverNotFound", "exact_W_hat", "Fourier", "Harmonic", "Periodic",
    "available_methods", "get_stepper", "ContactSystem", "IndependentSprings", "SingleNode",
    "W_from_W_hat", "W_hat_from_W", "steady_state", "CycleResult", "State", "SteadyState",
    "Scene", "make_scene", "Shakedown", "shakedown", "chain", "block_diagonal", "__version__",
]
