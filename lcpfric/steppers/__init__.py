"""Time steppers: each advances a :class:`~lcpfric.scene.Scene` one increment at a time.

``base``            the contract every stepper follows (the convex backends too)
``dissipation``     the dissipation of an increment: the one formula every stepper uses
``rates``, ``lcp``  the slip-rate LCP, limit crossings and events inside an increment
``explicit``        the paper's state-based stepper, events located inside increments
``projection``      the closed-form maximum-dissipation projection (diagonal K)
``active_set``      problem (P) on K by a primal-dual active-set method (many nodes, stiff K)
``continuum``       what the continuum contacts' steppers share
``mdr_bar``         the MDR sphere's bar equation, exact per increment
``halfplane_pdas``  the half-plane cylinder's primal-dual active set
``newton_cg``       the half-space's semismooth Newton on FFT products: the stepper; its
                    increments (``newton_increment``) and their steps (``newton_step``)
``slip_memory``     what a cycle remembers of its starting slips (d = 2)

The convex-solver backends live in :mod:`lcpfric.backends` and follow the same contract.
"""

from ..results import StepState
from .base import Stepper
from .explicit import ExplicitStepper
from .projection import ProjectionStepper

__all__ = ["Stepper", "StepState", "ExplicitStepper", "ProjectionStepper"]
