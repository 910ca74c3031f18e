r"""The plane (2-D, plane strain) contact of two identical cylinders by boundary elements on the
half-plane, d = 1.

Two identical elastic bodies (each E, ν; composite modulus E*) with an effective radius R (any
1-D profile ``h(x)`` through ``profile=``), loads per unit length: normal P(t) and tangential
Q(t). The surface ``[-L, L]`` around the largest contact is cut into elements of width Δ
carrying uniform tractions (pressure p_j, shear q_j); the nodes are their centres.

Influence coefficients
----------------------
For identical bodies in plane strain the relative surface displacements due to a pressure and
due to a shear have the same logarithmic kernel (Johnson, Contact Mechanics, §2.6), so one
matrix serves both problems: a uniform unit traction on element j displaces node i by

    A_ij = -(2/(π E*)) ℓ [L(w/ℓ)]_{w = x_i - x_j - Δ/2}^{x_i - x_j + Δ/2},   L(y) = y ln|y| - y.

The half-plane's displacement is defined up to a constant (the log kernel has no datum); ℓ fixes
it: displacements are those relative to points at distance ℓ (here twice the grid's length,
which also makes A positive definite). Under load control the constant only shifts the rigid
approach and the rigid tangential displacement; a support stiffness acts on the tangential
displacement measured from that datum.

The normal problem
------------------
At each instant, frictionless contact under P(t) (uncoupled from the shear): pressures p >= 0,
gaps ``g = h - d + A p >= 0``, ``p g = 0``, ``Δ Σ p = P`` with the rigid approach d an unknown;
solved by a primal-dual active-set iteration on the contact set (the set with positive pressure
gives ``A_SS p_S = d - h_S`` and d from the load; the set is then updated from ``p - g / A_ii``),
warm-started from the previous instant's set, each set's solve by the dense block of the
active-set backend (:class:`~lcpfric.linalg.blocks.DenseBlock`, updated when the set changes
by a few nodes). ``P <= 0`` is complete separation.

The tangential problem
----------------------
The nodes in contact carry friction forces ``F_i = -q_i Δ`` (lcpfric's sign: the slip opposes
F), with ``|F_i| <= μ N_i``, ``N_i = p_i Δ``; the relative slips s and the rigid tangential
displacement δ satisfy ``s = δ 1 + C F`` with ``C = A / Δ``; the bodies are held by Q(t) and by
the support: ``Σ F_i - k_support δ + Q = 0``. Each increment is problem (P), the
maximum-dissipation projection, solved by the same primal-dual active-set iteration as the
``active-set`` backend's compliance form with the load-control constraint: with the pattern
fixed, the sticking nodes S keep their slip, ``F_S = y - δ z`` with ``y = C_SS⁻¹ (s_S - C_SA
F_A)``, ``z = C_SS⁻¹ 1``, and δ from the equilibrium; the pattern is updated from ``F_i - Δs_i /
C_ii``. Separated nodes carry no force and no unknown (their slip follows the surface).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..linalg import PatternUpdate
from ..linalg import DenseBlock
from ..errors import InputError, SolverError
from .closed_forms import cylinder_contact
from .steady import ContactModel

__all__ = ["HalfPlaneCylinder", "MAX_NODES", "log_kernel", "entry_loads"]

#: largest number of elements (the influence matrix is dense: 8 N² bytes)
MAX_NODES = 6000
_MAX_ITER = 400
#: with a support, single changes by Murty's rule before the bounded least squares take over
_SINGLE_MAX = 64
_EPS = np.finfo(float).eps


def log_kernel(offsets: np.ndarray, width: float, Estar: float, datum: float) -> np.ndarray:
    """``A(k)``: the displacement at offset ``k Δ`` due to a uniform unit traction on an element
    of width Δ (module docstring)."""

    def L(y):
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(y == 0.0, 0.0, y * np.log(np.abs(y)) - y)

    w = np.asarray(offsets, dtype=float) * width
    return -(2.0 / (math.pi * Estar)) * datum * (L((w + width / 2) / datum)
                                                 - L((w - width / 2) / datum))


@dataclass
class _Surface:
    """The tangential state: relative slips of every node (``v``), rigid displacement δ, and
    the nodes on their upper and lower limits (the next increment's first pattern)."""

    v: np.ndarray
    delta: float
    up: np.ndarray
    dn: np.ndarray


class HalfPlaneCylinder(ContactModel):
    """Two identical cylinders in plane strain, by half-plane boundary elements (see the module
    docstring).

    Parameters
    ----------
    R, E, nu, mu : float
        Effective radius, each body's modulus and Poisson's ratio (``0 <= ν < 0.5``), friction.
    P, Q : Load or float
        Normal and tangential loads per unit length.
    k_support : float
        Tangential support stiffness (per unit length) in parallel with the contact (0: pure
        load control).
    nodes : int
        Elements across the largest contact width ``2 a_max``; the grid extends 3 % (at least
        two elements) beyond it on each side.
    profile : callable, optional
        The gap profile ``h(x)`` (default the cylinder's ``x² / (2R)``).

    Attributes
    ----------
    nodes : int
        Every element of the grid (the unknowns; ``nodes_across`` is the ``nodes`` given).
    x, dx : ndarray, float
        Element centres and width.
    A, C : ndarray
        The influence matrix (displacement per unit traction) and the compliance per unit
        force on an element, ``A / Δ``.
    """

    max_nodes = MAX_NODES

    def __init__(self, R, E, nu, mu, P, Q, *, k_support: float = 0.0, nodes: int = 400,
                 profile=None):
        super().__init__(E, nu, mu, P, Q, k_support, nodes)
        self.R = _checks.positive("R", R)
        self.a_max = cylinder_contact(self.P_max, self.R, self.E, self.nu)["a"]
        self.a0 = cylinder_contact(self.P0, self.R, self.E, self.nu)["a"]
        self.dx = 2.0 * self.a_max / self.nodes
        extra = max(2, math.ceil(0.03 * self.nodes))
        self.total = self.nodes + 2 * extra
        if self.total > MAX_NODES:
            raise InputError("nodes", f"{self.nodes} elements (+{2 * extra} beyond the contact) "
                                      f"exceed {MAX_NODES}: the influence matrix is dense")
        N = self.total
        self.x = (np.arange(N) - (N - 1) / 2.0) * self.dx
        h = (profile or (lambda x: x * x / (2.0 * self.R)))(self.x)
        self.h = _checks.finite_array("profile", h).reshape(N)
        datum = 2.0 * N * self.dx
        col = log_kernel(np.arange(N), self.dx, self.moduli["E*"], datum)
        from scipy.linalg import toeplitz

        self.A = toeplitz(col)                         # displacement per unit pressure
        self.C = self.A / self.dx                      # per unit force on an element
        self.cdiag = np.diag(self.C).copy()
        self._normal = DenseBlock(self.A)
        self._tangential = DenseBlock(self.C)
        self._cache: dict[float, np.ndarray] = {}
        self._set = np.flatnonzero(np.abs(self.x) < self.a0)
        self.nodes_across = self.nodes
        self._force_scale = self.mu * self.P_max * self.dx / (2 * self.a_max)
        self.nodes = N                                 # the unknowns of the grid

    # -- the normal problem ---------------------------------------------------------------------
    def pressure(self, P: float) -> np.ndarray:
        """The frictionless contact pressures under the load P (per unit length)."""
        P = float(P)
        if P <= 0.0:
            return np.zeros(self.total)
        got = self._cache.get(P)
        if got is not None:
            return got
        A, h, dx = self.A, self.h, self.dx
        diag = np.diag(A)
        S = self._set if self._set.size else np.array([int(np.argmin(h))])
        seen = set()
        for _ in range(_MAX_ITER):
            block = self._normal
            block.set(S)
            e = np.zeros(self.total)
            e[S] = 1.0
            idx, z = block.solve(e)
            hh = np.zeros(self.total)
            hh[S] = h[S]
            _, y = block.solve(hh)
            d = (P / dx + y.sum()) / z.sum()
            p = np.zeros(self.total)
            p[idx] = d * z - y
            g = h - d + A @ p
            g[S] = 0.0
            # an element at the entry load has p = g = 0: decided within round-off, not flipped
            tol = 1e-10 * P / (dx * self.nodes_across)
            new = np.flatnonzero(p - g / diag > tol)
            key = new.tobytes()
            if np.array_equal(new, S):
                break
            if key in seen:
                raise SolverError("half-plane normal problem: the contact set cycles",
                                  backend="halfplane", status="cycling")
            seen.add(key)
            S = new
        else:
            raise SolverError(f"half-plane normal problem: no contact set in {_MAX_ITER} "
                              f"iterations", backend="halfplane", status="max_iter")
        self._set = S
        p = np.maximum(p, 0.0)
        if len(self._cache) < 100_000:
            self._cache[P] = p
        return p

    # -- as an lcpfric system (ContactModel.system) -------------------------------------------
    def springs(self):
        """``(compliance operator, C⁻¹ 1, diag C)`` of the elements with the body held fixed."""
        from scipy.linalg import cho_factor, cho_solve
        from scipy.sparse.linalg import aslinearoperator

        w = cho_solve(cho_factor(self.C), np.ones(self.total))
        return aslinearoperator(self.C), w, self.cdiag.copy()

    def entry_loads(self) -> np.ndarray:
        """Per element, the normal load at which it comes into contact (inf: not below the
        largest load of the cycle): :func:`entry_loads`."""
        return entry_loads(self.A, self.h, self.dx, self.P_max)

    # -- the model protocol of lcpfric.contact.steady ------------------------------------------
    def limits(self, t) -> np.ndarray:
        P = np.atleast_1d(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float))
        return np.array([self.mu * self.dx * self.pressure(x) for x in P])

    def sizes(self, t) -> np.ndarray:
        """Half-width of the discrete contact: the outer edge of the outermost loaded element."""
        b = self.limits(t)
        out = np.zeros(b.shape[0])
        for j, row in enumerate(b):
            on = np.flatnonzero(row > 0)
            if on.size:
                out[j] = np.max(np.abs(self.x[on])) + self.dx / 2
        return out

    def start(self) -> _Surface:
        none = np.zeros(self.total, dtype=bool)
        return _Surface(np.zeros(self.total), 0.0, none, none)

    def scales(self) -> tuple[float, float]:
        q = self.Q.amplitude if not self.Q.is_constant else abs(self.Q.mean)
        return q * 4.0 / (math.pi * self.moduli["E*"]), self.mu * self.P_max

    def normalization(self) -> tuple[str, float]:
        return "W pi E*/(mu^2 P0^2)", math.pi * self.moduli["E*"] / (self.mu * self.P0) ** 2

    def increment(self, state: _Surface, b: np.ndarray, Q: float):
        """Problem (P) with the load-control constraint (module docstring): ``(state, F,
        Δs)``."""
        C, cd, ks = self.C, self.cdiag, self.k_support
        s0 = state.v
        # a limit within the solve's round-off of zero (an element at its entry load) carries
        # no force: the node is treated as separated
        contact = b > 1e-10 * self._force_scale
        up, dn = state.up & contact, state.dn & contact
        updates = PatternUpdate(contact)
        block = self._tangential
        # Murty's rule (the pattern rule's fallback) changes one node per iteration
        limit = _MAX_ITER + int(contact.sum())
        for _ in range(limit):
            F = np.where(up, b, np.where(dn, -b, 0.0))
            S = np.flatnonzero(contact & ~up & ~dn)
            if S.size:
                block.set(S)
                rhs = s0 - C @ F
                idx, y = block.solve(rhs)
                e = np.zeros(self.total)
                e[S] = 1.0
                _, z = block.solve(e)
                delta = (y.sum() + F.sum() + Q) / (z.sum() + ks)
                F[idx] = y - delta * z
            elif ks > 0.0:
                delta = (F.sum() + Q) / ks
            else:
                raise SolverError("half-plane: every node in contact slips or is separated "
                                  "under pure load control (gross sliding)",
                                  backend="halfplane", status="gross_sliding")
            s = delta + C @ F
            s[S] = s0[S]
            ds = s - s0
            # a node on its limit that neither slips nor leaves it (F tracks μN, as at the
            # edge of an in-phase contact) is decided within the solve's round-off (forces to
            # about 1e-14 of their scale), not flipped for ever
            tol = 1e-10 * self._force_scale + 64 * _EPS * (b + np.abs(F))
            nxt = updates.next(F - ds / cd, -b - tol, b + tol, up, dn)
            if nxt is None:
                np.clip(F, -b, b, out=F)  # round-off only (tol above)
                return _Surface(s, delta, up, dn), F, ds
            up, dn = nxt
            if ks > 0.0 and updates.stats["single_changes"] > _SINGLE_MAX:
                break                     # Murty's rule is slow here, or cycling: see below
        if ks > 0.0:
            # with a support the increment is a bounded least-squares problem: solved by
            # scipy's bounded-variable least squares, whose active set terminates (the
            # patterns above can cycle under gross sliding, a node flipping between its
            # bounds)
            return self._bounded(state, b, Q, contact)
        raise SolverError(f"half-plane: the stick/slip pattern did not settle in {limit} "
                          f"iterations", backend="halfplane", status="max_iter")

    def _bounded(self, state, b, Q, contact):
        """The increment with ``k_support > 0`` as ``min ½ Fᵀ (C + 1 1ᵀ/k_s) F + (Q/k_s - s0)ᵀ
        F`` over ``|F| <= b`` (its optimality conditions are problem (P)'s: the gradient is the
        increment's slip), by BVLS on the Cholesky factor; its answer is checked."""
        from scipy.linalg import cho_factor, solve_triangular
        from scipy.optimize import lsq_linear

        C, ks, s0 = self.C, self.k_support, state.v
        on = np.flatnonzero(contact)
        H = C[np.ix_(on, on)] + 1.0 / ks
        g = Q / ks - s0[on]
        U, _ = cho_factor(H, lower=False)                  # H = Uᵀ U
        U = np.triu(U)
        y = -solve_triangular(U, g, trans="T")              # ½|U F - y|² = ½FᵀHF + gᵀF + c
        sol = lsq_linear(U, y, bounds=(-b[on], b[on]), method="bvls", tol=1e-14,
                         max_iter=50 * on.size)
        F = np.zeros(self.total)
        F[on] = sol.x
        delta = (F.sum() + Q) / ks
        s = delta + C @ F
        ds = s - s0
        band = 1e-10 * self._force_scale + 64 * _EPS * (b + np.abs(F))
        up, dn = contact & (F >= b - band) & (ds < 0.0), contact & (F <= -b + band) & (ds > 0.0)
        stick = contact & ~up & ~dn
        # the natural map's residual: sticking nodes keep their slip, the others sit on
        # their limits with the slip opposing the force
        worst = max(float(np.max(np.abs(ds[stick]) / self.cdiag[stick], initial=0.0)),
                    float(np.max(np.abs(np.abs(F[~stick & contact]) - b[~stick & contact]),
                                 initial=0.0)))
        if not sol.success or worst > 1e-8 * self._force_scale:
            raise SolverError(f"half-plane: the bounded least-squares increment ended with "
                              f"residual {worst:.3g} (status {sol.status}: {sol.message})",
                              backend="halfplane", status=str(sol.status))
        s[stick] = s0[stick]
        ds[stick] = 0.0
        np.clip(F, -b, b, out=F)
        return _Surface(s, delta, up, dn), F, ds


