"""The periodic steady state of a continuum contact model, and its result type.

A model (:class:`~lcpfric.contact.mdr.MDRSphere`, :class:`~lcpfric.contact.halfplane.
HalfPlaneCylinder`) provides

* ``period``, ``nodes``, ``x`` (node positions), ``k_support``;
* ``limits(t)``: the friction limits ``μ N_i(t)`` on the grid (the normal problem, solved before
  any tangential computation: the problems are uncoupled), and ``sizes(t)``, the contact size
  (radius or half-width) at each instant;
* ``start()``: the tangential state of the virgin contact, and ``increment(state, b, Q)``: the
  increment to the next instant (limits b, tangential load Q), returning ``(state, F, dv)``:
  the new state, the friction forces and the slips of the increment (lcpfric's signs: the slip
  opposes F);
* ``scales()``: ``(displacement, force)`` scales for the convergence test, and
  ``normalization()``: ``(name, factor)`` with ``W_normalized = factor · W``;
* optionally ``restart(state, v)``: the state with the slips v. The driver then moves each
  cycle's start towards the cycle map's fixed point (Anderson's acceleration of the map from a
  cycle's starting slips to its ending ones, :class:`lcpfric.periodic.Anderson`); convergence
  is still a whole cycle that repeats. A model with ``dims = 2`` gives forces and slips node
  by node (n·2);
* optionally ``guess(state)`` after an increment, and ``increment(state, b, Q, guess)``: the
  driver keeps the guesses of a cycle's increments (where they fit in memory) and gives each
  to the same increment of the next cycle, its start: once the cycles nearly repeat, the
  increments are nearly solved before they begin;
* optionally ``memory()``: a :class:`~lcpfric.cycle_memory.SlipMemory` (or None), with
  ``restart``: what a cycle remembers of its starting slips, node by node, from the increments'
  slips and limits; the driver scales each cycle's change by it (a Newton step on the cycle
  map's diagonal blocks) before accelerating, so the nodes that slip little each cycle (d = 2's
  slow modes) settle in a few cycles;
* optionally ``loose_cycles`` (true), a ``tol`` attribute and ``increment(..., tol=)``: a model
  that settles over many cycles has its early cycles' increments solved loosely (to a hundredth
  of the last cycle's change, at most 1e-6), then to a tenth of the cycle tolerance (or to the
  model's own ``tol`` if that is tighter, down to a hundredth of the cycle tolerance); only a
  cycle at that accuracy ends the iteration. Increments solved to the cycle tolerance itself
  would leave the cycles' change hovering about it, from their own errors, for cycle after
  cycle. The increments hold about 1e-13 at best: a cycle tolerance under 1e-12 is refused
  before any work.

:func:`steady_state` runs cycles until the slips repeat, with the driver's own criterion
(:func:`~lcpfric.periodic.cycle_change`), and returns one :class:`ContactResult`. The slips
compared are those of the nodes in contact at the cycle's start, the state: a node out of
contact has no force, and its v (the relative displacement of the surfaces there) follows
from the others' forces, so a loosely solved cycle showed its force errors there (a d = 2
contact where nothing slips took 6 to 9 cycles instead of 3). A steady
cycle in which no element slips (W = 0) while the loads change issues a
:class:`~lcpfric.errors.ResolutionWarning`: a smooth contact slips at its edge under almost any
change of the loads, in a zone that may be thinner than an element.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, ConvergenceWarning, InputError, ResolutionWarning
from ..model.loads import Harmonic, Load
from ..periodic import Anderson, cycle_change
from ..results import State
from ..steppers.dissipation import increment_dissipation
from .closed_forms import moduli

__all__ = ["ContactResult", "ContactModel", "LevelNormal", "steady_state", "gross_sliding",
           "load"]

STICK, FORWARD, BACKWARD, SEPARATION = (int(State.STICK), int(State.FORWARD),
                                        int(State.BACKWARD), int(State.SEPARATION))
#: memory allowed for the recorded cycle and the limits on the grid
MAX_BYTES = 4 << 30
#: models with ``loose_cycles``: the increments' tolerance, this times the last cycle's change,
#: at most ``_LOOSE_MAX`` (and at least the model's own)
_LOOSE, _LOOSE_MAX = 1e-2, 1e-6
#: models with ``loose_cycles``: the last cycles' increments, this times the cycle tolerance (at
#: most the model's own tol, at least ``_LOOSE`` times the cycle tolerance)
_FINAL = 0.1
#: models with ``loose_cycles``: the smallest cycle tolerance (its increments, a tenth of it,
#: near the 1e-13 that they hold at best)
_TOL_MIN = 1e-12


@dataclass(frozen=True)
class ContactResult:
    """The periodic steady state of a continuum contact.

    Attributes
    ----------
    W : float
        Dissipation per cycle (last cycle): force x length (per unit length for a plane
        contact), in the units of the loads and lengths given.
    W_normalized : float
        ``W k_t0 / (μ² P0²)`` (sphere) or ``W π E* / (μ² P0²)`` (cylinder): ``normalization``.
    normalization : str
    W_cycles : ndarray
        W of every cycle run.
    contact_size_max : float
        The largest contact radius (sphere) or half-width (cylinder) over the cycle.
    k_t0 : float or None
        The sphere's initial tangential stiffness at P0 (None for a plane contact).
    nodes, nodes_in_contact_max : int
        Nodes of the grid; the most in contact at one instant.
    steps_per_cycle, cycles : int
    converged : bool
    change : float
        The last cycle's relative change (:func:`~lcpfric.periodic.cycle_change`).
    seconds : float
    t, x : ndarray
        The instants of the last cycle (``steps + 1``) and the node positions.
    size : ndarray
        The contact size at each instant.
    changes : ndarray
        The relative change of every cycle after the first (``cycles - 1`` values, the last
        is ``change``): how the cycles settled.
    extrapolations : int
        Cycles started elsewhere than where the last one ended (models with ``restart``):
        Anderson's accelerated starts, Aitken's where it stalls, and with ``memory()`` the
        preconditioned ones between them.
    state, F : ndarray or None
        ``(steps + 1, nodes)`` node states (:class:`~lcpfric.results.State`: stick, slipping
        forward or backward, separated) and friction forces of the last cycle, with
        ``record=True``.
    """

    W: float
    W_normalized: float
    normalization: str
    W_cycles: np.ndarray
    contact_size_max: float
    k_t0: float | None
    nodes: int
    nodes_in_contact_max: int
    steps_per_cycle: int
    cycles: int
    converged: bool
    change: float
    seconds: float
    t: np.ndarray
    x: np.ndarray
    size: np.ndarray
    state: np.ndarray | None = None
    F: np.ndarray | None = None
    extrapolations: int = 0
    changes: np.ndarray | None = None

    def stick_size(self) -> np.ndarray:
        """At each instant of the last cycle, the largest |x| of the sticking nodes that hold
        the centre (the stick radius or half-width; 0 when the centre does not stick). Needs
        ``record=True``."""
        if self.state is None:
            raise InputError("record", "the stick zone needs the recorded cycle (record=True)")
        x = self.x
        order = np.argsort(np.abs(x), kind="stable")
        half = (np.min(np.diff(np.sort(x))) / 2.0) if x.size > 1 else abs(x[0])
        out = np.zeros(self.state.shape[0])
        for j, s in enumerate(self.state):
            ranked = s[order]
            off = np.flatnonzero(ranked != STICK)
            inner = off[0] if off.size else ranked.size
            out[j] = abs(x[order[inner - 1]]) + half if inner else 0.0
        return out


def steady_state(model, steps: int = 400, *, tol: float = 1e-10, max_cycles: int = 200,
                 on_nonconvergence: str = "raise", record: bool = False,
                 t=None) -> ContactResult:
    """The periodic steady state of ``model`` on ``steps`` uniform increments per cycle (or on
    the grid ``t``, increasing from 0 to the period: a scene's, say), from the virgin contact
    (see the module docstring)."""
    start = time.perf_counter()
    if t is not None:
        t = _checks.finite_array("t", t).ravel()
        if t.size < 5 or t[0] != 0.0 or not np.all(np.diff(t) > 0) or not math.isclose(
                t[-1], model.period, rel_tol=1e-12):
            raise InputError("t", "must increase from 0 to the period, with at least 4 steps")
        steps = t.size - 1
    steps = _checks.positive_int("steps", steps, 4)
    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles,
                                                                on_nonconvergence)
    loose = getattr(model, "loose_cycles", False)
    if loose and tol < _TOL_MIN:
        raise InputError("tol", f"= {tol:g} is below what the increments can hold: the last "
                                f"cycles' increments are solved to a tenth of it, and they hold "
                                f"about 1e-13 at best; give tol >= {_TOL_MIN:g}")
    n = model.nodes
    dims = getattr(model, "dims", 1)
    need = n * (steps + 1) * 8 * (1 + (1 + dims if record else 0))
    if need > MAX_BYTES:
        raise InputError("steps", f"{steps} steps x {n} nodes would take {need / 2**30:.1f} GiB "
                                  f"(more than {MAX_BYTES / 2**30:.0f}); fewer steps or nodes")
    # the previous cycle's increments start the next cycle's (models with ``guess``), where
    # they fit in the memory left
    # (a guess: changes of the forces and their products, n·d floats each, and a pattern; the
    # previous cycle's and the current one's are held together)
    guessing = (getattr(model, "guess", None) is not None
                and need + 2 * n * steps * (16 * dims + 1) <= MAX_BYTES)
    if t is None:
        t = np.linspace(0.0, model.period, steps + 1)
    b = model.limits(t)                                       # (steps + 1, n)
    Q = np.asarray(model.Q(t), dtype=float)
    state = model.start()
    F = np.zeros(n * dims)
    # the nodes whose slips the cycles compare: those in contact at the cycle's start
    held = np.repeat(b[0] > 1e-10 * np.max(b, initial=0.0), dims)
    W_cycles, change, prev, smallest = [], math.inf, None, math.inf
    changes = []
    scales = model.scales()
    Fs = Ss = None
    accelerate = Anderson() if getattr(model, "restart", None) is not None else None
    # d = 2: each cycle's change is first scaled node by node by what the cycle remembers of
    # its start (a Newton step on the cycle map's diagonal blocks: lcpfric.cycle_memory)
    memory = (model.memory() if accelerate is not None
              and callable(getattr(model, "memory", None)) else None)
    R = None
    jumps = 0
    dv = None                 # the last increment's slips: the states at a cycle's start
    guesses = None
    accurate = True
    for _ in range(max_cycles):
        previous, guesses = guesses, ([] if guessing else None)
        options = {}
        if loose:
            # a slowly settling model solves its early cycles' increments loosely, each to a
            # hundredth of the last cycle's change (at most 1e-6), and to a tenth of the cycle
            # tolerance (or its own tol, if tighter) once the cycles nearly repeat; only a
            # cycle at that accuracy can end the iteration
            final = max(_LOOSE * tol, min(model.tol, _FINAL * tol))
            options["tol"] = max(final, _loose_tolerance(change))
            accurate = options["tol"] == final
        v0 = state.v.copy()
        if record:
            Fs = np.empty((steps + 1, n * dims))
            Ss = np.empty((steps + 1, n), dtype=np.int8)
            Fs[0], Ss[0] = F, _states(b[0], dv, dims)
        W = 0.0
        vmin, vmax = v0.copy(), v0.copy()
        if memory is not None:
            R = memory.start()
        for j in range(steps):
            if guesses is None:
                state, F1, dv = model.increment(state, b[j + 1], Q[j + 1], **options)
            else:
                state, F1, dv = model.increment(state, b[j + 1], Q[j + 1],
                                                previous[j] if previous else None, **options)
                guesses.append(model.guess(state))
            W += increment_dissipation(F, F1, dv, dims)
            if memory is not None:
                memory.update(R, dv, b[j + 1])
            if record:
                Fs[j + 1], Ss[j + 1] = F1, _states(b[j + 1], dv, dims)
            F = F1
            np.minimum(vmin, state.v, out=vmin)
            np.maximum(vmax, state.v, out=vmax)
        W_cycles.append(W)
        if prev is not None:
            # the slips of the nodes in contact at the cycle's start are the state; the
            # others' v is the relative displacement, derived from the forces
            change = float(cycle_change(np.max(np.abs(state.v - v0)[held], initial=0.0),
                                        np.max(vmax - vmin), W - prev, W, scales))
            changes.append(change)
            if accurate:
                smallest = min(smallest, change)
            if change <= tol and accurate:
                break
        prev = W
        end = state.v.copy()
        if memory is not None:
            # the preconditioned cycle map: its value is the next start, unless accelerated
            end = v0 + memory.step(R, end - v0)
        jump = accelerate(v0, end) if accelerate else None
        if jump is None and memory is not None:
            jump = end
        if jump is not None:
            state = model.restart(state, jump)
            jumps += 1
    converged = bool(change <= tol)
    if not converged and on_nonconvergence != "ignore":
        msg = (f"{type(model).__name__}: no periodic steady state after {len(W_cycles)} cycles "
               f"(relative change {change:.3g} > tol {tol:g}"
               + (f"; the smallest at full accuracy {smallest:.3g}" if smallest < math.inf
                  else "") + "); raise max_cycles or loosen tol")
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg, None)
        warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    name, factor = model.normalization()
    W = W_cycles[-1]
    if W == 0.0 and not (model.P.is_constant and model.Q.is_constant) and np.any(Q != 0.0):
        # no element slipped: a smooth contact slips at its edge (where p -> 0) under almost
        # any change of the loads, in a zone the grid may not resolve
        warnings.warn(f"{type(model).__name__}: no element slipped over the steady cycle "
                      f"(W = 0 on {n} nodes): a slip zone thinner than an element is not "
                      f"resolved (unless the loads change in proportion, |dQ/dP| < mu, "
                      f"where W = 0 is exact); "
                      f"{getattr(model, 'refine_hint', 'refine the grid')}",
                      ResolutionWarning, stacklevel=2)
    size = model.sizes(t)
    return ContactResult(W=W, W_normalized=W * factor, normalization=name,
                         W_cycles=np.asarray(W_cycles), contact_size_max=float(size.max()),
                         k_t0=getattr(model, "k_t0", None), nodes=n,
                         nodes_in_contact_max=int(np.max(np.count_nonzero(b > 0, axis=1))),
                         steps_per_cycle=steps, cycles=len(W_cycles), converged=converged,
                         change=change, seconds=time.perf_counter() - start, t=t, x=model.x,
                         size=size, state=Ss, F=Fs, extrapolations=jumps,
                         changes=np.asarray(changes))


def _loose_tolerance(change: float) -> float:
    """Models with ``loose_cycles``: the early cycles' increments' tolerance after a cycle whose
    change was ``change`` (a hundredth of it, at most ``_LOOSE_MAX``; the final tolerance is
    the floor). ``benchmarks/late_cycles.py`` measures other schedules against it."""
    return min(_LOOSE_MAX, _LOOSE * change)


def _states(b, dv, dims: int = 1) -> np.ndarray:
    """Node states: separated (no normal force), slipping (moved in the increment; for d = 2,
    forward means along +x), sticking."""
    s = np.full(b.shape, STICK, dtype=np.int8)
    if dv is not None and dims == 2:
        d2 = dv.reshape(-1, 2)
        moved = np.hypot(d2[:, 0], d2[:, 1]) > 0.0
        s[moved & (d2[:, 0] >= 0.0)] = FORWARD
        s[moved & (d2[:, 0] < 0.0)] = BACKWARD
    elif dv is not None:
        s[dv > 0.0] = FORWARD
        s[dv < 0.0] = BACKWARD
    s[b <= 0.0] = SEPARATION
    return s


def gross_sliding(model, steps: int) -> None:
    """Under pure load control (``k_support == 0``), refuse loads with ``|Q| > μ P`` at some
    instant (the grid and 20001 samples of the cycle): the whole contact would slide, with no
    equilibrium. Names the instants and the fix."""
    if model.k_support != 0.0:
        return
    T = model.period
    t = np.union1d(np.linspace(0.0, T, steps + 1), np.linspace(0.0, T, 20001))
    P, Q = model.P(t), model.Q(t)
    margin = 1e-12 * (abs(model.mu * model.P0) + np.abs(Q))
    plane = getattr(model, "dims", 1) == 2
    if plane:
        # d = 2 at |Q| = μP: the whole contact slides and nothing holds the body across the
        # load, so its transverse slip drifts and no cycle repeats
        margin = -1e-9 * abs(model.mu * model.P0)
    bad = t[np.abs(Q) > model.mu * np.maximum(P, 0.0) + margin]
    if bad.size:
        show = ", ".join(f"{x / T:.4g}" for x in bad[:: max(1, bad.size // 4)][:4])
        what = ("reaches μ P(t)" if plane else "> μ P(t)")
        why = ("slides, and with d = 2 nothing holds the body across the load: its transverse "
               "slip drifts and no cycle repeats" if plane
               else "slides and has no equilibrium")
        raise InputError("k_support", f"is 0 (pure load control) but |Q(t)| {what} at "
                                      f"{bad.size} of {t.size} sampled instants (fractions of "
                                      f"the period: {show}, ...): the whole contact {why}; "
                                      f"give the structure that holds the body, a support "
                                      f"stiffness k_support > 0, or loads with "
                                      f"|Q| {'<' if plane else '<='} μ P")


class ContactModel:
    """What every continuum model shares: two identical bodies (E, ν), friction μ, the loads
    P(t) and Q(t) (one period), the support stiffness, the number of nodes, and the steady
    state (:meth:`solve`). Subclasses add the geometry, the normal problem and the increment
    (the protocol of the module docstring)."""

    max_nodes = 200_000

    def __init__(self, E, nu, mu, P, Q, k_support, nodes):
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
        if self.nodes > self.max_nodes:
            raise InputError("nodes", f"must be at most {self.max_nodes}, got {self.nodes}")
        if not self.P.mean > 0:
            raise InputError("P", f"the mean normal load P0 must be > 0, got {self.P.mean!r}")
        self.P0 = float(self.P.mean)
        ts = np.linspace(0.0, self.period, 4097)
        self.P_max = float(max(np.max(self.P(ts)), self.P0))

    def solve(self, steps: int = 400, *, tol: float = 1e-10, max_cycles: int = 200,
              on_nonconvergence: str = "raise", record: bool = False, t=None) -> ContactResult:
        """The periodic steady state on ``steps`` uniform increments per cycle (or the grid
        ``t``), from the virgin contact: :func:`steady_state`. With ``k_support = 0`` loads with
        ``|Q| > μ P`` at some instant are refused first (:func:`gross_sliding`)."""
        gross_sliding(self, _checks.positive_int("steps", steps if t is None else 4, 4))
        return steady_state(self, steps, tol=tol, max_cycles=max_cycles,
                            on_nonconvergence=on_nonconvergence, record=record, t=t)


    # -- as an lcpfric system ---------------------------------------------------------------
    def normal_model(self) -> "LevelNormal":
        """The nodes' normal forces as an lcpfric normal model
        (:class:`~lcpfric.model.normal.NormalModel`)."""
        return LevelNormal(self)

    def system(self):
        """This contact as an lcpfric :class:`~lcpfric.model.ContactSystem` (matrix-free), for
        the other methods. With the nodes' own compliance ``C_s`` (the body held fixed), the
        rigid displacement eliminated gives ``F = K v - C_s⁻¹ 1 Q / (1ᵀ C_s⁻¹ 1 + k_s)`` with
        ``K⁻¹ = C_s + 1 1ᵀ / k_s`` (Sherman-Morrison): products only, no matrix formed. With
        ``dims = 2`` (the half-space) 1 becomes ``B = [1_x 1_y]`` and the load's coefficients
        ``-C_s⁻¹ B (k_s I + Bᵀ C_s⁻¹ B)⁻¹ e_x`` (Woodbury); ``springs()`` then gives
        ``C_s⁻¹ B`` as an ``(n·2, 2)`` array. Needs
        ``k_support > 0``: under pure load control K is singular (a common slip of every node
        is a rigid shift of the body)."""
        from scipy.sparse.linalg import LinearOperator

        from ..model import ContactSystem
        from ..model.loads import Harmonic, Periodic

        ks = self.k_support
        if ks <= 0.0:
            raise InputError("k_support", "is 0: under pure load control the contact's "
                                          "stiffness is singular (a rigid shift of the body), "
                                          "so it is no ContactSystem; use solve(), or give "
                                          "k_support > 0")
        Cs, w, cdiag = self.springs()
        d = getattr(self, "dims", 1)
        m = np.asarray(cdiag).size
        n = m // d

        def ones(x):                                                  # Bᵀ x, B = [1_x 1_y]
            return np.asarray(x, dtype=float).reshape(-1, 2).sum(axis=0)

        class _Compliance(LinearOperator):
            def __init__(self):
                super().__init__(dtype=float, shape=(m, m))

            def _matvec(self, x):
                x = np.asarray(x, dtype=float).reshape(-1)
                out = np.asarray(Cs.matvec(x), dtype=float).reshape(-1)
                if d == 1:
                    return out + x.sum() / ks
                return (out.reshape(-1, 2) + ones(x) / ks).reshape(-1)

            def _rmatvec(self, x):
                return self._matvec(x)

            def diagonal(self):
                return cdiag + 1.0 / ks

        # the loads: F = K v + c Q(t), c = -W (k_s I + Bᵀ W)⁻¹ e_x, W = C_s⁻¹ B (Woodbury)
        if d == 1:
            w = np.asarray(w, dtype=float).reshape(-1)
            coef = -w / (float(w.sum()) + ks)
        else:
            W = np.asarray(w, dtype=float).reshape(m, 2)
            BW = np.stack([W[0::2].sum(axis=0), W[1::2].sum(axis=0)])
            coef = -W @ np.linalg.solve(ks * np.eye(2) + BW, np.array([1.0, 0.0]))
        Q = self.Q
        loads = []
        for c in coef:
            if isinstance(Q, Harmonic):
                loads.append(Harmonic(c * Q.mean, abs(c) * Q.amplitude,
                                      Q.phase + (math.pi if c < 0 else 0.0), Q.omega))
            else:
                loads.append(Periodic(lambda t, c=c: c * Q(t), self.period, c * Q.mean))
        return ContactSystem(None, np.full(n, self.mu), tuple(loads), self.normal_model(),
                             dims=d, compliance=_Compliance())


class LevelNormal:
    """A contact model's normal forces as an lcpfric normal model: node i is in contact while
    P(t) exceeds its entry load (``model.entry_loads()``); those crossings are the transitions,
    sampled on 4096 points per period and polished by Brent's method."""

    def __init__(self, model):
        self.model = model
        self.levels = np.asarray(model.entry_loads(), dtype=float)

    @property
    def n(self) -> int:
        return self.model.nodes

    @property
    def period(self):
        return None if self.model.P.is_constant else self.model.period

    def reactions(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return (self.model.limits(t.ravel()) / self.model.mu).reshape(t.shape + (self.n,))

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
            inside = levels[np.searchsorted(levels, lo[j], side="right"):
                            np.searchsorted(levels, hi[j], side="left")]
            for c in inside:
                out.append(brentq(lambda x, c=c: float(P(x)) - c, ts[j], ts[j + 1],
                                  xtol=1e-14 * T))
        out = np.unique(np.asarray(out, dtype=float))
        return out[(out > t0) & (out < t1)]


def load(name: str, x) -> Load:
    """A Load, or a number as a constant load."""
    if isinstance(x, Load):
        return x
    try:
        value = float(x)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a Load (lcpfric.model.loads) or a number, got "
                               f"{type(x).__name__}") from None
    return Harmonic(_checks.finite(name, value), 0.0)
