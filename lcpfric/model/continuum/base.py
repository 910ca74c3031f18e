"""What every continuum contact model is: two identical elastic bodies (E, ν), friction μ, the
loads P(t) and Q(t) over one period, the support that holds the body, and its normal problem.

A model holds what the contact *is*: geometry, material, loads, support. It holds nothing that
changes during a solve (no statistics, no warm starts, no caches filled by a solve): the scene
(:func:`lcpfric.make_scene`) solves the normal problem once for the cycle's instants and keeps
the friction limits, and the stepper (``mdr-bar``, ``halfplane-pdas``, ``newton-cg``) carries
its own state from increment to increment.

The protocol a continuum model follows (every subclass implements it; :func:`lcpfric.make_scene`
and the steppers use nothing else):

``nodes``, ``dims``, ``x``
    the unknowns' nodes, the tangential directions (1 or 2), the nodes' positions;
``normal_problem()``
    a solver of the normal problem whose ``solution(t)`` is ``(limits, sizes, stats)``: the
    friction limits ``μ N_i(t)`` at the instants t (the normal problem, solved before any
    tangential computation: the problems are uncoupled), the contact size at each instant, and
    the normal solves' statistics; it may warm-start each instant from the last and remember
    the loads it solved (the model itself remembers nothing);
``load_scales(Q)``
    ``(displacement, force)`` scales of the loads with the tangential load Q, for the cycles'
    convergence measure (:func:`lcpfric.periodic.measure.cycle_change`);
``normalization()``
    ``(name, factor)`` with ``W_normalized = factor · W``;
``k_t0``
    the initial tangential stiffness at P0 (None for a plane contact);
``default_method``
    the registry name of the stepper that solves its increments.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ... import _checks
from ...errors import InputError
from ..loads import Harmonic, Load
from .closed_forms import moduli

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..system import ContactSystem

__all__ = ["ContactModel", "LevelNormal", "gross_sliding", "load"]


class ContactModel:
    """What every continuum model shares (the protocol of the module docstring).

    Two identical bodies (E, ν), friction μ, the loads P(t) and Q(t) (one period), the support
    stiffness and the number of nodes. Subclasses add the geometry and the normal problem.

    Parameters
    ----------
    E : float
        Each body's Young's modulus, > 0.
    nu : float
        Each body's Poisson's ratio, ``0 <= ν < 0.5``.
    mu : float
        Friction coefficient, > 0.
    P, Q : Load or float
        Normal and tangential loads; floats are constant loads. Their mean P0 must be > 0, and
        the two must share one period.
    k_support : float
        Tangential stiffness of the support in parallel with the contact, >= 0 (0: pure load
        control).
    nodes : int
        Number of nodes, from ``min_nodes`` to ``max_nodes``.

    Attributes
    ----------
    E, nu, mu, k_support : float
        As given.
    moduli : dict
        ``{"E*", "G*", "G", "eta"}`` (:func:`~lcpfric.model.continuum.closed_forms.moduli`).
    P, Q : Load
        The loads.
    period : float
        The loads' period (1.0 when neither varies).
    P0, P_max : float
        The mean normal load and the largest over the cycle (at least P0).
    nodes : int
        Number of nodes (the unknowns: ``nodes · dims`` tangential ones).
    dims : int
        Tangential directions per node.
    k_t0 : float or None
        The initial tangential stiffness at P0 (None for a plane contact).
    default_method : str
        The registry name of the stepper that solves its increments.

    Raises
    ------
    InputError
        A parameter out of range or not finite, a load that is neither a Load nor a number,
        P and Q of different periods, or P0 <= 0.
    """

    max_nodes = 200_000
    #: fewest nodes that resolve the contact (the springs or elements across it)
    min_nodes = 1
    dims = 1
    k_t0: float | None = None
    #: the driver's defaults (:func:`lcpfric.steady_state`)
    default_method = ""
    default_steps = 400
    default_max_cycles = 200
    default_placement = "uniform"
    #: what to do where no element slips (the driver's ResolutionWarning)
    refine_hint = "refine the grid"

    def __init__(
        self,
        E: float,
        nu: float,
        mu: float,
        P: Load | float,
        Q: Load | float,
        k_support: float,
        nodes: int,
    ) -> None:
        self.E = _checks.positive("E", E)
        self.mu = _checks.positive("mu", mu)
        self.moduli = moduli(self.E, nu)
        self.nu = float(nu)
        self.P, self.Q = load("P", P), load("Q", Q)
        periods = [ld.period for ld in (self.P, self.Q) if not ld.is_constant]
        if len(periods) == 2 and not math.isclose(periods[0], periods[1], rel_tol=1e-12):
            raise InputError("Q", f"P and Q must share one period; got {periods}")
        self.period = periods[0] if periods else 1.0
        self.k_support = _checks.nonnegative("k_support", k_support)
        self.nodes = _checks.positive_int("nodes", nodes)
        if self.nodes < self.min_nodes:
            raise InputError(
                "nodes",
                f"{self.nodes} nodes are too coarse to resolve the contact; give at least "
                f"{self.min_nodes}",
            )
        if self.nodes > self.max_nodes:
            raise InputError("nodes", f"must be at most {self.max_nodes}, got {self.nodes}")
        if not self.P.mean > 0:
            raise InputError("P", f"the mean normal load P0 must be > 0, got {self.P.mean!r}")
        self.P0 = float(self.P.mean)
        ts = np.linspace(0.0, self.period, 4097)
        self.P_max = float(max(np.max(self.P(ts)), self.P0))

    def normal_problem(self) -> Any:  # pragma: no cover - abstract
        """A solver of the normal problem (module docstring).

        Returns
        -------
        object
            An object whose ``solution(t)`` gives ``(limits, sizes, stats)``; each subclass
            returns its own.
        """
        raise NotImplementedError

    def normal_solution(self, t: ArrayLike) -> tuple[np.ndarray, np.ndarray, dict]:
        """``(limits, sizes, stats)`` at the instants t, by a new :meth:`normal_problem`.

        Parameters
        ----------
        t : float or array_like
            Instants of the cycle.

        Returns
        -------
        limits : ndarray
            The friction limits ``μ N_i`` of the nodes, ``(len(t), nodes)``.
        sizes : ndarray
            The contact size (radius or half-width) at each instant, ``(len(t),)``.
        stats : dict
            The normal solves' statistics (empty for a closed form).

        Raises
        ------
        SolverError
            An iterative normal problem failed
            (:class:`~lcpfric.model.continuum.halfplane.HalfPlaneCylinder`,
            :class:`~lcpfric.model.continuum.halfspace.HalfSpace`).
        """
        return self.normal_problem().solution(t)

    def load_scales(self, Q: Load) -> tuple[float, float]:
        """``(displacement, force)`` scales with the tangential load Q.

        The displacement scale is its amplitude (or mean, if constant) over the initial
        tangential stiffness, the force scale the largest friction limit μ P_max (for the
        cycles' convergence measure, :func:`lcpfric.periodic.measure.cycle_change`).

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
        return q / self.k_t0, self.mu * self.P_max

    def normalization(self) -> tuple[str, float]:
        """The normalized dissipation: ``W_normalized = factor · W``.

        Returns
        -------
        name : str
            Its formula, ``"W k_t0/(mu^2 P0^2)"``.
        factor : float
            ``k_t0 / (μ P0)²``.
        """
        return "W k_t0/(mu^2 P0^2)", self.k_t0 / (self.mu * self.P0) ** 2

    def with_support(self, k_support: float) -> ContactModel:
        """The same contact held by a support of stiffness ``k_support`` (a copy).

        Parameters
        ----------
        k_support : float
            Tangential stiffness of the support, >= 0 (0: pure load control).

        Returns
        -------
        ContactModel
            A shallow copy of this model (the same class) with the new support.

        Raises
        ------
        InputError
            ``k_support`` negative or not finite.
        """
        import copy

        out = copy.copy(self)
        out.k_support = _checks.nonnegative("k_support", k_support)
        return out

    # -- as an lcpfric system ---------------------------------------------------------------
    def normal_model(self) -> LevelNormal:
        """The nodes' normal forces as an lcpfric normal model.

        Node i is in contact while P(t) exceeds its entry load (``entry_loads()``).

        Returns
        -------
        LevelNormal
            A :class:`~lcpfric.model.normal.NormalModel` of the nodes.

        Raises
        ------
        InputError
            The model cannot give its entry loads
            (:class:`~lcpfric.model.continuum.halfspace.HalfSpace` beyond its dense limit).
        """
        return LevelNormal(self)

    def system(self) -> ContactSystem:
        """This contact as a matrix-free :class:`~lcpfric.model.ContactSystem`.

        For the discrete methods (:func:`lcpfric.model.continuum.bridge.contact_system`; needs
        ``k_support > 0``).

        Returns
        -------
        ContactSystem
            The nodes' slips as its unknowns, known by its compliance operator (the body on its
            support), with :meth:`normal_model` as its normal model.

        Raises
        ------
        InputError
            ``k_support`` is 0 (under pure load control the stiffness is singular), or the
            model cannot give its entry loads (:meth:`normal_model`).
        """
        from .bridge import contact_system

        return contact_system(self)


class LevelNormal:
    """A contact model's normal forces as an lcpfric normal model: node i is in contact while
    P(t) exceeds its entry load (``model.entry_loads()``); those crossings are the transitions,
    sampled on 4096 points per period and polished by Brent's method."""

    def __init__(self, model):
        self.model = model
        self.levels = np.asarray(model.entry_loads(), dtype=float)
        self.problem = model.normal_problem()  # warm-started from call to call

    @property
    def n(self) -> int:
        return self.model.nodes

    @property
    def period(self):
        return None if self.model.P.is_constant else self.model.period

    def reactions(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        limits = self.problem.solution(t.ravel())[0]
        return (limits / self.model.mu).reshape(t.shape + (self.n,))

    def scale(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        P = np.abs(np.asarray(self.model.P(t), dtype=float))
        return np.broadcast_to(P[..., None], t.shape + (self.n,)).copy()

    def always_in_contact(self) -> np.ndarray:
        ts = np.linspace(0.0, self.model.period, 4097)
        return self.levels < float(np.min(self.model.P(ts)))

    def transitions(self, t0: float, t1: float) -> np.ndarray:
        from scipy.optimize import brentq

        P = self.model.P
        if P.is_constant:
            return np.empty(0)
        T = self.model.period
        count = max(2, int(math.ceil(4096 * (t1 - t0) / T)))
        ts = np.linspace(t0, t1, count + 1)
        Ps = np.asarray(P(ts), dtype=float)
        out = []
        lo, hi = np.minimum(Ps[:-1], Ps[1:]), np.maximum(Ps[:-1], Ps[1:])
        levels = np.sort(np.unique(self.levels[np.isfinite(self.levels)]))
        for j in np.flatnonzero(hi > lo):
            inside = levels[
                np.searchsorted(levels, lo[j], side="right") : np.searchsorted(
                    levels, hi[j], side="left"
                )
            ]
            for c in inside:
                out.append(brentq(lambda x, c=c: float(P(x)) - c, ts[j], ts[j + 1], xtol=1e-14 * T))
        out = np.unique(np.asarray(out, dtype=float))
        return out[(out > t0) & (out < t1)]


def gross_sliding(model, Q: Load, steps: int) -> None:
    """Under pure load control (``k_support == 0``), refuse the tangential load Q when ``|Q| >
    μ P`` at some instant (the grid of ``steps`` increments and 20001 samples of the cycle):
    the whole contact would slide, with no equilibrium. Names the instants and the fix."""
    if model.k_support != 0.0:
        return
    T = model.period
    t = np.union1d(np.linspace(0.0, T, steps + 1), np.linspace(0.0, T, 20001))
    P, Qt = model.P(t), Q(t)
    margin = 1e-12 * (abs(model.mu * model.P0) + np.abs(Qt))
    plane = model.dims == 2
    if plane:
        # d = 2 at |Q| = μP: the whole contact slides and nothing holds the body across the
        # load, so its transverse slip drifts and no cycle repeats
        margin = -1e-9 * abs(model.mu * model.P0)
    bad = t[np.abs(Qt) > model.mu * np.maximum(P, 0.0) + margin]
    if bad.size:
        show = ", ".join(f"{x / T:.4g}" for x in bad[:: max(1, bad.size // 4)][:4])
        what = "reaches μ P(t)" if plane else "> μ P(t)"
        why = (
            "slides, and with d = 2 nothing holds the body across the load: its transverse "
            "slip drifts and no cycle repeats"
            if plane
            else "slides and has no equilibrium"
        )
        raise InputError(
            "k_support",
            f"is 0 (pure load control) but |Q(t)| {what} at "
            f"{bad.size} of {t.size} sampled instants (fractions of "
            f"the period: {show}, ...): the whole contact {why}; "
            f"give the structure that holds the body, a support "
            f"stiffness k_support > 0, or loads with "
            f"|Q| {'<' if plane else '<='} μ P",
        )


def load(name: str, x) -> Load:
    """A Load, or a number as a constant load."""
    if isinstance(x, Load):
        return x
    try:
        value = float(x)
    except (TypeError, ValueError):
        raise InputError(
            name, f"must be a Load (lcpfric.model.loads) or a number, got {type(x).__name__}"
        ) from None
    return Harmonic(_checks.finite(name, value), 0.0)
