"""Batched single-node scenes: many points of a parameter grid advanced together.

Each point (P̂1, Q̂1, φ) is the paper's normalized node (K = 1, f = 1, N = max(1 + P̂1 sin θ, 0),
Q = Q̂1 sin(θ + φ), θ = ωt) on its own time grid, built exactly as :func:`lcpfric.make_scene`
builds it: a separating point (P̂1 > 1) starts at its re-contact instant and has its separation
instant on the grid, so the steps stay second-order accurate. The grids of all points have the
same number of instants (a point that needs fewer repeats its last instant: an increment of
length zero, which changes nothing), so step j of every point is taken at once:

:func:`projection_W_hat`
    the closed-form projection (a clamp, K = 1) as one numpy expression over all points per
    step: the same numbers as ``steady_state(node, "projection")`` point by point, far faster.
:func:`batched_W_hat`
    the points stacked into one block-diagonal problem (P) per step (see
    :mod:`lcpfric.backends._problem`), so that one Clarabel or OSQP call advances them all. A
    separated point keeps its variable with the linear term 0 (its answer is F = 0), so the
    problem's structure never changes.

Both iterate whole cycles until every point repeats its previous cycle within ``tol`` (the
batched cycle loop, :func:`lcpfric.periodic.batched.run`, with the criterion of
:func:`lcpfric.steady_state`); a point's Ŵ is that of its first converged cycle, Ŵ = J / Q̂1 (0
at Q̂1 = 0), and NaN where it did not converge. They return Ŵ; their ``*_steady_states`` twins
return a :class:`~lcpfric.results.BatchResult` with the convergence of every point.
"""

from __future__ import annotations

import math
import time

import numpy as np

from . import _checks
from .errors import InputError, SolverError
from .periodic import batched
from .results import BatchResult
from .scene import PLACEMENTS, increments
from .steppers.dissipation import node_shares

__all__ = ["projection_W_hat", "batched_W_hat", "projection_steady_states", "batched_steady_states"]

TWO_PI = 2.0 * math.pi


class _Grids:
    """The time grids of many single-node scenes, as :func:`lcpfric.make_scene` builds them.

    Instant j of point p is, piecewise: ``a1 + j s1`` for j < n1 (the uniform or contact
    steps), the separation instant for n1 <= j < n2, ``a3 + (j - o3) s3`` for n2 <= j < n3,
    and the cycle's end from n3 on.
    """

    def __init__(self, P1, Q1, phi, steps: int, placement: str):
        self.P1, self.Q1, self.phi = P1, Q1, phi
        T = TWO_PI  # normalized: ω = 1
        h = T / steps
        sep = P1 > 1.0
        inv = np.divide(1.0, P1, out=np.zeros_like(P1), where=sep)
        base = np.arcsin(-inv)  # the roots of 1 + P̂1 sin θ (lcpfric.model.loads.Harmonic.zeros)
        start = np.where(sep, base + 1 * T, 0.0)  # re-contact (lcpfric.scene._start_time)
        th_s = np.where(sep, (math.pi - base) + 1 * T, np.nan)  # separation within the cycle
        end = start + T
        self.start, self.end, self.th_s, self.sep = start, end, th_s, sep
        npts = P1.size
        n1 = np.full(npts, steps)
        n2 = np.full(npts, steps)
        n3 = np.full(npts, steps)
        a1, s1 = start, (end - start) / steps  # np.linspace(start, end, steps + 1)
        a3, s3, o3 = start.copy(), s1.copy(), np.ones(npts, dtype=int)
        if placement == "uniform":
            # base points closer than 1e-9 h to the separation instant are dropped (make_scene)
            idx = np.where(sep, np.ceil((th_s - 1e-9 * h - start) / np.where(sep, s1, 1.0)), 0)
            idx = np.clip(np.nan_to_num(idx), 0, steps).astype(int)
            near = sep & (np.abs(idx * s1 + start - th_s) < 1e-9 * h)
            n1 = np.where(sep, idx, steps)
            n2 = np.where(sep, idx + 1, steps)
            n3 = np.where(sep, np.where(near, steps, steps + 1), steps)
            o3 = np.where(near, 0, 1)
        else:  # "contact": every step in contact, one increment over the separation
            length = th_s - start
            kc = np.where(
                sep,
                increments(np.where(sep, steps * length, 1.0) / np.where(sep, length, 1.0)),
                steps,
            )
            s1 = np.where(sep, length / kc, s1)
            n1 = np.where(sep, kc, steps)
            n2 = np.where(sep, kc + 1, steps)
            n3 = n2.copy()
        self.a1, self.s1, self.n1, self.n2, self.n3 = a1, s1, n1, n2, n3
        self.a3, self.s3, self.o3 = a3, s3, o3
        self.size = int(np.max(n3)) + 1  # instants per cycle, the same for every point
        self.zero = 64 * np.finfo(float).eps * (1.0 + P1)  # a few ulps of the normal load

    def at(self, j: int):
        """(θ, Q, N) of every point at instant j."""
        theta = np.where(
            j < self.n1,
            self.a1 + j * self.s1,
            np.where(
                j < self.n2,
                self.th_s,
                np.where(j < self.n3, self.a3 + (j - self.o3) * self.s3, self.end),
            ),
        )
        N = np.maximum(1.0 + self.P1 * np.sin(theta), 0.0)
        N[self.sep & (j >= self.n1) & (j < self.n2)] = 0.0  # exactly zero at separation
        N[N <= self.zero] = 0.0  # round-off at re-contact is no contact (as make_scene)
        Q = self.Q1 * np.sin(theta + self.phi)
        return theta, Q, N


