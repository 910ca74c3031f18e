r"""The half-space's increment for two bodies of different materials (Dundurs' β ≠ 0): the
normal and tangential problems coupled (:mod:`lcpfric.model.continuum.dissimilar`).

With β ≠ 0 the pressures depend on the shear (the gap gets ``J_β τ``, τ = F/h² the shear on
the loaded body) and the slips on the pressures (``s = δ + C F + D p``, ``D = −J_β``). Each
increment is solved by alternating the two problems to a fixed point (block Gauss-Seidel):

1. the tangential increment (the ``newton-cg`` increment, :mod:`.newton_increment`) under the
   limits ``μ p_k h²`` of the current pressures, with the slips' start shifted by ``D (p_k −
   p_prev)`` (the change of the pressure-induced slip is part of the increment's slip);
2. the frictionless normal problem (:func:`~lcpfric.model.continuum.normal3d.normal_contact`,
   warm-started) on the gap ``g0 + J_β τ`` under the total load P: ``p_{k+1}``;

until the pressures change by less than ``tol`` of their largest value (each tangential solve
starts from the previous iterate's forces). The map contracts like ``μ β`` times a factor of
order one (the coupling's share of the compliances): measured 5 to 8 iterations for μ = 0.3 to
0.5 and β up to 0.29 (a rigid base, ν = 0.3) to 1e-9. An increment that does not settle in
``max_iter`` iterations raises :class:`~lcpfric.errors.SolverError` (status ``"coupling"``)
naming the last change. β = 0 never comes here: the ``newton-cg`` stepper uses this only
where the model has a coupling (bit for bit the uncoupled path otherwise).

:func:`first_loading` runs the increments of a first loading at constant P without the driver
(the validation against tamaas, ``benchmarks/validation/halfspace_dissimilar.py``): from the
undeformed state (P and the first Q applied in the first increment: with one increment this is
the one-shot problem of a total-displacement solver) or from the normal loading (P alone first,
frictional where β ≠ 0, then Q in steps).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import InputError, SolverError
from ..model.continuum.influence import Counted
from ..model.continuum.normal3d import normal_contact

__all__ = ["CoupledIncrements", "first_loading"]

#: most normal/tangential alternations of one increment
MAX_ITER = 60


class CoupledIncrements:
    """The coupled increments of a half-space with β ≠ 0 (module docstring) around the
    uncoupled ones (``inner``, a :class:`~.newton_increment.HalfSpaceIncrements`).

    Parameters
    ----------
    inner : HalfSpaceIncrements
        The tangential increments.
    p_start : ndarray
        The pressures ``(N²,)`` of the starting state (its slips are measured from there).
    tol : float
        The fixed point's tolerance on the pressures' change (relative to their largest).
    max_iter : int
        Most alternations per increment.

    Attributes
    ----------
    p, Dp : ndarray
        The current pressures ``(N²,)`` and the slips ``D p`` they cause, node-major ``(n, d)``.
    stats : dict
        The inner increments' statistics (``increments`` counts their solves, one per
        alternation) with ``coupling_increments`` (the coupled increments),
        ``coupling_iterations`` (their alternations), ``coupling_max`` (the most in one) and
        ``coupling_normal_products`` (the normal solves' FFT products).
    """

    def __init__(self, inner, p_start, tol: float = 1e-9, max_iter: int = MAX_ITER):
        self.inner, self.model = inner, inner.model
        self.tol, self.max_iter = float(tol), int(max_iter)
        self.p = np.asarray(p_start, dtype=float).ravel().copy()
        self.Dp = self.Dp0 = self._slip(self.p)
        self.nop = Counted(self.model.op)
        self.stats = inner.stats
        keys = ("coupling_increments", "coupling_iterations", "coupling_max")
        for key in (*keys, "coupling_normal_products"):
            self.stats.setdefault(key, 0)

    @property
    def increment_tol(self) -> float:
        """The tangential increments' tolerance (the inner increments')."""
        return self.inner.tol

    def copy(self) -> CoupledIncrements:
        out = object.__new__(CoupledIncrements)
        out.__dict__.update(self.__dict__)
        out.inner = self.inner.copy()
        out.stats = out.inner.stats
        out.nop = Counted(self.model.op, self.nop.products)
        return out

    def _slip(self, p):
        m = self.model
        if not np.any(p):
            return np.zeros((m.nodes, m.dims))
        return m.coupling.slip(p.reshape(m.N, m.N)).reshape(m.dims, -1).T.copy()

    def compliance(self, F) -> np.ndarray:
        """The state's ``CF`` of the forces F: ``C F + D (p − p_start)`` at the current
        pressures (the slips are measured from the starting state; ``(n, d)``)."""
        return self.inner.compliance(F) + (self.Dp - self.Dp0)

    def increment(self, state, b, Q, guess=None, tol=None):
        """The coupled increment to the load of the limits b (``P = Σ b/μ``) and Q:
        ``(state, F, Δs)`` as the uncoupled increment's, the pressures kept in :attr:`p`."""
        m = self.model
        h2, n, d = m.h**2, m.nodes, m.dims
        P = float(np.sum(b)) / m.mu
        P_prev = float(self.p.sum()) * h2
        if P <= 0.0:
            p = np.zeros(n)
        elif P_prev > 0.0:
            p = self.p * (P / P_prev)
        else:
            p = np.asarray(b, dtype=float) / (m.mu * h2)
        change = np.inf
        for k in range(1, self.max_iter + 1):
            Dp = self._slip(p)
            start = replace(state, CF=state.CF + (Dp - self.Dp))
            self.inner.offset = Dp - self.Dp0  # its restarts form C F afresh
            new, F, ds = self.inner.increment(start, m.mu * h2 * p, Q, guess, tol)
            if P <= 0.0:
                break
            gap = m.coupling.gap((F.reshape(n, d) / h2).T.reshape(d, m.N, m.N))
            count = self.nop.products
            sol = normal_contact(self.nop, m.g0 + gap, P, p0=p.reshape(m.N, m.N))
            self.stats["coupling_normal_products"] += self.nop.products - count
            p_next = sol.p.ravel()
            change = float(np.max(np.abs(p_next - p))) / max(float(p_next.max()), 1e-300)
            if change <= self.tol:
                break
            # the next tangential solve starts from this iterate's forces and pattern
            guess = (new.F - state.F, new.delta - state.delta, new.side, new.CF - start.CF)
            p = p_next
        else:
            raise SolverError(
                f"half-space with dissimilar materials (beta = {m.beta:.4g}): the coupled "
                f"normal and tangential problems still change the pressures by {change:.3g} "
                f"of their largest after {self.max_iter} alternations (tol {self.tol:g}); "
                f"the coupling mu*beta = {m.mu * m.beta:.3g} may be too strong for the "
                f"fixed point: use smaller increments",
                backend="halfspace",
                status="coupling",
            )
        self.stats["coupling_increments"] += 1
        self.stats["coupling_iterations"] += k
        self.stats["coupling_max"] = max(self.stats["coupling_max"], k)
        self.p, self.Dp = p, Dp
        return new, F, ds


