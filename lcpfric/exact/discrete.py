"""The exact periodic steady state of a discrete system (d = 1), event by event.

The system is ``F = Q(θ) + K u``, ``|F_i| <= f_i N_i(θ)``, ``N_i = max(P_i(θ), 0)``, θ = ωt, with
every load harmonic at the one frequency ω (each node its own mean, amplitude and phase for P and
for Q) and K symmetric positive definite, dense or sparse.

Between events: closed form
---------------------------
Write every load as a *trig triple* ``x(θ) = c0 + cs sin θ + cc cos θ``. Within a fixed pattern
(each node stuck, slipping forward with ``F_i = -f_i P_i``, slipping backward with
``F_i = +f_i P_i``, or separated with ``F_i = 0``) the stuck nodes S keep their displacements
and the others B carry known forces, so::

    u_B(θ) = K_BB⁻¹ (F_B(θ) - Q_B(θ) - K_BS u_S),     F(θ) = Q(θ) + K u(θ)

are trig triples too. Every event is where one of them crosses zero:

* a stuck node reaches a friction limit: ``f_i P_i ∓ F_i = 0``;
* a slip rate vanishes: ``±du_i/dθ = 0``;
* a node separates or re-enters contact: ``P_i = 0``.

``c0 + R sin(θ + ψ) = 0`` is solved in closed form (:func:`next_entry`), and the dissipation
of a segment, ``Σ_slip ∫ f_i P_i |du_i|``, is integrated in closed form
(:func:`segment_dissipation`).

At an event: the rate problem
-----------------------------
Which nodes slip after an event is decided by the slip-rate complementarity problem, a P-matrix
LCP (:func:`lcpfric.steppers.rates.slip_rates`, the explicit stepper's too, with the
load rates at the event). The common case, one node changing state, is first tried as a guess
(the node that reached its limit slips, the node whose rate vanished sticks) and accepted when
the rates of the new pattern satisfy the LCP's conditions at the event; that is the LCP's unique
solution, at O(n²) instead of ``O(|B|³)``. Degenerate instants, where the first-order rates leave a
tie (a node touching its limit with zero margin rate), are resolved by the LCP with the load
rates a little after the event; an instant that still does not settle raises
:class:`~lcpfric.errors.SolverError` naming the nodes and their states, never a hang.

The inverse ``G = K_BB⁻¹`` is updated by bordering when a node joins B and by a rank-one
downdate when it leaves (``O(|B|²)`` each, compiled with the whole event loop:
:mod:`lcpfric.exact.loop`), and refactorized after ``max(64, |B|)`` updates or whenever the
equilibrium residual of the new pattern exceeds 1e-10 of the force scale.

Tolerances
----------
A margin or rate is *meaningfully* negative when its minimum is below ``-rel`` of its node's
force (or the system's rate) scale, ``rel = max(1e-13, 100 eps cond(K))``: round-off through
``K_BB⁻¹`` grows with the conditioning. Shallower dips, a node touching its limit without
slipping, are not events; the deepest one skipped is reported (``skipped_depth``), and the
dissipation it could hide is below that depth times the largest compliance times the largest
friction limit. A fresh pattern whose equilibrium residual exceeds ``max(1e-10, 1e3 eps cond(K))``
raises :class:`~lcpfric.errors.SolverError`.

Cycles
------
The first cycle starts at θ = 0 from an admissible state (forces ``clip(Q(0), -f N, f N)``).
The cycle map ``u(0) -> u(2π)`` is then solved by Newton's method with its exact Jacobian,
propagated along the cycle: a node that sticks holds ``u_j = U_j(θ)``, which depends on the
stuck displacements through ``-(G K_BS)_j`` and, when it is stopped by another node reaching
its limit (not by its own slip rate vanishing), on that event's angle, whose sensitivity is
``-(∂g/∂u_S) / g'`` for the margin g that triggered it. With the sequence of events settled
the convergence is quadratic; where a node sits on the threshold of slipping (a tiny slip that
appears in one cycle and not the next) the cycle map has a kink there and the convergence is
linear (``benchmarks/perf/exact_discrete.py`` reports the cycles). A node that never changes state
keeps its start displacement (the steady state is not unique in it, the dissipation is).
Cycles stop when the start displacements of two successive cycles agree to ``tol`` of the
largest displacement range over the cycle (what the slips are measured against; at least
the displacement ``max |Q1| / min K_ii`` the tangential amplitudes make; a mean
tangential load Q0 is taken out beforehand, as it only shifts u by ``-K⁻¹ Q0``), or to the
round-off ``100 eps cond(K) max(|u|, max f N / min K_ii)``, if larger; with uncoupled normal
reactions the steady dissipation is unique (Barber, Klarbring and Ciavarella), so the start
does not change it. When the first cycle already repeats (every node's history erased by
separation) no Jacobian is computed. Where Newton's step makes no progress (less than 10 % off
the change), it is halved from the best start so far, down to 1/8, then one plain cycle-map
step is taken. The number of cycles and of Newton steps is reported.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError
from ..periodic.measure import cycle_change
from ..results import State
from .clusters import STIFF, ClusterEventSolver
from .events import EventSolver
from .triples import TWO_PI, harmonic_triples, next_entry, segment_dissipation, value

if TYPE_CHECKING:
    from ..model import ContactSystem

__all__ = [
    "DiscreteCycle",
    "harmonic_triples",
    "next_entry",
    "segment_dissipation",
    "exact_system_cycle",
    "check_system",
]

STICK = int(State.STICK)
_FREE_STEPS = 6  # Newton steps from a worse start before going back (cluster coordinates)
_EPS = float(np.finfo(float).eps)


# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DiscreteCycle:
    """The exact steady cycle of a discrete system.

    Attributes
    ----------
    W : float
        Dissipation per cycle (model units).
    W_cycles : ndarray
        W of every cycle run (the last is the steady one).
    cycles : int
        Cycles run until the start of a cycle repeated (to ``tol``).
    change : float
        The relative change of the start displacements over the last cycle.
    events : int
        Events in the steady cycle.
    omega : float
        The loads' angular frequency (θ = ωt).
    theta, u, F, N, state : ndarray
        The steady cycle sampled at the angles ``theta`` (rows), one column per node.
    stats : dict
        ``events_per_cycle``, ``lcp_solves`` (fallbacks to the full rate LCP), ``degenerate``
        (instants resolved by look-ahead), ``refactorizations``, ``skipped_depth`` (the deepest
        dip not treated as an event, relative to its scale), ``seconds``.
    """

    W: float
    W_cycles: np.ndarray
    cycles: int
    change: float
    events: int
    omega: float
    theta: np.ndarray
    u: np.ndarray
    F: np.ndarray
    N: np.ndarray
    state: np.ndarray
    stats: dict = field(default_factory=dict)


def _condition(K) -> float:
    """cond(K) = λmax/λmin (symmetric positive definite), from the eigenvalues up to n = 3000;
    beyond, an estimate: the largest absolute row sum over the smallest diagonal entry."""
    n = K.shape[0]
    if n <= 3000:
        ev = np.linalg.eigvalsh(K)
        return float(ev[-1] / ev[0]) if ev[0] > 0 else np.inf
    return float(np.max(np.sum(np.abs(K), axis=1)) / np.min(np.diag(K)))


def _newton_step(J, r, status0, flipped):
    """δ with ``(I - J) δ = r``: the Newton step of the cycle map u -> u(2π) (J its Jacobian,
    r = u(2π) - u). A node stuck at the start that never changed state keeps its displacement
    whatever the others do (J has its unit row, r_i = 0): it is left out, as the steady state
    is not unique in it."""
    n = r.size
    keep = ~((status0 == STICK) & ~flipped)
    delta = np.zeros(n)
    if keep.any():
        A = np.eye(n)[np.ix_(keep, keep)] - J[np.ix_(keep, keep)]
        try:
            delta[keep] = np.linalg.solve(A, r[keep])
        except np.linalg.LinAlgError:
            delta[keep] = np.linalg.lstsq(A, r[keep], rcond=None)[0]
    return delta


def check_system(system):
    """(ω, Q triples, P triples) of a system ``exact`` can solve, or :class:`InputError` naming
    what it cannot and the methods that can."""
    from ..model import ContactSystem
    from ..model.normal import IndependentSprings

    if not isinstance(system, ContactSystem):
        raise InputError("model", f"expected a ContactSystem, got {type(system).__name__}")
    if system.dims != 1:
        raise InputError(
            "method",
            "'exact' for a ContactSystem handles d = 1; for d = 2 use "
            "'clarabel' or 'cvxpy:CLARABEL'",
        )
    if not isinstance(system.normal, IndependentSprings):
        raise InputError(
            "normal",
            "'exact' needs independent normal springs "
            "(IndependentSprings); use 'explicit' or a solver backend",
        )
    omegas = [
        q.omega
        for q in (*system.tangential_loads, *system.normal.loads)
        if getattr(q, "amplitudes", ()) and any(q.amplitudes)
    ]
    omega = omegas[0] if omegas else 1.0
    Qt = harmonic_triples(system.tangential_loads, omega, "tangential_loads")
    Pt = harmonic_triples(system.normal.loads, omega, "normal_loads")
    return omega, Qt, Pt


def exact_system_cycle(
    system: ContactSystem,
    samples: int = 2000,
    *,
    tol: float = 1e-12,
    max_cycles: int = 200,
    max_events: int | None = None,
    u0=None,
) -> DiscreteCycle:
    """The exact periodic steady state of a :class:`~lcpfric.model.ContactSystem`.

    For d = 1, harmonic loads of one frequency and independent normal springs. Event by event within
    a cycle, Newton's method on the cycle map between cycles (see the module docstring).
    ``steady_state(system, method="exact")`` calls it.

    Parameters
    ----------
    system : ContactSystem
        The system: d = 1, any symmetric positive definite K (dense or sparse),
        :class:`~lcpfric.model.IndependentSprings` normal model, every tangential and normal
        load harmonic (``Harmonic`` or a one-term ``Fourier``) at the one frequency ω.
    samples : int
        The steady cycle is sampled at ``samples + 1`` equally spaced instants (W does not
        depend on it), ``samples >= 4``.
    tol : float
        Periodicity, > 0: the start displacements of two successive cycles agree to ``tol`` of
        the largest displacement range over the cycle (at least ``max |Q1| / min K_ii``), or to
        the round-off ``100 eps cond(K) max(|u|, max f N / min K_ii)`` if that is larger.
    max_cycles : int
        Cap on the cycles, >= 1; reaching it raises
        :class:`~lcpfric.errors.ConvergenceError`.
    max_events : int, optional
        Cap on the events of one cycle (default 200 n + 1000); reaching it raises
        :class:`~lcpfric.errors.SolverError` naming the state.
    u0 : (n,) array_like, optional
        The displacements at θ = 0 (admissible: ``|Q(0) + K u0| <= f N(0)``, as
        :func:`lcpfric.steady_state` checks); the nodes in contact stick from there unless
        a limit is reached at θ = 0. Default: the forces ``clip(Q(0), -f N, f N)``.

    Returns
    -------
    DiscreteCycle
        W per cycle (model units), the W of every cycle run, the cycles and events, and the
        steady cycle sampled at ``samples + 1`` angles.

    Raises
    ------
    lcpfric.errors.InputError
        A system ``exact`` cannot solve (not a ContactSystem, d = 2, another normal model,
        loads that are not harmonic or not of one frequency), ``samples``, ``tol`` or
        ``max_cycles`` out of range, or dense n x n matrices over the memory limit
        (:mod:`lcpfric.memory`).
    lcpfric.errors.ConvergenceError
        No periodic steady state after ``max_cycles`` cycles.
    lcpfric.errors.SolverError
        More than ``max_events`` events in one cycle, an instant whose pattern does not
        settle, a pattern whose equilibrium residual exceeds the tolerance, or a ``K_BB``
        that is not positive definite.
    """
    start = time.perf_counter()
    omega, Qt, Pt = check_system(system)
    samples = _checks.positive_int("samples", samples, 4)
    tol = _checks.positive("tol", tol)
    max_cycles = _checks.positive_int("max_cycles", max_cycles)
    if system.coupling is not None:  # N = P + B u: the physical iteration (lcpfric.exact.coupled)
        from .coupled import coupled_system_cycle

        return DiscreteCycle(**coupled_system_cycle(
            system, Qt, Pt, omega, samples, tol=tol, u0=u0, max_events=max_events,
            max_cycles=max_cycles,
        ))  # fmt: skip
    f = system.friction
    n = f.size
    from .. import memory

    memory.check(
        8.0 * (6.0 * n * n + 3.0 * n * (samples + 1)),
        "model",
        f"the exact steady state of {n} nodes (dense n x n matrices: K, K_BB⁻¹, the "
        f"cycle's Jacobian)",
    )
    K = system.dense_stiffness().astype(float)
    # forces of order one: divide by a power of two (exact), W scales by its square
    size = float(
        max(
            np.max(np.abs(Qt[:, 0]) + np.hypot(Qt[:, 1], Qt[:, 2])),
            np.max(f * (np.abs(Pt[:, 0]) + np.hypot(Pt[:, 1], Pt[:, 2]))),
        )
    )
    scale = 2.0 ** round(math.log2(size)) if size > 0 and math.isfinite(size) else 1.0
    kappa = _condition(K)
    # the round-off of Cholesky factors and their updates does not see a diagonal scaling
    # (van der Sluis): the periodicity floor uses the condition of the scaled K
    d = 1.0 / np.sqrt(np.diag(K))
    kappa_scaled = _condition(d[:, None] * K * d[None, :])
    # a constant tangential load Q0 only shifts u by -K⁻¹ Q0 (F = Q + K u is unchanged): it is
    # taken out, so that displacements of a small amplitude are not computed on a large offset
    Q0 = Qt[:, 0].copy()
    Qt = Qt.copy()
    Qt[:, 0] = 0.0
    # a stiff system (eps cond(K) beyond STIFF) is solved in cluster coordinates, which keep
    # the stretches of its stiff springs (lcpfric.exact.clusters)
    Solver = ClusterEventSolver if _EPS * kappa > STIFF else EventSolver
    solver = Solver(K, f, Qt / scale, Pt / scale, samples, max_events or 200 * n + 1000, kappa)
    u_static = -solver.cho_solve(Q0) if np.any(Q0) else np.zeros(n)
    theta_s = np.linspace(0.0, TWO_PI, samples + 1)
    if u0 is None:
        u, status = solver.initial_state()
    else:  # Q0 taken out (u_static) and forces scaled, as the solver holds them
        x = (np.asarray(u0, dtype=float).ravel() - u_static) / scale
        if solver.structured:  # cluster coordinates: a root's u, the others' offsets from it
            root = solver.cl.canonical
            x = np.where(root == np.arange(n), x, x - x[root])
        u, status = solver.admissible(x, np.full(n, STICK, dtype=np.int8))
    floor = tol
    W_cycles, change = [], np.inf
    track, newton = False, 0
    best = None  # (change, start, its status, step) of the best start so far
    lam, free = 1.0, 0
    for _ in range(max_cycles):
        u_end, status_end, W, events, series = solver.cycle(u, status, theta_s, track)
        W_cycles.append(W * scale * scale)
        r = u_end - u
        # relative to the largest displacement range over the cycle (what the slips are
        # measured against), at least the displacement the tangential amplitudes make;
        # round-off is relative to |u| or the forces' displacement scale, times cond(K)
        # (the driver's measure, lcpfric.periodic.measure, on the start displacements, with no W
        # term: the cycles start from Newton's iterates, and W follows from the start)
        span = float(np.max(np.ptp(series[0], axis=0), initial=0.0))
        change = cycle_change(
            float(np.max(np.abs(r), initial=0.0)), span, 0.0, W, (solver.qscale, 0.0)
        )
        ref = max(span, solver.qscale)
        size = max(float(np.max(np.abs(u_end), initial=0.0)), ref, solver.rscale)
        floor = max(tol, 100.0 * _EPS * min(solver.kappa, kappa_scaled) * size / ref)
        if solver.structured:
            # coordinate by coordinate: a cluster's offsets against the stretch of its springs,
            # a root against its own range (one range for all would hide the stiff ones)
            change, floor = solver.state_change(r, u_end, np.ptp(series[0], axis=0)), tol
        if change <= floor:
            break
        progress = best is None or change < 0.9 * best[0]
        # a stiff system's cycle map has modes that contract by 1 - O(k_g / k_c) per cycle:
        # Newton's step along one lands where the pattern differs, a worse start at first;
        # a few Newton steps from there are taken before going back to the best start
        free = 0 if progress else free + 1
        if progress or (solver.structured and track and free <= _FREE_STEPS):
            # progress: Newton's step from here (the plain cycle-map step before the Jacobian
            # is tracked)
            step = r
            if track:
                J = solver.jacobian()
                if solver.structured:  # the step in u (where a held node is a unit row)
                    T, Ti = solver.transform()
                    step = Ti @ _newton_step(T @ J @ Ti, T @ r, status, solver.flipped)
                else:
                    step = _newton_step(J, r, status, solver.flipped)
                newton += 1
            if progress:
                best, lam = (change, u, status, step, u_end, status_end), 1.0
            u_next, guess = u + step, status_end
        elif lam > 0.125:
            # no progress: back from the best start along a shorter step (damped Newton)
            lam *= 0.5
            u_next, guess = best[1] + lam * best[3], best[5]
        else:
            # Newton's direction does not help here (a kink of the cycle map): one plain step
            # from the best start, whose result is accepted whatever it is
            u_next, guess = best[4], best[5]
            best, lam = None, 1.0
        # the tangent map pays O(n) per event on a chain, O(n²) on dense K: track from the
        # second cycle on unless the first already reached the orbit (a history erased by
        # separation), and then until the end
        # ... and not after a cycle that forgot its start (every node free at one instant):
        # the next one repeats it, and a Jacobian would go unused
        track = (track or change > 1e3 * tol) and not solver.erased
        u, status = solver.admissible(u_next, guess)
    else:
        raise ConvergenceError(
            f"exact: no periodic steady state after {max_cycles} cycles "
            f"(relative change of the start {change:.3g} > tol {tol:g}); "
            f"raise max_cycles",
            None,
        )
    Us, Fs, Ss = series
    N = np.maximum(value(Pt[None, :, :], theta_s[:, None]), 0.0)
    N = np.where(solver.never, 0.0, N)
    stats = dict(
        solver.stats,
        **solver.kernel_stats(),
        events_per_cycle=events,
        cycles=len(W_cycles),
        newton_steps=newton,
        condition=kappa,
        structured=solver.structured,
        periodicity_tol=floor,
        seconds=time.perf_counter() - start,
    )
    return DiscreteCycle(
        W=W_cycles[-1],
        W_cycles=np.asarray(W_cycles),
        cycles=len(W_cycles),
        change=change,
        events=events,
        omega=omega,
        theta=theta_s,
        u=Us * scale + u_static,
        F=Fs * scale,
        N=N,
        state=Ss,
        stats=stats,
    )
