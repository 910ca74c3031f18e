"""Continuum contacts of identical elastic bodies (uncoupled normal and tangential problems).

* :class:`MDRSphere` (:mod:`.mdr`): the Hertz contact of two spheres by the method of
  dimensionality reduction;
* :class:`HalfPlaneCylinder` (:mod:`.halfplane`): the plane contact of two cylinders (or any 1-D
  profile) by half-plane boundary elements;
* :class:`HalfSpace` (:mod:`.halfspace`): any surface (sphere, rounded punch, height map) on the
  3-D half-space by boundary elements on a grid, tractions along the load (d = 1) or in the
  plane (d = 2, Cerruti's coupling); products by FFT (:mod:`.influence`), the normal problem by
  constrained conjugate gradients (:mod:`.normal3d`);
* :mod:`.steady`: their periodic steady state (one driver) and result (:class:`ContactResult`);
* :mod:`.closed_forms`: the classical closed forms they are validated against.

The conventions are those of the project's contact notes (two identical bodies, each with E and
ν; R the effective radius; P and Q total forces, per unit length for the cylinder).
"""

from .closed_forms import (cattaneo_stick_ratio, ciavarella_jager_W, cylinder_contact,
                           cylinder_W, hertz_contact, mindlin_deresiewicz_W, moduli)
from .halfplane import HalfPlaneCylinder
from .halfspace import HalfSpace
from .mdr import MDRSphere
from .steady import ContactResult

__all__ = ["MDRSphere", "HalfPlaneCylinder", "HalfSpace", "ContactResult", "moduli",
           "hertz_contact", "cylinder_contact", "cattaneo_stick_ratio", "mindlin_deresiewicz_W",
           "cylinder_W", "ciavarella_jager_W"]
