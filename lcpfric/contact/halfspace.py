r"""The three-dimensional contact of two identical elastic bodies by boundary elements on the
half-space: any surface on a square grid, tangential tractions along the load (d = 1) or in the
plane (d = 2, the full Cerruti coupling).

The bodies (each E, ν) touch over a square grid of N x N square elements of side h carrying
uniform tractions; the nodes are the elements' centres. The surface is the gap at zero approach
``g0`` (``(N, N)``): a sphere (:meth:`HalfSpace.sphere`), a flat punch with rounded edges
(:meth:`HalfSpace.punch`) or a user height map (:class:`HalfSpace` itself). The loads are the
total normal force P(t) and the tangential force Q(t) along x.

Influence coefficients and products: :mod:`.influence` (Love's rectangle solutions, products by
zero-padded FFT; no matrix is formed).

The normal problem
------------------
At each instant, frictionless contact under P(t) (uncoupled from the shear: identical bodies),
by constrained conjugate gradients (:mod:`.normal3d`), each instant started from the previous
one's pressures. The friction limits are ``b_i = μ p_i h²``.

The tangential problem
----------------------
Friction forces ``F_i`` on the nodes in contact (lcpfric's sign: the slip opposes F; the shear
traction transmitted is ``-F_i/h²``), ``|F_i| <= b_i``; the relative slips s and the rigid
tangential displacement δ of the body satisfy ``s = δ + C F`` with C the Cerruti operator per
unit force (:mod:`.influence` divided by h²); the body is held by Q(t) and by a support of
stiffness ``k_support``: ``Σ F_i − k_support δ + Q = 0``. Each increment is problem (P), the
maximum-dissipation projection: the sticking nodes keep their slip, the slipping ones sit on
their limit with the slip opposite to the force.

It is solved as the nonsmooth equation ``F = proj_b(F − Δs(F)/c)`` (c the diagonal of C) by a
semismooth Newton method, warm-started from the previous increment (its forces extrapolated,
its pattern), or from the same increment of the previous cycle; the state carries ``C F`` and
the change's ``C ΔF`` (C is linear), so a start costs no product. With the pattern of a
Newton iterate fixed, the step is one symmetric positive definite linear system on the
sticking components and, for d = 2, the components of the slipping nodes' forces tangent to
their circle (with the diagonal term ``|Δs_i| / b_i``), under the equilibrium as a linear
constraint; it is solved by conjugate gradients, projected onto the constraint
(``k_support = 0``) or with the support's rank-d term (``k_support > 0``), one product with C
per iteration (and one for the known forces and the start together) and one with the
preconditioner, the inverse of the padded circulant operator; on the slipping nodes' tangential
unknowns, whose operator adds the diagonal term to C's c, it is scaled by ``sqrt(c / (c +
term))`` on both sides (symmetric). For d = 1
this is the primal-dual active-set iteration of the ``active-set`` backend (the slipping forces
are known), and its answer is exact once the pattern is right: a step with a new pattern is
solved to a hundredth of the residual (it only decides the next pattern; on a rough contact the
first patterns are often wrong), and a pattern that repeats once more to full accuracy. Where
the patterns stall (a large increment on a fine grid changes the state of thousands of nodes,
and Murty's rule, the pattern rule's fallback, changes one per iteration), d = 1 turns to the
damped steps of d = 2. For d = 2 each step is damped by a line search on the natural map's
residual, and the slip directions converge quadratically near the answer. The answer is
accepted when the natural-map residual is below ``tol × force scale`` on every node (the
force scale: the largest limit μ p h², or the force that moves a node by the loads'
displacement scale ``Q/k_t0``, if smaller: a small tangential load is solved as accurately as
a large one); an iteration that does not get there raises :class:`~lcpfric.errors.SolverError`.

Nodes out of contact carry no force and no unknown. d = 1 with ν > 0 takes the tractions along
the load with the x-x Cerruti coefficient (Mindlin's approximation); d = 2 adds the
transverse tractions and the coupling.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..linalg import PatternUpdate
from ..cycle_memory import SlipMemory, row_norms
from ..errors import InputError, SolverError
from .closed_forms import hertz_contact
from .influence import Convolution
from .normal3d import normal_contact
from .steady import ContactModel

__all__ = ["HalfSpace", "MAX_GRID", "MIN_ACROSS"]

#: largest grid side (the FFT works on a grid about twice as large)
MAX_GRID = 2048
#: fewest elements across the contact at the mean load
MIN_ACROSS = 8
#: bytes per point of the FFT's padded grid at the peak, by d (:meth:`HalfSpace.memory_estimate`)
MEMORY_PER_POINT = {1: 240, 2: 500}
_MAX_NEWTON = 60
#: d = 1: pattern iterations from the extrapolated start before the safe restart
_RESTART = 8
_EPS = np.finfo(float).eps
#: most elements for the exact entry loads (dense influence matrix) of ``system()``
DENSE_MAX = 2000
#: d = 2: the linear solves of the Newton steps are to this fraction of the residual
_ETA = 1e-2
#: d = 1: the linear solves of the steps with a new pattern are to this fraction of the
#: residual (the repeated pattern's to full accuracy)
_ETA1 = 1e-2
#: d = 1: single changes by Murty's rule before the damped Newton steps of d = 2 take over
_SINGLE_MAX = 32
#: the linear solves end with their residual below this fraction of the increment's
#: tolerance where the natural map's residual is checked after the step (d = 2, and d = 1's
#: loose or damped steps; ten times lower for each further step once one that began within ten
#: times the tolerance did not end the increment); d = 1's step with a repeated pattern ends
#: the increment unchecked, so it keeps a margin (``_CG_TOL1``): at 0.9 a cycle tolerance of
#: 1e-12 with increments at 1e-10 (the backends' cross-check) took 46 cycles, their errors
#: keeping the change about 1e-11
_CG_TOL, _CG_TOL1 = 0.9, 0.1


@dataclass
class _Tangential:
    """The tangential state: slips of every node (``v``, flat, n·d), the rigid displacement δ,
    the forces and the last increment's changes (the next increment's warm start), and the
    products ``C F`` and ``C ΔF`` (node-major ``(n, d)``), so that a start from these forces
    and changes costs no product. The forces are the solver's last iterate, within the
    tolerance of their limits (the increment returns them projected onto them)."""

    v: np.ndarray
    delta: np.ndarray
    F: np.ndarray
    dF: np.ndarray
    ddelta: np.ndarray
    side: np.ndarray          # d = 1: +1 / -1 on the upper / lower limit, else 0
    CF: np.ndarray
    CdF: np.ndarray


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
        ``[i, j]`` is the element at ``(x_i, y_j)``.
    spacing : float
        The element side h.
    dims : {1, 2}
        Tangential directions: 1 (tractions along the load) or 2 (in the plane).
    k_support : float
        Tangential support stiffness in parallel with the contact (0: pure load control).
    tol : float
        Relative tolerance of the tangential increments (natural-map residual / force scale).
        With d = 2 the steady-state driver solves the early cycles more loosely, and the last
        ones to a tenth of its cycle tolerance, or to ``tol`` if that is tighter (down to a
        hundredth of the cycle tolerance: ``loose_cycles``).

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
    stats : dict
        Time and products spent on the normal and on the tangential problems, Newton and CG
        iterations, and (d = 1) the increments whose patterns stalled (``stalled``: solved by
        the damped steps).
    """

    max_nodes = MAX_GRID * MAX_GRID
    #: what to do where no element slips (``steady_state``'s ResolutionWarning)
    refine_hint = "refine the grid or use the MDR model for a sphere"

    def __init__(self, E, nu, mu, P, Q, *, heights, spacing, dims: int = 1,
                 k_support: float = 0.0, tol: float = 1e-10, _a0=None, geometry="heightmap"):
        g0 = _checks.finite_array("heights", heights)
        if g0.ndim != 2 or g0.shape[0] != g0.shape[1] or g0.shape[0] < 4:
            raise InputError("heights", f"must be a square 2-D array (N x N, N >= 4), got "
                                        f"shape {g0.shape}")
        N = g0.shape[0]
        if N > MAX_GRID:
            raise InputError("heights", f"grid {N} x {N} exceeds {MAX_GRID} x {MAX_GRID}")
        if dims not in (1, 2):
            raise InputError("dims", f"must be 1 or 2, got {dims!r}")
        super().__init__(E, nu, mu, P, Q, k_support, N * N)
        self.h = _checks.positive("spacing", spacing)
        self.tol = _checks.positive("tol", tol)
        self.N, self.dims, self.geometry = N, int(dims), geometry
        self.g0 = g0 - g0.min()
        self._check_memory()
        self.op = Convolution(N, self.h, self.E, self.nu, self.dims)
        self.c = self.op.diagonal("xx") / self.h ** 2
        M = self.op.M
        # each node's first component in the FFT's padded layout (Convolution.view, flat)
        self._pos = self.dims * (np.arange(N)[:, None] * M + np.arange(N)[None, :]).ravel()
        self._cpos = self._pos // self.dims          # d = 2: each node's complex entry
        coords = (np.arange(N) - (N - 1) / 2.0) * self.h
        X, Y = np.meshgrid(coords, coords, indexing="ij")
        self.xy = np.stack([X.ravel(), Y.ravel()], axis=1)
        self.x = np.hypot(X, Y).ravel()            # distance from the grid's centre
        self.stats = {"normal_seconds": 0.0, "normal_products": 0, "normal_solves": 0,
                      "tangential_seconds": 0.0, "tangential_products": 0, "increments": 0,
                      "newton": 0, "cg": 0, "stalled": 0}
        self._cache: dict[float, np.ndarray] = {}
        self._first_right = True        # d = 1: the last increment's first pattern held
        self._last_p = None
        top = self.pressure(self.P_max)
        self.contact_max = int(np.count_nonzero(top))
        self._force_scale = self.mu * float(top.max()) * self.h ** 2
        p0 = self.pressure(self.P0)
        self.a_eq0 = math.sqrt(np.count_nonzero(p0) * self.h ** 2 / math.pi)
        across = 2.0 * self.a_eq0 / self.h
        if across < MIN_ACROSS:
            raise InputError("grid" if geometry in ("sphere", "punch") else "spacing",
                             f"the contact at the mean load spans about {across:.1f} "
                             f"elements across, fewer than {MIN_ACROSS}: the grid is too "
                             f"coarse to resolve it; refine the grid")
        edge = top.reshape(N, N)
        if np.any(edge[0]) or np.any(edge[-1]) or np.any(edge[:, 0]) or np.any(edge[:, -1]):
            raise InputError("heights", "the contact at the largest load reaches the grid's "
                                        "edge: the grid does not hold the contact; a larger "
                                        "grid (or surface) is needed")
        self.a0 = float(_a0) if _a0 is not None else self.a_eq0
        self.k_t0 = 2.0 * self.a0 * self.moduli["G*"]

    # -- constructors ---------------------------------------------------------------------------
    @classmethod
    def sphere(cls, R, E, nu, mu, P, Q, *, grid: int = 40, dims: int = 1,
               k_support: float = 0.0, tol: float = 1e-10):
        """Two spheres (effective radius R): ``g0 = r²/(2R)`` on a grid of ``grid`` elements
        across the largest Hertz contact diameter, plus 3 % (at least two elements) on each
        side. ``a0`` and ``k_t0`` are Hertz's (the normalization of the other models)."""
        R = _checks.positive("R", R)
        probe = ContactModel(E, nu, mu, P, Q, k_support, 1)
        a_max = hertz_contact(probe.P_max, R, E, nu)["a"]
        a0 = hertz_contact(probe.P0, R, E, nu)["a"]
        g, N, h = cls._grid(grid, a_max)
        r2 = g[:, None] ** 2 + g[None, :] ** 2
        model = cls(E, nu, mu, P, Q, heights=r2 / (2.0 * R), spacing=h, dims=dims,
                    k_support=k_support, tol=tol, _a0=a0, geometry="sphere")
        model.R, model.a_max, model.grid_across = R, a_max, grid
        return model

    @classmethod
    def punch(cls, R, radius, E, nu, mu, P, Q, *, grid: int = 40, dims: int = 1,
              k_support: float = 0.0, tol: float = 1e-10):
        """A flat punch of radius ``radius`` with edges rounded to the radius R:
        ``g0 = max(0, r − radius)²/(2R)``; the grid spans the largest contact (its radius by
        the method of dimensionality reduction, exact for axisymmetric bodies) as for
        :meth:`sphere`."""
        from .mdr import Axisymmetric
        from .closed_forms import moduli

        R, b = _checks.positive("R", R), _checks.positive("radius", radius)
        probe = ContactModel(E, nu, mu, P, Q, k_support, 1)
        shape = Axisymmetric(lambda r: np.maximum(r - b, 0.0) / R)
        a_max = float(np.max(shape.radius(probe.P_max, moduli(E, nu)["E*"])))
        g, N, h = cls._grid(grid, a_max)
        r = np.hypot(g[:, None], g[None, :])
        model = cls(E, nu, mu, P, Q, heights=np.maximum(r - b, 0.0) ** 2 / (2.0 * R),
                    spacing=h, dims=dims, k_support=k_support, tol=tol, geometry="punch")
        model.R, model.flat_radius, model.a_max, model.grid_across = R, b, a_max, grid
        return model

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
        """Bytes the model's arrays take at their peak (kernels, spectra, the solvers' work
        arrays, on the FFT's padded grid of M x M): ``MEMORY_PER_POINT[d] × M²``, measured
        (``tracemalloc``'s peak over a short solve, grids 40 to 120: at most 211 and 447 bytes
        per point for d = 1 and 2, checked by a test). The cycle's records are the driver's,
        which checks them itself."""
        M = Convolution.padded_size(self.N)
        return MEMORY_PER_POINT[self.dims] * M * M

    def _check_memory(self):
        """Refuse a grid whose arrays (:meth:`memory_estimate`) exceed 4 GiB."""
        need = self.memory_estimate()
        if need > 4 << 30:
            raise InputError("heights", f"a {self.N} x {self.N} grid with d = {self.dims} "
                                        f"needs about {need / 2**30:.1f} GiB for its arrays; "
                                        f"at most 4 GiB")

    # -- the normal problem ---------------------------------------------------------------------
    def pressure(self, P: float) -> np.ndarray:
        """The frictionless contact pressures ``(N²,)`` under the load P."""
        P = float(P)
        if P <= 0.0:
            return np.zeros(self.nodes)
        # loads equal to 12 digits share one solve (a harmonic P repeats its values twice a
        # cycle, up to round-off): their pressures differ by less than that
        key = float(f"{P:.11e}")
        got = self._cache.get(key)
        if got is not None:
            return got
        start, count = time.perf_counter(), self.op.products
        sol = normal_contact(self.op, self.g0, P, p0=self._last_p)
        self.stats["normal_seconds"] += time.perf_counter() - start
        self.stats["normal_products"] += self.op.products - count
        self.stats["normal_solves"] += 1
        self._last_p = sol.p
        p = sol.p.ravel()
        if len(self._cache) < 20_000:
            self._cache[key] = p
        return p

    def limits(self, t) -> np.ndarray:
        P = np.atleast_1d(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float))
        out = np.empty((P.size, self.nodes))
        for j, x in enumerate(P):
            out[j] = self.pressure(x)
        out *= self.mu * self.h ** 2
        return out

    def sizes(self, t) -> np.ndarray:
        """The radius of a disc of the discrete contact's area."""
        P = np.atleast_1d(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float))
        return np.array([math.sqrt(np.count_nonzero(self.pressure(x)) * self.h ** 2 / math.pi)
                         for x in P])

    # -- as an lcpfric system (ContactModel.system) ---------------------------------------------
    def springs(self):
        """``(compliance operator, C⁻¹ B, diag C)`` with the body held fixed, for
        :meth:`ContactModel.system`: the operator is the FFT product (matrix-free: the
        ``active-set`` backend solves d = 1 with products only, the other methods form C from
        products on small grids), ``C⁻¹ B`` by preconditioned conjugate gradients to 1e-13."""
        from scipy.sparse.linalg import LinearOperator

        n, d = self.nodes, self.dims
        m = n * d
        model = self

        class _FFT(LinearOperator):
            def __init__(self):
                super().__init__(dtype=float, shape=(m, m))

            def _matvec(self, x):
                return model.compliance(np.asarray(x, dtype=float).reshape(n, d)).reshape(-1)

            def _rmatvec(self, x):
                return self._matvec(x)

        op = _FFT()
        h2 = self.h ** 2
        stats = {"cg": 0}
        W = np.empty((m, d))
        for j in range(d):
            e = np.zeros((n, d))
            e[:, j] = 1.0
            x, _ = _cg(op.matvec, e.ravel(), np.zeros(m), None,
                       lambda r: self._apply("precondition", r, h2).reshape(-1),
                       1e-13 * float(np.max(np.abs(e))) * self.c, stats)
            W[:, j] = x
        return op, (W[:, 0] if d == 1 else W), np.full(m, self.c)

    def entry_loads(self) -> np.ndarray:
        """Per element, the normal load at which it enters the contact (dense: small grids):
        :func:`~lcpfric.contact.halfplane.entry_loads`, exact for the discrete problem."""
        from .halfplane import entry_loads

        if self.nodes > DENSE_MAX:
            raise InputError("grid", f"exact entry loads need the dense influence matrix of "
                                     f"{self.nodes} elements (at most {DENSE_MAX})")
        return entry_loads(self.op.dense("n"), self.g0, self.h ** 2, self.P_max)

    # -- the model protocol of lcpfric.contact.steady ------------------------------------------
    def start(self) -> _Tangential:
        m, d = self.nodes * self.dims, self.dims
        return _Tangential(np.zeros(m), np.zeros(d), np.zeros(m), np.zeros(m), np.zeros(d),
                           np.zeros(self.nodes, dtype=np.int8), np.zeros((self.nodes, d)),
                           np.zeros((self.nodes, d)))

    def restart(self, state: _Tangential, v: np.ndarray) -> _Tangential:
        """The state with the slips v (the driver's extrapolation): the slips are the state,
        the forces only the next solve's starting point. ``C F`` is formed afresh (one product
        a cycle: the sums carried from increment to increment gather no round-off beyond a
        cycle's)."""
        self.stats["tangential_products"] += 1
        return _Tangential(np.asarray(v, dtype=float).copy(), state.delta, state.F,
                           np.zeros_like(state.dF), np.zeros_like(state.ddelta), state.side,
                           self.compliance(state.F), np.zeros_like(state.CF))

    def scales(self) -> tuple[float, float]:
        q = self.Q.amplitude if not self.Q.is_constant else abs(self.Q.mean)
        return q / self.k_t0, self.mu * self.P_max

    def normalization(self) -> tuple[str, float]:
        return "W k_t0/(mu^2 P0^2)", self.k_t0 / (self.mu * self.P0) ** 2

    def compliance(self, F: np.ndarray) -> np.ndarray:
        """``C F``: relative tangential displacements ``(n, d)`` from forces ``(n, d)``."""
        return self._apply("tangential", F, 1.0 / self.h ** 2)

    def _apply(self, kind, F, factor):
        """The product ``kind`` (:meth:`~.influence.Convolution.padded`) of node-major forces
        ``(n, d)`` or flat, times ``factor``: ``(n, d)``."""
        return self._nodes(self.op.padded(kind, self._pad(F), factor))

    def _pad(self, F):
        """Node-major forces ``(n, d)`` or flat in the FFT's padded layout
        (:meth:`~.influence.Convolution.view`)."""
        N, d = self.N, self.dims
        buf = self.op.empty()
        self.op.view(buf)[:N, :N] = np.asarray(F, dtype=float).reshape(N, N, d)
        return buf

    def _nodes(self, buf):
        """A padded array's nodes, node-major ``(n, d)``, a copy."""
        N, d = self.N, self.dims
        return self.op.view(buf)[:N, :N].reshape(N * N, d)

    def guess(self, state: _Tangential):
        """What the same increment of the next cycle starts from: this increment's changes of
        the forces and of δ, its pattern and ``C ΔF`` (the driver keeps one per increment)."""
        return state.dF, state.ddelta, state.side, state.CdF

    def memory(self):
        """d = 2: the per-node memory of a cycle's starting slips, the steady-state driver's
        preconditioner of the cycle map (:mod:`lcpfric.cycle_memory`); None for d = 1 (a node
        that slips forgets its start)."""
        return SlipMemory(self.c, self.nodes) if self.dims == 2 else None

    @property
    def loose_cycles(self) -> bool:
        """d = 2 settles over many cycles: the driver solves the early ones loosely
        (:func:`~lcpfric.contact.steady.steady_state`)."""
        return self.dims == 2

    def increment(self, state: _Tangential, b: np.ndarray, Q: float, guess=None, tol=None):
        """Problem (P) (module docstring): ``(state, F, Δs)``. ``guess``: the same increment's
        :meth:`guess` from the previous cycle, the start (else the last increment's changes,
        extrapolated); ``tol``: this increment's tolerance, if not the model's own."""
        start, count = time.perf_counter(), self.op.products
        try:
            return self._increment(state, b, Q, guess, self.tol if tol is None else tol)
        finally:
            self.stats["tangential_seconds"] += time.perf_counter() - start
            self.stats["tangential_products"] += self.op.products - count
            self.stats["increments"] += 1

    def _increment(self, state, b, Q, guess, tol):
        n, d, ks, c = self.nodes, self.dims, self.k_support, self.c
        scale = self._force_scale
        tolF = tol * self._tolerance_scale()
        contact = b > 1e-10 * scale
        s0 = state.v.reshape(n, d)
        if guess is not None:
            # the start: this increment's changes in the previous cycle (exact once the
            # cycles repeat, so a converging steady state costs less and less per cycle)
            dF0, dd0, side0, CdF0 = guess
        elif np.any(state.F != state.dF):
            # else the last increment's changes, extrapolated (unless that one started from
            # the virgin contact: its change is a load applied at once, not a trend)
            dF0, dd0, side0, CdF0 = state.dF, state.ddelta, state.side, state.CdF
        else:
            dF0, dd0, side0, CdF0 = 0.0, 0.0, state.side, 0.0
        # no product: C is linear. The start may lie off the limits, or carry forces on nodes
        # that left the contact: the first step puts them right
        F = (state.F + dF0).reshape(n, d)
        delta = state.delta + dd0
        CF = state.CF + CdF0
        Qv = np.zeros(d)
        Qv[0] = Q
        updates = PatternUpdate(contact) if d == 1 else None
        up = dn = None
        restarted = loose = fresh = changed = False
        close = 0             # damped steps begun within ten times the tolerance
        # d = 1: Murty's rule changes one node per iteration, so allow one per node
        limit = _MAX_NEWTON + (int(contact.sum()) if d == 1 else 0)
        eq_tol = tolF * max(1, int(contact.sum()))
        ev = None             # d = 2: the residual at the iterate, if the line search has it
        damped = d == 2       # d = 1 turns to the damped steps if its patterns stall
        for it in range(limit):
            if not damped:
                ds = delta + CF - s0
                z = F - ds / c
                eq = _total(F) - ks * delta + Qv
                # the primal-dual active-set pattern, with Murty's rule once one repeats
                zz = z[:, 0]
                band = tolF + 64 * _EPS * (b + np.abs(F[:, 0]))
                if up is None:      # the previous increment's pattern, where still in contact,
                    # and (unless restarted) the nodes the extrapolated forces put beyond
                    side = state.side if restarted else side0
                    warm = (contact & (side > 0), contact & (side < 0))
                    up, dn = warm if restarted else updates.first(zz, -b - band, b + band,
                                                                  warm)
                    fresh = True
                else:
                    nxt = updates.next(zz, -b - band, b + band, up, dn)
                    if nxt is None and not loose:
                        break
                    fresh = nxt is not None     # else: a loose step's pattern repeats
                    if fresh:
                        up, dn = nxt
                        changed = True
                    if it == _RESTART and not restarted:
                        # a poor start (a large extrapolated change) can send the pattern
                        # astray: restart once from the previous increment's forces and
                        # pattern, the safe start
                        F, delta, CF = self._safe_start(state, b, contact)
                        updates = PatternUpdate(contact)
                        up, restarted = None, True
                        continue
                slip = up | dn
                zn = np.abs(zz)
                worst = float(np.max(np.abs(F[:, 0] - np.clip(zz, -b, b))[contact],
                                     initial=0.0))
                z = np.where(up, 1.0, -1.0)[:, None]              # the slip nodes' sides
                if updates.stats["single_changes"] > _SINGLE_MAX:
                    # the patterns stall (a large increment on a fine grid: thousands of
                    # nodes change state, and Murty's rule changes one per iteration): the
                    # damped semismooth Newton steps of d = 2, on intervals, from the previous
                    # increment's forces. From the stalled iterate (a wrong pattern, loosely
                    # solved) the line search crawled: 4153 Newton steps against 171 on grid
                    # 120 with 8 steps per cycle, the same W
                    damped = True
                    ev = None
                    F, delta, CF = self._safe_start(state, b, contact)
                    self.stats["stalled"] += 1
            if damped:
                if ev is None:
                    ev = self._natural(F, CF, delta, s0, b, contact, Qv)
                ds, z, zn, slip, worst, merit, eq = ev
                ev = None
                if worst <= tolF and float(np.max(np.abs(eq))) <= eq_tol:
                    break
                if it == 2 * _RESTART and not restarted:      # as for d = 1 below
                    F, delta, CF = self._safe_start(state, b, contact)
                    restarted = True
                    continue
            if ks <= 0.0 and np.any(contact) and not np.any(contact & ~slip):
                # an iterate with every node slipping has no equilibrium: unless the load
                # exceeds every limit (gross sliding), the nodes nearest to sticking stick,
                # as many as can carry what the others' slip forces leave of the load
                total = float(b[contact].sum())
                if abs(Q) > total * (1.0 + 1e-12):
                    raise SolverError(f"half-space: |Q| = {abs(Q):.6g} exceeds the sum of "
                                      f"the friction limits {total:.6g} (gross sliding)",
                                      backend="halfspace", status="gross_sliding")
                stuck = _nearest_to_sticking(z, zn, b, contact, Qv)
                slip[stuck] = False
                if d == 1:
                    up[stuck] = dn[stuck] = False
            self.stats["newton"] += 1
            # d = 1: a step whose pattern is new is solved loosely (its answer only says
            # which pattern comes next), once a pattern repeats to full accuracy; the first
            # pattern too, unless the last increment's first pattern was its answer
            loose = (not damped and fresh and _ETA1 * worst > 0.1 * tolF
                     and (it > 0 or not self._first_right))
            # the damped steps' linear solves stop at _CG_TOL of the tolerance; where a step
            # that began near it did not end the increment (the natural map's residual can
            # then hover about the tolerance), the next ones stop ten times lower each
            frac = _CG_TOL
            if damped and worst <= 10.0 * tolF:
                frac = max(_CG_TOL * 0.1 ** close, 1e-3)
                close += 1
            dF, dd, CdF = self._newton(F, ds, z, zn, b, contact, slip, eq, worst, tolF,
                                       _ETA1 if loose else (_ETA if damped else None), frac)
            if not damped:
                F += dF
                CF += CdF
                delta = delta + dd
            else:
                F, CF, delta, ev = self._step(merit, F, CF, delta, dF, CdF, dd, s0, b,
                                              contact, Qv)
        else:
            total = float(b[contact].sum())
            near = (f"; |Q| is {abs(Q) / total:.6f} of the sum of the friction limits, so "
                    f"close to gross sliding that the stick zone spans about one element: "
                    f"refine the grid or lower Q" if ks <= 0.0 and total > 0.0
                    and abs(Q) >= 0.999 * (1.0 - 1e-9) * total else "")
            raise SolverError(f"half-space tangential increment: residual {worst:.3g} above "
                              f"{tolF:.3g} after {limit} Newton iterations{near}",
                              backend="halfspace", status="max_iter")
        if d == 1:
            self._first_right = not changed
            if damped:
                up, dn = slip & (z[:, 0] > 0.0), slip & (z[:, 0] < 0.0)
        F_end = F.ravel().copy()
        _project(F, b)
        stick = contact & ~slip
        ds[stick] = 0.0
        v = s0 + ds
        F_flat = F.ravel()
        side = np.zeros(n, dtype=np.int8)
        if d == 1:
            side[up] = 1
            side[dn] = -1
        new = _Tangential(v.ravel(), delta, F_end, F_end - state.F, delta - state.delta, side,
                          CF, CF - state.CF)
        return new, F_flat, ds.ravel()

    def _tolerance_scale(self) -> float:
        """The increments' force scale: the largest limit, or, if smaller, the force that moves
        a node by the loads' displacement scale (the cycle criterion's), so an increment's
        error c·r stays below the criterion's tolerance however small the tangential load (at
        Q1 = 1e-4 μP0 the cycles never repeated: their change hovered at the increments'
        errors). From the current loads (a map changes Q between points)."""
        u = self.scales()[0]
        return min(self._force_scale, u / self.c) if u > 0.0 else self._force_scale

    def _safe_start(self, state, b, contact):
        """The previous increment's forces and rigid displacement (no extrapolation)."""
        F = state.F.reshape(self.nodes, self.dims).copy()
        F[~contact] = 0.0
        _project(F, b)
        return F, state.delta.copy(), self.compliance(F)

    def _natural(self, F, CF, delta, s0, b, contact, Qv):
        """d = 2 (and d = 1 once its patterns stall): the natural map's residual at ``(F, CF =
        C F, δ)`` (``contact``: the nodes in contact): ``(Δs, z, |z|, slipping, its largest
        component, the line search's merit |F - proj(z)|² + |equilibrium|², the
        equilibrium)`` with ``z = F - Δs/c``."""
        ds = CF + delta
        ds -= s0
        z = ds / -self.c
        z += F
        zn = row_norms(z) if self.dims == 2 else np.abs(z[:, 0])
        slip = zn > b
        slip &= contact
        scale = contact.astype(float)
        np.divide(b, zn, out=scale, where=slip)
        R = z * scale[:, None]
        np.subtract(F, R, out=R)
        eq = _total(F)
        if self.k_support:
            eq -= self.k_support * delta
        eq += Qv
        return (ds, z, zn, slip, float(np.max(np.abs(R), initial=0.0)),
                float(np.vdot(R, R) + eq @ eq), eq)

    def _step(self, m0, F, CF, delta, dF, CdF, dd, s0, b, contact, Qv):
        """d = 2 (and d = 1 once its patterns stall): the Newton step, its length halved from
        1 until the merit (``m0`` at the start) decreases (products are linear: ``C(F + α ΔF)
        = CF + α CΔF``, so a trial costs no FFT): ``(F, CF, δ)`` there and :meth:`_natural`
        of it."""
        alpha = 1.0
        for _ in range(12):
            trial = F + alpha * dF, CF + alpha * CdF, delta + alpha * dd
            ev = self._natural(*trial, s0, b, contact, Qv)
            if ev[5] <= (1.0 - 1e-4 * alpha) * m0:
                break
            alpha *= 0.5
        return (*trial, ev)

    def _newton(self, F, ds, z, zn, b, contact, slip, eq, worst, tolF, eta=None,
                frac=_CG_TOL):
        """One semismooth Newton step (module docstring): ``(ΔF, Δδ, C ΔF)``. For d = 2
        (:meth:`_newton2`) the linear solve is inexact while the residual ``worst`` is large
        (to ``1e-2`` of it: the slip directions are corrected by the next step anyway); for
        d = 1 it is to a tenth of the tolerance (``_CG_TOL1``), which ends the iteration when
        the pattern is right."""
        if self.dims == 2:
            return self._newton2(F, ds, z, zn, b, contact, slip, eq, worst, tolF, eta, frac)
        n, ks, c = self.nodes, self.k_support, self.c
        stick = np.flatnonzero(contact & ~slip)
        L = np.flatnonzero(slip)
        known = np.where(contact[:, None], 0.0, -F)          # off the contact: no force
        known[L, 0] = np.sign(z[L, 0]) * b[L] - F[L, 0]
        space = _Space(stick, self._pos, self.op)
        rhs = -ds[stick, 0]
        if space.size == 0:
            if ks <= 0.0:
                _every_node_slips()
            return known, (eq + _total(known)) / ks, self.compliance(known)
        cons = -(eq + _total(known))
        if ks > 0.0:
            x0 = np.zeros(space.size)
        else:
            x0 = np.full(space.size, float(cons[0]) / space.size)     # B = 1ᵀ: B⁺ cons
        # the known forces and the start in one product (linearity); the residual from it
        h2 = self.h ** 2
        N = self.N
        if np.any(known) or np.any(x0):
            start = self._pad(known)
            space.add(start, x0)
            first = self.op.padded("tangential", start, 1.0 / h2)
            res = rhs - space.restrict(first)
            total = self.op.view(first)[:N, :N].copy()
        else:
            res = rhs.copy()
            total = np.zeros((N, N, 1))
        # C of the step on the grid's nodes, summed from the products (the padded arrays'
        # corner: the rest is the wrap-around)
        acc = {"last": None}

        def M(x):
            acc["last"] = self.op.padded("tangential", space.embed(x), 1.0 / h2)
            return space.restrict(acc["last"])

        def step(alpha):
            np.add(total, alpha * self.op.view(acc["last"])[:N, :N], out=total)

        def pre(r):
            return space.restrict(self.op.padded("precondition", space.embed(r), h2))

        tol = (_CG_TOL1 if eta is None else frac) * c * tolF
        if eta is not None:
            tol = max(tol, eta * c * worst)
        if ks > 0.0:
            x, _ = _cg(lambda y: M(y) + y.sum() / ks, None, x0, None, pre, tol, self.stats,
                       step, res=res + float(cons[0]) / ks)
            dd = (np.array([x.sum()]) - cons) / ks
        else:

            def project(r):
                return r - r.mean()

            x, res = _cg(M, None, x0, project, pre, tol, self.stats, step, res=res)
            dd = np.array([res.sum() / space.size])
        return space.nodes(x, known), dd, total.reshape(n, 1)

    def _newton2(self, F, ds, z, zn, b, contact, slip, eq, worst, tolF, eta, frac):
        """d = 2: the Newton step of :meth:`_newton`, each node's force (and slip) one complex
        number x + i y, as in the FFT's padded layout. The unknowns: the sticking nodes'
        forces, and each slipping node's force along the tangent τ = i e of its circle (e its
        slip direction), held as t τ; the operator there adds the diagonal term
        ``c (1 − β)/β`` (β = b/|z|) to the τ-component of C's. The conjugate gradients see
        the unknowns as the floats of those complex numbers: their inner product is the real
        one, and a slipping node's two floats t τ_x, t τ_y carry the length t. The
        equilibrium's constraint B sums the forces: ``B u = Σ u`` (complex), and ``Bᵀ λ`` is λ
        on the sticking nodes and ``τ Re(τ̄ λ)`` on the slipping ones."""
        n, ks, c, N = self.nodes, self.k_support, self.c, self.N
        op = self.op
        Fc, zc, dsc = _complex(F), _complex(z), _complex(ds)
        stick = np.flatnonzero(contact & ~slip)
        L = np.flatnonzero(slip)
        ns = stick.size
        size = ns + L.size
        known = np.where(contact, 0.0, -Fc)                  # off the contact: no force
        zL = zn[L]
        e = zc[L] / zL                                       # the slip directions
        FL = Fc[L]
        known[L] = e * (b[L] - (e.conjugate() * FL).real)    # Re(ē F): F's part along e
        if size == 0:
            if ks <= 0.0:
                _every_node_slips()
            kn = _floats(known, n)
            return kn, (eq + _total(kn)) / ks, self.compliance(kn)
        tau = 1j * e                                         # the tangents
        taub = tau.conjugate()
        tx, ty = tau.real, tau.imag
        beta = b[L] / zL
        tdiag = c * (1.0 - beta) / beta
        idx = np.concatenate([self._cpos[stick], self._cpos[L]])
        rhs = np.empty(size, dtype=complex)
        rhs[:ns] = -dsc[stick]
        rhs[ns:] = tau * ((-c / beta) * (taub * FL).real)
        ksum = known.sum()
        cons = -(eq + np.array([ksum.real, ksum.imag]))
        # B Bᵀ: ns I plus the tangents' outer products
        BBt = np.array([[ns + tx @ tx, tx @ ty], [tx @ ty, ns + ty @ ty]])

        def bt(lam):
            """Bᵀ λ (λ: the two floats of a force sum) as the unknowns' floats."""
            out = np.empty(size, dtype=complex)
            out[:ns] = complex(lam[0], lam[1])
            out[ns:] = tau * (tx * lam[0] + ty * lam[1])
            return out.view(float)

        def bsum(r):                                         # B r: the force sums
            t = r.view(complex).sum()
            return np.array([t.real, t.imag])

        if ks > 0.0:
            x0 = np.zeros(2 * size)
        else:
            if _condition(BBt) > 1e12:
                raise SolverError("half-space: the sticking nodes cannot carry the load in "
                                  "every direction (gross sliding)", backend="halfspace",
                                  status="gross_sliding")
            Winv = _inverse(BBt)
            x0 = bt(Winv @ cons)                             # Bᵀ (B Bᵀ)⁻¹ cons
        h2 = self.h ** 2
        buf = op.empty()
        flat = buf.reshape(-1)

        def restrict(full, scale=None):
            """The unknowns' components of a padded array (the slipping nodes' along τ)."""
            w = full.reshape(-1)[idx]
            t = (taub * w[ns:]).real
            if scale is not None:
                t *= scale
            w[ns:] = tau * t
            return w

        # the known forces and the start in one product (linearity); the residual from it
        if x0.any() or known.any():
            buf[:N, :N] = known.reshape(N, N)
            u0 = x0.view(complex)
            flat[idx] += u0
            first = op.padded("tangential", buf, 1.0 / h2)
            buf[:N, :N] = 0.0
            res = rhs - restrict(first)
            res[ns:] -= tdiag * u0[ns:]
            total = first[:N, :N].copy()
        else:
            res = rhs.copy()
            total = np.zeros((N, N), dtype=complex)
        # C of the step on the grid's nodes, summed from the products (the padded arrays'
        # corner: the rest is the wrap-around)
        last = None

        def M(x):
            nonlocal last
            u = x.view(complex)
            flat[idx] = u
            last = op.padded("tangential", buf, 1.0 / h2)
            w = restrict(last)
            w[ns:] += tdiag * u[ns:]
            return w.view(float)

        def step(alpha):
            np.add(total, alpha * last[:N, :N], out=total)

        # the slipping nodes' unknowns carry the diagonal term besides C (the operator there
        # is about c + tdiag, where C's inverse assumes c): the preconditioner scaled
        # symmetrically by sqrt(c / (c + tdiag)) on those (M-D, grid 40: 21432 products to
        # 18894, the same cycles)
        wL = np.sqrt(c / (c + tdiag))
        weights = np.concatenate([np.ones(ns), wL])

        def pre(r):
            flat[idx] = r.view(complex) * weights
            return restrict(op.padded("precondition", buf, h2), wL).view(float)

        tol = frac * c * tolF
        tol = max(tol, (_ETA if eta is None else eta) * c * worst)
        if ks > 0.0:
            x, _ = _cg(lambda y: M(y) + bt(bsum(y) / ks), None, x0, None, pre, tol,
                       self.stats, step, res=res.view(float) + bt(cons / ks))
            dd = (bsum(x) - cons) / ks
        else:

            def project(r):
                return r - bt(Winv @ bsum(r))

            x, res = _cg(M, None, x0, project, pre, tol, self.stats, step,
                         res=res.view(float))
            dd = Winv @ bsum(res)
        u = x.view(complex)
        dF = known.copy()
        dF[stick] += u[:ns]
        dF[L] += u[ns:]
        return _floats(dF, n), dd, _floats(total.reshape(-1), n)


