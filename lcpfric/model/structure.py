"""A linear structure with Jenkins contacts, and its condensation onto the contacts' sliders.

The model
---------
A structure of n degrees of freedom, mass M and stiffness K (dense or scipy.sparse), carries
n_c Jenkins elements (a tangential spring ``kt_j`` in series with a Coulomb slider of slip
force ``mu_j N_j``, the normal load N_j constant). Element j joins the degrees of freedom
``(i, k)`` of ``contact_dofs[j]`` (``k = -1``: to the ground); its relative displacement is
``g_jᵀ x = x_i - x_k``. With ``w_j`` its slider's displacement and ``D = diag(kt)``::

    T_j = kt_j (g_jᵀ x - w_j),   |T_j| <= mu_j N_j,   w_j moves only where |T_j| = mu_j N_j,
                                                      in the direction of T_j
    K x + G T = f                (quasi-static equilibrium; G = [g_1 ... g_nc])

The *stuck* structure (every slider held) has the stiffness ``K + G D Gᵀ``; its modes
(:meth:`JointedStructure.stuck_modes`) are mass normalized, ``φᵀ M φ = 1``.

Condensation onto the sliders
-----------------------------
Under ``f = α M φ``, eliminating x from ``K x + G T = f`` and ``D⁻¹ T = Gᵀ x - w`` gives::

    T = α b + K_c v,   v = -w,   K_c = (D⁻¹ + Gᵀ K⁻¹ G)⁻¹,   b = K_c Gᵀ K⁻¹ M φ

which is lcpfric's discrete system ``F = Q + K u`` (:class:`~lcpfric.model.ContactSystem`) with
``F = T``, ``u = v``, ``Q(t) = α(t) b`` and the friction limits ``mu_j N_j``: its forward slip
(``du > 0``) has ``F = -f N``, the slider moving backward (``dw < 0``) under ``T = -mu N``, as
Jenkins' element does, and its dissipation ``-∮ F·du = ∮ T·dw`` is the sliders'. The compliance
form of K_c (the slider's 1/kt plus the structure's compliance at the contacts) has no
cancellation however stiff the contacts are. The modal amplitude is then::

    q = φᵀ M x = α c0 - bᵀ v,   c0 = φᵀ M K⁻¹ M φ - bᵀ (Gᵀ K⁻¹ M φ)

(``c0 = 1/ω0²`` for a mode of the stuck structure). K is factorized once (Cholesky, or SuperLU
for a sparse K) and ``n_c + 1`` right-hand sides are solved with it. Contacts with ``mu = 0``
carry no force and are left out of the condensation (they still stiffen the stuck modes).
The condensation needs K itself positive definite: a part of the structure held only by its
contacts would slide away without bound once they all slip.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from .sliders import SliderSystem, positive_definite

__all__ = ["JointedStructure", "MODE_TOL", "DENSE_MODES", "symmetric_matrix"]

#: a mode given as a vector must satisfy ``||K_s φ - λ M φ|| <= MODE_TOL ||K_s φ||``
MODE_TOL = 1e-6
#: up to this many degrees of freedom a sparse structure's modes come from a dense eigensolver
DENSE_MODES = 2000
#: relative tolerance of the symmetry and semi-definiteness checks (round-off of assembled matrices)
_REL = 1e-10
_BLOCK = 256  # right-hand sides solved at once in the condensation (bounds the memory)
#: a pivot of K's factorization below this share of its diagonal entry: K is singular to round-off
_PIVOT = 1e3 * float(np.finfo(float).eps)


def _is_sparse(A) -> bool:
    import scipy.sparse as sp

    return sp.issparse(A)


def symmetric_matrix(name: str, A, sparse: bool):
    """A finite, symmetric, square float matrix (CSC when ``sparse``) and its largest entry."""
    import scipy.sparse as sp

    if sp.issparse(A):
        A = sp.csc_matrix(A, dtype=float)
        values = A.data
    else:
        A = np.atleast_2d(_checks.finite_array(name, A))
        values = A
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise InputError(name, f"must be a square n x n matrix (n >= 1), got shape {A.shape}")
    if not np.all(np.isfinite(values)):
        raise InputError(name, "every entry must be finite")
    scale = float(np.max(np.abs(values), initial=0.0))
    asym = float(abs(A - A.T).max())
    if asym > _REL * scale:
        raise InputError(name, f"must be symmetric (largest |A - Aᵀ| is {asym:.3g})")
    A = 0.5 * (A + A.T)
    return (sp.csc_matrix(A) if sparse else A), scale


@dataclass(frozen=True)
class JointedStructure:
    """A linear structure (M, K) with Jenkins contacts between some of its degrees of freedom.

    Parameters
    ----------
    mass : (n, n) array_like or scipy.sparse matrix
        M, symmetric positive definite.
    stiffness : (n, n) array_like or scipy.sparse matrix
        K, symmetric positive semidefinite; the contacts' springs must make it definite
        (``K + G D Gᵀ``). The quasi-static cycle needs K definite on its own
        (:meth:`condense`).
    contact_dofs : (n_c, 2) or (n_c,) array_like of int
        The two degrees of freedom ``(i, k)`` each contact joins, 0-based; ``-1`` is the
        ground. A 1-D array joins each listed degree of freedom to the ground.
    contact_stiffness : float or (n_c,) array_like
        kt_j > 0, the tangential stiffness of each element.
    friction : float or (n_c,) array_like
        mu_j >= 0 (0: a contact that carries no force once the structure moves).
    normal_load : float or (n_c,) array_like
        N_j > 0, constant; the slip force is ``mu_j N_j``.

    Attributes
    ----------
    mass, stiffness
        As checked: both dense ndarrays, or both CSC matrices when either was sparse.
    contact_dofs : (n_c, 2) ndarray of int
        As checked.
    contact_stiffness, friction, normal_load : (n_c,) ndarray
        As checked.
    n, n_contacts : int
        Degrees of freedom and contacts.
    sparse : bool
        Whether the matrices are kept sparse.

    Raises
    ------
    InputError
        M or K not square, not of one size, not finite or not symmetric (to 1e-10 of the
        largest entry); M not positive definite; K not positive semidefinite (an eigenvalue
        below -1e-10 of the largest entry); ``K + G D Gᵀ`` not definite; a contact index out of
        ``[-1, n - 1]``, a contact joining a degree of freedom to itself or the ground to the
        ground; kt <= 0, mu < 0, N <= 0, or any not finite. Each error names the parameter.
    """

    mass: object
    stiffness: object
    contact_dofs: np.ndarray
    contact_stiffness: np.ndarray
    friction: np.ndarray
    normal_load: np.ndarray

    def __post_init__(self):
        sparse = _is_sparse(self.mass) or _is_sparse(self.stiffness)
        M, _ = symmetric_matrix("mass", self.mass, sparse)
        K, kscale = symmetric_matrix("stiffness", self.stiffness, sparse)
        n = M.shape[0]
        if K.shape != M.shape:
            raise InputError("stiffness", f"must be {n} x {n} like the mass, got {K.shape}")
        mscale = float(np.max(np.abs(M.data if sparse else M)))
        if mscale == 0 or not positive_definite(M):
            raise InputError("mass", "must be positive definite")
        dofs = self._dofs(n)
        nc = dofs.shape[0]
        per = {}
        for name, nonneg in (("contact_stiffness", False), ("friction", True),
                             ("normal_load", False)):  # fmt: skip
            arr = _checks.finite_array(name, getattr(self, name), nonneg=nonneg)
            try:
                arr = np.broadcast_to(arr, (nc,)).astype(float)
            except ValueError:
                raise InputError(name, f"needs a scalar or {nc} values (one per contact), "
                                 f"got shape {arr.shape}") from None  # fmt: skip
            if not nonneg and np.any(arr <= 0):
                raise InputError(name, f"every value must be > 0 (allowed range (0, inf)); "
                                 f"smallest given is {arr.min()}")  # fmt: skip
            per[name] = arr
        for name, value in (("mass", M), ("stiffness", K), ("contact_dofs", dofs), *per.items()):
            object.__setattr__(self, name, value)
        scale = max(kscale, float(np.max(per["contact_stiffness"])))
        if not positive_definite(K, _REL * scale):
            raise InputError(
                "stiffness",
                f"must be positive semidefinite (it has an eigenvalue below -{_REL:g} of its "
                f"largest entry)",
            )
        if not positive_definite(self.stuck_stiffness()):
            raise InputError(
                "stiffness",
                "K + the contacts' springs (the stuck structure) must be positive definite: "
                "every rigid-body motion of K must stretch a contact",
            )

    def _dofs(self, n: int) -> np.ndarray:
        raw = np.asarray(self.contact_dofs)
        if raw.dtype.kind == "f" and np.all(np.isfinite(raw)) and np.all(raw == np.round(raw)):
            raw = raw.astype(np.int64)
        if raw.dtype.kind not in "iu" or raw.size == 0:
            raise InputError("contact_dofs", f"needs one or more integer indices, got {raw!r}")
        if raw.ndim == 1:
            raw = np.stack([raw, np.full(raw.shape, -1)], axis=1)
        if raw.ndim != 2 or raw.shape[1] != 2:
            raise InputError("contact_dofs", f"must have the shape (n_c, 2), got {raw.shape}")
        dofs = raw.astype(np.int64)
        if np.any(dofs < -1) or np.any(dofs >= n):
            raise InputError("contact_dofs", f"every index must be in [-1, {n - 1}] (-1: ground)")
        if np.any(dofs[:, 0] == dofs[:, 1]):
            j = int(np.flatnonzero(dofs[:, 0] == dofs[:, 1])[0])
            raise InputError("contact_dofs", f"contact {j} joins {dofs[j, 0]} to itself")
        return dofs

    @property
    def n(self) -> int:
        """Degrees of freedom of the structure."""
        return self.mass.shape[0]

    @property
    def n_contacts(self) -> int:
        """Number of contacts."""
        return self.contact_dofs.shape[0]

    @property
    def sparse(self) -> bool:
        """Whether M and K are kept as scipy.sparse matrices."""
        return _is_sparse(self.mass)

    def contact_matrix(self):
        """G = [g_1 ... g_nc]: ``g_jᵀ x = x_i - x_k`` for the contact ``(i, k)``.

        Returns
        -------
        scipy.sparse.csc_matrix
            (n, n_c).
        """
        import scipy.sparse as sp

        rows, cols, vals = [], [], []
        for j, (i, k) in enumerate(self.contact_dofs):
            for dof, sign in ((i, 1.0), (k, -1.0)):
                if dof >= 0:
                    rows.append(dof)
                    cols.append(j)
                    vals.append(sign)
        return sp.csc_matrix((vals, (rows, cols)), shape=(self.n, self.n_contacts))

    def stuck_stiffness(self):
        """``K + G D Gᵀ``: the stiffness of the structure with every slider stuck.

        Returns
        -------
        ndarray or scipy.sparse.csc_matrix
            (n, n), sparse when the structure is.
        """
        G = self.contact_matrix()
        GDG = (G @ G.T.multiply(self.contact_stiffness[:, None])).tocsc()
        if self.sparse:
            return (self.stiffness + GDG).tocsc()
        return self.stiffness + GDG.toarray()

    def stuck_modes(self, count: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """The lowest modes of the stuck structure, ``(K + G D Gᵀ) φ = λ M φ``.

        Parameters
        ----------
        count : int, optional
            How many, from 1 to n.

        Returns
        -------
        eigenvalues : (count,) ndarray
            λ = ω0², ascending.
        modes : (n, count) ndarray
            φ, mass normalized (``φᵀ M φ = 1``), each with its largest entry positive.

        Raises
        ------
        InputError
            ``count`` out of range.
        """
        count = _checks.positive_int("count", count)
        if count > self.n:
            raise InputError("count", f"must be <= {self.n} (the degrees of freedom)")
        Ks = self.stuck_stiffness()
        if not self.sparse or self.n <= DENSE_MODES or count >= self.n - 1:
            from scipy.linalg import eigh

            dense = (lambda A: A.toarray()) if self.sparse else (lambda A: A)
            lam, V = eigh(dense(Ks), dense(self.mass), subset_by_index=[0, count - 1])
        else:
            from scipy.sparse.linalg import eigsh

            lam, V = eigsh(Ks, k=count, M=self.mass, sigma=0.0, which="LM")
            order = np.argsort(lam)
            lam, V = lam[order], V[:, order]
        V = V / np.sqrt(np.einsum("ij,ij->j", V, self.mass @ V))
        big = np.argmax(np.abs(V), axis=0)
        V = V * np.sign(V[big, np.arange(count)])
        return lam, V

    def mode(self, mode: int | np.ndarray = 0) -> tuple[float, np.ndarray]:
        """A mode of the stuck structure: by its index, or a given vector checked to be one.

        Parameters
        ----------
        mode : int or (n,) array_like
            The index among the stuck modes (0: the lowest), or a mode shape (any scale),
            which must satisfy ``||K_s φ - λ M φ|| <= MODE_TOL ||K_s φ||`` with λ its Rayleigh
            quotient.

        Returns
        -------
        eigenvalue : float
            λ = ω0².
        phi : (n,) ndarray
            The mode, mass normalized (a given vector keeps its sign).

        Raises
        ------
        InputError
            An index out of ``[0, n - 1]``, or a vector that is not finite, not of length n,
            zero, or not a mode of the stuck structure (named ``mode``).
        """
        if isinstance(mode, numbers.Integral) and not isinstance(mode, (bool, np.bool_)):
            if not 0 <= mode < self.n:
                raise InputError("mode", f"must be a mode index in [0, {self.n - 1}], got {mode}")
            lam, V = self.stuck_modes(int(mode) + 1)
            return float(lam[-1]), V[:, -1]
        phi = _checks.finite_array("mode", mode).ravel()
        if phi.shape != (self.n,):
            raise InputError("mode", f"needs an index or {self.n} values, got shape {phi.shape}")
        norm2 = float(phi @ (self.mass @ phi))
        if not norm2 > 0:
            raise InputError("mode", "must not be zero")
        phi = phi / np.sqrt(norm2)
        Kphi = self.stuck_stiffness() @ phi
        lam = float(phi @ Kphi)
        residual = float(np.linalg.norm(Kphi - lam * (self.mass @ phi)) / np.linalg.norm(Kphi))
        if not residual <= MODE_TOL:
            raise InputError(
                "mode",
                f"is not a mode of the stuck structure: ||K_s φ - λ M φ|| / ||K_s φ|| = "
                f"{residual:.3g} > {MODE_TOL:g} (λ = {lam:.6g}, its Rayleigh quotient)",
            )
        return lam, phi

    def condense(self, phi) -> SliderSystem:
        """The sliders' system for the modal load ``α M φ`` (module docstring).

        Parameters
        ----------
        phi : (n,) array_like
            The load shape (a mass-normalized mode of the stuck structure, :meth:`mode`).

        Returns
        -------
        SliderSystem
            K_c, b and c0 for the contacts with ``mu > 0``.

        Raises
        ------
        InputError
            K not positive definite (named ``stiffness``): a part of the structure held only by
            its contacts.
        """
        phi = np.asarray(phi, dtype=float)
        active = np.flatnonzero(self.friction > 0)
        G = self.contact_matrix()[:, active]
        solve = self._factor()
        Mphi = self.mass @ phi
        y = solve(Mphi)
        GKG = np.empty((active.size, active.size))
        for j0 in range(0, active.size, _BLOCK):
            cols = slice(j0, j0 + _BLOCK)
            GKG[:, cols] = G.T @ solve(G[:, cols].toarray())
        h = G.T @ y
        C = np.diag(1.0 / self.contact_stiffness[active]) + 0.5 * (GKG + GKG.T)
        from scipy.linalg import cho_factor, cho_solve

        c = cho_factor(C)
        Kc = cho_solve(c, np.eye(active.size))
        b = cho_solve(c, h)
        return SliderSystem(
            stiffness=0.5 * (Kc + Kc.T),
            load=b,
            modal_compliance=float(Mphi @ y - b @ h),
            friction=self.friction[active],
            normal_load=self.normal_load[active],
            contacts=active,
        )

    def _factor(self):
        """``r -> K⁻¹ r`` by one factorization of K, or InputError if K is not definite."""
        held = InputError(
            "stiffness",
            "must be positive definite for the quasi-static cycle: a part of the structure "
            "held only by its contacts slides away once they slip; tie it to the ground",
        )
        K = self.stiffness
        diag = np.asarray(K.diagonal(), dtype=float)
        if self.sparse:
            from scipy.sparse.linalg import splu

            try:
                lu = splu(K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                          options={"SymmetricMode": True})  # fmt: skip
            except RuntimeError:
                raise held from None
            pivots = lu.U.diagonal() / diag[np.argsort(lu.perm_c)]
            if not (np.array_equal(lu.perm_r, lu.perm_c) and np.all(pivots > _PIVOT)):
                raise held
            return lu.solve
        from scipy.linalg import LinAlgError, cho_factor, cho_solve

        try:
            c = cho_factor(K, lower=True)
        except LinAlgError:
            raise held from None
        if not np.all(np.diag(c[0]) ** 2 > _PIVOT * diag):
            raise held
        return lambda r: cho_solve(c, r)