def first_loading(
    model,
    Q: float,
    *,
    steps: int = 1,
    start: str = "undeformed",
    tol: float = 1e-10,
    max_iter: int = MAX_ITER,
) -> dict:
    """A first loading at the model's mean normal load P0, Q from 0 to ``Q`` (d = 1 or 2).

    Parameters
    ----------
    model : HalfSpace
        The contact (any β: with β = 0 the increments are the uncoupled ones).
    Q : float
        The final tangential load along x (``|Q| < μ P0``).
    steps : int
        Increments of Q.
    start : {"undeformed", "normal"}
        ``"undeformed"``: P and ``Q/steps`` in the first increment (``steps = 1``: the one-shot
        problem); ``"normal"``: P alone first, then Q in ``steps`` increments.
    tol : float
        The tangential increments' tolerance.
    max_iter : int
        Most alternations per increment (:class:`CoupledIncrements`).

    Returns
    -------
    dict
        ``p`` ``(N, N)``; ``tau`` ``(d, N, N)`` the shear tractions on the loaded body
        (``F/h²``); ``contact``, ``stick`` ``(N, N)`` masks (stick: in contact and not slipping
        in the last increment); ``iterations``: the alternations of each increment; ``stats``.

    Raises
    ------
    InputError
        ``start`` or ``steps`` out of range.
    SolverError
        An increment failed (:class:`CoupledIncrements`).
    """
    from .. import _checks
    from .newton_increment import HalfSpaceIncrements, Tangential

    if start not in ("undeformed", "normal"):
        raise InputError("start", f"must be 'undeformed' or 'normal', got {start!r}")
    steps = _checks.positive_int("steps", steps)
    N, n, d, h2 = model.N, model.nodes, model.dims, model.h**2
    P = model.P0
    b = model.mu * h2 * model.pressure(P)
    inner = HalfSpaceIncrements(model, tol, abs(Q) / model.k_t0 if Q else 0.0)
    coupled = model.coupling is not None
    context = CoupledIncrements(inner, np.zeros(n), max_iter=max_iter) if coupled else inner
    zero = np.zeros((n, d))
    state = Tangential(
        np.zeros(n * d),
        np.zeros(d),
        np.zeros(n * d),
        np.zeros(n * d),
        np.zeros(d),
        np.zeros(n, dtype=np.int8),
        zero,
        zero.copy(),
    )  # the virgin contact (as the newton-cg stepper's start)
    loads = [Q * j / steps for j in range(1, steps + 1)]
    if start == "normal":
        loads = [0.0] + loads
    iterations = []
    for Qj in loads:
        before = context.stats.get("coupling_iterations", 0)
        state, F, ds = context.increment(state, b, Qj)
        iterations.append(context.stats.get("coupling_iterations", 1) - before)
    p = context.p if coupled else b / (model.mu * h2)
    contact = p > 0.0
    moved = np.abs(ds.reshape(n, d)).max(axis=1) > 0.0
    return {
        "p": p.reshape(N, N),
        "tau": (F.reshape(n, d) / h2).T.reshape(d, N, N),
        "contact": contact.reshape(N, N),
        "stick": (contact & ~moved).reshape(N, N),
        "iterations": iterations,
        "stats": dict(context.stats),
    }
