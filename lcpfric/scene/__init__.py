"""The scene: one load cycle of a model sampled on a time grid, for every model.

A scene fixes everything a time-stepping method needs before it takes its first step: the grid
``t_0 < t_1 < ... < t_N`` over one period, the tangential loads ``Q(t_k)`` and the normal
reactions ``N(t_k)`` on it. Because the system is uncoupled, the instants where a normal load
crosses zero (separation, re-contact) are known in advance; they are placed on the grid, so that
no method has to locate them and none loses an order of accuracy there.

Placement of the remaining steps:

``"contact"`` (default)
    the steps are spread over the instants when at least one node is in contact; an interval in
    which every node is separated is one increment (nothing slips there, F = 0, u = -K⁻¹Q). With
    separation (P̂1 > 1) up to half the cycle is separated, and uniform steps would spend that
    share of the budget where nothing happens: measured on the single node at P̂1 from 1.5 to
    1e6, the error at a given step count is 2 to 8 times lower than with ``"uniform"`` (same
    second order). Without separation it is the uniform grid.
``"uniform"``
    ``steps_per_cycle`` equal increments over the period, plus the transition instants.

A continuum contact (:mod:`lcpfric.model.continuum`) has its scene on ``steps_per_cycle`` equal
increments (or a grid given), its normal problem solved once for those instants: the scene
keeps the friction limits of every node (``limits``), the contact size at each instant
(``sizes``), the total tangential load on the body (``Q``, along x) and the loads'
displacement and force scales (``scales``). Its stepper (``mdr-bar``, ``halfplane-pdas``,
``newton-cg``) advances the model on it; :func:`with_tangential_load` gives the same scene under
another tangential load (a map's points of one normal load share their normal problem).

A scene too large to hold its loads as arrays keeps them as :class:`Rows`, computed when asked
for (:mod:`lcpfric.scene.rows`, with the reductions that go chunk by chunk of rows).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks, memory
from ..errors import InputError
from ..model import ContactSystem, SingleNode
from .rows import Rows, column_max, column_reduce
from .rows import chunks as chunks  # re-exported: lcpfric.scene.chunks

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..model.continuum.base import ContactModel
    from ..model.loads import Load

__all__ = ["Scene", "Rows", "make_scene", "with_tangential_load", "increments", "column_reduce"]

PLACEMENTS = ("contact", "uniform")


@dataclass(frozen=True, eq=False)
class Scene:
    """A model over one load cycle on a fixed time grid.

    Made by :func:`make_scene` (and :func:`with_tangential_load`); the parameters are kept as
    the attributes of the same names (see Attributes for their full meaning).

    Parameters
    ----------
    system, model, t, Q, N, transitions, placement, steps_requested, limits, sizes, scales
        See Attributes; ``steps_requested`` and the next ones are optional.
    loads, stats, _cache
        Optional; ``_cache`` is internal (what the scene computes once), not to be given.

    Attributes
    ----------
    system : ContactSystem or None
        The (normalized, for a single node) system the steppers advance; None for a continuum
        contact, advanced by its own stepper.
    model : SingleNode, ContactModel or None
        The model the scene came from (None for a ContactSystem given as such).
    t : (N+1,) ndarray
        The grid, ``t[0]`` to ``t[0] + period``.
    Q : (N+1, m) ndarray or Rows
        Tangential loads on the grid (:class:`Rows`, computed when asked for, when Q and N
        would take more than :data:`LAZY_BYTES`); for a continuum contact ``(N+1,)``, the
        total tangential load on the body.
    N : (N+1, n) ndarray or Rows
        Normal reactions on the grid (``max(P, 0)`` for independent springs; a continuum
        contact's nodes' normal forces).
    transitions : ndarray
        The separation / re-contact instants placed on the grid.
    placement : str
        How the steps were placed (see module docstring).
    steps_requested : int
        The steps per cycle asked for (``steps`` is what the grid has, transitions added).
    limits : (N+1, n) ndarray or None
        A continuum contact's friction limits ``μ N_i`` on the grid, as its normal problem
        gives them; None for a system (its steppers form ``f N``).
    sizes : (N+1,) ndarray or None
        A continuum contact's contact size (radius or half-width) on the grid.
    scales : (float, float) or None
        A continuum contact's loads' displacement and force scales (the cycles' convergence
        measure, :func:`lcpfric.periodic.measure.cycle_change`).
    loads : (Load, Load) or None
        A continuum contact's normal and tangential loads.
    stats : dict
        The normal problem's statistics (solves, products, seconds), reported with the
        result's.
    steps, period, n, dims, m, held, contact
        Properties (below).
    """

    system: ContactSystem | None
    model: object
    t: np.ndarray
    Q: np.ndarray
    N: np.ndarray
    transitions: np.ndarray
    placement: str
    steps_requested: int = 0
    limits: np.ndarray | None = None
    sizes: np.ndarray | None = None
    scales: tuple | None = None
    loads: tuple | None = None
    stats: dict = field(default_factory=dict)
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def steps(self) -> int:
        """Number of increments in the cycle (steps per cycle plus inserted transitions)."""
        return self.t.size - 1

    @property
    def period(self) -> float:
        """The period of the model (of the system, for a discrete one)."""
        return self.model.period if self.system is None else self.system.period

    @property
    def n(self) -> int:
        """Nodes."""
        return self.model.nodes if self.system is None else self.system.n

    @property
    def dims(self) -> int:
        """Tangential directions per node."""
        return self.model.dims if self.system is None else self.system.dims

    @property
    def m(self) -> int:
        """Tangential unknowns, n·d."""
        return self.n * self.dims

    @property
    def held(self) -> np.ndarray:
        """A continuum contact's unknowns whose slips are its state, ``(m,)`` bool.

        Those of the nodes in contact at the cycle's start (a node out of contact has no force,
        and its slip follows from the others' forces).
        """
        b = self.limits[0]
        return np.repeat(b > 1e-10 * np.max(self.limits, initial=0.0), self.dims)

    @property
    def contact(self) -> np.ndarray:
        """(N+1, n) bool: node in contact (N > 0) at each grid instant."""
        if "contact" not in self._cache:
            N = self.N
            self._cache["contact"] = (
                Rows(lambda t, fn=N.fn: fn(t) > 0.0, N.t, N.width)
                if isinstance(N, Rows)
                else N > 0.0
            )
        return self._cache["contact"]


def _start_time(system: ContactSystem) -> float:
    """Start the cycle at a re-contact instant when every node separates at the same instants
    (a single node, for example): the state there is known exactly, so the driver converges in
    the fewest cycles. Otherwise start at t = 0."""
    T = system.period
    tr = system.normal.transitions(0.0, T)
    if tr.size == 0 or system.n != 1:
        return 0.0
    eps = 1e-9 * T
    for s in tr:
        after, before = system.normal.reactions(np.array([s + eps, s - eps]))[:, 0]
        if after > 0 and before <= 0:
            return float(s)
    return 0.0


def make_scene(
    system_or_model: ContactSystem | SingleNode | ContactModel,
    steps_per_cycle: int | None = None,
    *,
    placement: str | None = None,
    t0: float | None = None,
    grid: ArrayLike | None = None,
    history: bool = True,
) -> Scene:
    """Sample one cycle of a model on a time grid.

    Parameters
    ----------
    system_or_model : ContactSystem, SingleNode or ContactModel
        The model (a single node is sampled as its normalized system,
        :meth:`~lcpfric.model.SingleNode.system`).
    steps_per_cycle : int, optional
        Number of increments per cycle (>= 4), before the known transition instants are added
        (default: the model's, 2000 for a discrete system and 400 for a continuum contact).
    placement : {"uniform", "contact"}, optional
        See the module docstring (default: the model's; a continuum contact's steps are
        uniform).
    t0 : float, optional
        Start of the cycle; by default a re-contact instant for a single separating node, else 0.
    grid : array_like, optional
        A continuum contact's instants, increasing from 0 to the period (instead of
        ``steps_per_cycle`` uniform steps).
    history : bool
        Whether the cycle will be kept whole (for a continuum contact's memory estimate).

    Returns
    -------
    Scene
        The grid, the loads and the normal reactions on it (for a continuum contact, its
        normal problem solved at every instant).

    Raises
    ------
    InputError
        ``steps_per_cycle`` < 4 or not an integer; an unknown ``placement``; ``t0`` not finite,
        or given for a continuum contact; ``grid`` given for a discrete system, or not
        increasing from 0 to the period with at least 4 steps; not a model; a continuum
        contact whose cycle would exceed the memory limit (:mod:`lcpfric.memory`), or with
        ``k_support = 0`` and ``|Q| > μ P`` at some instant.
    SolverError
        A continuum contact's normal problem failed.
    """
    from ..model.continuum.base import ContactModel

    if isinstance(system_or_model, ContactModel):
        if t0 is not None:
            raise InputError("t0", "a continuum contact's cycle starts at t = 0")
        return _continuum_scene(system_or_model, steps_per_cycle, placement, grid, history)
    if grid is not None:
        raise InputError(
            "grid",
            "is for continuum contacts; a discrete system's grid is "
            "made of steps_per_cycle and placement",
        )
    if steps_per_cycle is None:
        steps_per_cycle = getattr(system_or_model, "default_steps", 2000)
    placement = "contact" if placement is None else placement
    steps = _checks.positive_int("steps_per_cycle", steps_per_cycle, minimum=4)
    if placement not in PLACEMENTS:
        raise InputError("placement", f"must be one of {PLACEMENTS}, got {placement!r}")
    model = system_or_model if isinstance(system_or_model, SingleNode) else None
    system = model.system() if model is not None else system_or_model
    if not isinstance(system, ContactSystem):
        raise InputError(
            "scene",
            "expected a SingleNode, a ContactSystem or a continuum "
            f"contact, got {type(system_or_model).__name__}",
        )
    T = system.period
    start = _start_time(system) if t0 is None else _checks.finite("t0", t0)
    end = start + T
    transitions = system.normal.transitions(start, end)
    if placement == "uniform" or transitions.size == 0:
        grid = np.linspace(start, end, steps + 1)
    else:
        grid = _contact_grid(system, start, end, transitions, steps)
    if transitions.size:
        # insert the transitions, dropping grid points within a tiny fraction of a step of one
        h = T / steps
        near = np.abs(grid[:, None] - transitions[None, :]).min(axis=1) < 1e-9 * h
        near[0] = near[-1] = False
        inner = transitions[(transitions > start + 1e-9 * h) & (transitions < end - 1e-9 * h)]
        grid = np.union1d(grid[~near], inner)
    grid[0], grid[-1] = start, end  # the cycle is exactly one period
    # Normal reactions within round-off of zero are zero: at the transition instants the loads'
    # roots are machine-precise, and the cycle's end (start + period) may be a root whose
    # evaluation leaves ~1e-13; treated as contact, that would turn a separated increment into a
    # contact one. The threshold is a few ulps of each node's load scale.
    zero = 64 * np.finfo(float).eps * column_max(system.normal.scale, grid, system.n)

    def reactions(t):
        N = system.normal.reactions(t)
        N[N <= zero] = 0.0
        return N

    if 8.0 * grid.size * (system.m + system.n) <= LAZY_BYTES:
        Q, N = system.tangential(grid), reactions(grid)
    else:
        Q, N = Rows(system.tangential, grid, system.m), Rows(reactions, grid, system.n)
    return Scene(system, model, grid, Q, N, transitions, placement, steps)


def _continuum_scene(model, steps, placement, grid, history) -> Scene:
    """A continuum contact's scene (module docstring): its normal problem solved on the grid,
    after the checks (loads, memory) that need no work."""
    from ..model.continuum.base import gross_sliding

    if placement not in (None, "uniform"):
        raise InputError(
            "placement",
            f"a continuum contact's steps are uniform (its cycle "
            f"starts at t = 0); got {placement!r}",
        )
    if grid is not None:
        t = _checks.finite_array("grid", grid).ravel()
        if (
            t.size < 5
            or t[0] != 0.0
            or not np.all(np.diff(t) > 0)
            or not math.isclose(t[-1], model.period, rel_tol=1e-12)
        ):
            raise InputError("grid", "must increase from 0 to the period, with at least 4 steps")
        steps = t.size - 1
    else:
        steps = _checks.positive_int(
            "steps_per_cycle", model.default_steps if steps is None else steps, 4
        )
        t = np.linspace(0.0, model.period, steps + 1)
    need = memory.continuum_bytes(model.nodes, model.dims, steps, history)
    memory.check(need, "steps_per_cycle", f"{steps} steps x {model.nodes} nodes (d = {model.dims})")
    gross_sliding(model, model.Q, steps if grid is None else 4)
    limits, sizes, stats = model.normal_solution(t)
    scene = Scene(
        None,
        model,
        t,
        np.empty(0),
        limits / model.mu,
        np.empty(0),
        "uniform",
        steps,
        limits=limits,
        sizes=sizes,
        stats=stats,
    )
    return _tangential(scene, model.Q)


def with_tangential_load(scene: Scene, Q: Load | float) -> Scene:
    """A continuum contact's scene under the tangential load Q instead.

    The normal problem is shared (a map's points of one normal load); Q is checked as
    :func:`make_scene` checks it.

    Parameters
    ----------
    scene : Scene
        A continuum contact's scene (:func:`make_scene`).
    Q : Load or float
        The new tangential load (a float is a constant load), of the scene's period.

    Returns
    -------
    Scene
        A copy of ``scene`` with the new Q on the grid, its scales and loads.

    Raises
    ------
    InputError
        ``scene`` is not a continuum contact's; Q is neither a Load nor a number, or has
        another period; ``k_support = 0`` and ``|Q| > μ P`` at some instant.
    """
    from ..model.continuum.base import gross_sliding, load

    if scene.system is not None:
        raise InputError("scene", "with_tangential_load is for a continuum contact's scene")
    Q = load("Q", Q)
    if not Q.is_constant and not math.isclose(Q.period, scene.period, rel_tol=1e-12):
        raise InputError("Q", f"must have the scene's period {scene.period!r}, got {Q.period!r}")
    gross_sliding(scene.model, Q, scene.steps)
    return _tangential(scene, Q)


def _tangential(scene: Scene, Q) -> Scene:
    model = scene.model
    values = np.asarray(Q(scene.t), dtype=float).reshape(scene.t.shape)
    return replace(scene, Q=values, scales=model.load_scales(Q), loads=(model.P, Q), _cache={})


#: a scene whose Q and N would take more bytes than this keeps them as :class:`Rows`
LAZY_BYTES = 256 * 2**20


def increments(x):
    """``ceil(x)`` (at least 1) for a share ``x = steps · L / total`` of the steps, ignoring the
    round-off of the ratio: 400.00000000000006 is 400 increments, not 401, whatever the period
    (otherwise the grid, and a time stepper's W, would depend on ω through round-off). Works on
    arrays too (:mod:`lcpfric.batch` builds the same grids)."""
    x = np.asarray(x, dtype=float)
    k = np.maximum(1, np.ceil(x * (1.0 - 64 * np.finfo(float).eps))).astype(int)
    return k if k.ndim else int(k)


def _contact_grid(
    system: ContactSystem, start: float, end: float, transitions: np.ndarray, steps: int
) -> np.ndarray:
    """Spread ``steps`` increments over the parts of the cycle where some node is in contact."""
    edges = np.concatenate([[start], transitions, [end]])
    mids = 0.5 * (edges[:-1] + edges[1:])
    any_contact = np.any(system.normal.reactions(mids) > 0.0, axis=-1)
    lengths = np.diff(edges)
    active = lengths * any_contact
    total = active.sum()
    pieces = []
    for a, b, L, on in zip(edges[:-1], edges[1:], active, any_contact):
        k = increments(steps * L / total) if on and total > 0 else 1
        pieces.append(np.linspace(a, b, k + 1)[:-1])
    pieces.append([end])
    return np.concatenate(pieces)