def _complex(X):
    """Node-major ``(n, 2)`` floats as n complex numbers x + i y (a view where X is
    contiguous)."""
    return np.ascontiguousarray(X).view(complex)[:, 0]


def _floats(Z, n):
    """n complex numbers as node-major ``(n, 2)`` floats (a view)."""
    return Z.view(float).reshape(n, 2)


def _every_node_slips():
    raise SolverError("half-space: every node in contact slips or is separated under pure "
                      "load control (gross sliding)", backend="halfspace",
                      status="gross_sliding")


def _nearest_to_sticking(z, zn, b, contact, Qv):
    """For an iterate with every node in contact slipping (its forces ``b z/|z|``) under pure
    load control: the nodes to stick, those nearest to sticking (the smallest ``|z|/b``),
    the fewest whose limits add up to what the other nodes' forces leave of the load (so
    the Newton step can balance it within their limits; one node alone, the old rule, made
    the line search crawl on a large increment: 2808 Newton steps on grid 96, 8 steps per
    cycle)."""
    inside = np.flatnonzero(contact)
    order = inside[np.argsort(zn[inside] / b[inside], kind="stable")]
    e = np.sign(z[order]) if z.shape[1] == 1 else z[order] / zn[order, None]
    pull = b[order, None] * e                       # each node's force while it slips
    # the load left to the stuck nodes with the first k + 1 of the order stuck
    left = Qv + pull.sum(axis=0) - np.cumsum(pull, axis=0)
    need = np.sqrt(np.einsum("ij,ij->i", left, left))
    k = int(np.argmax(np.cumsum(b[order]) >= need * (1.0 - 1e-12)))
    return order[: k + 1]


