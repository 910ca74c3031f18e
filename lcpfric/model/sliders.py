"""The condensed system of a jointed structure's sliders (:class:`SliderSystem`, built by
:meth:`lcpfric.model.structure.JointedStructure.condense`; the derivation is in
:mod:`lcpfric.model.structure`), and the definiteness test its checks use
(:func:`positive_definite`)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .. import _checks
from .loads import Harmonic
from .normal import IndependentSprings
from .system import ContactSystem

__all__ = ["SliderSystem", "positive_definite"]


def positive_definite(A, shift: float = 0.0) -> bool:
    """Whether ``A + shift I`` (symmetric) is positive definite: by Cholesky (dense) or by the
    signs of the pivots of a symmetric-mode LU without pivoting (sparse: Sylvester's inertia).

    Parameters
    ----------
    A : (n, n) ndarray or scipy.sparse matrix
        A symmetric matrix.
    shift : float, optional
        Added to the diagonal.

    Returns
    -------
    bool
        True when every eigenvalue of ``A + shift I`` is > 0.
    """
    import scipy.sparse as sp

    if not sp.issparse(A):
        try:
            np.linalg.cholesky(A + shift * np.eye(A.shape[0]))
        except np.linalg.LinAlgError:
            return False
        return True
    from scipy.sparse.linalg import splu

    B = sp.csc_matrix(A + shift * sp.identity(A.shape[0], format="csc"))
    try:
        lu = splu(B, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options={"SymmetricMode": True})  # fmt: skip
    except RuntimeError:  # exactly singular
        return False
    return bool(np.array_equal(lu.perm_r, lu.perm_c) and np.all(lu.U.diagonal() > 0))


@dataclass(frozen=True)
class SliderSystem:
    """A jointed structure condensed onto its sliders for one mode (module docstring).

    Parameters
    ----------
    stiffness : (n_a, n_a) ndarray
        K_c, symmetric positive definite (n_a: the contacts with ``mu > 0``).
    load : (n_a,) ndarray
        b: the contact forces per unit modal force α while every slider sticks.
    modal_compliance : float
        c0: the modal amplitude per unit α while every slider sticks (1/ω0² for a mode).
    friction, normal_load : (n_a,) ndarray
        mu and N of the contacts kept.
    contacts : (n_a,) ndarray of int
        Their indices among the structure's contacts.

    Attributes
    ----------
    stiffness, load, modal_compliance, friction, normal_load, contacts
        As given.
    first_slip : float
        The modal force α at which the first slider reaches its limit from the unloaded
        state, ``min_j mu_j N_j / |b_j|`` (inf if none is loaded).
    """

    stiffness: np.ndarray
    load: np.ndarray
    modal_compliance: float
    friction: np.ndarray
    normal_load: np.ndarray
    contacts: np.ndarray

    @property
    def first_slip(self) -> float:
        """α at which the first slider slips, ``min_j mu_j N_j / |b_j|`` (inf: none loaded)."""
        loaded = np.abs(self.load) > 0
        if not loaded.any():
            return float("inf")
        limit = self.friction * self.normal_load
        return float(np.min(limit[loaded] / np.abs(self.load[loaded])))

    def contact_system(self, alpha_max: float) -> ContactSystem:
        """The sliders' :class:`~lcpfric.model.ContactSystem` under ``α = alpha_max sin θ``.

        Parameters
        ----------
        alpha_max : float
            The modal force amplitude, > 0.

        Returns
        -------
        ContactSystem
            ``F = α(θ) b + K_c u``, ``|F_j| <= mu_j N_j`` (ω = 1, so t = θ), u = -w.
        """
        alpha_max = _checks.positive("alpha_max", alpha_max)
        # a negative b_j is the phase π: sin(θ + π) = -sin θ
        loads = [Harmonic(0.0, alpha_max * abs(b), 0.0 if b >= 0 else np.pi) for b in self.load]
        return ContactSystem(self.stiffness, self.friction, loads, self.normal)

    @cached_property
    def normal(self) -> IndependentSprings:
        """The constant normal loads N_j as lcpfric's normal model (built once)."""
        return IndependentSprings(tuple(Harmonic(float(N), 0.0) for N in self.normal_load))

    def modal_amplitude(self, alpha, u) -> np.ndarray:
        """q = α c0 - bᵀ u: the modal amplitude at the modal forces α and slider states u.

        Parameters
        ----------
        alpha : (k,) array_like
            Modal forces α.
        u : (k, n_a) array_like
            The condensed system's displacements (u = -w) at the same instants.

        Returns
        -------
        ndarray
            q, (k,).
        """
        u = np.asarray(u, dtype=float).reshape(len(np.atleast_1d(alpha)), -1)
        return np.asarray(alpha, dtype=float) * self.modal_compliance - u @ self.load
