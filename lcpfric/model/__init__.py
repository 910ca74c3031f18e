"""What the system is: loads, normal models, the general discrete system, the paper's single
node, and builders of common systems.

``loads``        periodic loads: :class:`Harmonic` (Eq. 1), :class:`Fourier`, :class:`Periodic`
                 (``load_base``: the base class :class:`Load` and :class:`Periodic`)
``normal``       the normal-model protocol and :class:`IndependentSprings` (Eq. 2)
``system``       :class:`ContactSystem`: ``F = Q + K u``, ``|F_i| <= f_i N_i`` (Eqs. 2-3)
                 (``system_checks``: the checks of its K and C)
``single_node``  :class:`SingleNode` (Fig. 2) and the normalization of Eq. (6)
                 (``normalization``: W ↔ Ŵ and the check of the units)
``builders``     :func:`chain`, :func:`block_diagonal`
``continuum``    continuum contacts: :class:`MDRSphere`, :class:`HalfPlaneCylinder`,
                 :class:`HalfSpace` (imported on first use)
"""

from .builders import block_diagonal, chain, chain_stiffness
from .loads import Fourier, Harmonic, Load, Periodic
from .normal import IndependentSprings, NormalModel
from .single_node import SingleNode, W_from_W_hat, W_hat_from_W
from .system import ContactSystem

__all__ = [
    "Load",
    "Harmonic",
    "Fourier",
    "Periodic",
    "NormalModel",
    "IndependentSprings",
    "ContactSystem",
    "SingleNode",
    "W_hat_from_W",
    "W_from_W_hat",
    "chain",
    "chain_stiffness",
    "block_diagonal",
    "MDRSphere",
    "HalfPlaneCylinder",
    "HalfSpace",
    "ContactModel",
]

_CONTINUUM = ("MDRSphere", "HalfPlaneCylinder", "HalfSpace", "ContactModel")


def __getattr__(name: str):
    # the continuum models import scipy's FFT and sparse modules: on first use only
    if name in _CONTINUUM:
        from . import continuum

        return getattr(continuum, name)
    raise AttributeError(f"module 'lcpfric.model' has no attribute {name!r}")
