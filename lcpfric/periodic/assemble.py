"""The steady state that the driver (:mod:`.driver`) returns, assembled from its cycles.

:func:`assemble` makes one :class:`~lcpfric.results.SteadyState` of the last cycle in the
model's units: a discrete system's series, a single node's with Eq. 6's normalization (``W_hat``),
a continuum contact's with its geometry (:class:`~lcpfric.results.ContactExtras`).
:func:`is_shakedown` says whether the cycle is a shakedown (the message says so), and
:func:`warn_unresolved` warns of a continuum contact's slip zone thinner than an element.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ResolutionWarning
from ..results import ContactExtras, CycleResult, State, SteadyState

__all__ = ["assemble", "is_shakedown", "warn_unresolved"]


def assemble(
    scene, solver, cyc, W_cycles, converged, change, requested, seconds, changes, extrapolations
) -> SteadyState:
    """The steady state of the cycle loop on ``scene``: ``cyc``, the last cycle in the model's
    units, with every cycle's W (``W_cycles``) and change (``changes``), whether it converged
    and its last ``change``, the steps per cycle requested, the wall ``seconds`` and the
    restarts of the acceleration (``extrapolations``, in the statistics when any). The message
    is "converged" or empty (the driver's to complete)."""
    model = scene.model
    rows = [0, -1] if cyc.t.size != scene.t.size else slice(None)
    stats = dict(cyc.stats)
    if extrapolations:
        stats["extrapolations"] = extrapolations
    B = getattr(scene.system, "coupling", None)
    N_all = scene.N
    if B is not None:  # N = P + B u, and how far a geometric approach may still be
        P = np.asarray(
            scene.system.normal.loads_at(scene.t[rows] if cyc.t.size != scene.t.size else scene.t)
        )
        N_all = P + cyc.u @ B.T
        stats.update(approach(changes))
    common = dict(
        cycles=len(W_cycles),
        converged=converged,
        method=solver.label,
        steps_requested=requested,
        steps_used=scene.steps,
        t=cyc.t,
        seconds=seconds,
        change=change,
        message="converged" if converged else "",
        changes=changes,
    )
    if scene.system is None:
        return _continuum(scene, cyc, W_cycles, rows, {**scene.stats, **stats}, common)
    if model is None:
        N = N_all if B is not None or cyc.t.size == scene.t.size else scene.N[[0, -1]]
        return SteadyState(
            W=float(W_cycles[-1]),
            W_cycles=W_cycles,
            v=cyc.u,
            F=cyc.F,
            N=np.asarray(N),
            state=cyc.state,
            solver_stats=stats,
            **common,
        )
    # a single node is advanced in the units f P0 (force), f P0/k11 (displacement): J = Q̂1 Ŵ
    fields = model.from_system(W_cycles, cyc.u[:, 0], cyc.F[:, 0], N_all[:, 0])
    return SteadyState(state=cyc.state[:, 0], solver_stats=stats, **fields, **common)


def approach(changes) -> dict:
    """How far a geometric approach may still be: ``ratio`` (the largest of the last two
    cycles' contractions) and ``remaining`` (``c ρ/(1 - ρ)``, the bound on the distance left,
    relative as the changes; the last change itself when the ratio is not below 0.95)."""
    c = np.asarray(changes if changes is not None else [], dtype=float)
    if c.size < 3 or not np.all(c[-3:-1] > 0):
        return {"ratio": float("nan"), "remaining": float(c[-1]) if c.size else float("nan")}
    rho = float(max(c[-1] / c[-2], c[-2] / c[-3]))
    return {
        "ratio": rho,
        "remaining": float(c[-1] * rho / (1 - rho)) if rho < 0.95 else float(c[-1]),
    }


def _continuum(scene, cyc, W_cycles, rows, stats, common) -> SteadyState:
    """A continuum contact's steady state, with its geometry (:class:`ContactExtras`)."""
    model = scene.model
    name, factor = model.normalization()
    W = W_cycles[-1]
    size = scene.sizes
    extras = ContactExtras(
        W_normalized=W * factor,
        normalization=name,
        contact_size_max=float(size.max()),
        k_t0=model.k_t0,
        nodes=model.nodes,
        nodes_in_contact_max=int(np.max(np.count_nonzero(scene.limits > 0, axis=1))),
        x=model.x,
        size=size,
    )
    return SteadyState(
        W=W,
        W_cycles=W_cycles,
        v=cyc.u,
        F=cyc.F,
        N=scene.N[rows],
        state=cyc.state,
        solver_stats=stats,
        contact=extras,
        **common,
    )


def is_shakedown(cyc: CycleResult) -> bool:
    """A shakedown: no node recorded slipping over the cycle and no dissipation at all."""
    return cyc.W == 0.0 and not np.any((cyc.state == State.FORWARD) | (cyc.state == State.BACKWARD))


def warn_unresolved(scene, W: float) -> None:
    """A continuum contact's steady cycle in which no element slips while the loads change:
    a smooth contact slips at its edge (where p -> 0) under almost any change of the loads, in
    a zone the grid may not resolve: warn (at the line that called
    :func:`~lcpfric.periodic.driver.steady_state`, which calls this)."""
    P, Q = scene.loads
    if W == 0.0 and not (P.is_constant and Q.is_constant) and np.any(scene.Q != 0.0):
        model = scene.model
        warnings.warn(
            f"{type(model).__name__}: no element slipped over the steady cycle "
            f"(W = 0 on {model.nodes} nodes): a slip zone thinner than an element is "
            f"not resolved (unless the loads change in proportion, |dQ/dP| < mu, "
            f"where W = 0 is exact); {model.refine_hint}",
            ResolutionWarning,
            stacklevel=3,
        )
