r"""The Hertz contact (sphere) by the method of dimensionality reduction (Popov and Heß), d = 1.

Two identical elastic spheres (effective radius R, each of modulus E and ratio ν; composite
moduli E*, G* of :func:`~lcpfric.contact.closed_forms.moduli`) under a normal load P(t) and a
tangential load Q(t) along one direction. The method of dimensionality reduction maps the 3-D
contact onto a row of independent springs on a rigid bar, the 1-D profile ``g(x) = x²/R``:

* **normal** (known before any tangential computation: the problems are uncoupled): at each
  instant the approach ``d = a²/R`` with the Hertz radius ``a = (3PR/(4E*))^(1/3)``; spring i
  on the cell ``[x_i - Δx/2, x_i + Δx/2]`` of ``[0, a_max]`` carries the normal force
  ``N_i = 2 E* ∫_cell max(0, d - x²/R) dx`` (the cell's exact share: ``Σ N_i = P`` exactly;
  the factor 2 counts the springs at ``±x``, which behave alike). ``P <= 0`` is complete
  separation;
* **tangential**: spring stiffness ``k_i = 2 G* Δx`` (so ``Σ k_i = 2 a G* = k_t0`` in full
  stick), spring force ``k_i (u - v_i)`` with ``v_i`` the slip of spring i and ``u`` the bar's
  displacement, ``|k_i (u - v_i)| <= μ N_i``; the bar is held by Q(t) and, in parallel with the
  contact, by a support of stiffness ``k_support`` (the structure that holds the body; 0 is
  pure load control): ``Σ_i k_i (u - v_i) + k_support u = Q``.

Within Mindlin's approximation this reproduces the 3-D contact (exactly when ν = 0): the 1-D
stick zone ``|x| < c`` is the 3-D stick radius, and the dissipation is the 3-D one.

The increment (no solver: a closed form serves)
-----------------------------------------------
The increment to ``t_{j+1}`` is problem (P) of the other backends, the maximum-dissipation
projection of the trial state, for this system: given the bar's displacement u the springs are
independent, and each one's answer is its return mapping ``F_i(u) = clip(k_i (v_i - u), -b_i,
b_i)``, ``b_i = μ N_i(t_{j+1})`` (lcpfric's sign: ``F_i = k_i (v_i - u)`` is the friction
force, and the slip opposes it). The bar's equilibrium ``h(u) = Σ F_i(u) - k_support u + Q = 0``
is one monotone piecewise-linear equation in u, solved exactly (:func:`bar_root`: a safeguarded
Newton iteration from the previous u, exact once a step keeps every spring on its side of its
breakpoints ``v_i ∓ b_i/k_i``; usually two or three O(n) passes); the rank-one coupling of the
springs through the bar is never formed as a matrix. With ``k_support = 0`` the equation has a
root only when ``|Q| <= μ P`` (else the whole contact slides): such loads are refused before
any work, naming the instants and the fix (a support stiffness).

The increments are the ``mdr-bar`` stepper's (:mod:`lcpfric.steppers.mdr_bar`); the cycles are
run by :func:`lcpfric.steady_state`.

Other axisymmetric profiles
---------------------------
``profile=`` replaces the sphere by any axisymmetric body ``z = f(r)``: :class:`PowerLaw`
(``f = c r^n``, in closed form: ``g = κ_n c |x|^n``, ``κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)``) or
:class:`Axisymmetric` (any ``f'``, the MDR transform ``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ``
by Gauss-Legendre quadrature). The contact radius at a load solves ``P = 2 E* (a g(a) -
∫_0^a g)``, the approach is ``d = g(a)``, the spring forces are the cells' exact shares of
``2 E* (d - g)`` as for the sphere.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ... import _checks
from ...errors import InputError
from .base import ContactModel
from .dissimilar import pair
from .profiles import Sphere

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from scipy.sparse.linalg import LinearOperator

    from ..loads import Load
    from .profiles import Axisymmetric, PowerLaw

__all__ = ["MDRSphere", "MAX_NODES"]

#: largest number of springs (the arrays are nodes x steps)
MAX_NODES = 200_000
#: fewest springs (elements) across the largest contact that resolve it
MIN_NODES = 10


class MDRSphere(ContactModel):
    """The Hertz contact of two identical spheres, by dimensionality reduction.

    See the module docstring.

    Parameters
    ----------
    R, E, nu, mu : float
        Effective radius, each body's Young's modulus and Poisson's ratio (``0 <= ν < 0.5``),
        friction coefficient. R may be None when a ``profile`` is given.
    P, Q : Load or float
        Normal and tangential loads (total forces); floats are constant loads. P(t) <= 0 is
        complete separation.
    k_support : float
        Tangential stiffness of the support in parallel with the contact (0: pure load
        control, where ``|Q| > μP`` at any instant is refused).
    nodes : int
        Springs on ``[0, a_max]``, a_max the largest contact radius over the cycle.
    profile : Sphere, PowerLaw, Axisymmetric or None, optional
        Another axisymmetric body in place of the sphere of radius R (module docstring): any
        object with the methods ``g(x)``, ``G(x)`` and ``radius(P, Estar)`` of
        :mod:`lcpfric.model.continuum.profiles`.
    E2, nu2 : float or None, optional
        A second body of another material (``E2 = inf``: rigid): accepted only where Dundurs' β
        is 0 (composite moduli, :func:`~lcpfric.model.continuum.dissimilar.pair`). For β ≠ 0
        the reduction has no consistent form: the pressure couples with the shear through a
        long-range kernel odd in x, the contact loses its axial symmetry under Q (the stick
        zone shifts, the pressure tilts) and even the normal loading slips radially (Spence),
        none of which independent springs on a bar can carry; use
        :class:`~lcpfric.model.continuum.halfspace.HalfSpace` (docs/validation.md).

    Attributes
    ----------
    R : float or None
        The effective radius.
    profile : Sphere, PowerLaw or Axisymmetric
        The body's 1-D profile.
    a_max, a0 : float
        The largest contact radius over the cycle, and the contact radius at P0.
    k_t0 : float
        The initial tangential stiffness at P0, ``2 a0 G*``.
    dx : float
        The springs' spacing, ``a_max / nodes``.
    x : (nodes,) ndarray
        The springs' positions (cell centres).
    k : (nodes,) ndarray
        The springs' tangential stiffnesses ``2 G* Δx``.

    Raises
    ------
    InputError
        A parameter out of range (:class:`~lcpfric.model.continuum.base.ContactModel`); no R
        and no profile; a profile that lacks ``g``, ``G`` or ``radius``; a second body with
        β ≠ 0 (named ``E2``, or ``nu2`` if only ν differs).
    """

    max_nodes = MAX_NODES
    min_nodes = MIN_NODES
    default_method = "mdr-bar"

    def __init__(
        self,
        R: float | None,
        E: float,
        nu: float,
        mu: float,
        P: Load | float,
        Q: Load | float,
        *,
        k_support: float = 0.0,
        nodes: int = 2000,
        profile: Sphere | PowerLaw | Axisymmetric | None = None,
        E2: float | None = None,
        nu2: float | None = None,
    ) -> None:
        super().__init__(E, nu, mu, P, Q, k_support, nodes)
        materials = pair(self.E, self.nu, E2, nu2)
        if materials is not None:
            if materials["beta"] != 0.0:
                raise InputError(
                    "nu2" if E2 == self.E else "E2",
                    f"the second body makes Dundurs' beta = {materials['beta']:.4g} (not 0): "
                    "the pressure then couples with the shear and the contact loses its axial "
                    "symmetry, which the MDR's independent springs cannot represent; use "
                    "HalfSpace.sphere(..., E2=..., nu2=...) (or rigid: E2=inf)",
                )
            self.moduli = materials
        self.R = None if R is None else _checks.positive("R", R)
        if profile is None:
            if self.R is None:
                raise InputError("R", "give the effective radius R, or a profile")
            profile = Sphere(self.R)
        for name in ("g", "G", "radius"):
            if not callable(getattr(profile, name, None)):
                raise InputError(
                    "profile", f"needs a method {name}() (see Sphere, PowerLaw, Axisymmetric)"
                )
        self.profile = profile
        Es = self.moduli["E*"]
        self.a_max = float(np.max(profile.radius(self.P_max, Es)))
        self.a0 = float(np.max(profile.radius(self.P0, Es)))
        self.k_t0 = 2.0 * self.a0 * self.moduli["G*"]
        self.dx = self.a_max / self.nodes
        self.x = (np.arange(self.nodes) + 0.5) * self.dx
        self.k = np.full(self.nodes, 2.0 * self.moduli["G*"] * self.dx)

    @classmethod
    def under_approach(
        cls, R: float | None, E: float, nu: float, mu: float, approach, Q=0.0, **options
    ) -> MDRSphere:
        """The sphere under a prescribed normal approach ``d(t)`` (a normal displacement)
        instead of a normal load: its load is ``P(t)``, the load whose approach is ``d(t)``
        (``2 E* (a g(a) - G(a))`` at the radius ``g(a) = d``, found by bisection to round-off),
        0 where ``d <= 0`` (the bodies apart: the contact separates, as a prescribed normal
        displacement makes it).

        Parameters
        ----------
        R, E, nu, mu : float
            As for the constructor.
        approach : Load or float
            The approach ``d(t)`` (its mean > 0: the bodies in contact on average).
        Q : Load or float, optional
            The tangential load (unused when the tangential motion is prescribed).
        **options
            The constructor's keywords (``nodes``, ``profile``, ``k_support``, ``E2``,
            ``nu2``).

        Returns
        -------
        MDRSphere
            The model, its P a :class:`~lcpfric.model.loads.Periodic` load of the approach's
            period.

        Raises
        ------
        InputError
            The constructor's, or an approach whose mean is not > 0 (named ``approach``).
        """
        from ..load_base import Periodic
        from .base import load

        d = load("approach", approach)
        if not d.mean > 0:
            raise InputError("approach", f"its mean must be > 0 (in contact), got {d.mean!r}")
        unit = cls(R, E, nu, mu, 1.0, 0.0, **{**options, "nodes": MIN_NODES})  # E*, profile

        def P(t):
            dt = np.asarray(d(np.asarray(t, dtype=float)), dtype=float)
            return unit.load_at_radius(_radius_at(unit.profile, np.maximum(dt, 0.0)))

        period = d.period if not d.is_constant else 1.0
        if d.is_constant:
            return cls(R, E, nu, mu, float(P(0.0)), Q, **options)
        return cls(R, E, nu, mu, Periodic(P, period), Q, **options)

    # -- the normal problem ---------------------------------------------------------------------
    def radius(self, t: ArrayLike) -> np.ndarray:
        """Contact radius a(t) (0 in separation): Hertz's for the sphere.

        Parameters
        ----------
        t : float or array_like
            Instants of the cycle.

        Returns
        -------
        ndarray
            a at each instant, the shape of ``t``.
        """
        P = np.maximum(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float), 0.0)
        return np.asarray(self.profile.radius(P, self.moduli["E*"]), dtype=float).reshape(P.shape)

    def approach(self, P: ArrayLike) -> float | np.ndarray:
        """The normal approach d = g(a(P)) (the C(P) of the Ciavarella-Jäger form).

        Parameters
        ----------
        P : float or array_like
            Normal loads.

        Returns
        -------
        float or ndarray
            d at each load, the shape of ``P`` (a float for a scalar).
        """
        P = np.asarray(P, dtype=float)
        d = np.asarray(self.profile.g(self.profile.radius(P, self.moduli["E*"])), dtype=float)
        return float(d.ravel()[0]) if P.ndim == 0 else d.reshape(P.shape)

    def normal_forces(self, t: ArrayLike) -> np.ndarray:
        """``(len(t), nodes)`` spring normal forces.

        Each cell's exact share of the pressure of the 1-D profile (their sum is P(t)).

        Parameters
        ----------
        t : float or array_like
            Instants of the cycle (a scalar counts as one).

        Returns
        -------
        ndarray
            The springs' normal forces N_i, ``(len(t), nodes)``.
        """
        a = self.radius(np.atleast_1d(t))[:, None]
        lo = self.x[None, :] - 0.5 * self.dx
        hi = np.minimum(self.x[None, :] + 0.5 * self.dx, a)
        d, G = self.profile.g(a), self.profile.G
        share = d * (hi - lo) - (G(np.maximum(hi, lo)) - G(lo))  # ∫_cell (d - g) dx
        return np.where(hi > lo, 2.0 * self.moduli["E*"] * share, 0.0)

    def tractions(self, F: ArrayLike) -> np.ndarray:
        """The 3-D shear traction at the spring positions (as radii) from spring forces F.

        The inverse MDR transform ``τ(r) = -(1/π) ∫_r^a q'(x) / √(x² - r²) dx`` of the line load
        ``q = F / (2 Δx)``, taken piecewise linear between the spring positions (flat at the
        centre, zero half a cell beyond the last spring), so that each piece integrates in
        closed form: ``∫ dx / √(x² - r²) = ln(x + √(x² - r²))``. lcpfric's force sign: the
        traction transmitted is ``-τ``; from the normal forces it gives the pressure.

        Parameters
        ----------
        F : (nodes,) array_like
            Spring forces.

        Returns
        -------
        ndarray
            τ at the radii ``x``, ``(nodes,)``.
        """
        q = np.append(np.asarray(F, dtype=float) / (2.0 * self.dx), 0.0)
        X = np.append(self.x, self.x[-1] + 0.5 * self.dx)
        slope = np.diff(q) / np.diff(X)  # on [X_k, X_k+1]
        r = self.x[:, None]

        def L(x):
            return np.log(x + np.sqrt(np.maximum(x * x - r * r, 0.0)))

        lo = np.maximum(X[None, :-1], r)
        hi = X[None, 1:]
        piece = np.where(hi > r, L(hi) - L(np.minimum(lo, hi)), 0.0)
        return -(piece @ slope) / math.pi

    # -- as an lcpfric system ---------------------------------------------------------------
    def load_at_radius(self, a: ArrayLike) -> np.ndarray:
        """The normal load whose contact radius is a: ``2 E* (a g(a) - ∫_0^a g)``.

        Parameters
        ----------
        a : float or array_like
            Contact radii.

        Returns
        -------
        ndarray
            The normal loads, the shape of ``a``.
        """
        a = np.asarray(a, dtype=float)
        return 2.0 * self.moduli["E*"] * (a * self.profile.g(a) - self.profile.G(a))

    def entry_loads(self) -> np.ndarray:
        """Per spring, the normal load at which it comes into contact.

        That is where the contact radius reaches its cell's inner edge.

        Returns
        -------
        ndarray
            ``(nodes,)`` loads.
        """
        return np.asarray(self.load_at_radius(self.x - 0.5 * self.dx), dtype=float)

    def springs(self) -> tuple[LinearOperator, np.ndarray, np.ndarray]:
        """The springs alone (the bar held fixed), for :meth:`ContactModel.system`.

        Returns
        -------
        compliance : LinearOperator
            ``diag(1/k)``.
        C_inv_ones : ndarray
            ``C⁻¹ 1 = k``, ``(nodes,)``.
        diagonal : ndarray
            The diagonal of C, ``1/k``.
        """
        from scipy.sparse.linalg import aslinearoperator
        import scipy.sparse as sp

        return aslinearoperator(sp.diags(1.0 / self.k)), self.k.copy(), 1.0 / self.k

    # -- the continuum model protocol (lcpfric.model.continuum.base) ---------------------------
    def normal_problem(self) -> ClosedFormNormal:
        """The normal problem in closed form (:class:`ClosedFormNormal`).

        Returns
        -------
        ClosedFormNormal
            Its ``solution(t)`` is ``(limits, sizes, stats)``: the friction limits
            ``μ N_i(t)``, the contact radius and no statistics.
        """
        return ClosedFormNormal(self)


class ClosedFormNormal:
    """The MDR sphere's normal problem: ``solution(t)`` is the friction limits ``μ N_i(t)``
    ``(len(t), nodes)``, the contact radius, and no statistics (closed form)."""

    def __init__(self, model):
        self.model = model

    def solution(self, t):
        m = self.model
        return m.mu * m.normal_forces(t), m.radius(t), {}


def _radius_at(profile, d: np.ndarray) -> np.ndarray:
    """The contact radius ``a`` with ``g(a) = d`` (g increasing from g(0) = 0), by bisection to
    round-off, vectorized; 0 where ``d <= 0``."""
    d = np.asarray(d, dtype=float)
    hi = np.ones_like(d)
    for _ in range(200):  # bracket: double until g(hi) >= d
        short = np.asarray(profile.g(hi), dtype=float) < d
        if not short.any():
            break
        hi = np.where(short, 2.0 * hi, hi)
    lo = np.zeros_like(d)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        below = np.asarray(profile.g(mid), dtype=float) < d
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return np.where(d > 0.0, 0.5 * (lo + hi), 0.0)
