"""Result types, one per level: a step (:class:`StepState`), a cycle (:class:`CycleResult`), a
steady state (:class:`SteadyState`, for every model: a continuum contact's geometry in its
``contact`` field, :class:`ContactExtras`) and a batch of steady states of many points
(:class:`BatchResult`). Sweeps return an ``xarray.Dataset`` (see :mod:`lcpfric.analysis.sweep`).

Every result is immutable: the driver builds new ones instead of changing a stepper's. The
step and cycle levels (:class:`State`, :class:`StepState`, :class:`CycleResult`) are defined
in :mod:`lcpfric.results.cycle`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import UndefinedQuantity
from .cycle import CycleResult, State, StepState

__all__ = [
    "State",
    "StepState",
    "CycleResult",
    "SteadyState",
    "BatchResult",
    "Normalization",
    "ContactExtras",
    "DynamicExtras",
]


@dataclass(frozen=True)
class Normalization:
    """The single node's units of Eq. (6).

    ``Ŵ = W / W``, ``v̂ = v / v``, ``F̂ = F / F``, ``N̂ = N / N`` with W = f P0 Q1 / k11,
    v = Q1 / k11, F = f P0, N = P0.

    Parameters
    ----------
    W, v, F, N : float
        The units, kept as the attributes of the same names.
    """

    W: float
    v: float
    F: float
    N: float


@dataclass(frozen=True)
class ContactExtras:
    """What a continuum contact's steady state adds (:attr:`SteadyState.contact`).

    Parameters
    ----------
    W_normalized, normalization, contact_size_max, k_t0, nodes, nodes_in_contact_max, x, size
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    W_normalized : float
        ``W k_t0 / (μ² P0²)`` (sphere, half-space) or ``W π E* / (μ² P0²)`` (cylinder).
    normalization : str
        The formula of ``W_normalized``, in words.
    contact_size_max : float
        The largest contact radius (sphere, half-space) or half-width (cylinder) over the cycle.
    k_t0 : float or None
        The initial tangential stiffness 2 a0 G* at P0 (None for the plane contact).
    nodes, nodes_in_contact_max : int
        Nodes of the grid; the most in contact at one instant.
    x : ndarray
        The nodes' positions (their distance from the centre: the radius for the sphere and
        the half-space, the signed coordinate for the cylinder).
    size : ndarray
        The contact size at each instant of the cycle's grid.
    """

    W_normalized: float
    normalization: str
    contact_size_max: float
    k_t0: float | None
    nodes: int
    nodes_in_contact_max: int
    x: np.ndarray
    size: np.ndarray


@dataclass(frozen=True)
class DynamicExtras:
    """What the steady state of a node with a mass, or of a
    :class:`~lcpfric.model.dynamic_system.DynamicSystem`, adds (:attr:`SteadyState.dynamics`).

    Parameters
    ----------
    beta, zeta, amplitude, velocity, floquet, stable, orbits, newton_iterations, periods
        Kept as the attributes of the same names (see Attributes).
    displacement : ndarray, optional
        A system's displacements x at the instants ``t`` (None for the node).

    Attributes
    ----------
    beta, zeta : float
        ω/Ω0 and the damping ratio (a system: Ω0 its first natural frequency with the
        contacts stuck, ζ NaN).
    amplitude : float or ndarray
        ``(max v - min v) / 2`` over the steady cycle, in the node's units; a system's, one
        per degree of freedom, of x.
    velocity : ndarray
        dv/dt (a system: dx/dt, one column per degree of freedom) at the instants ``t``.
    displacement : ndarray or None
        A system's x at the instants ``t``, one column per degree of freedom.
    floquet : ndarray
        The orbit's Floquet multipliers (complex; a stick phase makes one of them 0).
    stable : bool
        Both multipliers inside the unit circle.
    orbits : tuple of dict
        Every distinct periodic orbit found from the starts tried: ``W``, ``amplitude``,
        ``stable``, ``start`` (more than one: a :class:`~lcpfric.errors.MultipleSteadyStates`
        warning was issued).
    newton_iterations, periods : int
        Newton's iterations on the period map, and periods of motion computed in all.
    """

    beta: float
    zeta: float
    amplitude: float
    velocity: np.ndarray
    floquet: np.ndarray
    stable: bool
    orbits: tuple
    newton_iterations: int
    periods: int
    displacement: np.ndarray | None = None


@dataclass(frozen=True)
class SteadyState:
    """The periodic steady state found by :func:`lcpfric.steady_state`.

    Every field means the same for every input. Quantities are in the model's own units: for a
    dimensional :class:`~lcpfric.model.SingleNode` or any :class:`~lcpfric.model.ContactSystem`,
    the units of its stiffness and loads; for ``SingleNode.normalized(...)`` the units in which
    f P0 = 1 and k11 = 1 (then ``W = Q̂1 Ŵ``). The normalized quantities of Eq. (6) (``W_hat``,
    ``v_hat``) exist for a single node only; asking a general system for them raises
    :class:`~lcpfric.errors.UndefinedQuantity`.

    For a continuum contact ``v`` and ``F`` are the nodes' slips and friction forces
    (``(len(t), nodes·d)``), ``N`` the nodes' normal forces and ``state`` their states.

    Parameters
    ----------
    W, W_cycles, cycles, converged, method, steps_requested, steps_used, t, v, F, N, state
        Required; each is kept as the attribute of the same name (see Attributes).
    seconds, change, message, solver_stats, normalization, W_hat_cycles, changes, contact
        Likewise; ``seconds`` is required, the others are optional.
    dynamics
        Likewise, optional.

    Attributes
    ----------
    W : float
        Dissipation per cycle ``-∮ F dv`` (Eq. 5) of the last cycle.
    W_cycles : ndarray
        W of every cycle run, in order (the last is ``W``).
    cycles : int
        Cycles run (1 for the closed form, which computes one cycle of the periodic orbit).
    converged : bool
        Whether the last cycle repeated the previous one within ``tol`` (see
        :mod:`lcpfric.periodic`); always True for the closed form.
    method : str
        Registry name of the method.
    steps_requested : int
        The steps per cycle asked for (for the closed form: the number of samples of the
        returned time series, which does not affect W).
    steps_used : int
        Increments per cycle actually taken (the known separation and re-contact instants are
        added to the requested grid); 0 for the closed form, which takes no time steps.
    t, v, F, N, state : ndarray
        The last cycle's time series (for a single node v, F, N and state are 1-D; for a
        general system v and F are (len(t), m), N and state (len(t), n)).
    seconds : float
        Wall time of the computation.
    change : float
        The convergence measure of the last cycle (what ``tol`` is compared to).
    message : str
        What happened, in words.
    solver_stats : dict
        Backend statistics (solves, refinements, events), where there are any.
    normalization : Normalization or None
        The units of Eq. (6) for a single node; None for a general system.
    W_hat_cycles : ndarray or None
        Ŵ of every cycle (single node only).
    changes : ndarray or None
        The convergence measure of every cycle after the first (``cycles - 1`` values, the
        last is ``change``): how the cycles settled. None for the closed form.
    contact : ContactExtras or None
        A continuum contact's normalized dissipation and geometry; None for other models.
    dynamics : DynamicExtras or None
        A node with a mass: its amplitude, velocity, Floquet multipliers and the orbits found;
        None for the quasi-static models.
    W_hat, v_hat, W_normalized, steps_per_cycle, success
        Properties (below).
    """

    W: float
    W_cycles: np.ndarray
    cycles: int
    converged: bool
    method: str
    steps_requested: int
    steps_used: int
    t: np.ndarray
    v: np.ndarray
    F: np.ndarray
    N: np.ndarray
    state: np.ndarray
    seconds: float
    change: float = 0.0
    message: str = ""
    solver_stats: dict = field(default_factory=dict)
    normalization: Normalization | None = None
    W_hat_cycles: np.ndarray | None = None
    changes: np.ndarray | None = None
    contact: ContactExtras | None = None
    dynamics: DynamicExtras | None = None

    def _norm(self, name: str) -> Normalization:
        if self.normalization is None:
            raise UndefinedQuantity(
                name,
                "is defined for a single node (SingleNode, Eq. 6) "
                "only; a general system has W, v, F and N",
            )
        return self.normalization

    @property
    def W_hat(self) -> float:
        """Ŵ = k11 W / (f P0 Q1) (Eq. 6; 0 where Q1 = 0). Single node only."""
        self._norm("W_hat")
        return float(self.W_hat_cycles[-1])

    @property
    def W_normalized(self) -> float:
        """A continuum contact's normalized dissipation (:class:`ContactExtras`)."""
        if self.contact is None:
            raise UndefinedQuantity(
                "W_normalized",
                "is defined for continuum contacts only (MDRSphere, HalfPlaneCylinder, HalfSpace)",
            )
        return self.contact.W_normalized

    def stick_size(self) -> np.ndarray:
        """A continuum contact's stick size at each instant of the last cycle.

        The largest ``|x|`` of the sticking nodes that hold the centre, plus half the nodes'
        spacing (the stick radius or half-width; 0 when the centre does not stick). Needs the
        cycle's history (``history=True``).

        Returns
        -------
        ndarray
            The stick size at each instant of ``t``.

        Raises
        ------
        UndefinedQuantity
            The model is not a continuum contact.
        InputError
            The cycle was run without its history (named ``history``).
        """
        from ..errors import InputError

        if self.contact is None:
            raise UndefinedQuantity("stick_size", "is defined for continuum contacts only")
        if self.t.size != self.steps_used + 1:
            raise InputError("history", "the stick zone needs the whole cycle (history=True)")
        x = self.contact.x
        order = np.argsort(np.abs(x), kind="stable")
        half = (np.min(np.diff(np.sort(x))) / 2.0) if x.size > 1 else abs(x[0])
        out = np.zeros(self.state.shape[0])
        for j, s in enumerate(self.state):
            ranked = s[order]
            off = np.flatnonzero(ranked != State.STICK)
            inner = off[0] if off.size else ranked.size
            out[j] = abs(x[order[inner - 1]]) + half if inner else 0.0
        return out

    @property
    def v_hat(self) -> np.ndarray:
        """v̂ = k11 v / Q1 (Eq. 6). Single node only."""
        unit = self._norm("v_hat").v
        return self.v / unit if unit > 0 else np.zeros_like(self.v)

    @property
    def steps_per_cycle(self) -> int:
        """Increments per cycle actually taken (``steps_used``)."""
        return self.steps_used

    @property
    def success(self) -> bool:
        """Whether the driver reached a steady state (``converged``)."""
        return self.converged

    def summary(self) -> dict:
        """The scalar results as a JSON-serializable dict.

        Returns
        -------
        dict
            W (and Ŵ or the contact's results), the method, steps, cycles, convergence, time.
        """
        out = {"W": self.W}
        if self.normalization is not None:
            out["W_hat"] = self.W_hat
        if self.contact is not None:
            c = self.contact
            out.update(
                W_normalized=c.W_normalized,
                normalization=c.normalization,
                contact_size_max=c.contact_size_max,
                nodes=c.nodes,
                nodes_in_contact_max=c.nodes_in_contact_max,
            )
            if c.k_t0 is not None:
                out["k_t0"] = c.k_t0
        out.update(
            method=self.method,
            steps_requested=self.steps_requested,
            steps_used=self.steps_used,
            cycles=self.cycles,
            converged=self.converged,
            change=self.change,
            seconds=self.seconds,
            message=self.message,
        )
        return out

    def to_json(self) -> str:
        """The scalar results (:meth:`summary`) as a JSON string.

        Returns
        -------
        str
            ``json.dumps(self.summary())``.
        """
        return json.dumps(self.summary())

    def __repr__(self) -> str:
        head = (
            f"W_hat={self.W_hat!r}, "
            if self.normalization is not None
            else f"W_normalized={self.W_normalized!r}, "
            if self.contact is not None
            else ""
        )
        return (
            f"SteadyState({head}W={self.W!r}, method={self.method!r}, steps_used="
            f"{self.steps_used}, cycles={self.cycles}, converged={self.converged})"
        )