def _condition(A):
    """The condition number of a symmetric positive semi-definite 1 x 1 or 2 x 2 matrix
    (inf when singular)."""
    if A.shape[0] == 1:
        return 1.0 if A[0, 0] > 0.0 else math.inf
    m, r = 0.5 * (A[0, 0] + A[1, 1]), math.hypot(0.5 * (A[0, 0] - A[1, 1]), A[0, 1])
    return (m + r) / (m - r) if m - r > 0.0 else math.inf


def _inverse(A):
    """The inverse of a 1 x 1 or 2 x 2 matrix (closed form)."""
    if A.shape[0] == 1:
        return 1.0 / A
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    return np.array([[A[1, 1], -A[0, 1]], [-A[1, 0], A[0, 0]]]) / det


class _Space:
    """d = 1: the unknowns of a Newton step, the sticking nodes' forces. They live in the FFT's
    padded layout (``op.empty``; ``pos``: each node's entry in it): ``embed`` puts them in a
    padded array (zero elsewhere), ``add`` adds them to one, ``restrict`` takes them out of
    one, and ``nodes`` gives them as node-major forces."""

    def __init__(self, stick, pos, op):
        self.stick, self.op = stick, op
        self.idx = pos[stick]
        self.size = stick.size
        self.buf = op.empty()
        self.flat = self.buf.reshape(-1)

    def embed(self, x):
        """x in the space's own padded array (its other entries stay zero)."""
        self.flat[self.idx] = x
        return self.buf

    def add(self, buf, x):
        """``buf += embed(x)``, in place (a padded array)."""
        buf.reshape(-1)[self.idx] += x

    def restrict(self, full):
        """The unknowns' components of a padded array."""
        return full.reshape(-1).take(self.idx)

    def nodes(self, x, base):
        """``base`` (node-major ``(n, 1)``) plus the unknowns x, a new array."""
        out = base.copy()
        out[self.stick, 0] += x
        return out


