"""Amplitude-dependent frequency and damping of a jointed structure by quasi-static modal analysis.

For a mode φ of the stuck structure (modal mass 1, ``ω0² = λ``), the structure is loaded
quasi-statically with ``f = α M φ``, ``α = α_max sin θ``, from the unloaded state with every
slider at rest (``w = 0``). Its steady hysteresis cycle is computed exactly, event by event, by
lcpfric's solver of discrete systems (``steady_state(system, "exact")``) on the sliders'
condensed system (:mod:`lcpfric.model.structure`), not assumed to follow Masing's rules. With
the modal amplitude ``q = φᵀ M x`` over that cycle (Lacayo and Allen; Festjens et al.)::

    a = (max q - min q) / 2,    ω(a)² = α_max / a,    ζ(a) = W / (2π ω(a)² a²)

W being the sliders' dissipation per cycle. With constant normal loads the tangent compliance
of the structure is positive along any loading path (Drucker), so q rises with α: its extremes
are at ``θ = π/2`` and ``3π/2``, which the sampled cycle holds (``samples`` is a multiple of 4).
Where nothing slips over the steady cycle ``W = 0``, ``ζ = 0`` (``sticks``).

The amplitudes are asked as modal amplitudes a (α found by Brent's method on the monotone
``a(α)``, bracketed by the stuck stiffness: ``α c0 <= a(α)``; below the first slip
``a = α c0`` exactly) or as modal forces α_max directly.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..model.structure import JointedStructure

__all__ = ["ModalDamping", "modal_damping", "jenkins_oscillator"]

TWO_PI = 2.0 * math.pi
#: relative tolerance of α found for an asked amplitude (Brent's method)
RTOL = 1e-13


@dataclass(frozen=True)
class ModalDamping:
    """Frequency and damping of one mode against its amplitude (:func:`modal_damping`).

    Parameters
    ----------
    a, alpha_max, omega, omega_ratio, zeta, W, sticks, cycles, evaluations
        Per amplitude (see Attributes).
    omega0, a_slip, phi, mode_index, theta, q, stats
        See Attributes.

    Attributes
    ----------
    a : (k,) ndarray
        The modal amplitude, half the range of ``q = φᵀ M x`` over the steady cycle.
    alpha_max : (k,) ndarray
        The modal force amplitude α_max (the load is ``α_max sin θ M φ``).
    omega : (k,) ndarray
        ω(a) = sqrt(α_max / a), the secant frequency of the backbone.
    omega_ratio : (k,) ndarray
        ω(a) / ω0.
    zeta : (k,) ndarray
        ζ(a) = W / (2π ω² a²).
    W : (k,) ndarray
        Dissipation per cycle of the steady cycle (units of force x displacement).
    sticks : (k,) ndarray of bool
        Nothing slips over the steady cycle (W = 0, ζ = 0, ω = ω0).
    cycles : (k,) ndarray of int
        Cycles the exact solver ran for the returned steady cycle.
    evaluations : (k,) ndarray of int
        Steady cycles evaluated for the amplitude (more than one when α was searched).
    omega0 : float
        ω0, the frequency of the stuck structure's mode.
    a_slip : float
        The modal amplitude at which the first slider slips (below it ``a = α_max / ω0²``
        and nothing slips; inf if the mode loads no contact).
    phi : (n,) ndarray
        The mode, mass normalized.
    mode_index : int or None
        Its index among the stuck modes (None for a mode given as a vector).
    theta : (s + 1,) ndarray
        The angles θ = ωt at which the cycles are sampled, 0 to 2π.
    q : (k, s + 1) ndarray
        The modal amplitude over each steady cycle (the modal force is ``α_max sin θ``).
    stats : dict
        ``condense_seconds`` (modes, factorization and condensation), ``cycle_seconds`` (the
        exact steady cycles), ``solves`` (exact steady cycles computed; none below the first
        slip, where ``q = α c0``), ``contacts`` (the contacts with mu > 0).
    """

    a: np.ndarray
    alpha_max: np.ndarray
    omega: np.ndarray
    omega_ratio: np.ndarray
    zeta: np.ndarray
    W: np.ndarray
    sticks: np.ndarray
    cycles: np.ndarray
    evaluations: np.ndarray
    omega0: float
    a_slip: float
    phi: np.ndarray
    mode_index: int | None
    theta: np.ndarray
    q: np.ndarray
    stats: dict = field(default_factory=dict)

    @property
    def backbone(self) -> tuple[np.ndarray, np.ndarray]:
        """The backbone: the tips ``(a, α_max)`` of the steady cycles (ω² is its secant)."""
        return self.a, self.alpha_max

    def loop(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """The steady hysteresis loop of amplitude ``i``: modal force against modal amplitude.

        Parameters
        ----------
        i : int
            The amplitude's index.

        Returns
        -------
        alpha, q : (s + 1,) ndarray
            ``α_max sin θ`` and q at the angles :attr:`theta`.
        """
        return self.alpha_max[i] * np.sin(self.theta), self.q[i]


class _Cycles:
    """The steady cycle at a modal force α_max, computed once per α (cached for the search)."""

    def __init__(self, sliders, c0, first, samples):
        self.sliders, self.c0, self.first, self.samples = sliders, c0, first, samples
        self.theta = np.linspace(0.0, TWO_PI, samples + 1)
        self.sin = np.sin(self.theta)
        self.cache, self.evaluations, self.solves = {}, 0, 0

    def __call__(self, alpha: float) -> tuple:
        """(a, W, q over the cycle, cycles) at α_max = ``alpha``."""
        hit = self.cache.get(alpha)
        if hit is not None:
            return hit
        self.evaluations += 1
        s = self.sliders
        if alpha <= self.first:  # every slider sticks from the unloaded state: q = α c0
            q, W, cycles = alpha * self.c0 * self.sin, 0.0, 0
        else:
            from ..periodic.driver import steady_state

            self.solves += 1
            res = steady_state(s.contact_system(alpha), "exact", steps_per_cycle=self.samples)
            q = s.modal_amplitude(alpha * self.sin, res.v)
            W, cycles = float(res.W), int(res.cycles)
        out = (0.5 * float(np.max(q) - np.min(q)), W, q, cycles)
        self.cache[alpha] = out
        return out


def _values(name: str, values) -> np.ndarray:
    arr = _checks.finite_array(name, values).ravel()
    if arr.size == 0:
        raise InputError(name, "needs one or more values")
    if np.any(arr <= 0):
        raise InputError(
            name, f"every value must be > 0 (allowed range (0, inf)); smallest is {arr.min()}"
        )
    return arr


def _search(cyc: _Cycles, target: float) -> float:
    """α_max whose steady cycle has the amplitude ``target`` (Brent's method)."""
    c0, first = cyc.c0, cyc.first
    if target <= first * c0:  # below the first slip: a = α c0
        return target / c0
    from scipy.optimize import brentq

    lo, hi = first, target / c0  # a(lo) = lo c0 < target <= hi c0 <= a(hi)
    for _ in range(60):  # round-off can leave a(hi) a hair below the target
        if cyc(hi)[0] >= target:
            break
        hi *= 1.0 + 1e-9
    return float(brentq(lambda x: cyc(x)[0] - target, lo, hi, xtol=1e-300, rtol=RTOL))


def modal_damping(
    structure: JointedStructure,
    amplitude: ArrayLike | None = None,
    *,
    force: ArrayLike | None = None,
    mode: int | ArrayLike = 0,
    samples: int = 64,
) -> ModalDamping:
    """ω(a) and ζ(a) of a mode of a jointed structure, from its exact steady hysteresis cycles.

    Parameters
    ----------
    structure : JointedStructure
        The structure and its Jenkins contacts (:mod:`lcpfric.model.structure`); K must be
        positive definite on its own (a part held only by contacts would slide away).
    amplitude : float or array_like, optional
        The modal amplitudes a > 0 to compute (α_max found for each, to a relative 1e-13).
    force : float or array_like, optional
        The modal force amplitudes α_max > 0 instead (one steady cycle each). Give exactly
        one of ``amplitude`` and ``force``.
    mode : int or (n,) array_like, optional
        The stuck structure's mode: its index (0, the default: the lowest), or a vector checked
        to be a mode (:meth:`~lcpfric.model.structure.JointedStructure.mode`).
    samples : int, optional
        Instants per cycle of the returned cycles ``q``: a multiple of 4, >= 4 (ω, ζ and W do
        not depend on it).

    Returns
    -------
    ModalDamping
        a, α_max, ω, ω/ω0, ζ, W and whether the joint sticks, per amplitude, with the cycles.

    Raises
    ------
    InputError
        ``structure`` not a JointedStructure; neither or both of ``amplitude`` and ``force``;
        a value <= 0 or not finite; ``samples`` not a multiple of 4; a ``mode`` index out of
        range or a vector that is not a mode; K not positive definite (named ``stiffness``).
    lcpfric.errors.ConvergenceError, lcpfric.errors.SolverError
        The exact solver's (:func:`lcpfric.exact.discrete.exact_system_cycle`).

    Examples
    --------
    One mass on a spring k0 = 1 with a Jenkins element (kt = 1, slip force 0.5):

    >>> from lcpfric.model.structure import JointedStructure
    >>> s = JointedStructure([[1.0]], [[1.0]], [[0, -1]], 1.0, 0.5, 1.0)
    >>> r = modal_damping(s, [0.1, 2.0])
    >>> r.sticks.tolist(), r.omega_ratio.round(12).tolist()
    ([True, False], [1.0, 0.790569415042])
    """
    from ..model.structure import JointedStructure

    start = time.perf_counter()
    if not isinstance(structure, JointedStructure):
        raise InputError(
            "structure", f"expected a JointedStructure, got {type(structure).__name__}"
        )
    if (amplitude is None) == (force is None):
        raise InputError("amplitude", "give exactly one of amplitude (modal a) and force (α_max)")
    asked = _values("amplitude", amplitude) if force is None else _values("force", force)
    samples = _checks.positive_int("samples", samples, 4)
    if samples % 4:
        raise InputError(
            "samples", f"must be a multiple of 4 (θ = π/2, 3π/2 sampled), got {samples}"
        )
    index = None
    if not hasattr(mode, "__len__"):
        index = _checks.positive_int("mode", mode, 0)
    lam, phi = structure.mode(index if index is not None else mode)
    sliders = structure.condense(phi)
    first = sliders.first_slip if sliders.contacts.size else math.inf  # none: no friction
    cyc = _Cycles(sliders, sliders.modal_compliance, first, samples)
    condensed = time.perf_counter()
    rows = []
    for value in asked:
        before = cyc.evaluations
        alpha = float(value) if force is not None else _search(cyc, float(value))
        a, W, q, cycles = cyc(alpha)
        rows.append((alpha, a, W, q, cycles, cyc.evaluations - before))
        cyc.cache.clear()
    alpha = np.array([r[0] for r in rows])
    a = np.array([r[1] for r in rows])
    W = np.array([r[2] for r in rows])
    omega = np.sqrt(alpha / a)
    omega0 = math.sqrt(lam)
    return ModalDamping(
        a=a,
        alpha_max=alpha,
        omega=omega,
        omega_ratio=omega / omega0,
        zeta=W / (TWO_PI * omega**2 * a**2),
        W=W,
        sticks=W == 0,
        cycles=np.array([r[4] for r in rows]),
        evaluations=np.array([r[5] for r in rows]),
        omega0=omega0,
        a_slip=first * sliders.modal_compliance,
        phi=phi,
        mode_index=index,
        theta=cyc.theta,
        q=np.array([r[3] for r in rows]),
        stats={
            "condense_seconds": condensed - start,
            "cycle_seconds": time.perf_counter() - condensed,
            "solves": cyc.solves,
            "contacts": int(sliders.contacts.size),
        },
    )


def jenkins_oscillator(
    a: ArrayLike, k0: float, kt: float, slip_force: float, mass: float = 1.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The closed form of one mass on a spring k0 in parallel with one Jenkins element.

    The mode is ``φ = 1/√m``, so the displacement amplitude is ``X = a/√m``; the steady cycle is
    symmetric, the element's force at its tip ``F_J(X) = min(kt X, Fs)`` (Jenkins' backbone),
    and (notes, "Amplitude-dependent frequency and damping")::

        α_max = (k0 X + F_J(X)) / √m,     ω² = α_max / a = (k0 + F_J(X)/X) / m,
        W = 4 Fs (X - Fs/kt) for X > Fs/kt (else 0),     ζ = W / (2π ω² a²)

    which is ``ω² = k0 + F_J(a)/a`` for m = 1.

    Parameters
    ----------
    a : float or array_like
        Modal amplitudes, > 0.
    k0, kt, slip_force : float
        The spring, the element's stiffness (both > 0) and its slip force Fs = mu N (>= 0).
    mass : float, optional
        m > 0.

    Returns
    -------
    omega, zeta, W, alpha_max : ndarray
        ω(a), ζ(a), W(a) and α_max(a), the shape of ``a``.

    Raises
    ------
    InputError
        A parameter out of range or not finite.
    """
    a = _values("a", a).reshape(np.shape(a))
    k0, kt = _checks.positive("k0", k0), _checks.positive("kt", kt)
    Fs, m = _checks.nonnegative("slip_force", slip_force), _checks.positive("mass", mass)
    X = a / math.sqrt(m)
    FJ = np.minimum(kt * X, Fs)
    alpha = (k0 * X + FJ) / math.sqrt(m)
    omega2 = alpha / a
    W = np.where(X > Fs / kt, 4.0 * Fs * (X - Fs / kt), 0.0)
    return np.sqrt(omega2), W / (TWO_PI * omega2 * a**2), W, alpha
