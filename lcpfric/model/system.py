"""The general discrete system: ``F = Q(t) + K u``, ``|F_i| <= f_i N_i(t)`` (paper, Eqs. 2-3).

Conventions (paper, Eq. 2): the friction force is ``F = Q + K u`` and the normal reaction comes
from the normal model (:mod:`lcpfric.model.normal`); in separation ``N = 0``. Coulomb's law,
Eq. (3), asks ``||F_i|| <= f_i N_i``, with slip opposing the force. The dissipation per cycle is
``W = -∮ F · du`` (Eq. 5), in the units of force x displacement of K, Q and N.

Tangential stiffness or compliance
----------------------------------
The steppers work with K (``explicit``, ``projection``) or with C = K⁻¹ (the convex backends,
whose unknowns are the friction forces). A model that knows C directly passes it as
``compliance=`` and it is used as given, after a check that it is K⁻¹ (the checks of K and C:
:mod:`.system_checks`); otherwise C is computed from K once, on first use.

Matrix-free systems
-------------------
A model whose compliance is known only by its products (a half-space, where ``C x`` is an FFT
pair) passes ``stiffness=None`` and ``compliance=`` a
:class:`scipy.sparse.linalg.LinearOperator` (or anything
:func:`~scipy.sparse.linalg.aslinearoperator` accepts). Nothing m x m is then stored:
``method="active-set"`` solves it with products only (d = 1). For the other methods, and where
a dense matrix is asked for (:meth:`compliance_matrix`, :meth:`dense_stiffness`), C is formed
from m products, up to :data:`COMPLIANCE_DENSE` unknowns; beyond that they raise
:class:`~lcpfric.errors.InputError` naming ``active-set``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError
from .loads import Load, LoadSet
from .normal import NormalModel, check_normal_model
from .system_checks import check_compliance_operator, check_inverse, check_stiffness

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["ContactSystem", "COMPLIANCE_DENSE"]

#: largest system whose compliance is formed as a matrix for a scale (beyond it 1/K_ii is used)
#: and largest matrix-free system whose compliance is formed when a method needs a matrix
COMPLIANCE_DENSE = 2000


@dataclass(frozen=True)
class ContactSystem:
    """A discrete frictional system: ``F = Q(t) + K u``, ``|F_i| <= f_i N_i(t)``, the normal
    reactions prescribed, or ``N = P(t) + B u`` with a coupling block.

    Parameters
    ----------
    stiffness : (m, m) array_like or scipy.sparse matrix, or None
        Symmetric positive definite tangential stiffness K, m = n·d. None for a matrix-free
        system, known by its compliance operator (see the module docstring).
    friction : (n,) array_like
        Friction coefficients f_i > 0.
    tangential_loads : sequence of m Load
        Q(t), ordered node by node (node i owns entries ``i*d .. i*d + d - 1``).
    normal : NormalModel
        The normal model giving N_i(t) (:mod:`lcpfric.model.normal`; the paper's is
        :class:`IndependentSprings`).
    dims : int
        Tangential directions per node, 1 or 2.
    compliance : (m, m) array_like or LinearOperator, optional
        C = K⁻¹, when the model provides it (a half-space model knows its influence
        coefficients, for example). With a stiffness it is checked against it: ``max |K C - I|``
        must be below 1e-8 (on the full matrices up to m = 2000, on 8 random vectors beyond).
        Without it, C is computed from K on first use (:meth:`compliance_matrix`). With
        ``stiffness=None`` it is the system's only operator: its products must be finite,
        symmetric and positive (checked on two random vectors).
    coupling : (n, n) array_like, optional
        The normal-tangential coupling block B of a coupled system, ``N = P(t) + B u`` in
        contact (d = 1; :mod:`lcpfric.model.coupling`): checked well posed (Klarbring's
        condition) on construction; a zero block is the uncoupled system (``coupling``
        None). ``lcpfric.shakedown`` decides a coupled system's safe state; ``exact``,
        ``explicit`` and the convex backends solve its steady state from a start
        (:data:`lcpfric.model.coupling.COUPLED_METHODS`; the others say so).
    _cache : dict, optional
        Internal: what the system computes once (its period, factorizations, C); set by the
        system itself, not to be given.

    Attributes
    ----------
    stiffness : ndarray, scipy.sparse.csc_matrix or None
        K as checked (CSC for a sparse K; None for a matrix-free system).
    friction : (n,) ndarray
        The friction coefficients.
    tangential_loads : tuple of Load
        Q(t), m loads.
    normal : NormalModel
        The normal model.
    dims : int
        Tangential directions per node.
    compliance : ndarray, LinearOperator or None
        C as given (a dense array once checked against K; the operator of a matrix-free
        system).
    coupling : ndarray or None
        The coupling block B as checked, or None (an uncoupled system).
    n, m : int
        Nodes and tangential unknowns (m = n·d).
    period : float
        The loads' common period (1.0 when nothing varies).
    matrix_free : bool
        Whether the system is known by its compliance operator only.

    Raises
    ------
    InputError
        ``dims`` not 1 or 2; a friction coefficient <= 0 or not finite; a normal model that
        lacks a member of :class:`~lcpfric.model.normal.NormalModel` or has another number of
        nodes; K not finite, not m x m, not symmetric or not positive definite; not m loads,
        or loads of different periods; a compliance that is not K⁻¹, or (matrix-free) not a
        finite, symmetric, positive m x m operator; neither stiffness nor compliance; a
        coupling block that is not n x n and finite, with d = 2 or without K, or not well
        posed (:func:`lcpfric.model.coupling.check_coupling`).
    """

    #: the driver's defaults (:func:`lcpfric.steady_state`)
    default_method = "exact"
    default_steps = 2000
    default_max_cycles = 100
    default_placement = "contact"

    stiffness: object
    friction: np.ndarray
    tangential_loads: tuple
    normal: NormalModel
    dims: int = 1
    compliance: object = None
    coupling: object = None
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self):
        if self.dims not in (1, 2):
            raise InputError("dims", f"must be 1 or 2 tangential directions, got {self.dims!r}")
        f = _checks.finite_array("friction", self.friction, nonneg=True).ravel()
        if np.any(f <= 0):
            raise InputError("friction", "every friction coefficient must be > 0")
        object.__setattr__(self, "friction", f)
        n = f.size
        check_normal_model(self.normal)
        if self.normal.n != n:
            raise InputError(
                "normal", f"needs {n} normal loads (one per node), got {self.normal.n}"
            )
        m = n * self.dims
        K = self.stiffness
        if K is None:
            object.__setattr__(self, "compliance", check_compliance_operator(self.compliance, m))
        else:
            K = check_stiffness(K, m)
        object.__setattr__(self, "stiffness", K)
        loads = tuple(self.tangential_loads)
        if len(loads) != m or not all(isinstance(q, Load) for q in loads):
            raise InputError("tangential_loads", f"needs {m} Load objects (n·d), got {len(loads)}")
        object.__setattr__(self, "tangential_loads", loads)
        periods = [p.period for p in loads if not p.is_constant]
        if self.normal.period is not None:
            periods.append(float(self.normal.period))
        period = periods[0] if periods else 1.0
        if any(not math.isclose(p, period, rel_tol=1e-12) for p in periods):
            raise InputError(
                "loads", f"all loads must share one period; got {sorted(set(periods))}"
            )
        object.__setattr__(self, "_cache", {"period": period})
        if self.compliance is not None and K is not None:
            object.__setattr__(self, "compliance", check_inverse(K, self.compliance, m))
        if self.coupling is not None:
            from .coupling import check_coupling
            from .normal import IndependentSprings

            if self.dims != 1 or K is None or not isinstance(self.normal, IndependentSprings):
                raise InputError(
                    "coupling",
                    "a coupling block needs d = 1, a stiffness matrix K and prescribed normal "
                    "loads (IndependentSprings: N = P(t) + B u)",
                )
            B = check_coupling(self.coupling, self.dense_stiffness(), f)
            # B = 0 is the uncoupled system itself (today's path, bit for bit)
            object.__setattr__(self, "coupling", B if np.any(B) else None)

    @property
    def matrix_free(self) -> bool:
        """The system is known by its compliance operator only (``stiffness=None``)."""
        return self.stiffness is None

    def _formed(self) -> np.ndarray:
        """C of a matrix-free system as a matrix (m products), up to COMPLIANCE_DENSE."""
        if "C" not in self._cache:
            if self.m > COMPLIANCE_DENSE:
                raise InputError(
                    "method",
                    f"this matrix-free system has {self.m} unknowns: its "
                    f"compliance is formed only up to "
                    f"{COMPLIANCE_DENSE}; use method='active-set', "
                    f"which needs its products only",
                )
            C = np.asarray(self.compliance.matmat(np.eye(self.m)), dtype=float)
            self._cache["C"] = 0.5 * (C + C.T)
        return self._cache["C"]

    @property
    def n(self) -> int:
        """Number of contact nodes."""
        return self.friction.size

    @property
    def m(self) -> int:
        """Number of tangential unknowns, n·d."""
        return self.friction.size * self.dims

    @property
    def period(self) -> float:
        """The loads' common period (1.0 when nothing varies)."""
        return self._cache["period"]

    def compliance_matrix(self) -> np.ndarray:
        """C = K⁻¹ (dense), computed once.

        Returns
        -------
        ndarray
            C, (m, m): the compliance given, K⁻¹, or (matrix-free) C formed from m products and
            symmetrized.

        Raises
        ------
        InputError
            A matrix-free system of more than :data:`COMPLIANCE_DENSE` unknowns (named
            ``method``: use ``method="active-set"``).
        """
        if self.matrix_free:
            return self._formed()
        if self.compliance is not None:
            return np.asarray(
                self.compliance.toarray()
                if hasattr(self.compliance, "toarray")
                else self.compliance,
                dtype=float,
            )
        if "C" not in self._cache:
            K = self.stiffness.toarray() if hasattr(self.stiffness, "toarray") else self.stiffness
            self._cache["C"] = np.linalg.inv(K)
        return self._cache["C"]

    def dense_stiffness(self) -> np.ndarray:
        """K as a dense array (matrix-free: the inverse of C formed, computed once).

        Returns
        -------
        ndarray
            K, (m, m).

        Raises
        ------
        InputError
            A matrix-free system of more than :data:`COMPLIANCE_DENSE` unknowns (named
            ``method``: use ``method="active-set"``).
        """
        if self.matrix_free:
            if "K" not in self._cache:
                self._cache["K"] = np.linalg.inv(self._formed())
            return self._cache["K"]
        K = self.stiffness
        return K.toarray() if hasattr(K, "toarray") else np.asarray(K)

    def tangential(self, t: ArrayLike) -> np.ndarray:
        """Q(t) with shape ``t.shape + (m,)``.

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            The tangential loads, shape ``t.shape + (m,)``.
        """
        if "loads" not in self._cache:
            self._cache["loads"] = LoadSet(self.tangential_loads)
        return self._cache["loads"](t)

    def is_diagonal(self) -> bool:
        """K has no off-diagonal entry (uncoupled unknowns).

        Returns
        -------
        bool
            True when every off-diagonal entry of K is zero (False for a matrix-free system,
            treated as coupled).
        """
        if "diagonal" not in self._cache:
            K = self.stiffness
            if K is None:  # matrix-free: treated as coupled
                off = 1
            elif hasattr(K, "tocoo"):
                coo = K.tocoo()
                off = np.count_nonzero(coo.data[coo.row != coo.col])
            else:
                off = np.count_nonzero(K - np.diag(np.diag(K)))
            self._cache["diagonal"] = bool(off == 0)
        return self._cache["diagonal"]

    def solve(self, r: np.ndarray) -> np.ndarray:
        """``K⁻¹ r`` by a factorization of K kept for the next call.

        Dense Cholesky, or SuperLU for a sparse K: no compliance matrix is formed. Matrix-free:
        one product with C.

        Parameters
        ----------
        r : ndarray
            Right-hand side(s), (m,) or (m, k).

        Returns
        -------
        ndarray
            ``K⁻¹ r``, the shape of ``r`` (matrix-free: (m,) only).
        """
        if self.matrix_free:
            return np.asarray(self.compliance.matvec(np.asarray(r, dtype=float)), dtype=float)
        fac = self._cache.get("factor")
        if fac is None:
            K = self.stiffness
            if hasattr(K, "tocsc"):
                from scipy.sparse.linalg import splu

                lu = splu(K.tocsc())
                fac = self._cache["factor"] = lu.solve
            else:
                from scipy.linalg import cho_factor, cho_solve

                c = cho_factor(K)
                fac = self._cache["factor"] = lambda x, c=c: cho_solve(c, x)
        return fac(np.asarray(r, dtype=float))

    def stiffness_times(self, u: np.ndarray) -> np.ndarray:
        """``K u``; for a matrix-free system the solution x of ``C x = u``.

        Matrix-free, by conjugate gradients (:func:`scipy.sparse.linalg.cg`, to 1e-13
        relative), used only to start from a given u or to move a start (the steppers carry
        the forces).

        Parameters
        ----------
        u : ndarray
            Tangential displacements, (m,).

        Returns
        -------
        ndarray
            ``K u``, (m,).

        Raises
        ------
        SolverError
            Matrix-free: the conjugate gradients did not converge (status ``"maxiter"``).
        """
        u = np.asarray(u, dtype=float)
        if not self.matrix_free:
            return self.stiffness @ u
        if not np.any(u):
            return np.zeros_like(u)
        from scipy.sparse.linalg import cg

        x, info = cg(self.compliance, u, rtol=1e-13, atol=0.0, maxiter=20 * self.m + 100)
        if info != 0:
            from ..errors import SolverError

            raise SolverError(
                f"K u of a matrix-free system: conjugate gradients stopped after {info} iterations",
                backend="cg",
                status="maxiter",
            )
        return x

    def compliance_diagonal(self) -> np.ndarray:
        """The diagonal of C = K⁻¹, computed once.

        Formed for a dense or small system; for a diagonal or large stiffness 1/K_ii (a bound
        from below, exact when K is diagonal); for a matrix-free system the operator's own
        ``diagonal()`` if it has one, else formed up to :data:`COMPLIANCE_DENSE` unknowns, else
        its mean from 16 random sign probes (a scale for tests and for the pattern iteration,
        never for an answer).

        Returns
        -------
        ndarray
            (m,), every entry finite and > 0.

        Raises
        ------
        InputError
            The diagonal found is not finite and positive (named ``compliance``).
        """
        if "cdiag" in self._cache:
            return self._cache["cdiag"]
        m = self.m
        if self.matrix_free:
            own = getattr(self.compliance, "diagonal", None)
            if callable(own):
                d = np.asarray(own(), dtype=float).ravel()
            elif m <= COMPLIANCE_DENSE:
                d = np.diag(self._formed()).copy()
            else:
                z = np.random.default_rng(7).choice([-1.0, 1.0], size=(m, 16))
                d = np.full(m, float(np.mean(z * self.compliance.matmat(z))))
        elif self.is_diagonal() or m > COMPLIANCE_DENSE:
            d = 1.0 / np.asarray(self.stiffness.diagonal(), dtype=float)
        else:
            d = np.diag(self.compliance_matrix()).copy()
        if d.shape != (m,) or not np.all(np.isfinite(d) & (d > 0)):
            raise InputError("compliance", "its diagonal must be finite and positive")
        self._cache["cdiag"] = d
        return d
