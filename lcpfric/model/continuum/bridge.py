"""A continuum contact as a discrete :class:`~lcpfric.model.ContactSystem` (matrix-free), so that
the discrete methods (``active-set``, ``clarabel``, ...) can solve it and be compared with the
contact's own stepper.

With the nodes' own compliance ``C_s`` (the body held fixed), the rigid displacement
eliminated gives ``F = K v - C_s⁻¹ 1 Q / (1ᵀ C_s⁻¹ 1 + k_s)`` with ``K⁻¹ = C_s + 1 1ᵀ / k_s``
(Sherman-Morrison): products only, no matrix formed. With ``dims = 2`` (the half-space) 1
becomes ``B = [1_x 1_y]`` and the load's coefficients ``-C_s⁻¹ B (k_s I + Bᵀ C_s⁻¹ B)⁻¹ e_x``
(Woodbury); the model's ``springs()`` then gives ``C_s⁻¹ B`` as an ``(n·2, 2)`` array. It needs
``k_support > 0``: under pure load control K is singular (a common slip of every node is a rigid
shift of the body).

Under a prescribed rigid-body displacement ``x(t)`` (along x) the body is held by the motion, not
by a support: the limit ``k_s -> ∞`` with ``Q / k_s = x``, so ``K = C_s⁻¹`` and
``F = K v - C_s⁻¹ B e_x x(t)`` (:func:`displacement_system`); the force the contact transmits
to the body is ``T = -Σ F_x``. No support stiffness is needed.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse.linalg import LinearOperator

from ...errors import InputError
from ..loads import Harmonic, Periodic
from ..system import ContactSystem

__all__ = ["contact_system", "displacement_system", "SupportedCompliance"]


class SupportedCompliance(LinearOperator):
    """``C = C_s + B Bᵀ / k_s``: the nodes' compliance with the body on its support (module
    docstring); ``diagonal()`` is known without a product."""

    def __init__(self, springs, cdiag, k_support: float, dims: int):
        m = np.asarray(cdiag).size
        super().__init__(dtype=float, shape=(m, m))
        self.springs, self.cdiag, self.ks, self.d = springs, cdiag, float(k_support), dims

    def _matvec(self, x):
        x = np.asarray(x, dtype=float).reshape(-1)
        out = np.asarray(self.springs.matvec(x), dtype=float).reshape(-1)
        if self.d == 1:
            return out + x.sum() / self.ks
        return (out.reshape(-1, 2) + x.reshape(-1, 2).sum(axis=0) / self.ks).reshape(-1)

    def _rmatvec(self, x):
        return self._matvec(x)

    def diagonal(self):
        return self.cdiag + 1.0 / self.ks


def contact_system(model) -> ContactSystem:
    """The model as a matrix-free :class:`~lcpfric.model.ContactSystem` (module docstring); its
    normal reactions are the model's (:class:`~lcpfric.model.continuum.base.LevelNormal`)."""
    if getattr(model, "coupling", None) is not None:
        raise InputError(
            "method",
            f"the two materials couple the pressure with the shear (Dundurs' beta = "
            f"{model.beta:.4g}), which a ContactSystem (its normal reactions given in "
            f"advance) cannot carry: solve the model itself with newton-cg "
            f"(lcpfric.steady_state(model))",
        )
    ks = model.k_support
    if ks <= 0.0:
        raise InputError(
            "k_support",
            "is 0: under pure load control the contact's "
            "stiffness is singular (a rigid shift of the body), "
            "so it is no ContactSystem; solve the model itself "
            "(lcpfric.steady_state(model)), or give k_support > 0",
        )
    Cs, w, cdiag = model.springs()
    d = model.dims
    m = np.asarray(cdiag).size
    n = m // d
    # the loads: F = K v + c Q(t), c = -W (k_s I + Bᵀ W)⁻¹ e_x, W = C_s⁻¹ B (Woodbury)
    if d == 1:
        w = np.asarray(w, dtype=float).reshape(-1)
        coef = -w / (float(w.sum()) + ks)
    else:
        W = np.asarray(w, dtype=float).reshape(m, 2)
        BW = np.stack([W[0::2].sum(axis=0), W[1::2].sum(axis=0)])
        coef = -W @ np.linalg.solve(ks * np.eye(2) + BW, np.array([1.0, 0.0]))
    Q = model.Q
    loads = []
    for c in coef:
        if isinstance(Q, Harmonic):
            loads.append(
                Harmonic(
                    c * Q.mean, abs(c) * Q.amplitude, Q.phase + (math.pi if c < 0 else 0.0), Q.omega
                )
            )
        else:
            loads.append(Periodic(lambda t, c=c: c * Q(t), model.period, c * Q.mean))
    return ContactSystem(
        None,
        np.full(n, model.mu),
        tuple(loads),
        model.normal_model(),
        dims=d,
        compliance=SupportedCompliance(Cs, cdiag, ks, d),
    )


def displacement_system(model, amplitude: float, offset: float = 0.0) -> ContactSystem:
    """The contact under the prescribed rigid-body displacement ``x(t) = offset + amplitude
    cos ωt`` along x (ω = 2π / the model's period), as a matrix-free
    :class:`~lcpfric.model.ContactSystem` (module docstring): its unknowns the nodes' slips,
    its compliance the nodes' own ``C_s`` (the body held by the motion), its loads
    ``-C_s⁻¹ B e_x x(t)``, its normal reactions the model's. The contact's tangential force is
    ``T = -Σ F_x`` of the system's forces.

    Parameters
    ----------
    model : ContactModel
        An MDR sphere, a half-plane cylinder or a half-space (its tangential load and support
        are not used).
    amplitude, offset : float
        The motion's amplitude (>= 0) and mean.

    Returns
    -------
    ContactSystem
        The displacement-driven contact.

    Raises
    ------
    InputError
        A coupled model (dissimilar materials), an amplitude < 0 or not finite, or a model
        that cannot give its entry loads.
    """
    if getattr(model, "coupling", None) is not None:
        raise InputError(
            "model",
            f"the two materials couple the pressure with the shear (Dundurs' beta = "
            f"{model.beta:.4g}): not a ContactSystem",
        )
    a, x0 = float(amplitude), float(offset)
    if not (math.isfinite(a) and a >= 0.0):
        raise InputError("amplitude", f"must be finite and >= 0, got {amplitude!r}")
    if not math.isfinite(x0):
        raise InputError("offset", f"must be finite, got {offset!r}")
    Cs, w, cdiag = model.springs()
    d = model.dims
    m = np.asarray(cdiag).size
    coef = -(
        np.asarray(w, dtype=float).reshape(-1) if d == 1 else np.asarray(w).reshape(m, 2)[:, 0]
    )
    omega = 2.0 * math.pi / model.period
    # c x(t) = c x0 + |c| a sin(ωt + π/2 (+ π where c < 0))
    loads = tuple(
        Harmonic(c * x0, abs(c) * a, 0.5 * math.pi + (math.pi if c < 0 else 0.0), omega)
        for c in coef
    )
    return ContactSystem(
        None,
        np.full(m // d, model.mu),
        loads,
        model.normal_model(),
        dims=d,
        compliance=SupportedCompliance(Cs, cdiag, math.inf, d),
    )