def _inputs(P1, Q1, phi, steps_per_cycle, placement, tol, max_cycles, on_nonconvergence):
    P1 = _checks.finite_array("P1", P1, nonneg=True)
    Q1 = _checks.finite_array("Q1", Q1, nonneg=True)
    phi = _checks.finite_array("phi", phi)
    try:
        P1, Q1, phi = np.broadcast_arrays(P1, Q1, phi)
    except ValueError:
        raise InputError(
            "P1",
            f"P1, Q1 and phi must broadcast together; got shapes "
            f"{np.shape(P1)}, {np.shape(Q1)}, {np.shape(phi)}",
        ) from None
    steps = _checks.positive_int("steps_per_cycle", steps_per_cycle, minimum=4)
    if placement not in PLACEMENTS:
        raise InputError("placement", f"must be one of {PLACEMENTS}, got {placement!r}")
    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles, on_nonconvergence)
    shape = P1.shape
    if P1.size == 0:
        raise InputError("P1", "needs at least one point")
    grids = _Grids(
        P1.ravel().astype(float),
        Q1.ravel().astype(float),
        phi.ravel().astype(float),
        steps,
        placement,
    )
    return grids, shape, tol, max_cycles


class _Points:
    """The points of a grid as a batched stepper (:mod:`lcpfric.periodic.batched`): ``advance(j,
    Q, N, u, F) -> (u, F)`` takes every point to instant j."""

    def __init__(self, grids: _Grids, advance):
        self.grids, self.advance = grids, advance
        self.size = grids.P1.size
        self.steps = grids.size - 1

    def init(self):
        _theta, Q, _N = self.grids.at(0)
        u = np.zeros(self.size)
        return u, Q + u

    def step(self, j, state):
        u, F = state
        _theta, Q, N = self.grids.at(j + 1)
        u1, F1 = self.advance(j + 1, Q, N, u, F)
        return (u1, F1), node_shares(F, F1, u1 - u)  # each point is one node

    def unknowns(self, state):
        return state[0][:, None]

    def scales(self):
        """K = f = 1: the loads' displacement scale is the range of Q over the cycle, the force
        scale the largest N."""
        _theta, Q, N = self.grids.at(0)
        qlo, qhi, nmax = Q.copy(), Q.copy(), N.copy()
        for j in range(1, self.grids.size):
            _theta, Q, N = self.grids.at(j)
            np.minimum(qlo, Q, out=qlo)
            np.maximum(qhi, Q, out=qhi)
            np.maximum(nmax, N, out=nmax)
        return qhi - qlo, nmax


