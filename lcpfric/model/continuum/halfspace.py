r"""The three-dimensional contact of two elastic bodies by boundary elements on the half-space:
any surface on a square grid, tangential tractions along the load (d = 1) or in the plane (d =
2, the full Cerruti coupling). Different materials (``E2``, ``nu2``; a rigid base): composite
moduli, and for Dundurs' β ≠ 0 the pressure coupled with the shear (:mod:`.dissimilar`; the
coupled increments: :mod:`lcpfric.steppers.coupled_halfspace`). The bodies (E, ν) touch
over a grid of N x N square elements of side h carrying uniform tractions; the nodes are the
elements' centres. The surface is the gap at zero approach ``g0`` (``(N, N)``): a sphere
(:meth:`HalfSpace.sphere`), a flat punch with rounded edges (:meth:`HalfSpace.punch`) or a user
height map (:class:`HalfSpace` itself). The loads are the total normal force P(t) and the
tangential force Q(t) along x.

Influence coefficients and products: :mod:`.influence` (Love's rectangle solutions, products by
zero-padded FFT; no matrix is formed); the compliance's on the grid: :mod:`.halfspace_compliance`.

The normal problem
------------------
At each instant, frictionless contact under P(t) (uncoupled from the shear where β = 0), by
constrained conjugate gradients (:mod:`.normal3d`), each instant started from the previous
one's pressures. The friction limits are ``b_i = μ p_i h²``.

The tangential problem, each increment's problem (P), is the ``newton-cg`` stepper's
(:mod:`lcpfric.steppers.newton_cg`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ... import _checks, memory
from ...errors import InputError
from .approach import DENSE_MAX, entry_loads, halfspace_under_approach
from .base import ContactModel
from .closed_forms import moduli
from .dissimilar import attach, pair
from .halfspace_compliance import apply, compliance, compliance_springs, nodes, pad  # noqa: F401
from .influence import Convolution
from .normal3d import NormalProblem

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from scipy.sparse.linalg import LinearOperator

    from ..loads import Load

__all__ = ["HalfSpace", "NormalProblem", "MAX_GRID", "MIN_ACROSS", "MEMORY_PER_POINT", "compliance"]

#: largest grid side (the FFT works on a grid about twice as large)
MAX_GRID = 2048
#: fewest elements across the contact at the mean load
MIN_ACROSS = 8
#: bytes per point of the FFT's padded grid at the peak, by d (:meth:`HalfSpace.memory_estimate`)
MEMORY_PER_POINT = {1: 240, 2: 500}


class HalfSpace(ContactModel):
    """Two identical elastic bodies touching over a surface on a square grid (module docstring).

    Parameters
    ----------
    E, nu, mu : float
        Each body's modulus and Poisson's ratio (``0 <= ν < 0.5``), friction coefficient.
    P, Q : Load or float
        Total normal and tangential (along x) loads.
    heights : (N, N) array_like
        The gap at zero approach (the sum of the two surfaces' heights), on the grid; index
        ``[i, j]`` is the element at ``(x_i, y_j)``. Every entry must be finite; a masked
        array with masked points is refused (every grid point is a surface point).
    spacing : float
        The element side h.
    dims : {1, 2}
        Tangential directions: 1 (tractions along the load) or 2 (in the plane).
    k_support : float
        Tangential support stiffness in parallel with the contact (0: pure load control).
    E2, nu2 : float or None, optional
        Body 2 (the base), if it differs from body 1 (E, ν, the loaded body); ``E2 = inf``: a
        rigid base. None: identical bodies (:func:`.dissimilar.pair`).
    _a0 : float or None, optional
        Internal (:meth:`sphere`): the contact radius at P0 for the normalization.
    geometry : str, optional
        Internal: ``"heightmap"``, or ``"sphere"`` / ``"punch"`` from those constructors.

    Attributes
    ----------
    N, h : int, float
        Grid side and element side; ``nodes = N²``.
    g0 : ndarray
        The surface.
    op : Convolution
        The influence operators.
    a0, k_t0 : float
        The contact radius at P0 (Hertz's for the sphere, else the radius of the discrete
        contact's area) and ``k_t0 = 2 a0 G*``, the normalization.
    c : float
        Each element's self-compliance (per unit force).
    pos, cpos : ndarray
        Each node's first component in the FFT's padded layout (flat), and (d = 2) its complex
        entry.
    beta, coupling : float, Coupling or None
        Dundurs' β and, where β ≠ 0, the coupled products (:mod:`.dissimilar`).
    force_scale : float
        The largest friction limit of an element, ``μ max p h²`` at P_max.
    normal_seed : (dict, ndarray)
        The pressures at P_max and P0, solved at construction: every normal solve
        (:class:`NormalProblem`) starts from them.
    x, xy : ndarray
        Each node's distance from the grid's centre ``(N²,)``, and its coordinates ``(N², 2)``.

    Raises
    ------
    InputError
        A parameter out of range (as for the base class; heights a finite square N x N array,
        4 <= N <= 2048), arrays over the memory limit (:mod:`lcpfric.memory`), or a contact
        that spans fewer than 8 elements at P0 or reaches the grid's edge at P_max.
    SolverError
        The normal problem at P_max or P0 failed.
    """

    max_nodes = MAX_GRID * MAX_GRID
    default_method = "newton-cg"
    #: what to do where no element slips (``steady_state``'s ResolutionWarning)
    refine_hint = "refine the grid or use the MDR model for a sphere"

    def __init__(
        self,
        E: float,
        nu: float,
        mu: float,
        P: Load | float,
        Q: Load | float,
        *,
        heights: ArrayLike,
        spacing: float,
        dims: int = 1,
        k_support: float = 0.0,
        _a0: float | None = None,
        geometry: str = "heightmap",
        E2: float | None = None,
        nu2: float | None = None,
    ) -> None:
        if np.ma.isMaskedArray(heights):
            if np.ma.count_masked(heights):
                raise InputError(
                    "heights",
                    f"a masked array ({np.ma.count_masked(heights)} points masked) is not "
                    "supported: every grid point is a surface point; to keep points out of "
                    "contact give them a gap larger than the approach at the largest load "
                    "(heights.filled(a large value)), or crop the surface",
                )
            heights = np.ma.getdata(heights)
        g0 = _checks.finite_array("heights", heights)
        if g0.ndim != 2 or g0.shape[0] != g0.shape[1] or g0.shape[0] < 4:
            raise InputError(
                "heights", f"must be a square 2-D array (N x N, N >= 4), got shape {g0.shape}"
            )
        N = g0.shape[0]
        if N > MAX_GRID:
            raise InputError("heights", f"grid {N} x {N} exceeds {MAX_GRID} x {MAX_GRID}")
        if dims not in (1, 2):
            raise InputError("dims", f"must be 1 or 2, got {dims!r}")
        super().__init__(E, nu, mu, P, Q, k_support, N * N)
        self.h = _checks.positive("spacing", spacing)
        self.N, self.dims, self.geometry = N, int(dims), geometry
        self.g0 = g0 - g0.min()
        self._check_memory()
        second = attach(self, E2, nu2)  # moduli, beta, coupling, E2, nu2
        self.op = Convolution(N, self.h, self.E, self.nu, self.dims, second)
        self.c = self.op.diagonal("xx") / self.h**2
        M = self.op.M
        # each node's first component in the FFT's padded layout (Convolution.view, flat)
        self.pos = self.dims * (np.arange(N)[:, None] * M + np.arange(N)[None, :]).ravel()
        self.cpos = self.pos // self.dims  # d = 2: each node's complex entry
        coords = (np.arange(N) - (N - 1) / 2.0) * self.h
        X, Y = np.meshgrid(coords, coords, indexing="ij")
        self.xy = np.stack([X.ravel(), Y.ravel()], axis=1)
        self.x = np.hypot(X, Y).ravel()  # distance from the grid's centre
        self.normal_seed = ({}, None)
        normal = NormalProblem(self)
        top = normal.pressure(self.P_max)
        self.contact_max = int(np.count_nonzero(top))
        self.force_scale = self.mu * float(top.max()) * self.h**2
        p0 = normal.pressure(self.P0)
        self.normal_seed = (dict(normal.cache), normal.last)
        self.a_eq0 = math.sqrt(np.count_nonzero(p0) * self.h**2 / math.pi)
        across = 2.0 * self.a_eq0 / self.h
        if across < MIN_ACROSS:
            raise InputError(
                "grid" if geometry in ("sphere", "punch") else "spacing",
                f"the contact at the mean load spans about {across:.1f} "
                f"elements across, fewer than {MIN_ACROSS}: the grid is too "
                f"coarse to resolve it; refine the grid",
            )
        edge = top.reshape(N, N)
        if np.any(edge[0]) or np.any(edge[-1]) or np.any(edge[:, 0]) or np.any(edge[:, -1]):
            raise InputError(
                "heights",
                "the contact at the largest load reaches the grid's "
                "edge: the grid does not hold the contact; a larger "
                "grid (or surface) is needed",
            )
        self.a0 = float(_a0) if _a0 is not None else self.a_eq0
        self.k_t0 = 2.0 * self.a0 * self.moduli["G*"]

    # -- constructors ---------------------------------------------------------------------------
    @classmethod
    def sphere(
        cls,
        R: float,
        E: float,
        nu: float,
        mu: float,
        P: Load | float,
        Q: Load | float,
        *,
        grid: int = 40,
        dims: int = 1,
        k_support: float = 0.0,
        E2: float | None = None,
        nu2: float | None = None,
    ) -> HalfSpace:
        """Two spheres (effective radius R): ``g0 = r²/(2R)``.

        On a grid of ``grid`` elements across the largest Hertz contact diameter, plus 3 % (at
        least two elements) on each side. ``a0`` and ``k_t0`` are Hertz's (the normalization
        of the other models).

        Parameters
        ----------
        R : float
            Effective radius, > 0.
        E, nu, mu, P, Q
            As for :class:`HalfSpace`.
        grid : int, optional
            Elements across the largest contact diameter, >= 8 (<= 2048 with the margins).
        dims, k_support, E2, nu2 : optional
            As for :class:`HalfSpace`.

        Returns
        -------
        HalfSpace
            The model, with the attributes ``R``, ``a_max`` and ``grid_across`` added.

        Raises
        ------
        InputError
            ``R`` or ``grid`` out of range, or as for :class:`HalfSpace`.
        SolverError
            As for :class:`HalfSpace`.
        """
        R = _checks.positive("R", R)
        probe = ContactModel(E, nu, mu, P, Q, k_support, 1)
        Es = (pair(probe.E, probe.nu, E2, nu2) or probe.moduli)["E*"]
        a_max, a0 = ((3.0 * x * R / (4.0 * Es)) ** (1.0 / 3.0) for x in (probe.P_max, probe.P0))
        g, N, h = cls._grid(grid, a_max)
        r2 = g[:, None] ** 2 + g[None, :] ** 2
        model = cls(
            E,
            nu,
            mu,
            P,
            Q,
            heights=r2 / (2.0 * R),
            spacing=h,
            dims=dims,
            k_support=k_support,
            _a0=a0,
            geometry="sphere",
            E2=E2,
            nu2=nu2,
        )
        model.R, model.a_max, model.grid_across = R, a_max, grid
        return model

    @classmethod
    def punch(
        cls,
        R: float,
        radius: float,
        E: float,
        nu: float,
        mu: float,
        P: Load | float,
        Q: Load | float,
        *,
        grid: int = 40,
        dims: int = 1,
        k_support: float = 0.0,
        E2: float | None = None,
        nu2: float | None = None,
    ) -> HalfSpace:
        """A flat punch of radius ``radius`` with edges rounded to the radius R.

        ``g0 = max(0, r − radius)²/(2R)``; the grid spans the largest contact (its radius by
        the method of dimensionality reduction, exact for axisymmetric bodies) as for
        :meth:`sphere`.

        Parameters
        ----------
        R, radius : float
            Radius of the rounded edges and of the flat face, > 0.
        E, nu, mu, P, Q, grid, dims, k_support, E2, nu2
            As for :meth:`sphere`.

        Returns
        -------
        HalfSpace
            The model, with ``R``, ``flat_radius``, ``a_max`` and ``grid_across`` added.

        Raises
        ------
        InputError
            ``R``, ``radius`` or ``grid`` out of range, or as for :class:`HalfSpace`.
        SolverError
            As for :class:`HalfSpace`.
        """
        from .profiles import Axisymmetric

        R, b = _checks.positive("R", R), _checks.positive("radius", radius)
        probe = ContactModel(E, nu, mu, P, Q, k_support, 1)
        shape = Axisymmetric(lambda r: np.maximum(r - b, 0.0) / R)
        Es = (pair(probe.E, probe.nu, E2, nu2) or moduli(E, nu))["E*"]
        a_max = float(np.max(shape.radius(probe.P_max, Es)))
        g, N, h = cls._grid(grid, a_max)
        r = np.hypot(g[:, None], g[None, :])
        model = cls(
            E,
            nu,
            mu,
            P,
            Q,
            heights=np.maximum(r - b, 0.0) ** 2 / (2.0 * R),
            spacing=h,
            dims=dims,
            k_support=k_support,
            geometry="punch",
            E2=E2,
            nu2=nu2,
        )
        model.R, model.flat_radius, model.a_max, model.grid_across = R, b, a_max, grid
        return model

    under_approach = classmethod(halfspace_under_approach)

    @staticmethod
    def _grid(grid, a_max):
        grid = _checks.positive_int("grid", grid, MIN_ACROSS)
        extra = max(2, math.ceil(0.03 * grid))
        N = grid + 2 * extra
        if N > MAX_GRID:
            raise InputError("grid", f"{grid} elements across (+{2 * extra}) exceed {MAX_GRID}")
        h = 2.0 * a_max / grid
        return (np.arange(N) - (N - 1) / 2.0) * h, N, h

    def memory_estimate(self) -> int:
        """Bytes the model's arrays take at their peak: ``MEMORY_PER_POINT[d] × M²``.

        Kernels, spectra, the solvers' work arrays, on the FFT's padded grid of M x M;
        measured (``tracemalloc``'s peak over a short solve, grids 40 to 120: at most 211 and
        447 bytes per point for d = 1 and 2, checked by a test). The cycle's records are the
        driver's, which checks them itself.

        Returns
        -------
        int
            The estimate in bytes.
        """
        M = Convolution.padded_size(self.N)
        return MEMORY_PER_POINT[self.dims] * M * M

    def _check_memory(self):
        """Refuse a grid whose arrays (:meth:`memory_estimate`) exceed the memory limit
        (:mod:`lcpfric.memory`)."""
        memory.check(
            self.memory_estimate(),
            "heights",
            f"a {self.N} x {self.N} grid with d = {self.dims} (its arrays)",
        )

    # -- the normal problem ---------------------------------------------------------------------
    def normal_problem(self) -> NormalProblem:
        """A solver of the frictionless normal problem, started from :attr:`normal_seed`.

        Returns
        -------
        NormalProblem
            Its ``solution(t)`` is ``(limits, sizes, stats)`` (:class:`NormalProblem`).
        """
        return NormalProblem(self, self.normal_seed)

    def pressure(self, P: float) -> np.ndarray:
        """The frictionless contact pressures ``(N²,)`` under the load P.

        Parameters
        ----------
        P : float
            Total normal load (P <= 0: separation, zero pressures).

        Returns
        -------
        ndarray
            The pressure on each element, ``(N²,)``.

        Raises
        ------
        SolverError
            The constrained conjugate gradients did not converge.
        """
        return self.normal_problem().pressure(P)

    # -- as an lcpfric system (ContactModel.system) ---------------------------------------------
    def springs(self) -> tuple[LinearOperator, np.ndarray, np.ndarray]:
        """``(compliance operator, C⁻¹ B, diag C)`` with the body held fixed.

        For :meth:`ContactModel.system`: the operator is the FFT product (matrix-free: the
        ``active-set`` backend solves d = 1 with products only, the other methods form C from
        products on small grids), ``C⁻¹ B`` by preconditioned conjugate gradients to 1e-13.

        Returns
        -------
        tuple of (LinearOperator, ndarray, ndarray)
            C ``(m, m)``, m = N² d; ``C⁻¹ B`` ``(m,)`` (d = 1) or ``(m, 2)``; diag C ``(m,)``.
        """
        return compliance_springs(self)

    def entry_loads(self) -> np.ndarray:
        """Per element, the normal load at which it enters the contact (dense: small grids).

        By :func:`~lcpfric.model.continuum.approach.entry_loads`, exact for the discrete
        problem.

        Returns
        -------
        ndarray
            ``(N²,)`` loads; inf: not below the largest load of the cycle.

        Raises
        ------
        InputError
            More than 2000 elements (named ``grid``).
        """
        if self.nodes > DENSE_MAX:
            raise InputError(
                "grid",
                f"exact entry loads need the dense influence matrix of "
                f"{self.nodes} elements (at most {DENSE_MAX})",
            )
        return entry_loads(self.op.dense("n"), self.g0, self.h**2, self.P_max)
