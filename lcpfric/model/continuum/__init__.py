"""Continuum contacts of identical elastic bodies (uncoupled normal and tangential problems).

``base``          :class:`ContactModel`, what every continuum model is (material, loads,
                  support) and the protocol its scene and stepper use
``mdr``           :class:`MDRSphere`: the Hertz contact by the method of dimensionality
                  reduction (``profiles``: other axisymmetric bodies)
``halfplane``     :class:`HalfPlaneCylinder`: the plane contact by half-plane boundary elements
``halfspace``     :class:`HalfSpace`: any surface on the 3-D half-space by boundary elements on
                  a grid, tractions along the load (d = 1) or in the plane (d = 2); products by
                  FFT (``influence``; the tangential compliance's on the grid:
                  ``halfspace_compliance``), the normal problem by constrained conjugate
                  gradients (``normal3d``)
``dissimilar``    two bodies of different materials on the half-space: composite moduli,
                  Dundurs' β and the coupled influence coefficients (``HalfSpace(E2=, nu2=)``)
``bridge``        a contact as a matrix-free :class:`~lcpfric.model.ContactSystem`
``closed_forms``  the classical closed forms they are validated against

Their increments are steppers (``mdr-bar``, ``halfplane-pdas``, ``newton-cg``: see
:mod:`lcpfric.methods`); their steady state is :func:`lcpfric.steady_state`. The conventions are
those of the project's contact notes (two identical bodies, each with E and ν; R the effective
radius; P and Q total forces, per unit length for the cylinder).
"""

from .base import ContactModel
from .closed_forms import (
    cattaneo_stick_ratio,
    ciavarella_jager_W,
    cylinder_contact,
    cylinder_W,
    hertz_contact,
    mindlin_deresiewicz_W,
    moduli,
)
from .halfplane import HalfPlaneCylinder
from .halfspace import HalfSpace
from .mdr import MDRSphere
from .profiles import Axisymmetric, PowerLaw, Sphere

__all__ = [
    "ContactModel",
    "MDRSphere",
    "HalfPlaneCylinder",
    "HalfSpace",
    "Sphere",
    "PowerLaw",
    "Axisymmetric",
    "moduli",
    "hertz_contact",
    "cylinder_contact",
    "cattaneo_stick_ratio",
    "mindlin_deresiewicz_W",
    "cylinder_W",
    "ciavarella_jager_W",
]