def _periodic(
    grids: _Grids,
    advance,
    tol: float,
    max_cycles: int,
    on_nonconvergence: str,
    shape,
    method: str,
    steps: int,
    start: float,
) -> BatchResult:
    """Whole cycles of every point (:func:`lcpfric.periodic.batched.run`; the clamp is
    non-expansive, so the largest change of v over a cycle is the change of its starting
    value: the cycles compare their starts)."""
    Q1 = grids.Q1

    def W_hat(J):
        return np.where(Q1 > 0, J / np.where(Q1 > 0, Q1, 1.0), 0.0)

    return batched.run(
        _Points(grids, advance),
        tol=tol,
        max_cycles=max_cycles,
        on_nonconvergence=on_nonconvergence,
        measure="cycles",
        quantity="W_hat",
        values=W_hat,
        method=method,
        steps_requested=steps,
        shape=shape,
        start=start,
    )


def projection_steady_states(
    P1,
    Q1,
    phi,
    steps_per_cycle: int = 2000,
    placement: str = "uniform",
    *,
    tol: float = 1e-10,
    max_cycles: int = 100,
    on_nonconvergence: str = "raise",
) -> BatchResult:
    """Steady states of many points by the closed-form projection, vectorized over the points.

    Parameters
    ----------
    P1, Q1, phi : array_like
        The normalized parameters (P̂1, Q̂1 >= 0; φ in radians); broadcast together.
    steps_per_cycle : int
        Increments per cycle (>= 4); the separation instant is added, as in
        :func:`lcpfric.make_scene`.
    placement : {"uniform", "contact"}
        Step placement (see :mod:`lcpfric.scene`).
    tol, max_cycles, on_nonconvergence
        As in :func:`lcpfric.steady_state`, per point.

    Returns
    -------
    BatchResult
        Ŵ, convergence, cycles and change per point.
    """
    start = time.perf_counter()
    grids, shape, tol, max_cycles = _inputs(
        P1, Q1, phi, steps_per_cycle, placement, tol, max_cycles, on_nonconvergence
    )

    def advance(j, Q, N, u, F):
        f_tr = Q + u
        F1 = np.minimum(np.maximum(f_tr, -N), N)  # the clamp, Eq. (3) with K = f = 1
        return u + (F1 - f_tr), F1

    return _periodic(
        grids,
        advance,
        tol,
        max_cycles,
        on_nonconvergence,
        shape,
        "projection",
        int(steps_per_cycle),
        start,
    )


def projection_W_hat(
    P1,
    Q1,
    phi,
    steps_per_cycle: int = 2000,
    placement: str = "uniform",
    *,
    tol: float = 1e-10,
    max_cycles: int = 100,
    on_nonconvergence: str = "raise",
):
    """Ŵ of :func:`projection_steady_states` (ndarray, or float for scalar input).

    Examples
    --------
    >>> import numpy as np
    >>> W = projection_W_hat([0.5, 1.5], 2.0, 0.6 * np.pi, 4000)
    >>> W.shape
    (2,)
    """
    return projection_steady_states(
        P1,
        Q1,
        phi,
        steps_per_cycle,
        placement,
        tol=tol,
        max_cycles=max_cycles,
        on_nonconvergence=on_nonconvergence,
    ).W_hat


