"""Continuum contacts of identical elastic bodies (uncoupled normal and tangential problems).

So far: the classical closed forms the continuum models are validated against
(:mod:`lcpfric.contact.closed_forms`). The conventions are those of the project's contact notes
(two identical bodies, each with E and ν; R the effective radius; P and Q total forces, per unit
length for the cylinder).
"""

from .closed_forms import (cattaneo_stick_ratio, ciavarella_jager_W, cylinder_contact,
                           cylinder_W, hertz_contact, mindlin_deresiewicz_W, moduli)

__all__ = ["moduli", "hertz_contact", "cylinder_contact", "cattaneo_stick_ratio",
           "mindlin_deresiewicz_W", "cylinder_W", "ciavarella_jager_W"]
