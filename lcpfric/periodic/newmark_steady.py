"""The periodic steady state of a :class:`~lcpfric.model.dynamic_system.DynamicSystem` by the
``newmark`` method: shooting (:func:`lcpfric.periodic.shooting.shoot`) on the Newmark period
map with its propagated Jacobian (:mod:`~lcpfric.steppers.newmark_system`), from the
equivalent linear response (:mod:`lcpfric.periodic.first_guess`) or a given start, verified by
one more period, reported as a :class:`~lcpfric.results.SteadyState`."""

from __future__ import annotations

import time

import numpy as np

from ..errors import InputError, SolverError
from .first_guess import equivalent_linear_start
from .shooting import shoot
from ..results import DynamicExtras, State, SteadyState
from ..steppers.newmark_system import APART, STICK, NewmarkSystem

__all__ = ["system_steady_state", "shooting_tolerance"]


def shooting_tolerance(steps: int) -> float:
    """The periodicity asked of an orbit, relative to the state's size: 1e-10, or the period
    map's own round-off (about 64 eps an increment) where that is larger."""
    return max(1e-10, 64 * np.finfo(float).eps * steps)


def start_vector(path, system, u0):
    """The first guess: ``u0`` as ``z = (x, x', w_J)`` (checked), or the equivalent linear
    response."""
    if u0 is None:
        return equivalent_linear_start(system)
    z = np.asarray(u0, dtype=float).ravel()
    if z.size != path.unknowns() or not np.all(np.isfinite(z)):
        raise InputError("u0", f"a DynamicSystem starts from z = (x, x', w_J): {path.unknowns()} "
                         f"finite numbers")  # fmt: skip
    return z


def system_steady_state(model, steps, max_cycles=100, u0=None, backend=None, options=None,
                        label="newmark") -> SteadyState:  # fmt: skip
    """The steady state of a dynamic system by shooting (module docstring).

    Parameters
    ----------
    model : DynamicSystem
        The system (d = 2 contacts: Jenkins elements only).
    steps : int
        Equal increments per period (the separations' instants are added).
    max_cycles : int, optional
        Newton iterations at most.
    u0 : array_like, optional
        The first guess ``z = (x, x', w_J)`` at t = 0.
    backend : str, optional
        The convex backend of the increments (default: a clip for one contact, else
        ``"clarabel"``).
    options : dict, optional
        The backend's options.
    label : str, optional
        The method's name in the result.

    Returns
    -------
    SteadyState
        ``t`` the grid; ``v`` the contacts' relative displacements ``Gᵀx``, ``F`` their forces
        T, ``N`` their normal loads, ``state`` their modes; ``dynamics`` with the amplitude
        of every degree of freedom, the velocities, ``displacement`` x, the Floquet multipliers
        and Newton's count.

    Raises
    ------
    InputError
        A rigid d = 2 contact; a bad ``u0``.
    SolverError
        Shooting did not converge in ``max_cycles`` Newton iterations (status ``"shooting"``),
        an increment's solver failed (the solver's status), or an increment's events did not
        settle (status ``"events"``).
    """
    start = time.perf_counter()
    path = NewmarkSystem(model, backend, options)
    if model.dims == 2:
        path.check_discs()
    z0 = start_vector(path, model, u0)
    tol = shooting_tolerance(steps)

    def period_map(z):
        z1, _, J, _ = path.period(z, steps, jacobian=True)
        return z1, J

    res = shoot(period_map, z0, tol, max_iterations=max_cycles)
    if not res.converged:
        raise SolverError(
            f"{label}: the periodic orbit not found by shooting (max |Φ(z) - z| / max |z| = "
            f"{res.residual:.3g} after {res.iterations} Newton iterations; tolerance {tol:.3g})",
            backend=label,
            status="shooting",
        )
    z_end, W, _, (t, rec) = path.period(res.z, steps, record=True)
    x = np.array([r[0][0][:, 0] for r in rec])
    xd = np.array([r[0][1][:, 0] for r in rec])
    T = np.array([r[1][:, 0] for r in rec])
    N = np.array([model.normal(ti) for ti in t])
    if model.dims == 1:
        modes = np.array([r[2] for r in rec])
        states = np.select(
            [modes == STICK, modes == APART, modes == 1],
            [State.STICK, State.SEPARATION, State.FORWARD],
            State.BACKWARD,
        ).astype(np.int8)
    else:  # d = 2: slip where a slider moves over the increment ending at the instant
        w = np.array([r[0][3][:, 0] for r in rec])
        dw = np.vstack([np.zeros((1, w.shape[1])), np.diff(w, axis=0)])
        moved = np.hypot(dw[:, 0::2], dw[:, 1::2]) > 1e-12 * max(float(np.abs(w).max()), 1e-300)
        states = np.where(moved, State.FORWARD, State.STICK).astype(np.int8)
        states[N <= 0] = State.SEPARATION
    mult = np.linalg.eigvals(res.jacobian)
    amp = 0.5 * (x.max(axis=0) - x.min(axis=0))
    stable = bool(np.all(np.abs(mult) < 1.0 - 1e-9))
    Omega = model.natural_frequency()
    extras = DynamicExtras(
        beta=model.omega / Omega,
        zeta=float("nan"),
        amplitude=amp,
        velocity=xd,
        floquet=mult,
        stable=stable,
        orbits=(
            {
                "W": float(W),
                "amplitude": float(amp.max()),
                "stable": stable,
                "start": "given" if u0 is not None else "equivalent linear",
            },
        ),  # fmt: skip
        newton_iterations=res.iterations,
        periods=res.periods,
        displacement=x,
    )
    return SteadyState(
        W=float(W),
        W_cycles=np.atleast_1d(float(W)),
        cycles=res.periods,
        converged=True,
        method=label,
        steps_requested=steps,
        steps_used=int(t.size - 1),
        t=t,
        v=x @ model.G,
        F=T,
        N=N,
        state=states,
        seconds=time.perf_counter() - start,
        change=res.residual,
        message=f"{label} (average acceleration, events located, increments by "
        f"{path.inc.label}): periodic orbit by shooting in {res.iterations} Newton "
        f"iterations, {res.periods} periods",
        solver_stats={
            "increments": path.increments,
            "events": path.events,
            **path.inc.stats,
        },  # fmt: skip
        dynamics=extras,
    )
