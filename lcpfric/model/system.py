"""The general discrete system: ``F = Q(t) + K u``, ``|F_i| <= f_i N_i(t)`` (paper, Eqs. 2-3).

Conventions (paper, Eq. 2): the friction force is ``F = Q + K u`` and the normal reaction comes
from the normal model (:mod:`lcpfric.model.normal`); in separation ``N = 0``. Coulomb's law,
Eq. (3), asks ``||F_i|| <= f_i N_i``, with slip opposing the force. The dissipation per cycle is
``W = -∮ F · du`` (Eq. 5), in the units of force x displacement of K, Q and N.

Tangential stiffness or compliance
----------------------------------
The steppers work with K (``explicit``, ``projection``) or with C = K⁻¹ (the convex backends,
whose unknowns are the friction forces). A model that knows C directly passes it as
``compliance=`` and it is used as given, after a check that it is K⁻¹; otherwise C is computed
from K once, on first use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from ..errors import InputError
from .loads import Load, LoadSet
from .normal import NormalModel, check_normal_model

__all__ = ["ContactSystem"]


@dataclass(frozen=True)
class ContactSystem:
    """A discrete uncoupled frictional system: ``F = Q(t) + K u``, ``|F_i| <= f_i N_i(t)``.

    Parameters
    ----------
    stiffness : (m, m) array_like or scipy.sparse matrix
        Symmetric positive definite tangential stiffness K, m = n·d.
    friction : (n,) array_like
        Friction coefficients f_i > 0.
    tangential_loads : sequence of m Load
        Q(t), ordered node by node (node i owns entries ``i*d .. i*d + d - 1``).
    normal : NormalModel
        The normal model giving N_i(t) (:mod:`lcpfric.model.normal`; the paper's is
        :class:`IndependentSprings`).
    dims : int
        Tangential directions per node, 1 or 2.
    compliance : (m, m) array_like, optional
        C = K⁻¹, when the model provides it (a half-space model knows its influence
        coefficients, for example). It is checked against the stiffness: ``max |K C - I|`` must
        be below 1e-8 (on the full matrices up to m = 2000, on 8 random vectors beyond).
        Without it, C is computed from K on first use (:meth:`compliance_matrix`).
    """

    stiffness: object
    friction: np.ndarray
    tangential_loads: tuple
    normal: NormalModel
    dims: int = 1
    compliance: object = None
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self):
        import scipy.sparse as sp

        if self.dims not in (1, 2):
            raise InputError("dims", f"must be 1 or 2 tangential directions, got {self.dims!r}")
        f = _checks.finite_array("friction", self.friction, nonneg=True).ravel()
        if np.any(f <= 0):
            raise InputError("friction", "every friction coefficient must be > 0")
        object.__setattr__(self, "friction", f)
        n = f.size
        check_normal_model(self.normal)
        if self.normal.n != n:
            raise InputError("normal", f"needs {n} normal loads (one per node), got {self.normal.n}")
        m = n * self.dims
        K = self.stiffness
        if sp.issparse(K):
            K = sp.csc_matrix(K, dtype=float)
            dense = K.toarray() if m <= 2000 else None
        else:
            K = _checks.finite_array("stiffness", K)
            K = np.atleast_2d(K)
            dense = K
        if K.shape != (m, m):
            raise InputError("stiffness", f"must be {m} x {m} (n·d), got {K.shape}")
        if dense is not None:
            if not np.all(np.isfinite(dense)):
                raise InputError("stiffness", "every entry must be finite")
            if not np.allclose(dense, dense.T, rtol=1e-12, atol=0.0):
                raise InputError("stiffness", "must be symmetric")
            try:
                np.linalg.cholesky(dense)
            except np.linalg.LinAlgError:
                raise InputError("stiffness", "must be positive definite") from None
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
            raise InputError("loads", f"all loads must share one period; got {sorted(set(periods))}")
        object.__setattr__(self, "_cache", {"period": period})
        if self.compliance is not None:
            self._check_compliance()

    def _check_compliance(self) -> None:
        """A supplied C must be K⁻¹: ``max |K C x - x| <= 1e-8 max |x|``."""
        C = self.compliance
        C = np.asarray(C.toarray() if hasattr(C, "toarray") else C, dtype=float)
        m = self.m
        if C.shape != (m, m) or not np.all(np.isfinite(C)):
            raise InputError("compliance", f"must be a finite {m} x {m} matrix, got shape "
                                           f"{C.shape}")
        X = np.eye(m) if m <= 2000 else np.random.default_rng(0).standard_normal((m, 8))
        err = float(np.max(np.abs(self.stiffness @ (C @ X) - X)))
        if not err <= 1e-8:
            raise InputError("compliance", f"must be the inverse of the stiffness: "
                                           f"max |K C x - x| = {err:.3g} > 1e-8 on unit vectors")
        object.__setattr__(self, "compliance", C)

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
        return self._cache["period"]

    def compliance_matrix(self) -> np.ndarray:
        """C = K⁻¹ (dense), computed once."""
        if self.compliance is not None:
            return np.asarray(self.compliance.toarray() if hasattr(self.compliance, "toarray")
                              else self.compliance, dtype=float)
        if "C" not in self._cache:
            K = self.stiffness.toarray() if hasattr(self.stiffness, "toarray") else self.stiffness
            self._cache["C"] = np.linalg.inv(K)
        return self._cache["C"]

    def dense_stiffness(self) -> np.ndarray:
        K = self.stiffness
        return K.toarray() if hasattr(K, "toarray") else np.asarray(K)

    def tangential(self, t) -> np.ndarray:
        """Q(t) with shape ``t.shape + (m,)``."""
        if "loads" not in self._cache:
            self._cache["loads"] = LoadSet(self.tangential_loads)
        return self._cache["loads"](t)

    def is_diagonal(self) -> bool:
        """K has no off-diagonal entry (uncoupled unknowns)."""
        if "diagonal" not in self._cache:
            K = self.stiffness
            if hasattr(K, "tocoo"):
                coo = K.tocoo()
                off = np.count_nonzero(coo.data[coo.row != coo.col])
            else:
                off = np.count_nonzero(K - np.diag(np.diag(K)))
            self._cache["diagonal"] = bool(off == 0)
        return self._cache["diagonal"]

    def solve(self, r: np.ndarray) -> np.ndarray:
        """``K⁻¹ r`` by a factorization of K kept for the next call (dense Cholesky, or SuperLU
        for a sparse K): no compliance matrix is formed."""
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
