r"""The frictionless normal problem of a boundary-element grid along its path of contact sets, and
a contact under a prescribed normal approach (issue 39: the normal side of a displacement-driven
contact given as a normal displacement, not a load).

On a grid with a dense influence matrix A (displacement per unit pressure), gap ``h`` at zero
approach and element area, the frictionless contact under the approach d has pressures
``p >= 0`` and gaps ``g = h - d + A p >= 0`` with ``p g = 0``. With the contact set S fixed the
pressures are affine in d (``A_SS p_S = d 1 - h_S``), so the load ``P = area Σ p`` is affine in
d too: ``P = area (d Z - Y)`` with ``Z = 1ᵀ A_SS⁻¹ 1`` and ``Y = 1ᵀ A_SS⁻¹ h_S``; the set
changes where an outside element's gap, affine in d, reaches zero. Following the sets from the
first touch (:func:`contact_sets`) gives, exactly for the discrete problem and assuming the set
only grows with the approach (a convex surface):

* each element's **entry load** (:func:`entry_loads`, the transitions of the models' normal
  reactions), and
* the **load-approach relation** ``P(d)``, piecewise linear with a breakpoint at each change of
  the set (:class:`ApproachTable`).

With similar materials the normal problem does not see the shear, and the frictionless
problem's load and approach determine each other one to one, so a contact under a prescribed
approach ``d(t)`` is the same contact under the load ``P(d(t))``
(:func:`approach_load`), 0 where the bodies are apart. ``HalfPlaneCylinder.under_approach``
and ``HalfSpace.under_approach`` build their models so.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _checks
from ...errors import InputError
from ...linalg import DenseBlock
from ..load_base import Periodic

#: most elements for the dense influence matrix of the exact entry loads and approach table
DENSE_MAX = 2000

__all__ = [
    "contact_sets",
    "entry_loads",
    "ApproachTable",
    "approach_load",
    "prescribed_approach",
    "halfspace_under_approach",
    "DENSE_MAX",
]


def contact_sets(A: np.ndarray, h: np.ndarray, area: float):
    """The contact sets of the grid as the approach grows from the first touch (module
    docstring).

    Parameters
    ----------
    A : ndarray
        The dense influence matrix ``(N, N)`` (displacement per unit pressure).
    h : ndarray
        The gap at zero approach ``(N,)``.
    area : float
        The element area (width in the plane).

    Yields
    ------
    tuple
        ``(d_next, Z, Y, new)``: the approach at which the current set ends, the set's load
        coefficients (``P = area (d Z - Y)`` on it) and the elements that enter at ``d_next``;
        the first tuple's set is the elements of the lowest gap. The last tuple has ``d_next =
        inf`` (no element left to enter) and ``new`` empty.
    """
    h = np.asarray(h, dtype=float).ravel()
    N = h.size
    S = np.flatnonzero(h <= h.min() + 1e-14 * (np.abs(h).max() + 1e-300))
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
            yield d_next, Z, Y, np.array([], dtype=int)
            return
        new = np.flatnonzero(d_star <= d_next + 1e-12 * abs(d_next))
        yield d_next, Z, Y, new
        P = (d_next * Z - Y) * area
        S = np.union1d(S, new)
    yield np.inf, Z, Y, np.array([], dtype=int)  # pragma: no cover - every element entered


def entry_loads(A: np.ndarray, h: np.ndarray, area: float, P_max: float) -> np.ndarray:
    """Per element of a boundary-element grid, the normal load at which it comes into contact
    (:func:`contact_sets`; elements that enter together, as symmetric ones do, are added
    together).

    Parameters
    ----------
    A, h, area
        As for :func:`contact_sets`.
    P_max : float
        The largest load of interest.

    Returns
    -------
    ndarray
        ``(N,)`` loads: 0 for the first set, inf for the elements not in contact below
        ``P_max``.
    """
    h = np.asarray(h, dtype=float).ravel()
    levels = np.full(h.size, np.inf)
    levels[h <= h.min() + 1e-14 * (np.abs(h).max() + 1e-300)] = 0.0
    for d_next, Z, Y, new in contact_sets(A, h, area):
        if not np.isfinite(d_next):
            break
        P = (d_next * Z - Y) * area
        if P > P_max:
            break
        levels[new] = P
    return levels


class ApproachTable:
    """The load-approach relation ``P(d)`` of a grid, exact for the discrete problem (module
    docstring): piecewise linear through the breakpoints where the contact set changes.

    Parameters
    ----------
    A, h, area
        As for :func:`contact_sets`.
    d_max : float
        The largest approach of interest (> the first touch); the last set's line reaches it.

    Attributes
    ----------
    d, P : ndarray
        The breakpoints: approaches (increasing, from the first touch ``min h``) and loads
        (from 0).
    """

    def __init__(self, A, h, area: float, d_max: float) -> None:
        h = np.asarray(h, dtype=float).ravel()
        d, P = [float(h.min())], [0.0]
        for d_next, Z, Y, _ in contact_sets(A, h, area):
            end = min(d_next, float(d_max))
            if end > d[-1]:
                d.append(end)
                P.append(float((end * Z - Y) * area))
            if d_next >= d_max:
                break
        self.d, self.P = np.array(d), np.array(P)
        self.P[0] = 0.0

    def __call__(self, d) -> np.ndarray:
        """The load at the approaches d (0 where ``d`` is below the first touch: apart).

        Parameters
        ----------
        d : float or array_like
            Approaches (at most the table's ``d_max``).

        Returns
        -------
        ndarray
            The loads, the shape of ``d``.
        """
        d = np.asarray(d, dtype=float)
        return np.where(d <= self.d[0], 0.0, np.interp(d, self.d, self.P))

    def slope(self, d) -> np.ndarray:
        """``dP/dd`` at the approaches d (the normal contact stiffness; 0 apart).

        Parameters
        ----------
        d : float or array_like
            Approaches.

        Returns
        -------
        ndarray
            The slopes, the shape of ``d``.
        """
        d = np.asarray(d, dtype=float)
        k = np.diff(self.P) / np.diff(self.d)
        i = np.clip(np.searchsorted(self.d, d, side="right") - 1, 0, k.size - 1)
        return np.where(d <= self.d[0], 0.0, k[i])


def approach_load(table: ApproachTable, approach) -> Periodic | float:
    """The normal load ``P(t) = table(d(t))`` of a prescribed approach ``d(t)`` (a float for a
    constant approach), with its derivative ``P'(d) d'(t)``.

    Parameters
    ----------
    table : ApproachTable
        The grid's load-approach relation.
    approach : Load
        The approach ``d(t)``.

    Returns
    -------
    Periodic or float
        The load.
    """
    if approach.is_constant:
        return float(table(approach.mean))
    return Periodic(
        lambda t: table(approach(np.asarray(t, dtype=float))),
        approach.period,
        derivative=lambda t: table.slope(approach(t)) * np.asarray(approach.derivative(t)),
    )


def prescribed_approach(approach):
    """The approach ``d(t)`` as a load, checked, and its largest value.

    Parameters
    ----------
    approach : Load or float
        The approach (its mean > 0: the bodies in contact on average).

    Returns
    -------
    d : Load
        The approach.
    d_max : float
        Its largest value over the cycle.

    Raises
    ------
    InputError
        Not a load or a finite number, or a mean that is not > 0 (named ``approach``).
    """
    from .base import load

    d = load("approach", approach)
    if not d.mean > 0:
        raise InputError("approach", f"its mean must be > 0 (in contact), got {d.mean!r}")
    d_max = float(d.mean) if d.is_constant else max(float(d.mean), d.extrema()[1])
    return d, d_max


def halfspace_under_approach(
    cls,
    E: float,
    nu: float,
    mu: float,
    approach,
    Q=0.0,
    *,
    R: float | None = None,
    grid: int = 40,
    heights=None,
    spacing: float | None = None,
    dims: int = 1,
    k_support: float = 0.0,
):
    """The half-space under a prescribed normal approach ``d(t)`` (measured from the first
    touch of the grid's surface, ``g0 - min g0``) instead of a normal load: its load is
    ``P(d(t))``, exact for the grid (:class:`ApproachTable`; the grid's dense influence matrix:
    at most 2000 elements), 0 where the bodies are apart. ``HalfSpace.under_approach``.

    Parameters
    ----------
    cls : type
        :class:`~lcpfric.model.continuum.halfspace.HalfSpace` (bound by the classmethod).
    E, nu, mu : float
        As for the constructor (identical bodies).
    approach : Load or float
        The approach ``d(t)`` (its mean > 0).
    Q : Load or float, optional
        The tangential load (unused when the tangential motion is prescribed).
    R : float, optional
        A sphere of effective radius R on a grid of ``grid`` elements across Hertz's contact
        diameter at the largest approach (``2 sqrt(R d_max)``), plus the margins of
        ``HalfSpace.sphere``; or
    heights, spacing : optional
        a surface on its grid, as for the constructor.
    grid : int, optional
        With ``R``: elements across the largest contact.
    dims, k_support : optional
        As for the constructor.

    Returns
    -------
    HalfSpace
        The model, its P a :class:`~lcpfric.model.loads.Periodic` load (with ``R``: the
        attributes ``R``, ``a_max`` and ``grid_across`` as from ``HalfSpace.sphere``).

    Raises
    ------
    InputError
        Both or neither of ``R`` and ``heights`` (named ``R``), more than 2000 elements
        (``grid``), an approach whose mean is not > 0, or as for the constructor.
    """
    from .closed_forms import moduli
    from .influence import Convolution

    d, d_max = prescribed_approach(approach)
    if (R is None) == (heights is None):
        raise InputError("R", "give R (a sphere) or heights and spacing (a surface), not both")
    Es = moduli(E, nu)["E*"]
    a_max = None
    if R is not None:
        R = _checks.positive("R", R)
        a_max = math.sqrt(R * d_max)
        g, N, spacing = cls._grid(grid, a_max)
        heights = (g[:, None] ** 2 + g[None, :] ** 2) / (2.0 * R)
    g0 = _checks.finite_array("heights", heights)
    h = _checks.positive("spacing", spacing)
    if g0.ndim != 2 or g0.shape[0] != g0.shape[1] or g0.shape[0] < 4:
        raise InputError("heights", f"must be a square 2-D array (N x N, N >= 4), got {g0.shape}")
    if g0.size > DENSE_MAX:
        raise InputError(
            "grid" if R is not None else "heights",
            f"the exact load-approach relation needs the dense influence matrix of {g0.size} "
            f"elements (at most {DENSE_MAX})",
        )
    op = Convolution(g0.shape[0], h, E, nu, 1)
    table = ApproachTable(op.dense("n"), g0 - g0.min(), h * h, d_max)
    P = approach_load(table, d)
    P0 = float(P.mean) if isinstance(P, Periodic) else float(P)
    options = {"heights": g0, "spacing": h, "dims": dims, "k_support": k_support}
    if R is None:
        return cls(E, nu, mu, P, Q, **options)
    a0 = (3.0 * P0 * R / (4.0 * Es)) ** (1.0 / 3.0)
    model = cls(E, nu, mu, P, Q, **options, _a0=a0, geometry="sphere")
    model.R, model.a_max, model.grid_across = R, a_max, grid
    return model