def _project(F, b):
    """Forces onto their discs (d = 1: the interval), in place."""
    if F.shape[1] == 1:
        np.clip(F[:, 0], -b, b, out=F[:, 0])
        return
    norm = row_norms(F)
    scale = np.ones_like(norm)
    np.divide(b, norm, out=scale, where=norm > b)
    F *= scale[:, None]


def _total(X):
    """The column sums of an ``(n, d)`` array (a product with ones: ``sum(axis=0)`` of a
    narrow array is several times slower)."""
    return np.ones(X.shape[0]) @ X


def _cg(M, g, x, project, pre, tol, stats, step=None, max_iter=None, res=None):
    """Preconditioned conjugate gradients for ``M x = g`` from x (on the null space of the
    constraint when ``project`` is given: the preconditioner is then ``Π pre Π``), until the
    (projected) residual is below ``tol`` everywhere. Returns x and the unprojected residual
    ``g - M x`` (whose part off the null space gives the constraint's multiplier). ``step(α)``
    is told each multiple of the last product of M added to x (1 for the start), so the
    caller can sum the products into ``C x`` without one more. ``res``: the residual ``g - M
    x`` at the start, if the caller has it (g is then not needed)."""
    if res is not None:
        pass
    elif np.any(x):
        res = g - M(x)
        if step is not None:
            step(1.0)
    else:
        res = g.copy()
    r = res if project is None else project(res)
    if float(np.max(np.abs(r))) <= tol:
        return x, res
    z = pre(r) if project is None else project(pre(r))
    p = z.copy()
    rz = float(r @ z)
    limit = max_iter or max(200, 4 * r.size)
    for _ in range(limit):
        stats["cg"] += 1
        Mp = M(p)
        alpha = rz / float(p @ Mp)
        if step is not None:
            step(alpha)
        x = x + alpha * p
        res = res - alpha * Mp
        r = res if project is None else project(res)
        if float(np.max(np.abs(r))) <= tol:
            return x, res
        z = pre(r) if project is None else project(pre(r))
        rz_new = float(r @ z)
        p = z + (rz_new / rz) * p
        rz = rz_new
    raise SolverError(f"half-space: conjugate gradients did not reach {tol:.3g} in {limit} "
                      f"iterations", backend="halfspace", status="max_iter")
