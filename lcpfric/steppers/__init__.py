"""Time steppers: each advances a :class:`~lcpfric.scene.Scene` one increment at a time.

``base`` states the contract; ``explicit`` is the paper's state-based algorithm; ``projection``
is the closed-form maximum-dissipation projection. The convex-solver backends live in
:mod:`lcpfric.backends` and follow the same contract.
"""

from .base import Stepper, StepState
from .explicit import ExplicitStepper
from .projection import ProjectionStepper

__all__ = ["Stepper", "StepState", "ExplicitStepper", "ProjectionStepper"]
