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

The tangential problem is the ``halfplane-pdas`` stepper's
(:mod:`lcpfric.steppers.halfplane_pdas`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np

from ... import _checks
from ...errors import InputError, SolverError
from ...linalg import DenseBlock
from .approach import entry_loads
from .base import ContactModel
from .closed_forms import cylinder_contact, moduli

if TYPE_CHECKING:
    from scipy.sparse.linalg import LinearOperator

    from ..loads import Load

__all__ = ["HalfPlaneCylinder", "NormalProblem", "MAX_NODES", "log_kernel"]

#: largest number of elements (the influence matrix is dense: 8 N² bytes)
MAX_NODES = 6000
#: fewest springs (elements) across the largest contact that resolve it
MIN_NODES = 10
_MAX_ITER = 400


def log_kernel(offsets: np.ndarray, width: float, Estar: float, datum: float) -> np.ndarray:
    """``A(k)``: the displacement at offset ``k Δ`` due to a uniform unit traction on an element
    of width Δ (module docstring)."""

    def L(y):
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(y == 0.0, 0.0, y * np.log(np.abs(y)) - y)

    w = np.asarray(offsets, dtype=float) * width
    return (
        -(2.0 / (math.pi * Estar))
        * datum
        * (L((w + width / 2) / datum) - L((w - width / 2) / datum))
    )


class HalfPlaneCylinder(ContactModel):
    """Two identical cylinders in plane strain, by half-plane boundary elements.

    See the module docstring.

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
    datum : float, optional
        The distance ℓ from the contact at which the displacements are measured (module
        docstring: the approach is relative to it), at least twice the grid's length
        (default: twice the grid's length).
    half_width : float, optional
        The half-width the grid's elements span (default Hertz's at the largest load,
        ``a_max``).

    Attributes
    ----------
    nodes : int
        Every element of the grid (the unknowns; ``nodes_across`` is the ``nodes`` given).
    nodes_across : int
        The ``nodes`` given.
    total : int
        Every element of the grid (``nodes``).
    x, dx : ndarray, float
        Element centres and width.
    h : ndarray
        The gap profile at the element centres.
    A, C : ndarray
        The influence matrix (displacement per unit traction) and the compliance per unit
        force on an element, ``A / Δ``.
    cdiag : ndarray
        The diagonal of C.
    a_max, a0 : float
        The largest half-width over the cycle and the half-width at P0 (Hertz's).
    force_scale : float
        An element's force scale (the increments' tolerances are relative to it).

    Raises
    ------
    InputError
        A parameter out of range (:class:`~lcpfric.model.continuum.base.ContactModel`); more
        than 6000 elements in the grid (the influence matrix is dense); a profile that is not
        finite.
    """

    max_nodes = MAX_NODES
    min_nodes = MIN_NODES
    default_method = "halfplane-pdas"

    def __init__(
        self,
        R: float,
        E: float,
        nu: float,
        mu: float,
        P: Load | float,
        Q: Load | float,
        *,
        k_support: float = 0.0,
        nodes: int = 400,
        profile: Callable | None = None,
        datum: float | None = None,
        half_width: float | None = None,
    ) -> None:
        super().__init__(E, nu, mu, P, Q, k_support, nodes)
        self.R = _checks.positive("R", R)
        self.a_max = cylinder_contact(self.P_max, self.R, self.E, self.nu)["a"]
        if half_width is not None:
            self.a_max = _checks.positive("half_width", half_width)
        self.a0 = cylinder_contact(self.P0, self.R, self.E, self.nu)["a"]
        self.dx = 2.0 * self.a_max / self.nodes
        extra = max(2, math.ceil(0.03 * self.nodes))
        self.total = self.nodes + 2 * extra
        if self.total > MAX_NODES:
            raise InputError(
                "nodes",
                f"{self.nodes} elements (+{2 * extra} beyond the contact) "
                f"exceed {MAX_NODES}: the influence matrix is dense",
            )
        N = self.total
        self.x = (np.arange(N) - (N - 1) / 2.0) * self.dx
        h = (profile or (lambda x: x * x / (2.0 * self.R)))(self.x)
        self.h = _checks.finite_array("profile", h).reshape(N)
        if datum is None:
            datum = 2.0 * N * self.dx
        elif not _checks.positive("datum", datum) >= 2.0 * N * self.dx:
            raise InputError(
                "datum",
                f"must be finite and at least twice the grid's length, "
                f"{2.0 * N * self.dx:.6g} (the influence matrix is then positive definite), "
                f"got {datum!r}",
            )
        self.datum = float(datum)
        col = log_kernel(np.arange(N), self.dx, self.moduli["E*"], datum)
        from scipy.linalg import toeplitz

        self.A = toeplitz(col)  # displacement per unit pressure
        self.C = self.A / self.dx  # per unit force on an element
        self.cdiag = np.diag(self.C).copy()
        self.nodes_across = self.nodes
        #: an element's force scale (the increments' tolerances are relative to it)
        self.force_scale = self.mu * self.P_max * self.dx / (2 * self.a_max)
        self.nodes = N  # the unknowns of the grid

    @classmethod
    def under_approach(
        cls, R: float, E: float, nu: float, mu: float, approach, Q=0.0, *, datum: float, **options
    ) -> HalfPlaneCylinder:
        """The cylinder under a prescribed normal approach ``d(t)`` of the points at distance
        ℓ (``datum``) from the contact, instead of a normal load: its load is ``P(d(t))``,
        exact for the grid (:class:`~.approach.ApproachTable`), 0 where the bodies are apart.
        The grid spans Hertz's half-width at the largest approach
        (:func:`~.closed_forms.cylinder_approach`) unless ``half_width`` is given.

        Parameters
        ----------
        R, E, nu, mu : float
            As for the constructor.
        approach : Load or float
            The approach ``d(t)`` (its mean > 0).
        Q : Load or float, optional
            The tangential load (unused when the tangential motion is prescribed).
        datum : float
            ℓ: the bodies' size, at least twice the grid's length.
        **options
            The constructor's ``nodes``, ``profile``, ``k_support``, ``half_width``.

        Returns
        -------
        HalfPlaneCylinder
            The model, its P a :class:`~lcpfric.model.loads.Periodic` load.

        Raises
        ------
        InputError
            The constructor's, an approach whose mean is not > 0, or a ``datum`` too small for
            the largest approach (its contact wider than ℓ).
        """
        from scipy.optimize import brentq

        from .approach import ApproachTable, approach_load, prescribed_approach
        from .closed_forms import cylinder_approach

        d, d_max = prescribed_approach(approach)
        ell = _checks.positive("datum", datum)
        if "half_width" not in options:  # the load of the approach d_max: δ(P) grows up to a = ℓ
            top = math.pi * moduli(E, nu)["E*"] * ell * ell / (4.0 * R)
            if cylinder_approach(top, R, E, nu, ell) <= d_max:
                raise InputError(
                    "datum",
                    f"ℓ = {ell:.6g} is too small for the largest approach {d_max:.6g} (the "
                    f"contact would be wider than ℓ): ℓ is the bodies' size",
                )
            P_top = brentq(lambda P: cylinder_approach(P, R, E, nu, ell) - d_max, 0.0, top)
            options["half_width"] = cylinder_contact(P_top, R, E, nu)["a"]
        grid = cls(R, E, nu, mu, 1.0, 0.0, datum=ell, **options)  # the grid (any load)
        table = ApproachTable(grid.A, grid.h, grid.dx, d_max)
        return cls(R, E, nu, mu, approach_load(table, d), Q, datum=ell, **options)

    # -- the normal problem ---------------------------------------------------------------------
    def normal_problem(self) -> NormalProblem:
        """A solver of the frictionless normal problem.

        Its contact set is warm-started from the last load it solved.

        Returns
        -------
        NormalProblem
            A new solver (:class:`NormalProblem`), whose ``solution(t)`` is
            ``(limits, sizes, stats)``.
        """
        return NormalProblem(self)

    def pressure(self, P: float) -> np.ndarray:
        """The frictionless contact pressures under the load P (per unit length).

        Parameters
        ----------
        P : float
            Normal load per unit length (P <= 0: separation, zero pressures).

        Returns
        -------
        ndarray
            The pressure on each element, ``(nodes,)``.

        Raises
        ------
        SolverError
            The active-set iteration cycles or finds no contact set in 400 iterations.
        """
        return self.normal_problem().pressure(P)

    def load_scales(self, Q: Load) -> tuple[float, float]:
        """``(displacement, force)`` scales with the tangential load Q.

        The displacement scale is its amplitude (or mean, if constant) times ``4 / (π E*)``
        (a plane contact has no initial tangential stiffness), the force scale the largest
        friction limit μ P_max.

        Parameters
        ----------
        Q : Load
            The tangential load.

        Returns
        -------
        displacement, force : float
            The two scales.
        """
        q = Q.amplitude if not Q.is_constant else abs(Q.mean)
        return q * 4.0 / (math.pi * self.moduli["E*"]), self.mu * self.P_max

    def normalization(self) -> tuple[str, float]:
        """The normalized dissipation: ``W_normalized = factor · W``.

        Returns
        -------
        name : str
            Its formula, ``"W pi E*/(mu^2 P0^2)"``.
        factor : float
            ``π E* / (μ P0)²``.
        """
        return "W pi E*/(mu^2 P0^2)", math.pi * self.moduli["E*"] / (self.mu * self.P0) ** 2

    # -- as an lcpfric system (ContactModel.system) -------------------------------------------
    def springs(self) -> tuple[LinearOperator, np.ndarray, np.ndarray]:
        """The elements with the body held fixed, for :meth:`ContactModel.system`.

        Returns
        -------
        compliance : LinearOperator
            C.
        C_inv_ones : ndarray
            ``C⁻¹ 1``, ``(nodes,)``.
        diagonal : ndarray
            The diagonal of C.
        """
        from scipy.linalg import cho_factor, cho_solve
        from scipy.sparse.linalg import aslinearoperator

        w = cho_solve(cho_factor(self.C), np.ones(self.total))
        return aslinearoperator(self.C), w, self.cdiag.copy()

    def entry_loads(self) -> np.ndarray:
        """Per element, the normal load at which it comes into contact (:func:`entry_loads`).

        Returns
        -------
        ndarray
            ``(nodes,)`` loads; inf: not below the largest load of the cycle.
        """
        return entry_loads(self.A, self.h, self.dx, self.P_max)


class NormalProblem:
    """The frictionless normal problem of a :class:`HalfPlaneCylinder` under a sequence of loads:
    a primal-dual active-set iteration on the contact set (module docstring), warm-started from
    the previous load's set, the set's solves by a :class:`~lcpfric.linalg.DenseBlock` updated
    when the set changes by a few nodes. Loads solved once are remembered (a harmonic P repeats
    its values twice a cycle). ``stats``: ``normal_solves``."""

    def __init__(self, model):
        self.model = model
        self.block = DenseBlock(model.A)
        self.cache: dict[float, np.ndarray] = {}
        self.set = np.flatnonzero(np.abs(model.x) < model.a0)
        self.stats = {"normal_solves": 0}

    def solution(self, t):
        """``(limits, sizes, stats)`` at the instants t
        (:meth:`HalfPlaneCylinder.normal_solution`)."""
        model = self.model
        P = np.atleast_1d(np.asarray(model.P(np.asarray(t, dtype=float)), dtype=float))
        b = np.array([model.mu * model.dx * self.pressure(x) for x in P])
        sizes = np.zeros(b.shape[0])
        for j, row in enumerate(b):
            on = np.flatnonzero(row > 0)
            if on.size:
                sizes[j] = np.max(np.abs(model.x[on])) + model.dx / 2
        return b, sizes, dict(self.stats)

    def pressure(self, P: float) -> np.ndarray:
        """The frictionless contact pressures under the load P (per unit length)."""
        P = float(P)
        if P <= 0.0:
            return np.zeros(self.model.total)
        got = self.cache.get(P)
        if got is not None:
            return got
        model = self.model
        A, h, dx = model.A, model.h, model.dx
        diag = np.diag(A)
        S = self.set if self.set.size else np.array([int(np.argmin(h))])
        self.stats["normal_solves"] += 1
        seen = set()
        for _ in range(_MAX_ITER):
            block = self.block
            block.set(S)
            e = np.zeros(model.total)
            e[S] = 1.0
            idx, z = block.solve(e)
            hh = np.zeros(model.total)
            hh[S] = h[S]
            _, y = block.solve(hh)
            d = (P / dx + y.sum()) / z.sum()
            p = np.zeros(model.total)
            p[idx] = d * z - y
            g = h - d + A @ p
            g[S] = 0.0
            # an element at the entry load has p = g = 0: decided within round-off, not flipped
            tol = 1e-10 * P / (dx * model.nodes_across)
            new = np.flatnonzero(p - g / diag > tol)
            key = new.tobytes()
            if np.array_equal(new, S):
                break
            if key in seen:
                raise SolverError(
                    "half-plane normal problem: the contact set cycles",
                    backend="halfplane",
                    status="cycling",
                )
            seen.add(key)
            S = new
        else:
            raise SolverError(
                f"half-plane normal problem: no contact set in {_MAX_ITER} iterations",
                backend="halfplane",
                status="max_iter",
            )
        self.set = S
        p = np.maximum(p, 0.0)
        if len(self.cache) < 100_000:
            self.cache[P] = p
        return p