def entry_loads(A: np.ndarray, h: np.ndarray, area: float, P_max: float) -> np.ndarray:
    """Per element of a boundary-element grid (dense influence matrix A per unit pressure, gap
    h at zero approach, element area), the normal load at which it comes into contact (inf: not
    below ``P_max``). Exact for the discrete problem: with the contact set fixed, pressures and
    gaps are affine in the load, so each next element's entry is where its gap, an affine
    function of the approach d, reaches zero; one solve per change of the set (elements that
    enter together, as symmetric ones do, are added together). Assumes the set only grows with
    the load (a convex surface)."""
    h = np.asarray(h, dtype=float).ravel()
    N = h.size
    levels = np.full(N, np.inf)
    S = np.flatnonzero(h <= h.min() + 1e-14 * (np.abs(h).max() + 1e-300))
    levels[S] = 0.0
    block = DenseBlock(A)
    P = 0.0
    for _ in range(N):
        block.set(S)
        z, y = np.zeros(N), np.zeros(N)
        e = np.zeros(N)
        e[S] = 1.0
        idx, zz = block.solve(e)
        z[idx] = zz
        hh = np.zeros(N)
        hh[S] = h[S]
        idx, yy = block.solve(hh)
        y[idx] = yy
        Z, Y = z.sum(), y.sum()
        Az, Ay = A[:, S] @ z[S], A[:, S] @ y[S]
        d_now = (P / area + Y) / Z
        closing = 1.0 - Az
        out = np.ones(N, dtype=bool)
        out[S] = False
        with np.errstate(divide="ignore", invalid="ignore"):
            d_star = np.where(out & (closing > 0), (h - Ay) / closing, np.inf)
        d_star[d_star < d_now * (1 - 1e-12)] = np.inf
        d_next = float(d_star.min())
        if not np.isfinite(d_next):
            break
        P = (d_next * Z - Y) * area
        if P > P_max:
            break
        new = np.flatnonzero(d_star <= d_next + 1e-12 * abs(d_next))
        levels[new] = P
        S = np.union1d(S, new)
    return levels
