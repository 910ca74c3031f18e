"""Time steppers: each advances a :class:`~lcpfric.scene.Scene` one increment at a time.

``base``         the contract every stepper follows (and the convex backends too)
``dissipation``  the dissipation of an increment: the one formula every stepper uses
``explicit``     the paper's state-based stepper, events located inside increments
``lcp``          the P-matrix LCP of slip rates (principal pivoting)
``projection``   the closed-form maximum-dissipation projection (diagonal K)

The convex-solver backends live in :mod:`lcpfric.backends` and follow the same contract.
"""

from ..results import StepState
from .base import Stepper
from .explicit import ExplicitStepper
from .projection import ProjectionStepper

__all__ = ["Stepper", "StepState", "ExplicitStepper", "ProjectionStepper"]