def batched_steady_states(
    P1,
    Q1,
    phi,
    method: str = "clarabel",
    steps_per_cycle: int = 2000,
    placement: str = "uniform",
    *,
    tol: float = 1e-10,
    max_cycles: int = 100,
    on_nonconvergence: str = "raise",
    **options,
) -> BatchResult:
    """Steady states of many points, all advanced by one solver call per step (a
    block-diagonal problem (P)).

    Parameters
    ----------
    P1, Q1, phi, steps_per_cycle, placement, tol, max_cycles, on_nonconvergence
        As in :func:`projection_steady_states`.
    method : str
        A convex backend: ``"clarabel"`` or ``"osqp"`` (any name of
        :func:`lcpfric.available_methods` backed by :mod:`lcpfric.backends` works).
    **options
        Passed to the backend (``refine``, ``check_tol``, solver settings).

    Returns
    -------
    BatchResult
    """
    import scipy.sparse as sp

    from .backends import ConvexStepper, IncrementProblem, accept
    from .methods import get_stepper

    start = time.perf_counter()
    grids, shape, tol, max_cycles = _inputs(
        P1, Q1, phi, steps_per_cycle, placement, tol, max_cycles, on_nonconvergence
    )
    stepper = get_stepper(method, **options)
    if not isinstance(stepper, ConvexStepper):
        raise InputError(
            "method",
            f"batched_steady_states needs a convex-solver backend such "
            f"as 'clarabel' or 'osqp', got {method!r}; for the closed "
            f"form use projection_steady_states",
        )
    npts = grids.P1.size
    idx = np.arange(npts)
    prob = IncrementProblem(
        idx, idx, 1, sp.identity(npts, format="csc"), None, diagonal=True, full=True
    )
    prob.handle = stepper.guarded(stepper.build, prob, stepper.settings_for(1))
    fs = max(1.0 + float(np.max(grids.P1, initial=0.0)), float(np.max(grids.Q1, initial=0.0)))
    label = f"batched {stepper.label}"

    def advance(j, Q, N, u, F):
        contact = N > 0.0
        q = np.where(contact, -(Q + u), 0.0)  # a separated point: q = 0, so F = 0
        b = np.where(contact, N, 1.0)
        x, status, ok = stepper.guarded(stepper.solve, prob, q, stepper.bounds(prob, b))
        if not ok:
            raise SolverError(
                f"{label}: step {j} ended with solver status {status!s} "
                f"({stepper.status_category(status)})",
                backend=stepper.label,
                status=str(status),
            )
        F1, stick, res, _kind = accept(
            prob,
            np.array(x, dtype=float),
            q,
            b,
            refine=stepper.refine,
            active_tol=stepper.active_tol,
            check_tol=stepper.check_tol,
            fscale=fs,
            cscale=1.0,
        )
        if F1 is None:
            raise SolverError(
                f"{label}: step {j}: the solver reported {status!s} but its "
                f"answer fails lcpfric's residual check {res}",
                backend=stepper.label,
                status=str(status),
                residuals=res,
            )
        F1 = F1.copy()
        F1[~contact] = 0.0
        u1 = F1 - Q
        if stick is not None:  # a refined stick point keeps its displacement exactly
            stick &= contact
            u1[stick] = u[stick]
        return u1, F1

    return _periodic(
        grids,
        advance,
        tol,
        max_cycles,
        on_nonconvergence,
        shape,
        f"batched {stepper.label}",
        int(steps_per_cycle),
        start,
    )


def batched_W_hat(
    P1,
    Q1,
    phi,
    method: str = "clarabel",
    steps_per_cycle: int = 2000,
    placement: str = "uniform",
    *,
    tol: float = 1e-10,
    max_cycles: int = 100,
    on_nonconvergence: str = "raise",
    **options,
):
    """Ŵ of :func:`batched_steady_states` (ndarray, or float for scalar input)."""
    return batched_steady_states(
        P1,
        Q1,
        phi,
        method,
        steps_per_cycle,
        placement,
        tol=tol,
        max_cycles=max_cycles,
        on_nonconvergence=on_nonconvergence,
        **options,
    ).W_hat
