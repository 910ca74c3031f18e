r"""A vibrating structure with frictional contacts: :class:`DynamicSystem` (issue 40, item 1).

The model
---------
A linear structure of n degrees of freedom x, mass M, damping C and stiffness K (dense or
scipy.sparse; ``rayleigh`` forms ``C = αM + βK``), under a forcing harmonic at ω, carries
n_c frictional contacts. Contact j acts on the relative displacement ``g_jᵀ x`` (one degree of
freedom against the ground, or the difference of two; d = 2 contacts act on two directions)
through a tangential spring ``kt_j`` in series with a Coulomb slider at ``w_j`` (Jenkins'
element; ``kt_j = inf`` is a rigid contact: the slider is the degree of freedom itself, as the
paper's node)::

    M x'' + C x' + K x + G T = f(t),       f(t) = f0 + Re(f̂ e^{iωt})
    T_j = kt_j (g_jᵀ x - w_j),             ||T_j|| <= mu_j N_j(t)
    N_j(t) = max(0, N0_j + Re(N̂_j e^{iωt}))
    w_j moves only where ||T_j|| = mu_j N_j, in the direction of T_j

The normal loads are prescribed (the normal direction stays quasi-static, as in the paper);
where ``N_j = 0`` the contact is apart and carries no force. The dissipation per cycle is
``W = ∮ Σ_j T_j · dw_j``. The paper's dynamic node is the one-degree-of-freedom system with a
rigid contact (``f = -Q``, ``T = -F`` in the paper's convention ``F = Q + k v + c v' + m v''``):
:meth:`DynamicSystem.from_node`.

The methods: ``newmark`` (:mod:`lcpfric.steppers.newmark_system`: Newmark's average
acceleration, each increment problem (P) in the metric of the effective stiffness, solved by
any convex backend, the events located; the periodic state by shooting).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from .sliders import positive_definite
from .structure import symmetric_matrix

__all__ = ["DynamicSystem", "rayleigh"]


def rayleigh(mass, stiffness, alpha: float, beta: float):
    """Rayleigh's damping ``C = α M + β K`` (dense or sparse, as the matrices are).

    Parameters
    ----------
    mass, stiffness : (n, n) array_like or scipy.sparse matrix
        M and K.
    alpha, beta : float
        The coefficients, >= 0.

    Returns
    -------
    ndarray or scipy.sparse matrix
        C.

    Raises
    ------
    InputError
        ``alpha`` or ``beta`` negative or not finite.
    """
    import scipy.sparse as sp

    a = _checks.nonnegative("alpha", alpha)
    b = _checks.nonnegative("beta", beta)
    if sp.issparse(mass) or sp.issparse(stiffness):
        return sp.csc_matrix(a * sp.csc_matrix(mass) + b * sp.csc_matrix(stiffness))
    return a * np.asarray(mass, dtype=float) + b * np.asarray(stiffness, dtype=float)


def _per_contact(name, value, nc, *, positive=True, allow_inf=False):
    arr = np.asarray(value, dtype=float) if not isinstance(value, str) else value
    if allow_inf and isinstance(arr, np.ndarray):
        finite = np.where(np.isinf(arr) & (arr > 0), 1.0, arr)
        _checks.finite_array(name, finite)
    else:
        arr = _checks.finite_array(name, value)
    try:
        arr = np.broadcast_to(arr, (nc,)).astype(float)
    except ValueError:
        raise InputError(name, f"needs a number or {nc} values (one per contact), got shape "
                         f"{np.shape(arr)}") from None  # fmt: skip
    if positive and np.any(arr <= 0):
        raise InputError(name, f"every value must be > 0 (allowed range (0, inf)); smallest "
                         f"given is {arr.min()}")  # fmt: skip
    return arr


def _complex(name, value, shape):
    try:
        arr = np.asarray(value, dtype=complex)
    except (TypeError, ValueError):
        raise InputError(name, f"expected numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(name, "every value must be finite")
    try:
        return np.broadcast_to(arr, shape).astype(complex)
    except ValueError:
        raise InputError(name, f"needs shape {shape}, got {arr.shape}") from None


@dataclass(frozen=True, eq=False)
class DynamicSystem:
    """A linear structure (M, C, K) with Jenkins or rigid frictional contacts, forced at ω.

    Parameters
    ----------
    mass, stiffness : (n, n) array_like or scipy.sparse matrix
        M (symmetric positive definite) and K (symmetric positive semidefinite).
    damping : (n, n) array_like or scipy.sparse matrix, optional
        C, symmetric positive semidefinite (default none; :func:`rayleigh` forms αM + βK).
    contacts : sequence
        One entry per contact. d = 1: a degree of freedom (against the ground) or a pair
        ``(i, k)`` (on ``x_i - x_k``). d = 2: a pair ``(ix, iy)`` of the two directions
        (against the ground) or ``((ix, iy), (kx, ky))``. Indices are 0-based.
    friction : float or (n_c,) array_like
        mu_j > 0.
    normal_load : float or (n_c,) array_like
        N0_j, the mean normal loads.
    omega : float
        The circular frequency ω > 0 of the forcing and of the normal loads.
    force : (n,) array_like of complex, optional
        f̂: ``f(t) = f0 + Re(f̂ e^{iωt})`` (a real entry a is ``a cos ωt``). Default zero.
    force_mean : (n,) array_like, optional
        f0 (default zero).
    normal_amplitude : float or (n_c,) array_like of complex, optional
        N̂_j: ``N_j(t) = max(0, N0_j + Re(N̂_j e^{iωt}))`` (default 0: constant loads).
    contact_stiffness : float or (n_c,) array_like, optional
        kt_j > 0, or ``inf`` for a rigid contact (the default).
    dims : int, optional
        Tangential directions per contact, 1 (default) or 2.

    Attributes
    ----------
    n, n_contacts, dims : int
        Degrees of freedom, contacts and directions per contact.
    G : (n, n_c·d) ndarray
        The contacts' directions (column ``j·d + k``: direction k of contact j).
    rigid : (n_c,) bool ndarray
        The rigid contacts (``kt = inf``).
    period : float
        2π/ω.

    Raises
    ------
    InputError
        A matrix not square, of another size, not symmetric or not finite; M not positive
        definite, K or C not positive semidefinite; a contact index out of range or a contact
        on itself; mu, kt <= 0; ``N0 + |N̂| <= 0`` for a contact (never in contact); ω <= 0; a
        forcing of another length; any value not finite. Each error names the parameter.
    """

    mass: object
    stiffness: object
    contacts: object
    friction: object
    normal_load: object
    omega: float
    damping: object = None
    force: object = None
    force_mean: object = None
    normal_amplitude: object = 0.0
    contact_stiffness: object = math.inf
    dims: int = 1

    is_dynamic = True
    default_method = "newmark"
    default_steps = 400
    default_max_cycles = 100
    #: the methods that solve a DynamicSystem (the driver refuses the others by name)
    dynamic_methods = ("newmark",)

    def __post_init__(self):
        import scipy.sparse as sp

        dims = self.dims
        if dims not in (1, 2) or isinstance(dims, bool):
            raise InputError("dims", f"must be 1 or 2, got {dims!r}")
        sparse = any(sp.issparse(A) for A in (self.mass, self.stiffness, self.damping))
        M, _ = symmetric_matrix("mass", self.mass, sparse)
        n = M.shape[0]
        K, kscale = symmetric_matrix("stiffness", self.stiffness, sparse)
        C = (sp.csc_matrix((n, n)) if sparse else np.zeros((n, n))) if self.damping is None \
            else symmetric_matrix("damping", self.damping, sparse)[0]  # fmt: skip
        for name, A in (("stiffness", K), ("damping", C)):
            if A.shape != (n, n):
                raise InputError(name, f"must be {n} x {n} like the mass, got {A.shape}")
        if not positive_definite(M):
            raise InputError("mass", "must be positive definite")
        for name, A in (("stiffness", K), ("damping", C)):
            s = float(np.max(np.abs(A.data if sparse else A), initial=0.0))
            if s > 0 and not positive_definite(A, 1e-10 * s):
                raise InputError(name, "must be positive semidefinite")
        G = self._directions(n, dims)
        nc = G.shape[1] // dims
        omega = _checks.positive("omega", self.omega)
        mu = _per_contact("friction", self.friction, nc)
        N0 = _per_contact("normal_load", self.normal_load, nc, positive=False)
        Nh = _complex("normal_amplitude", self.normal_amplitude, (nc,))
        if np.any(N0 + np.abs(Nh) <= 0):
            j = int(np.flatnonzero(N0 + np.abs(Nh) <= 0)[0])
            raise InputError("normal_load", f"contact {j} is never pressed (N0 + |N̂| <= 0)")
        kt = _per_contact("contact_stiffness", self.contact_stiffness, nc, allow_inf=True)
        f = _complex("force", 0.0 if self.force is None else self.force, (n,))
        f0 = _checks.finite_array("force_mean", 0.0 if self.force_mean is None
                                  else self.force_mean)  # fmt: skip
        try:
            f0 = np.broadcast_to(f0, (n,)).astype(float)
        except ValueError:
            raise InputError("force_mean", f"needs {n} values, got shape {f0.shape}") from None
        checked = {"mass": M, "stiffness": K, "damping": C, "omega": omega, "friction": mu,
                   "normal_load": N0, "normal_amplitude": Nh, "contact_stiffness": kt,
                   "force": f, "force_mean": f0}  # fmt: skip
        for name, value in checked.items():
            object.__setattr__(self, name, value)
        object.__setattr__(self, "G", G)

    def _directions(self, n, dims):
        raw = list(self.contacts) if np.ndim(self.contacts) else [self.contacts]
        if not raw:
            raise InputError("contacts", "needs one or more contacts")
        cols = []
        for j, entry in enumerate(raw):
            e = np.asarray(entry)
            if e.dtype.kind == "f" and np.all(e == np.round(e)):
                e = e.astype(np.int64)
            if e.dtype.kind not in "iu":
                raise InputError(
                    "contacts", f"contact {j}: integer indices expected, got {entry!r}"
                )
            if dims == 1:
                e = e.reshape(-1)
                if e.size not in (1, 2):
                    raise InputError("contacts", f"contact {j}: a dof or a pair (i, k) for d = 1")
                pairs = [(int(e[0]), int(e[1]) if e.size == 2 else -1)]
            else:
                if e.shape not in ((2,), (2, 2)):
                    raise InputError("contacts", f"contact {j}: (ix, iy) or ((ix, iy), (kx, ky)) "
                                     "for d = 2")  # fmt: skip
                pairs = [(int(e[k]), -1) for k in range(2)] if e.ndim == 1 else \
                    [(int(e[0, k]), int(e[1, k])) for k in range(2)]  # fmt: skip
            for i, k in pairs:
                if not (0 <= i < n) or not (-1 <= k < n) or i == k:
                    raise InputError("contacts", f"contact {j}: indices must be in [0, {n - 1}] "
                                     f"(the second may be -1, the ground) and differ")  # fmt: skip
                g = np.zeros(n)
                g[i] = 1.0
                if k >= 0:
                    g[k] = -1.0
                cols.append(g)
        return np.column_stack(cols)

    @classmethod
    def from_node(cls, node) -> DynamicSystem:
        """The paper's dynamic node (:class:`~lcpfric.model.SingleNode` with a mass and
        harmonic loads) as a one-degree-of-freedom system with a rigid contact.

        Parameters
        ----------
        node : SingleNode
            A node with a mass under harmonic loads.

        Returns
        -------
        DynamicSystem
            ``m x'' + c x' + k11 x + T = -Q(t)``, ``|T| <= f N(t)`` (``T = -F``).

        Raises
        ------
        InputError
            ``node`` has no mass, coupling or loads that are not harmonic.
        """
        if not getattr(node, "is_dynamic", False) or not node.is_harmonic:
            raise InputError("node", "needs a SingleNode with a mass under harmonic loads")
        P, Q = node.normal_load, node.tangential_load
        Qh = Q.amplitude * np.exp(1j * (Q.phase - math.pi / 2))  # A sin(ωt + ψ) = Re(Â e^{iωt})
        Ph = P.amplitude * np.exp(1j * (P.phase - math.pi / 2))
        return cls(mass=node.mass, stiffness=node.k11, damping=node.damping, contacts=[0],
                   friction=node.f, normal_load=P.mean, normal_amplitude=Ph, omega=node.omega,
                   force=[-Qh], force_mean=[-Q.mean])  # fmt: skip

    # -- sizes and loads ----------------------------------------------------------------------
    @property
    def n(self) -> int:
        """Degrees of freedom."""
        return self.mass.shape[0]

    @property
    def n_contacts(self) -> int:
        """Contacts."""
        return self.friction.size

    @property
    def rigid(self) -> np.ndarray:
        """The rigid contacts (``kt = inf``)."""
        return np.isinf(self.contact_stiffness)

    @property
    def period(self) -> float:
        """2π/ω."""
        return 2.0 * math.pi / self.omega

    def forcing(self, t: float, rate: bool = False) -> np.ndarray:
        """The forcing f(t), or its derivative.

        Parameters
        ----------
        t : float
            The instant.
        rate : bool, optional
            Return f'(t) instead.

        Returns
        -------
        ndarray
            (n,).
        """
        e = np.exp(1j * self.omega * t)
        if rate:
            return (1j * self.omega * self.force * e).real
        return self.force_mean + (self.force * e).real

    def normal(self, t: float, rate: bool = False) -> np.ndarray:
        """The normal loads N(t), or their derivatives (0 where apart).

        Parameters
        ----------
        t : float
            The instant.
        rate : bool, optional
            Return N'(t) instead.

        Returns
        -------
        ndarray
            (n_c,).
        """
        e = np.exp(1j * self.omega * t)
        raw = self.normal_load + (self.normal_amplitude * e).real
        if rate:
            return np.where(raw > 0, (1j * self.omega * self.normal_amplitude * e).real, 0.0)
        return np.maximum(raw, 0.0)

    def separation_instants(self) -> np.ndarray:
        """The instants in [0, T) where a normal load reaches 0 (the time grids hold them).

        Returns
        -------
        ndarray
            Sorted instants (empty when no contact separates).
        """
        out = []
        for N0, Nh in zip(self.normal_load, self.normal_amplitude):
            A = abs(Nh)
            if A > abs(N0):  # N0 + A cos(ωt + ψ) = 0
                c = math.acos(-N0 / A)
                psi = math.atan2(Nh.imag, Nh.real)
                for s in (c, -c):
                    out.append(((s - psi) / self.omega) % self.period)
        return np.unique(np.array(out, dtype=float))

    def natural_frequency(self) -> float:
        """Ω1, the first natural frequency of the structure with every contact stuck (a rigid
        contact holds its degrees of freedom, a Jenkins contact adds its spring).

        Returns
        -------
        float
            Ω1 (``inf`` when the rigid contacts hold every degree of freedom).
        """
        import scipy.linalg as sla

        M = self.mass.toarray() if hasattr(self.mass, "toarray") else self.mass
        K = self.stiffness.toarray() if hasattr(self.stiffness, "toarray") else self.stiffness
        d = self.dims
        rig = np.repeat(self.rigid, d)
        kt = np.repeat(np.where(self.rigid, 0.0, self.contact_stiffness), d)
        Ks = K + (self.G * kt) @ self.G.T
        B = sla.null_space(self.G[:, rig].T) if rig.any() else np.eye(self.n)
        if B.shape[1] == 0:
            return math.inf
        lam = sla.eigh(B.T @ Ks @ B, B.T @ M @ B, eigvals_only=True)
        return float(math.sqrt(max(lam[0], 0.0)))
