"""Harmonic balance: the contact forces of an interface as Fourier coefficients.

``fourier``   the real Fourier conventions (``[c0, a1, b1, ..., aH, bH]``), the sampling
              matrix E and the discrete transform D: one copy
``jenkins``   the Jenkins element marched over sampled periodic input to its steady cycle,
              vectorized over elements, d = 1 (exact for piecewise-linear input) and d = 2
``jacobian``  the exact Jacobian of the force coefficients from the cycle's stick, slip and
              separation samples
``aft``       alternating frequency-time: :func:`jenkins_aft` (force coefficients, Jacobian, W,
              the cycle) and :func:`jenkins_residual` (a flat vector in, the force vector and a
              sparse Jacobian out, for a harmonic-balance residual)
``balance``   a small harmonic-balance solver with pseudo-arclength continuation over ω
              (:func:`forced_response`) for structures with Jenkins contacts, driving the AFT
``pyharm``    lcpfric's Jenkins element as a pyHarm element (its extension point; needs
              ``pip install pyharm-os``, imported only when used)
"""

from .aft import AFTResult, jenkins_aft, jenkins_residual
from .balance import ForcedResponse, forced_response, harmonic_residual
from .fourier import (
    FourierBasis,
    check_samples,
    fourier_basis,
    harmonics_of,
    trapezoid_coefficients,
)
from .jenkins import JenkinsCycle, jenkins_march

__all__ = [
    "AFTResult",
    "ForcedResponse",
    "forced_response",
    "harmonic_residual",
    "jenkins_aft",
    "jenkins_residual",
    "FourierBasis",
    "fourier_basis",
    "trapezoid_coefficients",
    "check_samples",
    "harmonics_of",
    "JenkinsCycle",
    "jenkins_march",
]