@dataclass(frozen=True)
class BatchResult:
    """Steady states of many points advanced together.

    Single-node points (:mod:`lcpfric.batch`) or the MDR sphere's map points
    (:func:`lcpfric.analysis.contact_maps.mdr_W_normalized`), by the batched cycle loop
    (:mod:`lcpfric.periodic.batched`).

    Parameters
    ----------
    values, quantity, converged, cycles, change, method, steps_requested, steps_used, seconds
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    values : ndarray (or float for scalar input)
        Per point, the quantity ``quantity`` of its first converged cycle; NaN where the point
        did not converge in ``max_cycles`` (``converged`` False; never a value that did not
        converge).
    quantity : str
        ``"W_hat"`` (single nodes, Eq. 6) or ``"W_normalized"`` (continuum contacts).
    converged : ndarray of bool
        Per point, whether its cycle repeated within ``tol``.
    cycles : ndarray of int
        Per point, the cycle at which it converged (``max_cycles`` where it did not).
    change : ndarray
        Per point, the last convergence measure.
    method : str
        Registry name of the method.
    steps_requested, steps_used : int
        As in :class:`SteadyState` (``steps_used`` is the largest over the points).
    seconds : float
        Wall time of the computation.
    W_hat, W_normalized, unconverged
        Properties (below); asking for the quantity the batch does not hold raises
        :class:`~lcpfric.errors.UndefinedQuantity`.
    """

    values: Any
    quantity: str
    converged: np.ndarray
    cycles: np.ndarray
    change: np.ndarray
    method: str
    steps_requested: int
    steps_used: int
    seconds: float = 0.0

    def _get(self, name: str):
        if self.quantity != name:
            raise UndefinedQuantity(name, f"this batch holds {self.quantity}")
        return self.values

    @property
    def W_hat(self) -> np.ndarray | float:
        """Ŵ per point (single-node batches)."""
        return self._get("W_hat")

    @property
    def W_normalized(self) -> np.ndarray | float:
        """The normalized dissipation per point (continuum contacts)."""
        return self._get("W_normalized")

    @property
    def unconverged(self) -> int:
        """The number of points that did not converge (their value is NaN)."""
        return int(np.size(self.converged) - np.count_nonzero(self.converged))
